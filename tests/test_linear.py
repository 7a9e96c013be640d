"""The slab solver without contact: order, stability, conservation, waves
(formulation.md sections 2 and 7)."""

import numpy as np
import pytest

from conftest import bar, make_case, solve
from vstpetsc.line.model import build_model, dense, modes

E, RHO, L = 1.0, 1.0, 1.0          # c = 1


def modal_solution(ops, fixed, u0, v0, t):
    """Semi-discrete solution (exact in time) of M u'' + K u = 0."""
    w2, phi, free = modes(ops, fixed)
    w = np.sqrt(w2)
    M = dense(ops)[0][np.ix_(free, free)]
    q0, p0 = phi.T @ M @ u0[free], phi.T @ M @ v0[free]
    u, v = np.zeros_like(u0), np.zeros_like(v0)
    u[free] = phi @ (np.cos(w * t) * q0 + np.sin(w * t) / w * p0)
    v[free] = phi @ (-w * np.sin(w * t) * q0 + np.cos(w * t) * p0)
    return u, v


def test_third_order_against_semidiscrete_modes(tmp_path):
    ne, T = 16, 1.0
    model = build_model(make_case(0.1, T, [bar("bar", (0.0, L), ne, E=E, rho=RHO)]))
    w2, phi, free = modes(model.ops, [0])
    u0 = np.zeros(model.mesh.nnodes)
    u0[free] = phi[:, 0] / abs(phi[:, 0]).max() + 0.3 * phi[:, 1] / abs(phi[:, 1]).max()
    u_ex, v_ex = modal_solution(model.ops, [0], u0, np.zeros_like(u0), T)
    errors = []
    dts = T / np.array([10, 20, 40, 80])
    for dt in dts:
        case = make_case(float(dt), T, [bar("bar", (0.0, L), ne, E=E, rho=RHO,
                                            u0=np.column_stack([model.mesh.x, u0]))],
                         bcs=[dict(body="bar", end="left", type="fixed")], every=1000000)
        r = solve(tmp_path, case)
        assert np.isclose(r["time"][-1], T)
        eu = np.abs(r["body/bar/u"][-1] - u_ex).max() / np.abs(u_ex).max()
        ev = np.abs(r["body/bar/v"][-1] - v_ex).max() / np.abs(v_ex).max()
        errors.append((eu, ev))
    errors = np.array(errors)
    order_u = np.polyfit(np.log(dts), np.log(errors[:, 0]), 1)[0]
    order_v = np.polyfit(np.log(dts), np.log(errors[:, 1]), 1)[0]
    print(f"third-order check: errors {errors.tolist()}, orders u {order_u:.3f} v {order_v:.3f}")
    assert order_u >= 2.8 and order_v >= 2.8


@pytest.mark.parametrize("fixed", [True, False])
def test_energy_never_grows_even_far_beyond_cfl(tmp_path, fixed):
    ne = 50
    h = L / ne
    dt = 100 * h                       # 100 times the CFL limit h / c
    case = make_case(dt, 200 * dt,
                     [bar("bar", (0.0, L), ne, E=E, rho=RHO,
                          v0=[[0.0, 0.0], [0.5, 1.0], [1.0, -0.3]],
                          u0=[[0.0, 0.0], [0.3, 0.02], [1.0, 0.0]])],
                     bcs=[dict(body="bar", end="left", type="fixed")] if fixed else ())
    r = solve(tmp_path, case)
    energy = r["energy/kinetic"] + r["energy/strain"]
    assert np.all(np.isfinite(energy))
    assert np.all(np.diff(energy) <= 1e-12 * energy[0])
    assert np.abs(r["body/bar/v"]).max() < 10.0


def test_free_bar_gains_exactly_the_applied_impulse(tmp_path):
    # traction (force per area along +x) on the right end, break points not on slab edges
    hist = [[0.0, 0.0], [0.0123, 3.0], [0.037, -1.0], [0.05, 2.0]]
    area, dt, end = 0.7, 0.004, 0.06
    case = make_case(dt, end, [bar("bar", (0.0, L), 20, E=E, rho=RHO, area=area, v0=0.25)],
                     bcs=[dict(body="bar", end="right", type="traction", value=hist)])
    r = solve(tmp_path, case)
    M, _ = dense(build_model(case).ops)
    lumped = M.sum(axis=0)
    p = r["body/bar/v"] @ lumped
    t, f = np.array(hist).T
    tt = np.r_[t, end]
    ff = np.r_[f, f[-1]]                        # the history holds its last value
    impulse = area * np.trapz(ff, tt)
    assert np.isclose(p[0], RHO * area * L * 0.25, rtol=1e-13)
    assert abs(p[-1] - p[0] - impulse) <= 1e-10 * abs(impulse)


def test_velocity_front_arrives_at_far_end_after_L_over_c(tmp_path):
    Eb, rho, V = 2.0e11, 7850.0, 1.0
    c = np.sqrt(Eb / rho)
    ne = 200
    dt = 0.5 * (L / ne) / c
    case = make_case(dt, 1.5 * L / c, [bar("bar", (0.0, L), ne, E=Eb, rho=rho)],
                     bcs=[dict(body="bar", end="left", type="velocity", value=V)])
    r = solve(tmp_path, case)
    t, v_end = r["time"], r["body/bar/v"][:, -1]
    arrival = t[np.argmax(v_end > V)]           # the free end reaches 2 V: crossing V marks the front
    print(f"front arrival {arrival:.6e} s, L/c = {L / c:.6e} s, ({(arrival - L / c) / dt:+.2f} dt)")
    assert abs(arrival - L / c) <= 3 * dt
    assert abs(v_end[-1] - 2 * V) < 0.05 * V    # free-end doubling


def test_two_bars_without_contact_do_not_interact(tmp_path):
    a = bar("a", (0.0, 1.0), 30, E=1.0, rho=2.0, v0=[[0.0, 0.0], [1.0, 1.0]])
    b = bar("b", (1.0, 3.0), 40, E=5.0, rho=1.0, area=3.0, u0=[[1.0, 0.0], [3.0, 0.01]])
    bc = [dict(body="a", end="left", type="fixed")]
    both = solve(tmp_path, make_case(0.01, 1.0, [a, b], bcs=bc, every=10), name="both")
    only_a = solve(tmp_path, make_case(0.01, 1.0, [a], bcs=bc, every=10), name="a")
    only_b = solve(tmp_path, make_case(0.01, 1.0, [b], every=10), name="b")
    for name, single in (("a", only_a), ("b", only_b)):
        for key in ("u", "v", "stress"):
            assert np.allclose(both[f"body/{name}/{key}"], single[f"body/{name}/{key}"],
                               rtol=0, atol=1e-14 * (1 + np.abs(single[f"body/{name}/{key}"]).max()))
    assert np.allclose(both["energy/kinetic"], only_a["energy/kinetic"] + only_b["energy/kinetic"])


def test_result_file_layout_and_every(tmp_path):
    dt, n, every = 0.01, 23, 5
    case = make_case(dt, n * dt, [bar("left", (0.0, 1.0), 10, v0=1.0), bar("right", (1.5, 2.0), 7)],
                     contacts=[dict(pair=["left", "right"])], every=every)
    r = solve(tmp_path, case)
    kept = np.array([0, 5, 10, 15, 20, 23])
    assert np.allclose(r["time"], kept * dt)
    nt = kept.size
    shapes = {"time": (nt,), "body/left/x": (11,), "body/left/u": (nt, 11),
              "body/left/v": (nt, 11), "body/left/stress": (nt, 10),
              "body/right/x": (8,), "body/right/u": (nt, 8), "body/right/stress": (nt, 7),
              "contact/0/gap": (nt,), "contact/0/force": (nt,), "contact/0/impulse": (nt,),
              "energy/kinetic": (nt,), "energy/strain": (nt,),
              "solver/newton_iterations": (nt,), "solver/linear_iterations": (nt,)}
    for key, shape in shapes.items():
        assert r[key].shape == shape, key
    for attr in ("status", "version", "case", "petsc_options", "mpi_size", "formulation"):
        assert attr in r.attrs, attr
    assert r.attrs["status"] == "completed"
    assert r.attrs["case"] == case.to_toml()
    assert r.attrs["mpi_size"] == 1 and r.attrs["formulation"] == "power"
    assert r["solver/newton_iterations"][0] == 0 and r["contact/0/force"][0] == 0
    assert np.allclose(r["body/left/v"][0], 1.0) and np.allclose(r["contact/0/gap"][0], 0.5)
    assert np.allclose(r["body/right/x"], np.linspace(1.5, 2.0, 8))
