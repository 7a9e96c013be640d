"""Sweeps: vstpetsc.sweep and `vstpetsc sweep` (one rank here; two ranks in
test_parallel.py): rows equal the runs' own summaries, a homogeneous
problem scales exactly, a failed run is a row, a second sweep skips what
is done, the summary plots."""

import csv
import os

import numpy as np
import pytest

import vstpetsc
from conftest import bar, cli, make_case, write_case
from vstpetsc.runner.sweep import quantities, read_summary


def wall_case():
    """A bar touching a wall at zero gap: the problem is positively
    homogeneous in v0, so doubling v0 doubles every force exactly."""
    return make_case(0.01, 1.5, [bar("bar", (0.0, 1.0), 20, E=1.0, rho=1.0, v0=1.0)],
                     contacts=[dict(pair=["bar", "wall"], wall=1.0, formulation="power")])


def test_rows_are_the_runs_summaries_and_scale_exactly(tmp_path):
    case = wall_case()
    rows = vstpetsc.sweep(case, {"body.bar.v0": [0.5, 1.0, 2.0]}, str(tmp_path / "s"))
    assert [r["status"] for r in rows] == ["completed"] * 3
    assert [r["body.bar.v0"] for r in rows] == [0.5, 1.0, 2.0]
    for r in rows:
        direct = vstpetsc.run(case.with_value("body.bar.v0", r["body.bar.v0"]),
                              output=str(tmp_path / "direct.h5"), quiet=True)
        assert quantities(direct) == {k: r[k] for k in quantities(direct)}
    for key in ("force_peak_0", "impulse_0", "stress_min_bar"):
        assert rows[1][key] != 0
        assert rows[2][key] == 2 * rows[1][key] and rows[0][key] == 0.5 * rows[1][key], key
    header, data = read_summary(str(tmp_path / "s" / "summary.csv"))
    assert header[:4] == ["body.bar.v0", "file", "status", "wall_time"]
    assert data["force_peak_0"] == [r["force_peak_0"] for r in rows]     # 17 digits


def test_failed_run_is_a_row_and_a_second_sweep_skips_completed_runs(tmp_path):
    case = write_case(tmp_path, wall_case())
    out = tmp_path / "s"
    p = cli("sweep", case, "--set", "body.bar.elements=10,0,30", "-o", out)
    assert p.returncode == 3, p.stderr
    with open(out / "summary.csv") as f:
        rows = list(csv.DictReader(f))
    assert [r["status"] for r in rows] == ["completed", "failed", "completed"]
    assert "elements" in rows[1]["message"] and rows[1]["force_peak_0"] == ""
    assert "1 failed" in p.stdout
    stamps = {n: os.stat(out / n).st_mtime_ns for n in ("run-0.h5", "run-2.h5")}
    again = cli("sweep", case, "--set", "body.bar.elements=10,0,30", "-o", out, "--quiet")
    assert again.returncode == 3
    assert stamps == {n: os.stat(out / n).st_mtime_ns for n in stamps}
    with open(out / "summary.csv") as f:
        later = list(csv.DictReader(f))
    # completed runs are read back (their own wall time); the failed one is tried again
    assert [later[i]["wall_time"] for i in (0, 2)] == [rows[i]["wall_time"] for i in (0, 2)]
    # a file of another case is not taken for done
    longer = write_case(tmp_path, wall_case().with_value("time.end", 1.6), "longer")
    cli("sweep", longer, "--set", "body.bar.elements=10,0,30", "-o", out, "--quiet")
    assert os.stat(out / "run-0.h5").st_mtime_ns != stamps["run-0.h5"]
    assert vstpetsc.Result(out / "run-0.h5").case().nslabs == 160


def test_sweep_plot_and_bad_arguments(tmp_path):
    case = write_case(tmp_path, wall_case())
    out = tmp_path / "s"
    assert cli("sweep", case, "--set", "body.bar.v0=1,2", "-o", out).returncode == 0
    p = cli("plot", out / "summary.csv", "--y", "impulse_0", "-o", tmp_path / "f.png")
    assert p.returncode == 0 and (tmp_path / "f.png").stat().st_size > 1000, p.stderr
    for args, words in (
            (["--set", "body.bar.v0"], "give KEY=V1,V2"),
            (["--set", "nonsense=1,2"], "a path is table.key"),
            (["--set", "body.bar.v0=1,", ], "an empty value"),
            ([], "at least one --set"),
            (["--set", "body.bar.v0=1", "--ranks-per-run", "2"], "a whole divisor of the 1")):
        p = cli("sweep", case, *args, "-o", out)
        assert p.returncode == 2 and p.stderr.count("\n") == 1 and words in p.stderr, p.stderr
    p = cli("plot", out / "summary.csv", "--y", "nope")
    assert p.returncode == 2 and "--y nope: no such column" in p.stderr


@pytest.mark.parametrize("text, value", [("1", 1), ("2.5e-3", 2.5e-3), ("power", "power"),
                                         ('"seed"', "seed"), ("true", True)])
def test_setting_values_read_as_toml(text, value):
    from vstpetsc.runner.sweep import parse_setting
    assert parse_setting(f"contact.0.x={text}") == ("contact.0.x", [value])
    assert np.isscalar(parse_setting(f"k={text},{text}")[1][1])


def test_capacity_sweep_draws_a_bearing_graph(tmp_path):
    """A capacity sweep of a blow: the blow count grows with the capacity,
    and `plot` draws the bearing graph from summary.csv."""
    from test_soil import blow
    case = write_case(tmp_path, blow(n=10, dt=1.6e-4))
    out = tmp_path / "bearing"
    p = cli("sweep", case, "--set", "soil.0.capacity=0.5e6,1e6,2e6", "-o", out, "--quiet")
    assert p.returncode == 0, p.stderr
    header, data = read_summary(str(out / "summary.csv"))
    assert {"set_0", "blow_count_0", "transferred_energy", "stress_min_pile"} <= set(header)
    assert np.all(np.diff(data["blow_count_0"]) > 0)
    p = cli("plot", out / "summary.csv", "-o", tmp_path / "bearing.png")
    assert p.returncode == 0 and (tmp_path / "bearing.png").stat().st_size > 10000, p.stderr
