"""Coulomb friction in the compiled Newton (vstpetsc.line.native.penalty: a pair's
friction runs beside its penalty pair in penalty_newton.c, its slab
integrals coulomb.h's).

What is guaranteed, and why:
- the Newton is the Python one (vstpetsc.line.reduced_newton) bit for bit when
  both solve the step's dense system the same way: a pair with friction
  is two acting laws, whose 4 x 4 step numpy gives to LAPACK and the C to
  its own Gaussian elimination; with the Python's replaced by that
  elimination (written here in floats) every slab's y, terms, friction
  state and iteration count are equal bit for bit;
- with LAPACK, so in a run against ``-vst_native 0``, the two differ in
  the last bits of each step, and each slab's converged coordinates by up
  to the Newton's tolerance (rtol 1e-12 of their size): every series
  within 1e-9 of its own largest value (tests/agreement.py; a stiff
  block's shear stress is G / h times its displacements' rounding, the
  largest relative difference), the iterations within one;
- a restart of the compiled run is the uninterrupted one bit for bit
  (tests/test_friction.py, which runs compiled)."""

import os

import numpy as np
import pytest

import vstpetsc
from agreement import assert_runs_agree, datasets
from conftest import bar, make_case, solve
from test_contact import initial_state
from test_friction import G_ACC, RHO, block_case, column_case, pulse_velocity
from vstpetsc import native
from vstpetsc.line.native import penalty as penalty_native
from vstpetsc.line import reduced_newton
from vstpetsc.errors import SolveFailed
from vstpetsc.line.laws.friction import CoulombFriction
from vstpetsc.line.model import build_model
from vstpetsc.line.reduced_newton import ReducedNewton

pytestmark = pytest.mark.skipif(native.library() is None, reason="kernels not built")
FORMS = ("seed", "power")
EXAMPLES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "examples")


def solve_dense_as_c(M, r):
    """penalty_newton.c solve_dense in floats: Gaussian elimination with
    partial pivoting, the same operations in the same order."""
    M, x, m = [list(row) for row in M], list(r), len(r)
    for k in range(m):
        p = k
        for i in range(k + 1, m):
            if abs(M[i][k]) > abs(M[p][k]):
                p = i
        if M[p][k] == 0.0 or M[p][k] != M[p][k]:
            return None
        M[k], M[p], x[k], x[p] = M[p], M[k], x[p], x[k]
        for i in range(k + 1, m):
            ratio = M[i][k] / M[k][k]
            for j in range(k, m):
                M[i][j] -= ratio * M[k][j]
            x[i] -= ratio * x[k]
    for k in range(m - 1, -1, -1):
        s = x[k]
        for j in range(k + 1, m):
            s -= M[k][j] * x[j]
        x[k] = s / M[k][k]
    return x if all(np.isfinite(x)) else None


def block_solver(form):
    """A slab solver of a block on a shaking wall with friction (its pair
    and the friction law), ready for slab 1."""
    from petsc4py import PETSc

    from vstpetsc.petsc.options import SolverOptions
    from vstpetsc.line.solver.slab_solver import SlabSolver

    case = make_case(0.05, 1.0, [bar("block", (0.0, 1.0), 5, E=1.0, rho=1.0, G=0.5)],
                     contacts=[dict(pair=["wall", "block"], wall=0.0, formulation=form,
                                    friction=0.3, wall_shear_velocity=0.5)])
    model = build_model(case)
    s = SlabSolver(model, 0.05, PETSc.COMM_SELF, SolverOptions(native=False))
    s.set_state(*initial_state(model))
    return s


def random_slab(rng, pair, friction):
    """Random state of the laws for one slab and (y0, start): the gap, the
    stretch (inside, on or beyond the limit), the wall's velocities."""
    pair.gn = rng.normal(0.0, 0.02) * rng.integers(0, 2)
    limit = friction.mu * pair.penalty * 0.02 / friction.stiffness
    friction.stretch = limit * rng.choice([rng.uniform(-1.0, 1.0), 1.0, -1.0, 2.0])
    friction.wall_v = tuple(rng.normal(0.0, 0.5, 2) * rng.integers(0, 2))
    scale = rng.choice([0.01, 0.1, 1.0])
    y0 = np.concatenate([rng.normal(0.0, 1.0, 2), rng.normal(0.0, scale, 2)])
    start = None if rng.random() < 0.5 else y0 + rng.normal(0.0, 0.2, 4)
    return y0, start


def run(newton, laws, y0, start):
    """(y, f, the pair's integrals, the FrictionSlab, iterations) or the error."""
    for law in laws.laws:
        law.last = "unset"
    try:
        y = newton.solve(y0, 1, start)
    except SolveFailed as exc:
        return str(exc)
    pair, friction = laws.laws
    return (np.array(y, dtype=float).tolist(), laws.f.tolist(), pair.last, friction.last,
            newton.iterations)


def both_newtons(python, compiled, laws, rng):
    """(a random slab's state, the Python Newton's answer, the compiled
    one's), each from the same state of the pair and its friction."""
    pair, friction = laws.laws
    state = random_slab(rng, pair, friction)
    saved = (pair.gn, friction.stretch, friction.wall_v)
    a = run(python, laws, *state)
    pair.gn, friction.stretch, friction.wall_v = saved
    return state, a, run(compiled, laws, *state)


@pytest.mark.parametrize("form", FORMS)
def test_random_slabs_are_the_python_newton_bit_for_bit(form, rng, monkeypatch):
    """With the Python's dense solve made the C's elimination."""
    monkeypatch.setattr(reduced_newton, "_solve_dense", solve_dense_as_c)
    laws = block_solver(form).nonlinear.laws
    pair, friction = laws.laws
    assert isinstance(friction, CoulombFriction) and penalty_native.takes(laws.laws)
    S = block_solver(form).nonlinear.coupling.S_red
    python, compiled = ReducedNewton(laws, S), penalty_native.NativeNewton(laws, S)
    seen = set()
    for _ in range(1500):
        state, a, b = both_newtons(python, compiled, laws, rng)
        assert a == b, state
        if not isinstance(a, str) and a[3] is not None:
            seen.add("slip" if a[3].slip else "stick")
            seen.add("released" if a[3].released else "inside")
    assert seen == {"slip", "stick", "released", "inside"}


@pytest.mark.parametrize("form", FORMS)
def test_random_slabs_with_lapack_agree_to_the_newton_tolerance(form, rng):
    laws = block_solver(form).nonlinear.laws
    pair, friction = laws.laws
    S = block_solver(form).nonlinear.coupling.S_red
    python, compiled = ReducedNewton(laws, S), penalty_native.NativeNewton(laws, S)
    for _ in range(500):
        _, a, b = both_newtons(python, compiled, laws, rng)
        if isinstance(a, str) or isinstance(b, str):
            assert a == b
            continue
        scale = np.abs(a[0]).max() + np.abs(a[1]).max()
        assert np.abs(np.subtract(a[0], b[0])).max() <= 1e-11 * scale
        assert np.abs(np.subtract(a[1], b[1])).max() <= 1e-11 * scale
        assert (a[3] is None) == (b[3] is None) and abs(a[4] - b[4]) <= 1


def thrown(form):
    """A block thrown up from a shaking wall: it lands, slides, flies again
    (partial pieces as the gap closes and opens inside slabs)."""
    return make_case(1e-4, 0.6, [bar("block", (0.0, 1.0), 4, E=2e10, rho=RHO, G=1e10,
                                     v0=2.0)],
                     contacts=[{"pair": ["wall", "block"], "wall": 0.0, "friction": 0.2,
                                "formulation": form, "wall_shear_velocity": 1.0}],
                     every=1, gravity={"g": -G_ACC})


def sliding(form):
    """bench/friction_cost.py's column on a wall that shakes both ways,
    and a block on a pulse (it slides, then sticks), by ``form``.  The
    block is dropped from rest rather than started static: a static
    block's axial velocities are rounding (about 1e-13), which no path
    repeats to a share of their own size."""
    t = np.linspace(0.0, 1.2, 200)
    if form == "power":
        return column_case(100.0, 32, (t, 1.5 * np.sin(4.0 * np.pi * t)), 1.2)
    doc = block_case(pulse_velocity(5.0, 0.2, 0.4), 0.4, every=10, G=1e9).to_dict()
    doc["contact"][0]["formulation"] = "seed"
    del doc["gravity"]["initial"]
    return vstpetsc.Case.from_dict(doc)


def stack(form):
    """Two columns on a shaking wall, friction at the base and between
    them, the upper one dropped: two pairs and two friction laws, both
    sliding."""
    t = np.linspace(0.0, 0.3, 50)
    wall = np.column_stack([t, 2.0 * np.sin(20.0 * t)]).tolist()
    return make_case(2.5e-4, 0.3, [bar("a", (0.0, 2.0), 10, E=1e9, rho=2000.0, Vs=200.0),
                                   bar("b", (2.0, 4.0), 10, E=1e9, rho=2000.0, Vs=150.0,
                                       v0=-0.1)],
                     contacts=[{"pair": ["wall", "a"], "wall": 0.0, "friction": 0.3,
                                "formulation": form, "wall_shear_velocity": wall},
                               {"pair": ["a", "b"], "friction": 0.2, "formulation": form}],
                     gravity={"g": -G_ACC}, every=4)


@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("make", [thrown, sliding, stack])
def test_runs_are_the_python_runs(tmp_path, make, form):
    case = make(form)
    a = solve(tmp_path, case, "c")
    b = solve(tmp_path, case, "p", options=["-vst_native", "0"])
    assert "compiled" in a.attrs["solver"] and "compiled" not in b.attrs["solver"]
    da = datasets(a)
    assert_runs_agree(da, datasets(b), 1e-9, iterations=1)
    for k in range(len(case.contacts)):
        assert np.abs(da[f"contact/{k}/slip"]).max() > 0.0
    assert da["energy/friction"][-1] > 0.0


@pytest.mark.parametrize("example", ["sliding-block.toml", "dam-interface.toml"])
def test_wall_velocities_ahead_are_each_slabs_own(example):
    """CoulombFriction.start_time takes the wall's velocities of many
    slabs from one call of its history: each one the value of the slab's
    own call (a table or an integrated record), on the driver's times and
    off them, forwards, backwards (a restart) and after a jump."""
    case = vstpetsc.Case.from_toml(os.path.join(EXAMPLES, example))
    laws = [law for law in build_model(case).nonlinear if isinstance(law, CoulombFriction)]
    assert laws
    law, dt = laws[0], case.dt
    if law.wall is None:        # a pair of bodies: give it the other example's wall
        law.wall = next(other for other in build_model(vstpetsc.Case.from_toml(
            os.path.join(EXAMPLES, "sliding-block.toml"))).nonlinear
            if isinstance(other, CoulombFriction)).wall
    times = [(k - 1) * dt for k in [*range(1, 1500), 700, 3, 2, 1200, 40000, 40001]]
    for t in times + [t0 + 0.37 * dt for t0 in times[::50]]:
        law.start_time(t)
        assert law.wall_v == (float(law.wall(t)), float(law.wall(t + dt))), t
