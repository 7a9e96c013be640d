"""The quick benchmark runs and reports every field with a finite value
(speed itself is reported by `make bench`, never asserted)."""

import json
import os
import shutil
import subprocess
import sys

from conftest import ROOT


def test_bench_quick_reports_every_field(tmp_path):
    p = subprocess.run([sys.executable, os.path.join(ROOT, "bench", "run.py"), "--quick",
                        "--out", str(tmp_path)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    res = json.loads((tmp_path / "results.json").read_text())
    for row in res["limit"]:
        for key in ("elements", "slabs", "solve_min_ms", "solve_median_ms", "apply_min_ms",
                    "apply_median_ms", "slab_min_ms", "slab_median_ms", "ratio",
                    "ratio_median", "ratio_apply", "peak_memory_MB"):
            assert isinstance(row[key], (int, float)) and row[key] > 0, key
    for key in ("no_contact_ms", "contact_ms", "ratio"):
        assert res["contact"][key] > 0
    smooth = res["peer"]["smooth"]
    for method in ("vstfem", "alpha2_r1", "alpha2_r0.5"):
        assert len(smooth[method]) >= 3
        for point in smooth[method]:
            assert point["error"] > 0 and point["wall"] > 0
    # v-ST/FEM is third order: observed order between the two finest step counts
    import math
    last = smooth["vstfem"][-2:]
    order = math.log(last[0]["error"] / last[1]["error"]) / math.log(last[1]["steps"] / last[0]["steps"])
    assert order >= 2.5
    for method in ("vstfem", "alpha2_r1", "alpha2_r0.5"):
        m = res["peer"]["impact"][method]
        assert m["plateau_mean"] > 0 and m["oscillation"] >= 0 and m["wall"] > 0
    assert abs(res["peer"]["impact"]["vstfem"]["plateau_mean"] - 0.5) < 0.05
    ov = res["overhead"]
    assert {r["case"] for r in ov["rows"]} == {"free", "held", "impact", "soil",
                                              "free (-vst_native 0)",
                                              "held (-vst_native 0)", "impact (-vst_native 0)"}
    for row in ov["rows"]:
        for key in ("slab_min_us", "slab_median_us", "floor_min_us", "floor_median_us",
                    "ratio", "ratio_median"):
            assert row[key] > 0, key
        # the contact cases keep a pair active (timed over those slabs)
        assert row["active_share"] >= 0.5 or row["case"].startswith("free")
    assert ov["bar_wall_min_s"] > 0
    pile = res["pile"]
    assert len(pile["vstpetsc"]) == 2 and len(pile["smith"]) == 3
    for row in pile["vstpetsc"] + pile["smith"]:
        assert row["set"] > 0 and row["wall"] > 0 and row["transferred"] > 0
    text = (tmp_path / "README.md").read_text()
    assert "| elements |" in text and "| case | elements |" in text


def test_readme_only_keeps_the_other_benchmarks_sections(tmp_path):
    """bench/run.py --readme-only rewrites its own part of README.md from
    results.json and keeps the sections the benchmarks after it wrote
    (OpenSees, sweeps, pile at equal accuracy, fixed cost; it used to drop
    them): a stale copy of the committed README comes back byte for byte,
    and results.json, its input, is not rewritten."""
    committed = open(os.path.join(ROOT, "bench", "README.md")).read()
    later = ("## Against OpenSees", "## Sweeps on two ranks",
             "## Pile driving at equal accuracy", "## Fixed cost of a run")
    assert all(f"\n{title}" in committed for title in later)
    shutil.copy(os.path.join(ROOT, "bench", "results.json"), tmp_path)
    (tmp_path / "README.md").write_text(committed.replace(
        "## Against the physical limit\n", "## Against the physical limit\n\nstale\n"))
    before = os.stat(tmp_path / "results.json").st_mtime_ns
    p = subprocess.run([sys.executable, os.path.join(ROOT, "bench", "run.py"), "--readme-only",
                        "--out", str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stdout + p.stderr
    assert (tmp_path / "README.md").read_text() == committed
    assert os.stat(tmp_path / "results.json").st_mtime_ns == before


def test_the_parallel_benchmarks_start_no_mpi_themselves():
    """bench/parallel_solvers.py and sweep_speed.py run `mpirun`; a parent
    that has started Open MPI (importing petsc4py does) makes those
    children exit 1 without a word, which once emptied the parallel table."""
    code = ("import sys; import parallel_solvers, sweep_speed; "
            "sys.exit('petsc4py' in sys.modules or 'mpi4py' in sys.modules)")
    p = subprocess.run([sys.executable, "-c", code], cwd=os.path.join(ROOT, "bench"),
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
