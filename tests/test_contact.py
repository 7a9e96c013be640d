"""Penalty contact against the exact solutions of formulation.md section 7
(c = sqrt(E/rho), Z = rho c A), for both formulations."""

import re

import numpy as np
import pytest
from petsc4py import PETSc

import vstpetsc
from conftest import bar, cli, compliance_delay, make_case, solve, write_case
from vstpetsc.line.model import build_model, dense, initial_state

FORMS = ["seed", "power"]
NE, DT = 50, 0.01          # h = 0.02 for L = 1: dt = c dt / h = 0.5
G0, V0 = 0.1, 1.0


def phase(r, k=0):
    """(start, end, impulse) of the contact phase of pair k, from slab impulses."""
    t, J = r["time"], r[f"contact/{k}/impulse"]
    on = np.nonzero(J > 0)[0]
    return t[on[0] - 1], t[on[-1]], J.sum()


def momentum(r, name):
    """Momentum of body ``name`` at every kept time (consistent mass)."""
    case = vstpetsc.Case.from_text(r.attrs["case"])
    model = build_model(case)
    b = [x.name for x in case.bodies].index(name)
    lumped = dense(model.ops)[0].sum(axis=0)[model.mesh.nodes(b)]
    return r.body(name).v @ lumped


def check_iterations(r, pairs=(0,)):
    newton = r["solver/newton_iterations"]
    J = sum(r[f"contact/{k}/impulse"] for k in pairs)
    assert newton.max() <= 10
    assert np.all(newton[J == 0] == 0)     # no contact: the linear solve alone


def energy(r):
    return r["energy/kinetic"] + r["energy/strain"]


@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("side", ["right", "left"])
def test_bar_against_rigid_wall(tmp_path, form, side):
    v0, pair, wall = (V0, ["bar", "wall"], 1.0 + G0) if side == "right" else \
        (-V0, ["wall", "bar"], -G0)
    r = solve(tmp_path, make_case(DT, 3.0, [bar("bar", (0.0, 1.0), NE, E=1.0, rho=1.0, v0=v0)],
                                  contacts=[dict(pair=pair, wall=wall, formulation=form)]))
    start, end, J = phase(r)
    Z, c = 1.0, 1.0
    print(f"{form} {side}: start {start:.4f} (exact {G0 / V0}), duration {end - start:.4f} "
          f"(exact 2), mean force / Z v0 = {J / (end - start) / (Z * V0):.5f}, "
          f"v after / v0 = {momentum(r, 'bar')[-1] / V0:.5f}, "
          f"energy after / before = {energy(r)[-1] / energy(r)[0]:.5f}")
    assert abs(start - G0 / V0) <= 2 * DT
    assert abs((end - start) - 2.0 / c - compliance_delay(r, Z)) <= 2 * DT
    assert abs(J - 2.0 * V0) <= 0.03 * V0           # the momentum m v0 = 1 turned round
    sign = 1 if side == "right" else -1
    v_after = momentum(r, "bar")[-1]            # mass 1
    assert abs(v_after + sign * V0) <= 0.03 * V0
    assert abs(energy(r)[-1] - energy(r)[0]) <= 0.02 * energy(r)[0]
    assert np.all(energy(r) <= energy(r)[0] * (1 + 1e-12))
    check_iterations(r)


def two_bars(form, E2=1.0, rho2=1.0, penalty=None, end=3.0, every=1):
    extra = {} if penalty is None else {"penalty": penalty}
    return make_case(DT, end, [bar("striker", (0.0, 1.0), NE, E=1.0, rho=1.0, v0=V0),
                               bar("target", (1.0 + G0, 2.0 + G0), NE, E=E2, rho=rho2)],
                     contacts=[dict(pair=["striker", "target"], formulation=form, **extra)],
                     every=every)


@pytest.mark.parametrize("form", FORMS)
def test_two_identical_bars(tmp_path, form):
    r = solve(tmp_path, two_bars(form))
    start, end, J = phase(r)
    p1 = momentum(r, "striker")
    p2 = momentum(r, "target")
    print(f"{form}: duration {end - start:.4f} (exact 2), force / (Z v0/2) = "
          f"{J / (end - start) / 0.5:.5f}, striker p {p1[-1]:.5f}, target p {p2[-1]:.5f}")
    assert abs(start - G0 / V0) <= 2 * DT
    assert abs((end - start) - 2.0 - compliance_delay(r, 0.5)) <= 2 * DT
    assert abs(J - V0) <= 0.03 * V0                 # the striker's momentum handed on
    assert abs(p1[-1]) <= 0.02 * p1[0]
    assert abs(p2[-1] - p1[0]) <= 0.02 * p1[0]
    # the contact impulse acts equally and oppositely: total momentum is exact
    total = p1 + p2
    assert np.all(np.abs(total - total[0]) <= 1e-10 * abs(total[0]))
    assert abs(energy(r)[-1] - energy(r)[0]) <= 0.02 * energy(r)[0]
    assert np.all(energy(r) <= energy(r)[0] * (1 + 1e-12))
    check_iterations(r)


@pytest.mark.parametrize("form", FORMS)
def test_impedance_mismatch_force_plateau(tmp_path, form):
    # target: c2 = 2, Z2 = 2; reflected waves return after min(2 L1/c1, 2 L2/c2) = 1
    r = solve(tmp_path, two_bars(form, E2=4.0, rho2=1.0, end=1.5))
    t, F = r["time"], r["contact/0/force"]
    impact = G0 / V0
    window = (t > impact + 0.2) & (t <= impact + 0.9)
    plateau = F[window].mean()
    exact = 1.0 * 2.0 * V0 / 3.0
    print(f"{form}: plateau {plateau:.5f}, exact Z1 Z2 v0/(Z1+Z2) = {exact:.5f}")
    assert abs(plateau - exact) <= 0.03 * exact
    p = momentum(r, "striker") + momentum(r, "target")
    assert np.all(np.abs(p - p[0]) <= 1e-10 * abs(p[0]))
    check_iterations(r)


@pytest.mark.parametrize("form", FORMS)
def test_chain_of_three_bars_passes_the_momentum_on(tmp_path, form):
    """Two pairs in one case: the striker's momentum goes through the middle
    bar to the last one, and a wall behind it sends the last bar back."""
    case = make_case(DT, 4.5, [bar("a", (0.0, 1.0), NE, E=1.0, rho=1.0, v0=V0),
                               bar("b", (1.0 + G0, 2.0 + G0), NE, E=1.0, rho=1.0),
                               bar("c", (2.0 + 2 * G0, 3.0 + 2 * G0), NE, E=1.0, rho=1.0)],
                     contacts=[dict(pair=["a", "b"], formulation=form),
                               dict(pair=["b", "c"], formulation=form),
                               dict(pair=["c", "wall"], wall=10.0, formulation=form)],
                     every=5)
    r = solve(tmp_path, case)
    pa, pb, pc = momentum(r, "a"), momentum(r, "b"), momentum(r, "c")
    total = pa + pb + pc
    print(f"{form}: final momenta a {pa[-1]:.4f} b {pb[-1]:.4f} c {pc[-1]:.4f}")
    assert np.all(np.abs(total - total[0]) <= 1e-10 * abs(total[0]))
    assert abs(pa[-1]) <= 0.03 and abs(pb[-1]) <= 0.03 and abs(pc[-1] - V0) <= 0.03
    assert np.all(r["contact/2/impulse"] == 0)           # the far wall is never reached
    assert r["contact/0/impulse"].max() > 0 and r["contact/1/impulse"].max() > 0
    check_iterations(r, pairs=(0, 1, 2))


def test_penalty_controls_penetration(tmp_path):
    base = solve(tmp_path, two_bars("seed", end=1.5), name="default")
    eps = base.contact(0).attrs["penalty"]
    stiff = solve(tmp_path, two_bars("seed", penalty=10 * eps, end=1.5), name="stiff")
    pen_base, pen_stiff = -base["contact/0/gap"].min(), -stiff["contact/0/gap"].min()
    print(f"largest penetration: default {pen_base:.3e}, tenfold {pen_stiff:.3e}, "
          f"1% of v0 L / c = {0.01 * V0:.3e}")
    assert 0 < pen_stiff < pen_base
    assert pen_base < 0.01 * V0 * 1.0 / 1.0


def test_result_does_not_depend_on_newton_tolerance(tmp_path):
    base = solve(tmp_path, two_bars("seed", end=1.5), name="default")
    tight = solve(tmp_path, two_bars("seed", end=1.5), name="tight",
                  options=["-snes_rtol", "1e-14", "-ksp_rtol", "1e-15"])
    for key in ("body/striker/u", "body/target/v", "contact/0/force"):
        scale = np.abs(tight[key]).max()
        assert np.abs(base[key] - tight[key]).max() <= 1e-8 * scale, key


def test_finite_difference_jacobian_gives_the_same_run(tmp_path):
    base = solve(tmp_path, two_bars("power", end=1.0), name="analytic")
    fd = solve(tmp_path, two_bars("power", end=1.0), name="fd", options=["-vst_fd_jacobian"])
    scale = np.abs(base["contact/0/force"]).max()
    assert np.abs(base["contact/0/force"] - fd["contact/0/force"]).max() <= 1e-6 * scale


@pytest.mark.parametrize("form", FORMS)
def test_assembled_jacobian_matches_finite_differences(form):
    """J from formJacobian against differences of formFunction (full-space
    Newton), in a penetrating state of a bar pair and a wall pair."""
    s = two_pair_solver(form, newton="full")
    s.solve(1)
    f = s.nonlinear.newton
    # a state inside the active region (the converged one), perturbed
    X = s.X.copy()
    X.array += 0.01 * np.random.default_rng(1).normal(size=X.array.size)
    f.formJacobian(f.snes, X, f.J, f.J)
    F0, F1, e, Je, Ae = (X.duplicate() for _ in range(5))
    h = 1e-7
    n = X.getSize()
    active = False
    for j in [2 * 6, 2 * 6 + 1, 2 * 7, 2 * 7 + 1, n - 2, n - 1]:   # pair dofs
        Xp, Xm = X.copy(), X.copy()
        Xp.array[j] += h
        Xm.array[j] -= h
        f.formFunction(f.snes, Xp, F0)
        f.formFunction(f.snes, Xm, F1)
        fd = (F0.array - F1.array) / (2 * h)
        e.zeroEntries()
        e.array[j] = 1.0
        f.J.mult(e, Je)
        s.A.mult(e, Ae)
        assert np.allclose(fd, Je.array, rtol=1e-6, atol=1e-8 * np.abs(Je.array).max()), j
        active |= not np.allclose(Je.array, Ae.array)
    assert active          # the contact block is not zero in this state
    # the Woodbury preconditioner inverts the shell exactly
    r, y, Jy = X.duplicate(), X.duplicate(), X.duplicate()
    r.setRandom()
    f.snes.getKSP().getPC().apply(r, y)
    f.J.mult(y, Jy)
    assert np.allclose(Jy.array, r.array, rtol=0, atol=1e-10 * np.abs(r.array).max())


def two_pair_solver(form, newton="condensed"):
    """A slab solver of two bars (a pair) and a wall (a pair), ready for slab 1."""
    from vstpetsc.petsc.options import SolverOptions
    from vstpetsc.line.solver.slab_solver import SlabSolver

    case = make_case(0.05, 1.0, [bar("a", (0.0, 1.0), 6, E=1.0, rho=1.0, v0=2.0),
                                 bar("b", (1.01, 2.0), 5, E=3.0, rho=1.0, v0=-1.0)],
                     contacts=[dict(pair=["a", "b"], formulation=form),
                               dict(pair=["b", "wall"], wall=2.001, formulation=form)])
    model = build_model(case)
    s = SlabSolver(model, 0.05, PETSc.COMM_SELF, SolverOptions(newton=newton))
    s.set_state(*initial_state(model))
    none = (np.zeros(0, int), np.zeros((0, 2)))
    s.rhs(none, none, np.zeros((0, 2)))
    return s


def full_residual(s):
    """A X - b + the laws' rows: the slab equations at the solver's X."""
    F = s.X.duplicate()
    s.A.mult(s.X, F)
    F.axpy(-1.0, s.b)
    c, _ = s.laws.residual(s.nonlinear.coupling.velocities(s.X))
    s.nonlinear.coupling.gather.add_rows(F, s.nonlinear.coupling.WE @ c)
    return F


@pytest.mark.parametrize("form", FORMS)
def test_condensed_jacobian_matches_finite_differences(form):
    """The default Newton works on the pairs' reduced coordinates:
    r(y) = y - y0 + S f(y), Jacobian I + S f'(y)."""
    from vstpetsc.line.solver.newton import SnesCondensed

    s = two_pair_solver(form)
    newton, _ = s.solve(1)
    assert newton > 0
    coupling = s.nonlinear.coupling
    c = SnesCondensed(coupling, fd_jacobian=False, rank=0)
    c.y0 = coupling.coordinates(s.X) + 0.3        # any y0: r is affine in it
    y = coupling.coordinates(s.X) + 0.01 * np.random.default_rng(2).normal(size=c.k)
    X = PETSc.Vec().createSeq(c.k)
    X.array = y
    c.formJacobian(c.snes, X, None, None)
    h = 1e-7
    fd = np.array([(c.residual(y + h * e) - c.residual(y - h * e)) / (2 * h)
                   for e in np.eye(c.k)]).T
    assert np.allclose(c.J, fd, rtol=1e-6, atol=1e-8 * np.abs(fd).max())
    assert np.abs(c.J - np.eye(c.k)).max() > 1e-2         # contact is active here
    # the converged state satisfies the full slab equations
    assert full_residual(s).norm() <= 1e-9 * s.b.norm()


def test_condensed_and_full_newton_agree(tmp_path):
    base = solve(tmp_path, two_bars("seed", end=1.5), name="condensed")
    full = solve(tmp_path, two_bars("seed", end=1.5), name="full",
                 options=["-vst_newton", "full"])
    for key in ("body/striker/u", "body/target/v", "contact/0/force"):
        scale = np.abs(full[key]).max()
        assert np.abs(base[key] - full[key]).max() <= 1e-9 * scale, key


def test_forced_solve_failure_exits_3_and_keeps_slabs(tmp_path):
    case = write_case(tmp_path, two_bars("seed", end=1.0))
    full = cli("run", case, "-o", tmp_path / "full.h5", "--quiet")
    assert full.returncode == 0, full.stderr
    p = cli("run", case, "-o", tmp_path / "fail.h5", "--quiet", "-snes_max_it", "1",
            "-snes_rtol", "1e-15")
    assert p.returncode == 3, p.stderr
    assert "Traceback" not in p.stderr
    failed, ref = vstpetsc.Result(tmp_path / "fail.h5"), vstpetsc.Result(tmp_path / "full.h5")
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "DIVERGED_MAX_IT" in lines[0], p.stderr
    k = int(re.search(r"slab (\d+):", lines[0]).group(1))
    assert ref["solver/newton_iterations"][k] > 0     # it failed on a contact slab
    assert failed.attrs["status"] == "failed"
    assert failed["time"].size == k          # t = 0 and slabs 1 .. k-1
    assert np.array_equal(failed["body/striker/u"], ref["body/striker/u"][:k])
    assert np.array_equal(failed["contact/0/force"], ref["contact/0/force"][:k])


def test_aij_storage_gives_the_same_run(tmp_path):
    base = solve(tmp_path, two_bars("power", end=1.0), name="baij")
    aij = solve(tmp_path, two_bars("power", end=1.0), name="aij",
                options=["-vst_mat_type", "aij"])
    for key in ("body/striker/v", "contact/0/force"):
        scale = np.abs(base[key]).max()
        assert np.abs(base[key] - aij[key]).max() <= 1e-10 * scale, key


def test_unusable_solver_option_is_a_clean_error(tmp_path):
    case = write_case(tmp_path, two_bars("seed", end=0.2))
    p = cli("run", case, "-o", tmp_path / "r.h5", "-pc_factor_mat_solver_type", "superlu_dist")
    assert p.returncode == 2 and "Traceback" not in p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "superlu_dist does not support matrix type" in lines[0][:160]
    assert cli("run", case, "-o", tmp_path / "r.h5", "--quiet", "-pc_factor_mat_solver_type",
               "superlu_dist", "-vst_mat_type", "aij").returncode == 0
