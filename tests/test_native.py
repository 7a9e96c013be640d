"""The compiled Newton for penalty pairs (vstpetsc.line.native.penalty) repeats the
Python Newton (vstpetsc.line.reduced_newton): bit for bit while at most one pair
acts in a slab, to rounding when several do; whole runs are the same."""

import numpy as np
import pytest

from conftest import bar, make_case, solve
from test_contact import FORMS, two_pair_solver
from vstpetsc import native
from vstpetsc.line.native import penalty as penalty_native
from vstpetsc.errors import SolveFailed
from vstpetsc.line.reduced_newton import ReducedNewton


def test_the_kernel_is_built():
    """`make install` compiles it; without it runs fall back to Python,
    which this suite would not notice otherwise."""
    assert native.library() is not None


def newtons(form):
    """(Python, compiled) Newtons on the same pairs and S."""
    s = two_pair_solver(form)
    laws, S = s.laws, s.nonlinear.coupling.S_red
    return laws, ReducedNewton(laws, S), penalty_native.NativeNewton(laws, S)


def run_both(laws, py, c, y0, gn, start):
    """Each Newton's (y, f, the pairs' integrals, iterations) or its error."""
    out = []
    for newton in (py, c):
        for law, g in zip(laws.laws, gn):
            law.gn, law.last = g, "unset"
        try:
            y = newton.solve(y0, 1, start)
            out.append((np.array(y, dtype=float), laws.f.copy(),
                        [law.last for law in laws.laws], newton.iterations))
        except SolveFailed as exc:
            out.append(str(exc))
    return out


@pytest.mark.parametrize("form", FORMS)
def test_random_slabs_against_the_python_newton(form, rng, monkeypatch):
    laws, py, c = newtons(form)
    # whether a Newton step of the Python run had both pairs acting (its
    # dense solve is LAPACK's, the compiled one's Gaussian elimination)
    several = []
    step = ReducedNewton._step

    def watched(self, outs, r):
        several.append(sum(out is not None for out in outs) > 1)
        return step(self, outs, r)

    monkeypatch.setattr(ReducedNewton, "_step", watched)
    dt = laws.laws[0].dt
    exact = close = 0
    for _ in range(3000):
        y0 = rng.normal(0.0, 2.0, 4)
        gn = rng.normal(0.0, 0.02, 2) * rng.integers(0, 2, 2)
        start = None if rng.random() < 0.5 else y0 + rng.normal(0.0, 0.5, 4)
        several.clear()
        a, b = run_both(laws, py, c, y0, gn * dt / 0.05, start)
        if isinstance(a, str) or isinstance(b, str):
            assert a == b
            continue
        if not any(several):
            for x, y in zip(a[:2], b[:2]):
                assert np.array_equal(x, y)
            assert a[2] == b[2] and a[3] == b[3]
            exact += 1
        else:
            scale = np.abs(a[0]).max() + np.abs(a[1]).max()
            assert np.abs(a[0] - b[0]).max() <= 1e-12 * scale
            assert np.abs(a[1] - b[1]).max() <= 1e-12 * scale
            assert abs(a[3] - b[3]) <= 1
            close += 1
    assert exact > 1000 and close > 100          # both branches exercised


def three_bars(form):
    return make_case(0.01, 3.0, [bar("a", (0.0, 1.0), 40, E=1.0, rho=1.0, v0=1.0),
                                 bar("b", (1.02, 2.0), 30, E=1.0, rho=1.0),
                                 bar("c", (2.01, 3.0), 30, E=2.0, rho=1.0, v0=-0.5)],
                     contacts=[dict(pair=["a", "b"], formulation=form),
                               dict(pair=["b", "c"], formulation=form),
                               dict(pair=["c", "wall"], wall=3.05, formulation=form)])


@pytest.mark.parametrize("form", FORMS)
def test_whole_runs_are_the_python_runs(tmp_path, form):
    """Three bars and a wall: the same result files, the Newton named."""
    case = three_bars(form)
    a = solve(tmp_path, case, "c", options=[])
    b = solve(tmp_path, case, "p", options=["-vst_native", "0"])
    assert "compiled" in a.attrs["solver"] and "compiled" not in b.attrs["solver"]
    assert a.contact(0).impulse.max() > 0 and a.contact(1).impulse.max() > 0
    for key in ("body/a/v", "body/b/u", "body/c/stress", "contact/0/force",
                "contact/1/force", "contact/2/gap", "energy/numerical"):
        x, y = a[key], b[key]
        assert np.abs(x - y).max() <= 1e-10 * (np.abs(x).max() or 1.0), key
    assert np.abs(a["solver/newton_iterations"] - b["solver/newton_iterations"]).max() <= 1
