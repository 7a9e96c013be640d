"""Loads, damping, supports, absorbing ends, variable sections, history
files and the energy balance (docs/loads.md) against exact solutions."""

import numpy as np
import pytest
import scipy.optimize

import vstpetsc
from conftest import bar, cli, make_case, solve, write_case
from vstpetsc.line.model import build_model, dense, modes

FIXED_LEFT = dict(body="bar", end="left", type="fixed")


def unit_bar(ne, **extra):
    """A bar of length 1 with E = rho = A = 1 (c = 1, Z = 1) unless given."""
    return bar("bar", (0.0, 1.0), ne, **{"E": 1.0, "rho": 1.0, **extra})


def order(dts, errors):
    return np.polyfit(np.log(dts), np.log(errors), 1)[0]


def test_winkler_foundation_uniform_motion(tmp_path):
    """A free-free bar on springs k per length, uniform v0: every point is
    an oscillator, u = v0 / w sin(w t), w = sqrt(k / (rho A)); third order."""
    k, v0 = 4.0, 0.3
    w = np.sqrt(k)
    T = 2 * np.pi / w
    errors, dts = [], T / np.array([20, 40, 80])
    for dt in dts:
        case = make_case(float(dt), T, [unit_bar(8, v0=v0, foundation={"stiffness": k})],
                         every=1000)
        r = solve(tmp_path, case)
        u_ex = v0 / w * np.sin(w * r.time[-1])
        errors.append(np.abs(r.body("bar").u[-1] - u_ex).max() / (v0 / w))
        assert np.ptp(r.body("bar").u[-1]) < 1e-12           # stays uniform
    print(f"Winkler: errors {errors}, order {order(dts, errors):.2f}")
    assert errors[-1] < 1e-4 and order(dts, errors) >= 2.8


def damped_mode(ops, fixed, alpha, beta, t):
    """Tip displacement of the first mode released from rest with modal
    damping zeta = alpha/(2w) + beta w/2 (exact in time), and w, zeta."""
    w2, phi, free = modes(ops, fixed)
    w = np.sqrt(w2[0])
    zeta = alpha / (2 * w) + beta * w / 2
    wd = w * np.sqrt(1 - zeta ** 2)
    q = np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t))
    return q, phi[:, 0], free, w, zeta


@pytest.mark.parametrize("alpha,beta", [(0.3, 0.0), (0.0, 0.02)])
def test_rayleigh_damping_of_the_first_mode(tmp_path, alpha, beta):
    ne = 20
    model = build_model(make_case(0.1, 1.0, [unit_bar(ne, damping={"alpha": alpha,
                                                                     "beta": beta})]))
    _, phi, free, w, zeta = damped_mode(model.ops, [0], alpha, beta, np.zeros(1))
    shape = np.zeros(model.mesh.nnodes)
    shape[free] = phi / phi[-1]
    T = 2 * np.pi / w
    case = make_case(T / 200, 3 * T, [unit_bar(ne, u0=np.column_stack([model.mesh.x, shape]),
                                               damping={"alpha": alpha, "beta": beta})],
                     bcs=[FIXED_LEFT])
    r = solve(tmp_path, case)
    q, _, _, _, _ = damped_mode(model.ops, [0], alpha, beta, r.time)
    tip = r.body("bar").u[:, -1]
    print(f"alpha {alpha} beta {beta}: zeta {zeta:.4f}, max error {np.abs(tip - q).max():.2e}")
    assert 0.01 < zeta < 0.2
    assert np.abs(tip - q).max() < 1e-4
    e = r.energy
    assert e["damping"][-1] > 0.2 * (e["kinetic"][0] + e["strain"][0])   # 3 periods at 1-10 %
    assert np.abs(e["numerical"]).max() < 1e-5 * (e["kinetic"][0] + e["strain"][0])


def pulse(t, duration=0.25, amplitude=0.1):
    """A smooth velocity pulse sin^2 (pi t / duration)."""
    return np.where((t > 0) & (t < duration), amplitude * np.sin(np.pi * t / duration) ** 2, 0.0)


def test_absorbing_end_lets_the_pulse_in_and_out(tmp_path):
    """Incident pulse at an absorbing left end, free right end: the free end
    moves at 2 v_in(t - L/c); the pulse leaves through the base again."""
    ne, dt = 400, 0.00125
    ts = np.linspace(0.0, 0.25, 201)
    incident = {"table": np.column_stack([ts, pulse(ts)]).tolist()}
    case = make_case(dt, 3.0, [unit_bar(ne)],
                     bcs=[dict(body="bar", end="left", type="absorbing", incident=incident)])
    r = solve(tmp_path, case)
    t, v_end = r.time, r.body("bar").v[:, -1]
    error = np.abs(v_end - 2 * pulse(t - 1.0)).max() / 0.2
    e = r.energy["kinetic"] + r.energy["strain"]
    print(f"absorbing: free-end error {error:.2e}, energy left {e[-1] / e.max():.2e}")
    assert error < 0.01
    assert e[-1] < 1e-4 * e.max()
    balance = r.energy["numerical"]
    assert balance.min() > -1e-9 * e.max() and balance[-1] < 1e-3 * e.max()


@pytest.mark.parametrize("where", ["resonance", "half wavelength"])
def test_soil_layer_amplification(tmp_path, where):
    """A soft layer (height H, impedance Zs) on elastic rock (Zr) under a
    harmonic incident wave: steady surface amplitude over the outcrop
    amplitude 1 / sqrt(cos^2 kH + a^2 sin^2 kH), a = Zs / Zr."""
    H, a = 1.0, 0.25
    f = 0.25 if where == "resonance" else 0.5          # c / 4H and c / 2H
    ne, dt = 100, 0.005
    periods = 24
    ts = np.arange(0.0, periods / f + dt, dt / 4)
    ramp = np.minimum(ts * f / 2, 1.0)                  # over two periods
    incident = {"table": np.column_stack([ts, 0.01 * ramp * np.sin(2 * np.pi * f * ts)]).tolist()}
    case = make_case(dt, periods / f, [unit_bar(ne)], every=1,
                     bcs=[dict(body="bar", end="left", type="absorbing", impedance=1.0 / a,
                               incident=incident)])
    r = solve(tmp_path, case)
    t, v = r.time, r.body("bar").v[:, -1]
    last = t > t[-1] - 4 / f
    amplification = 0.5 * np.ptp(v[last]) / (2 * 0.01)
    k = 2 * np.pi * f
    exact = 1 / np.sqrt(np.cos(k * H) ** 2 + a ** 2 * np.sin(k * H) ** 2)
    print(f"{where}: amplification {amplification:.4f}, exact {exact:.4f}")
    assert abs(amplification / exact - 1) < 0.02


def first_frequency(t, u):
    """Angular frequency from the zero crossings of u(t) (linear interpolation)."""
    s = np.nonzero(np.diff(np.sign(u)) != 0)[0]
    crossings = t[s] - u[s] * (t[s + 1] - t[s]) / (u[s + 1] - u[s])
    return np.pi / np.mean(np.diff(crossings))


@pytest.mark.parametrize("tip", ["mass", "stiffness"])
def test_tip_mass_and_spring_frequency(tmp_path, tip):
    """Fixed-free bar with a tip mass m: beta tan beta = rho A L / m; with a
    tip spring k: tan beta = -beta E A / (k L); w = beta c / L."""
    ne, value = 100, 0.5
    support = {"body": "bar", "end": "right", "type": "support", tip: value}
    if tip == "mass":
        beta = scipy.optimize.brentq(lambda b: b * np.tan(b) - 1.0 / value, 0.1, np.pi / 2 - 1e-9)
    else:
        beta = scipy.optimize.brentq(lambda b: np.tan(b) + b / value, np.pi / 2 + 1e-9, np.pi)
    model = build_model(make_case(0.1, 1.0, [unit_bar(ne)], bcs=[FIXED_LEFT, support]))
    w2, phi, free = modes(model.ops, [0])
    shape = np.zeros(model.mesh.nnodes)
    shape[free] = phi[:, 0] / phi[-1, 0]
    T = 2 * np.pi / beta
    case = make_case(T / 400, 4 * T, [unit_bar(ne, u0=np.column_stack([model.mesh.x, shape]))],
                     bcs=[FIXED_LEFT, support])
    r = solve(tmp_path, case)
    w = first_frequency(r.time, r.body("bar").u[:, -1])
    print(f"tip {tip}: w {w:.6f}, exact beta c / L = {beta:.6f}")
    assert abs(w / beta - 1) < 2e-3


def test_bar_hanging_under_sudden_gravity(tmp_path):
    """Bar fixed at x = 0, gravity g along +x switched on at t = 0: the
    exact modal series of u(L, t) = u_s(L) - sum a_n cos(w_n t)."""
    g, ne = 0.5, 100
    case = make_case(0.005, 3.0, [unit_bar(ne)], bcs=[FIXED_LEFT], gravity={"g": g})
    r = solve(tmp_path, case)
    betas = (2 * np.arange(1, 2001) - 1) * np.pi / 2
    # u_s(x) = g (x - x^2/2) (E = rho = L = 1): a_n = 2 int_0^1 u_s sin(beta_n x) dx
    # = 2 g / beta_n^3, and sin(beta_n) = (-1)^(n+1) at the tip
    a = 2 * g / betas ** 3 * np.sin(betas)
    t = r.time
    exact = g / 2 - (a[:, None] * np.cos(betas[:, None] * t)).sum(axis=0)
    error = np.abs(r.body("bar").u[:, -1] - exact).max() / (g / 2)
    print(f"hanging bar: tip error {error:.2e}")
    assert error < 5e-3


def test_step_in_area_transmits_two_a2_over_a1_plus_a2(tmp_path):
    """A velocity step v0 at the left end of a bar whose area steps from A1
    to A2 at L/2: incident force Z1 v0, transmitted 2 A2 / (A1 + A2) of it."""
    A1, A2, v0, ne = 1.0, 3.0, 0.1, 400
    area = [[0.0, A1], [0.5, A1], [0.5, A2], [1.0, A2]]
    case = make_case(0.00125, 0.9, [unit_bar(ne, area=area)],
                     bcs=[dict(body="bar", end="left", type="velocity", value=v0)])
    r = solve(tmp_path, case)
    t, s = r.time, r.body("bar").stress
    x_mid = 0.5 * (r.body("bar").x[1:] + r.body("bar").x[:-1])
    in1, in2 = np.argmin(np.abs(x_mid - 0.3)), np.argmin(np.abs(x_mid - 0.7))
    incident = -A1 * s[(t > 0.4) & (t < 0.6), in1].mean()          # compression
    transmitted = -A2 * s[(t > 0.8) & (t < 0.9), in2].mean()
    print(f"area step: incident {incident:.5f} (Z1 v0 = {v0}), transmitted ratio "
          f"{transmitted / incident:.5f} (exact {2 * A2 / (A1 + A2):.5f})")
    assert abs(incident / v0 - 1) < 0.01
    assert abs(transmitted / incident / (2 * A2 / (A1 + A2)) - 1) < 0.02


def semidiscrete(ops, fixed, u0, force, t, alpha):
    """Exact-in-time solution of M u'' + alpha M u' + K u = F (constant F),
    from u0 at rest, modal (for alpha * M damping)."""
    w2, phi, free = modes(ops, fixed)
    w = np.sqrt(w2)
    M = dense(ops)[0][np.ix_(free, free)]
    q0, p = phi.T @ M @ u0[free], phi.T @ force[free]
    qs = p / w2
    zeta = alpha / (2 * w)
    wd = w * np.sqrt(1 - zeta ** 2)
    d = q0 - qs
    q = qs + np.exp(-zeta * w * t) * (d * np.cos(wd * t) + zeta * w / wd * d * np.sin(wd * t))
    u = np.zeros_like(u0)
    u[free] = phi @ q
    return u


def test_third_order_with_damping_and_gravity(tmp_path):
    """Mode 1 around the static deflection, Rayleigh damping, gravity: the
    semi-discrete solution is smooth, and the slab-end error falls as dt^3."""
    ne, T, alpha, g = 16, 1.0, 0.4, -0.3
    model = build_model(make_case(0.1, T, [unit_bar(ne)], gravity={"g": g}))
    w2, phi, free = modes(model.ops, [0])
    M, K = dense(model.ops)
    lumped = M.sum(axis=1)
    u0 = np.zeros(model.mesh.nnodes)
    u0[free] = np.linalg.solve(K[np.ix_(free, free)], g * lumped[free])
    u0[free] += phi[:, 0] / abs(phi[:, 0]).max() * 0.1
    u_ex = semidiscrete(model.ops, [0], u0, lumped * g, T, alpha)
    errors, dts = [], T / np.array([10, 20, 40, 80])
    for dt in dts:
        case = make_case(float(dt), T, [unit_bar(ne, u0=np.column_stack([model.mesh.x, u0]),
                                                 damping={"alpha": alpha})],
                         bcs=[FIXED_LEFT], gravity={"g": g}, every=10000)
        r = solve(tmp_path, case)
        errors.append(np.abs(r.body("bar").u[-1] - u_ex).max() / np.abs(u_ex).max())
    print(f"damping + gravity: errors {errors}, order {order(dts, errors):.2f}")
    assert order(dts, errors) >= 2.8


def jump_energy(case):
    """The energy of the velocity jumps at slab starts, summed over the
    slabs by stepping the slab solver and reading v^{n+} (independent of
    the energy book)."""
    from petsc4py import PETSc

    from vstpetsc.line.loading import SlabLoads
    from vstpetsc.line.model import band_mult, initial_state
    from vstpetsc.petsc.options import SolverOptions
    from vstpetsc.line.solver.slab_solver import SlabSolver

    model = build_model(case)
    loads = SlabLoads(model.laws, case.dt)
    s = SlabSolver(model, case.dt, PETSc.COMM_SELF, SolverOptions(), loads)
    u, v = initial_state(model)
    s.set_state(u, v)
    total, jumps = 0.0, [0.0]
    for k in range(1, case.nslabs + 1):
        t0 = (k - 1) * case.dt
        s.rhs(*loads.slab(k))
        s.solve(k)
        s.laws.finish_slab(t0, case.dt)
        z = s.X.getArray(readonly=True).reshape(-1, 2)
        d = z @ s.V[0] - v
        total += 0.5 * d @ band_mult(model.ops.m_diag, model.ops.m_off, d)
        v = z @ s.V[1]
        jumps.append(total)
        s.advance()
    return np.array(jumps)


BALANCE_CASES = {
    "damped, gravity, foundation, support": lambda: make_case(
        0.01, 2.0, [unit_bar(30, v0=[[0.0, 0.0], [1.0, 0.2]], damping={"beta": 0.01},
                             foundation={"stiffness": 2.0, "damping": 0.1})],
        bcs=[FIXED_LEFT, dict(body="bar", end="right", type="support", stiffness=3.0,
                              damping=0.2, mass=0.5)], gravity={"g": [[0.0, 0.0], [1.0, -1.0]]}),
    "velocity end, traction, contact": lambda: make_case(
        0.01, 3.0, [bar("a", (0.0, 1.0), 30, E=1.0, rho=1.0),
                    bar("b", (1.02, 2.0), 20, E=2.0, rho=1.0)],
        contacts=[dict(pair=["a", "b"], formulation="power")],
        bcs=[dict(body="a", end="left", type="velocity", value=[[0.0, 0.0], [0.5, 0.2],
                                                                   [1.0, 0.0]]),
             dict(body="b", end="right", type="traction", value=[[0.0, 0.0], [2.0, -0.05]])]),
    "absorbing end with an incident wave": lambda: make_case(
        0.01, 2.0, [unit_bar(40)],
        bcs=[dict(body="bar", end="left", type="absorbing", impedance=2.0,
                  incident=[[0.0, 0.0], [0.3, 0.1], [0.6, 0.0]])]),
}


@pytest.mark.parametrize("name", BALANCE_CASES)
def test_numerical_energy_is_the_jump_energy(tmp_path, name):
    case = BALANCE_CASES[name]()
    r = solve(tmp_path, case)
    e = r.energy
    scale = max(np.abs(e[k]).max() for k in e)
    jumps = jump_energy(case)
    print(f"{name}: numerical {e['numerical'][-1]:.6e}, jumps {jumps[-1]:.6e}, scale {scale:.3g}")
    assert np.abs(e["numerical"] - jumps).max() <= 1e-9 * scale
    assert e["numerical"].min() >= -1e-10 * scale
    assert np.all(np.diff(e["numerical"]) >= -1e-10 * scale)


def test_numerical_energy_is_small_on_smooth_motion(tmp_path):
    """A few hundred slabs per period of the first mode, damping, gravity:
    the discretisation dissipates less than 1e-6 of the energy in play."""
    ne = 20
    model = build_model(make_case(0.1, 1.0, [unit_bar(ne)]))
    w2, phi, free = modes(model.ops, [0])
    shape = np.zeros(model.mesh.nnodes)
    shape[free] = 0.1 * phi[:, 0] / phi[-1, 0]
    T = 2 * np.pi / np.sqrt(w2[0])
    case = make_case(T / 400, 2 * T, [unit_bar(ne, u0=np.column_stack([model.mesh.x, shape]),
                                               damping={"alpha": 0.1})],
                     bcs=[FIXED_LEFT], gravity={"g": -0.01})
    e = solve(tmp_path, case).energy
    budget = max(e["kinetic"][0] + e["strain"][0] + e["external"].max(), 1e-300)
    print(f"smooth: numerical {e['numerical'][-1]:.3e} of {budget:.3e}")
    assert 0 <= e["numerical"][-1] < 1e-6 * budget


def test_static_start_on_an_absorbing_base_stays_at_rest(tmp_path):
    """A column on an absorbing base under gravity, started in its static
    state: nodal displacements exact (linear elements, consistent load) and
    nothing moves."""
    g, ne = -0.2, 50
    case = make_case(0.01, 2.0, [unit_bar(ne)], gravity={"g": g, "initial": "static"},
                     bcs=[dict(body="bar", end="left", type="absorbing")])
    r = solve(tmp_path, case)
    x = r.body("bar").x
    exact = g * (x - x * x / 2)                    # E = rho = A = L = 1, base at x = 0
    u = r.body("bar").u
    assert np.abs(u[0] - exact).max() < 1e-12 * np.abs(exact).max()
    assert np.abs(u - u[0]).max() < 1e-10 * np.abs(exact).max()
    assert np.abs(r.body("bar").v).max() < 1e-10


def test_stress_envelopes_cover_every_slab(tmp_path):
    case = make_case(0.01, 1.0, [unit_bar(20, v0=[[0.0, 0.0], [1.0, 0.3]])], bcs=[FIXED_LEFT])
    every1 = solve(tmp_path, case, name="every1")
    sparse = solve(tmp_path, case.with_value("output.every", 7), name="sparse")
    s = every1.body("bar").stress
    for r in (every1, sparse):
        assert np.array_equal(r.body("bar").stress_min, s.min(axis=0))
        assert np.array_equal(r.body("bar").stress_max, s.max(axis=0))


def record_files(tmp_path):
    """A CSV and a PEER AT2 file of the same acceleration samples."""
    t = np.round(np.arange(0, 101) * 0.01, 10)
    acc = 0.05 * np.sin(2 * np.pi * 3 * t) * np.exp(-t)
    csv = tmp_path / "motion.csv"
    csv.write_text("time,acc\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(t, acc)))
    at2 = tmp_path / "motion.AT2"
    at2.write_text("PEER NGA STRONG MOTION DATABASE RECORD\nsynthetic\n"
                   "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=  101, DT=   .0100 SEC\n"
                   + "\n".join("  ".join(f"{a!r}" for a in acc[i:i + 5]) for i in range(0, 101, 5))
                   + "\n")
    return t, acc


@pytest.mark.parametrize("form", ["csv by name", "csv by number", "AT2", "table"])
def test_histories_from_files_equal_inline_tables(tmp_path, form):
    """The same samples inline or from a file: identical result files,
    scale and integrate included."""
    t, acc = record_files(tmp_path)
    if form == "AT2":
        t = 0.01 * np.arange(t.size)         # sample k at k DT, as the format defines
    source = {"csv by name": {"file": "motion.csv", "column": "acc"},
              "csv by number": {"file": "motion.csv", "column": 2},
              "AT2": {"file": "motion.AT2"},
              "table": {"table": np.column_stack([t, acc]).tolist()}}[form]
    inline = {"table": np.column_stack([t, acc]).tolist(), "scale": 9.81, "integrate": True}
    runs = []
    for name, value in (("file", {**source, "scale": 9.81, "integrate": True}),
                        ("inline", inline)):
        case = make_case(0.004, 0.6, [unit_bar(20)], folder=tmp_path,
                         bcs=[dict(body="bar", end="left", type="velocity", value=value)])
        runs.append(solve(tmp_path, case, name=name))
    a, b = runs
    assert np.array_equal(a.body("bar").u, b.body("bar").u)
    assert np.array_equal(a.body("bar").v, b.body("bar").v)
    # the base velocity is the exact integral of 9.81 acc (linear between
    # samples) from 0: quadratic between samples
    a_rec = 9.81 * acc
    v_rec = np.concatenate(([0.0], np.cumsum(0.5 * (a_rec[1:] + a_rec[:-1]) * np.diff(t))))
    k = np.minimum(np.searchsorted(t, a.time, side="right") - 1, t.size - 2)
    s = a.time - t[k]
    exact = v_rec[k] + a_rec[k] * s + (a_rec[k + 1] - a_rec[k]) * s ** 2 / (2 * (t[k + 1] - t[k]))
    assert np.allclose(a.body("bar").v[:, 0], exact, rtol=0, atol=1e-14)


BAD = [
    ("negative damping", {"body": [unit_bar(4, damping={"alpha": -1.0})]},
     "body[0] (bar).damping.alpha: must be >= 0"),
    ("zero impedance", {"bc": [dict(body="bar", end="left", type="absorbing", impedance=0.0)]},
     "bc[0].impedance: must be positive"),
    ("support on a contact end", {"contact": [dict(pair=["bar", "wall"], wall=1.1)],
                                  "bc": [dict(body="bar", end="right", type="support", mass=1.0)]},
     "bc[0].end: the right end of 'bar' is in contact[0]"),
    ("support twice", {"bc": [dict(body="bar", end="right", type="support", mass=1.0),
                              dict(body="bar", end="right", type="fixed")]},
     "bc[1].end: the right end of 'bar' already has bc[0]"),
    ("empty support", {"bc": [dict(body="bar", end="right", type="support")]},
     "bc[0]: a support needs stiffness, damping and/or mass"),
    ("missing file", {"bc": [dict(body="bar", end="left", type="velocity",
                                  value={"file": "nosuch.csv"})]}, "cannot read"),
    ("unknown column", {"bc": [dict(body="bar", end="left", type="velocity",
                                    value={"file": "motion.csv", "column": "vel"})]},
     "no column named 'vel'"),
    ("non-numeric row", {"bc": [dict(body="bar", end="left", type="velocity",
                                     value={"file": "bad.csv"})]}, "row 3: not a number"),
    ("non-increasing times", {"bc": [dict(body="bar", end="left", type="velocity",
                                          value={"file": "back.csv"})]}, "times must increase"),
    ("table outside the body", {"body": [unit_bar(4, E=[[2.0, 1.0], [3.0, 2.0]])]},
     "body[0] (bar).E: the table covers x in [2, 3]"),
    ("decreasing material table", {"body": [unit_bar(4, rho=[[0.0, 1.0], [0.6, 1.0],
                                                              [0.5, 2.0], [1.0, 2.0]])]},
     "must not decrease"),
    ("gravity without g", {"gravity": {"initial": "static"}}, "gravity.g: missing required key"),
    ("static with u0", {"body": [unit_bar(4, u0=0.1)], "gravity": {"g": -1.0,
                                                                  "initial": "static"}},
     "gravity.initial: \"static\" computes the initial displacements"),
    ("static with a free body", {"gravity": {"g": -1.0, "initial": "static"}},
     "is free to move as a whole"),
]


@pytest.mark.parametrize("name,tables,message", BAD, ids=[b[0] for b in BAD])
def test_bad_input_names_the_key(tmp_path, name, tables, message):
    record_files(tmp_path)
    (tmp_path / "bad.csv").write_text("t,v\n0,1\n1,x\n")
    (tmp_path / "back.csv").write_text("0,1\n1,2\n0.5,3\n")
    doc = {"time": {"dt": 0.1, "end": 1.0}, "body": [unit_bar(4)], **tables}
    path = tmp_path / "case.toml"
    path.write_text(vstpetsc.input.toml_text.dumps(doc))
    p = cli("run", path, "-o", tmp_path / "r.h5")
    assert p.returncode == 2 and "Traceback" not in p.stderr, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], p.stderr


def test_info_prints_the_energy_balance(tmp_path):
    case = BALANCE_CASES["damped, gravity, foundation, support"]()
    r = solve(tmp_path, case)
    p = cli("info", r.path)
    assert p.returncode == 0, p.stderr
    e = r.energy
    line = [l for l in p.stdout.splitlines() if "numerical" in l][0]
    assert f"{e['numerical'][-1]:.4g}" in line and f"{e['damping'][-1]:.4g}" in p.stdout
    assert "stress" in p.stdout


def test_case_file_with_history_files_round_trips(tmp_path):
    record_files(tmp_path)
    case = make_case(0.01, 0.2, [unit_bar(4)], folder=tmp_path,
                     bcs=[dict(body="bar", end="left", type="velocity",
                               value={"file": "motion.csv", "column": "acc"})])
    path = write_case(tmp_path, case)
    again = vstpetsc.Case.from_toml(path)
    assert again == case and str(tmp_path / "motion.csv") in again.inputs()
    p = cli("run", path, "-o", tmp_path / "motion.csv")
    assert p.returncode == 2 and "input file" in p.stderr
