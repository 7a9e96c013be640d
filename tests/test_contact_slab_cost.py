"""The compiled penalty slab on one rank (vstpetsc.line.native.penalty.PenaltySlab
bound to the solver's arrays): it reads the pairs' unknowns, subtracts
their influence, closes the slab (u += z_2, b += carry f) and finds each
acting pair's pieces of the slab itself.  Runs equal the Python path
(-vst_native 0) to rounding: every series, the events and the gauges."""

import numpy as np
import pytest

from agreement import assert_runs_agree, datasets
from conftest import bar, make_case, solve
from vstpetsc import native
from vstpetsc.line.native import penalty as penalty_native
from vstpetsc.line.laws import penalty
from vstpetsc.kernels.gap import active_intervals, gap_coefficients

pytestmark = pytest.mark.skipif(native.library() is None, reason="kernels not built")

C = np.sqrt(2.0e11 / 7850.0)
# series that differ between runs whatever the path


def held(cfl, elements=100, slabs=1000):
    """bench/overhead.py's held (cfl 0.5) and impact (cfl 1) cases: a steel
    bar between two walls at zero gap, v0 = 1 m/s, with two gauges."""
    dt = cfl / elements / C
    return make_case(dt, slabs * dt, [bar("bar", (0.0, 1.0), elements, v0=1.0)],
                     contacts=[dict(pair=["bar", "wall"], wall=1.0),
                               dict(pair=["wall", "bar"], wall=0.0)],
                     gauge=[{"name": "mid", "body": "bar", "x": 0.5},
                            {"name": "end", "body": "bar", "x": 1.0}])


def bars_and_wall():
    """Three bars, two body pairs and a wall pair, chattering."""
    return make_case(0.01, 6.0, [bar("a", (0.0, 1.0), 40, E=1.0, rho=1.0, v0=1.0),
                                 bar("b", (1.02, 2.0), 30, E=1.0, rho=1.0),
                                 bar("c", (2.01, 3.0), 30, E=2.0, rho=1.0, v0=-0.5)],
                     contacts=[dict(pair=["a", "b"]), dict(pair=["b", "c"]),
                               dict(pair=["c", "wall"], wall=3.05)],
                     gauge=[{"name": "b-in", "body": "b", "x": 1.5}])


def assert_same_runs(tmp_path, case):
    """The compiled run and the Python one: the same datasets, equal to
    rounding (Newton iterations within one); returns the compiled file's."""
    solve(tmp_path, case, "c")
    solve(tmp_path, case, "p", options=["-vst_native", "0"])
    a, b = datasets(tmp_path / "c.h5"), datasets(tmp_path / "p.h5")
    # energy terms that stay near zero (the walls' work) round on the total's scale
    assert_runs_agree(a, b, 1e-10, iterations=1)
    return a


@pytest.mark.parametrize("cfl", [0.5, 1.0])
def test_held_and_impact_runs_are_the_python_runs(tmp_path, cfl):
    a = assert_same_runs(tmp_path, held(cfl))
    assert a["contact/0/impulse"].max() > 0 and a["contact/1/impulse"].max() > 0
    assert a["gauge/mid/v"].size > 0 and np.abs(a["gauge/end/stress"]).max() > 0


def test_body_pairs_with_events_are_the_python_runs(tmp_path):
    a = assert_same_runs(tmp_path, bars_and_wall())
    assert all(a[f"contact/{k}/event_count"][-1] >= 2 for k in range(3))   # closes, opens


def test_the_slab_is_bound_on_one_rank(tmp_path):
    """On one rank the compiled slab works on the solver's arrays (no
    numpy gather, PETSc product or carry rows in Python)."""
    from petsc4py import PETSc

    from vstpetsc.runner.driver import TimeLoop

    loop = TimeLoop(held(0.5, slabs=20), str(tmp_path / "r.h5"), PETSc.COMM_WORLD, True,
                    None, None)
    loop.execute(False, "")
    newton = loop.solver.nonlinear.newton
    assert isinstance(newton, penalty_native.PenaltySlab) and newton.serial


def test_the_compiled_pieces_are_active_intervals(tmp_path, monkeypatch):
    """Each acting pair's pieces of the slab from the compiled slab are
    exactly active_intervals at its converged rates, in every slab (the
    impact case opens and closes inside slabs)."""
    seen = {"given": 0, "inside": 0}
    finish = penalty.PenaltyContact.finish_slab

    def checked(law, t0, dt):
        if law.last is not None:
            assert law.pieces is not None
            assert law.pieces == active_intervals(*gap_coefficients(law.gn, *law.rates, dt))
            seen["given"] += 1
            seen["inside"] += law.pieces != [(0.0, 1.0)]
        return finish(law, t0, dt)

    monkeypatch.setattr(penalty.PenaltyContact, "finish_slab", checked)
    solve(tmp_path, held(1.0, slabs=600), "c")
    solve(tmp_path, bars_and_wall(), "b")
    assert seen["given"] > 500 and seen["inside"] > 10
