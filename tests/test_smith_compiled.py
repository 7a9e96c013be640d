"""The compiled slab for Smith soil (native/smith_slab.c) against the
Python path (-vst_native 0, the checked reference): one node's integrals
on random slabs (yield, unloading, the toe's gap opening, its damping
factor turning), and whole runs: the bundled pile, a bearing-graph sweep,
two soil tables with a penalty pair and a wall, a blow continued from a
restart."""

import io

import numpy as np
import pytest

import vstpetsc
from conftest import bar, make_case, solve
from agreement import assert_runs_agree, datasets
from vstpetsc import native
from vstpetsc import bundled
from vstpetsc.kernels.smith import smith_integrals
from vstpetsc.line.native import smith_slab

pytestmark = pytest.mark.skipif(native.library() is None, reason="kernels not built")


def random_slab(rng, toe):
    """A slab that may yield (inside or from its start), unload, turn, open
    the toe's gap or turn its damping factor 1 + J v negative."""
    dt, k, Ru = 0.1, 2.0, rng.uniform(0.05, 0.3)
    q = Ru / k
    J = float(rng.choice([0.0, rng.uniform(0.0, 2.0), rng.uniform(2.0, 8.0)]))
    wn, (y1, y2) = rng.uniform(-0.2, 0.2), rng.uniform(-3.0, 3.0, 2)
    e0 = rng.choice([rng.uniform(-q if not toe else -0.2, q), q, -q, 0.0])
    return wn, wn - e0, y1, y2, dt, k, Ru, J, toe


def test_one_node_equals_the_python_integrals(rng):
    lib = native.library()
    seen = set()
    for c in range(4000):
        args = random_slab(rng, bool(c % 2))
        want = smith_integrals(*args)
        got = smith_slab.node_integrals(lib, *args)
        if want is None:
            assert got is None
            continue
        wn, p = args[0], args[1]
        seen.add(("toe" if args[8] else "shaft", want[6] != p))
        scale = max(map(abs, want[:6]))
        assert max(abs(a - b) for a, b in zip(got[:6], want[:6])) <= 1e-14 * scale
        assert abs(got[6] - want[6]) <= 1e-15 * max(abs(want[6]), abs(wn), 1e-3)
    # slips and elastic slabs, at the toe and on the shaft
    assert seen == {("toe", True), ("toe", False), ("shaft", True), ("shaft", False)}


def test_one_cushion_equals_the_python_integrals(rng):
    """Loading from the start or inside, unloading on the slab's earlier or
    later M, letting go, with the spans where it pushes."""
    from vstpetsc.line.laws.cushion import cushion_integrals

    lib = native.library()
    kinds = set()
    for c in range(4000):
        dt, k = 0.1, 2.0
        ku = k / rng.uniform(0.3, 1.0) ** 2
        gn, (d1, d2) = rng.uniform(-0.1, 0.05), rng.uniform(-2.0, 2.0, 2)
        M = float(rng.choice([0.0, rng.uniform(0.0, 0.15)]))
        want = cushion_integrals(gn, d1, d2, dt, k, ku, M)
        got = smith_slab.cushion_integrals(lib, gn, d1, d2, dt, k, ku, M)
        if want is None:
            assert got is None
            continue
        kinds.add((len(want[7]), want[6] > max(M, -gn)))
        scale = max(map(abs, want[:6]))
        assert max(abs(a - b) for a, b in zip(got[:6], want[:6])) <= 1e-14 * scale
        assert got[6] == want[6] and got[7] == list(want[7])
    # one and two pieces pushing; loading inside the slab raising M, and not
    assert {(1, True), (1, False), (2, False)} <= kinds


def assert_equal_runs(a, b, rtol=1e-9):
    """The compiled run and the Python one agree to rounding (tests/agreement:
    the compiled step sums in another order), with the same Newton
    iterations and the soil tables' set equal to rounding."""
    da, db = datasets(a), datasets(b)
    assert_runs_agree(da, db, rtol)
    tables = sum(1 for key in da if key.startswith("soil/") and key.endswith("/toe_slip"))
    for k in range(tables):
        sa, sb = a.group_attrs(f"soil/{k}")["set"], b.group_attrs(f"soil/{k}")["set"]
        assert abs(sa - sb) <= 1e-12 * abs(sb), (sa, sb)


def both(tmp_path, case, name, how="the slab matrix's bands"):
    """The run compiled and with -vst_native 0; the compiled one must name
    its Newton and how it steps."""
    a = solve(tmp_path, case, f"{name}-c")
    b = solve(tmp_path, case, f"{name}-p", options=["-vst_native", "0"])
    assert f"steps on {how}" in a.attrs["solver"] and "compiled" not in b.attrs["solver"]
    return a, b


def test_the_pile_example_equals_the_python_path(tmp_path):
    case = vstpetsc.Case.from_toml(bundled.path("pile"))
    a, b = both(tmp_path, case, "pile")
    assert a.group_attrs("soil/0")["set"] > 0.005          # the blow drives the pile
    assert_equal_runs(a, b)


@pytest.mark.parametrize("capacity", [0.5e6, 3.0e6])
def test_a_bearing_graph_sweep_equals_the_python_path(tmp_path, capacity):
    """The bundled pile at the ends of its documented capacity sweep (a
    large set, and a small one with the toe near refusal), cut at 20 ms."""
    case = vstpetsc.Case.from_toml(bundled.path("pile"))
    case = case.with_value("soil.0.capacity", capacity).with_value("time.end", 0.02)
    assert_equal_runs(*both(tmp_path, case, f"cap{capacity:g}"))


def two_tables_and_a_wall():
    """A pile (left toe, moving left) on two soil tables, pushed by a bar
    through a penalty pair, a wall beyond its toe (a Python law in the
    compiled slab's callback)."""
    return make_case(2e-5, 0.006, [bar("pile", (-5.0, 0.0), 30, area=0.01),
                                   bar("ram", (0.001, 1.0), 6, area=0.04, v0=-5.0)],
                     contacts=[dict(pair=["pile", "ram"]),
                               dict(pair=["wall", "pile"], wall=-5.0004)],
                     soil=[{"body": "pile", "capacity": 4e5, "toe_share": 0.4,
                            "shaft": {"quake": 2e-3, "damping": 0.3, "from": -5.0,
                                      "to": -2.0},
                            "toe": {"quake": 2e-3, "damping": 0.5, "end": "left"}},
                           {"body": "pile", "capacity": 2e5, "toe_share": 0.0,
                            "shaft": {"quake": 1e-3, "damping": 0.1, "from": -2.0,
                                      "to": 0.0}}])


def test_two_tables_a_pair_and_a_wall_equal_the_python_path(tmp_path):
    a, b = both(tmp_path, two_tables_and_a_wall(), "two")
    assert a.contact(1).impulse.max() > 0                   # the toe reaches the wall
    assert a.group_attrs("soil/1")["set"] == 0.0             # no toe in table 1
    assert_equal_runs(a, b)
    for k in (0, 1):
        assert np.abs(a.series(f"soil/{k}")["energy"][-1]) > 0


def test_few_soil_nodes_on_a_long_pile_step_with_the_dense_s(tmp_path):
    """Soil on the last 4 % of a 400-element pile and its toe: a step with
    the dense S costs less than one over 401 nodes' bands; the run equals
    the Python path."""
    case = make_case(2e-5, 0.004, [bar("pile", (0.0, 20.0), 400, area=0.01, v0=3.0)],
                     soil=[{"body": "pile", "capacity": 3e5, "toe_share": 0.5,
                            "shaft": {"quake": 2e-3, "damping": 0.2, "from": 19.2,
                                      "to": 20.0},
                            "toe": {"quake": 2e-3, "damping": 0.5}}])
    a, b = both(tmp_path, case, "dense", how="a dense S")
    assert a.group_attrs("soil/0")["set"] > 0
    assert_equal_runs(a, b)


def test_a_restart_continues_the_compiled_blow_bit_for_bit(tmp_path):
    case = vstpetsc.Case.from_toml(bundled.path("pile")).with_value("time.end", 0.02)
    full = solve(tmp_path, case, "full")
    part = str(tmp_path / "part.h5")
    vstpetsc.run(case.with_value("time.end", 0.008), output=part, quiet=True,
                 out=io.StringIO())
    again = vstpetsc.run(case, output=part, restart=True, quiet=True, out=io.StringIO())
    for key in ("toe_force", "shaft_force", "energy", "toe_slip"):
        assert np.array_equal(again.series("soil/0")[key], full.series("soil/0")[key]), key
    for key in ("soil/0/slip", "body/pile/u", "body/ram/v", "energy/soil"):
        assert np.array_equal(again[key], full[key]), key
    assert again.group_attrs("soil/0")["set"] == full.group_attrs("soil/0")["set"]


def test_the_pile_bench_reports_every_field(tmp_path):
    """bench/pile_speed.py --quick: both methods reach the accuracy, every
    time is positive, its README section is written."""
    import json
    import subprocess
    import sys

    from conftest import ROOT

    (tmp_path / "README.md").write_text("# Benchmarks\n")
    p = subprocess.run([sys.executable, "pile_speed.py", "--quick", "--out", str(tmp_path)],
                       cwd=f"{ROOT}/bench", capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    res = json.loads((tmp_path / "pile_speed.json").read_text())
    for method in ("vstpetsc", "smith"):
        row = res[method]
        assert abs(row["sets"][str(row["size"])] / res["reference"] - 1) <= res["tol"]
        assert 0 < row["min"] <= row["median"]
    assert all(0 < r["min"] <= r["median"] for r in res["slab"].values())
    assert "## Pile driving at equal accuracy" in (tmp_path / "README.md").read_text()


def test_the_compiled_gauge_row_equals_the_python_one(tmp_path, monkeypatch):
    """Gauges at ends, inside elements and at a node of two bars in
    contact: the compiled row (native/gauge_row.c) and Gauges.fill on the
    probe give the same series bit for bit (the same operations; a run on
    several ranks uses the probe)."""
    from test_gauges import case as gauge_case
    from vstpetsc.line.native import gauge_row

    a = solve(tmp_path, gauge_case(end=1.0), "g-c")
    monkeypatch.setattr(gauge_row.GaugeRow, "of", classmethod(lambda cls, *args: None))
    b = solve(tmp_path, gauge_case(end=1.0), "g-p")
    da, db = datasets(a), datasets(b)
    keys = [k for k in da if k.startswith("gauge/")]
    assert len(keys) == 6 * 4
    for key in keys:
        assert np.abs(da[key]).max() > 0 and np.array_equal(da[key], db[key]), key
