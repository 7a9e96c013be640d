"""The slab solver without contact: order, stability, conservation, waves
(formulation.md sections 2 and 7)."""

import numpy as np
import pytest

from conftest import body, run_text, table, time_table
from vstpetsc.case import Body
from vstpetsc.mesh import build_layout, modes

E, RHO, L = 1.0, 1.0, 1.0          # c = 1


def modal_solution(layout, fixed, u0, v0, t):
    """Semi-discrete solution (exact in time) of M u'' + K u = 0."""
    w2, phi, free = modes(layout, fixed)
    w = np.sqrt(w2)
    M = (np.diag(layout.m_diag) + np.diag(layout.m_off, 1)
         + np.diag(layout.m_off, -1))[np.ix_(free, free)]
    q0, p0 = phi.T @ M @ u0[free], phi.T @ M @ v0[free]
    u, v = np.zeros_like(u0), np.zeros_like(v0)
    u[free] = phi @ (np.cos(w * t) * q0 + np.sin(w * t) / w * p0)
    v[free] = phi @ (-w * np.sin(w * t) * q0 + np.cos(w * t) * p0)
    return u, v


def test_third_order_against_semidiscrete_modes(tmp_path):
    ne, T = 16, 1.0
    lay = build_layout([Body("bar", (0.0, L), ne, E, RHO)])
    w2, phi, free = modes(lay, [0])
    u0 = np.zeros(lay.nnodes)
    u0[free] = phi[:, 0] / abs(phi[:, 0]).max() + 0.3 * phi[:, 1] / abs(phi[:, 1]).max()
    u_ex, v_ex = modal_solution(lay, [0], u0, np.zeros_like(u0), T)
    errors = []
    dts = T / np.array([10, 20, 40, 80])
    for dt in dts:
        text = (time_table(float(dt), T, every=1000000)
                + body("bar", (0.0, L), ne, E=E, rho=RHO,
                       u0=[[float(x), float(u)] for x, u in zip(lay.x, u0)])
                + table("bc", body="bar", end="left", type="fixed"))
        r = run_text(tmp_path, text)
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
    text = (time_table(dt, 200 * dt)
            + body("bar", (0.0, L), ne, E=E, rho=RHO, v0=[[0.0, 0.0], [0.5, 1.0], [1.0, -0.3]],
                   u0=[[0.0, 0.0], [0.3, 0.02], [1.0, 0.0]]))
    if fixed:
        text += table("bc", body="bar", end="left", type="fixed")
    r = run_text(tmp_path, text)
    energy = r["energy/kinetic"] + r["energy/strain"]
    assert np.all(np.isfinite(energy))
    assert np.all(np.diff(energy) <= 1e-12 * energy[0])
    assert np.abs(r["body/bar/v"]).max() < 10.0


def test_free_bar_gains_exactly_the_applied_impulse(tmp_path):
    # traction (force per area along +x) on the right end, break points not on slab edges
    hist = [[0.0, 0.0], [0.0123, 3.0], [0.037, -1.0], [0.05, 2.0]]
    area, dt, end = 0.7, 0.004, 0.06
    text = (time_table(dt, end) + body("bar", (0.0, L), 20, E=E, rho=RHO, area=area, v0=0.25)
            + table("bc", body="bar", end="right", type="traction", value=hist))
    r = run_text(tmp_path, text)
    lay = build_layout([Body("bar", (0.0, L), 20, E, RHO, area)])
    lumped = lay.m_diag + np.r_[lay.m_off, 0] + np.r_[0, lay.m_off]
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
    text = (time_table(dt, 1.5 * L / c) + body("bar", (0.0, L), ne, E=Eb, rho=rho)
            + table("bc", body="bar", end="left", type="velocity", value=V))
    r = run_text(tmp_path, text)
    t, v_end = r["time"], r["body/bar/v"][:, -1]
    arrival = t[np.argmax(v_end > V)]           # the free end reaches 2 V: crossing V marks the front
    print(f"front arrival {arrival:.6e} s, L/c = {L / c:.6e} s, ({(arrival - L / c) / dt:+.2f} dt)")
    assert abs(arrival - L / c) <= 3 * dt
    assert abs(v_end[-1] - 2 * V) < 0.05 * V    # free-end doubling


def test_two_bars_without_contact_do_not_interact(tmp_path):
    a = body("a", (0.0, 1.0), 30, E=1.0, rho=2.0, v0=[[0.0, 0.0], [1.0, 1.0]])
    b = body("b", (1.0, 3.0), 40, E=5.0, rho=1.0, area=3.0, u0=[[1.0, 0.0], [3.0, 0.01]])
    bc = table("bc", body="a", end="left", type="fixed")
    tt = time_table(0.01, 1.0, every=10)
    both = run_text(tmp_path, tt + a + b + bc, name="both")
    only_a = run_text(tmp_path, tt + a + bc, name="a")
    only_b = run_text(tmp_path, tt + b, name="b")
    for name, single in (("a", only_a), ("b", only_b)):
        for key in ("u", "v", "stress"):
            assert np.allclose(both[f"body/{name}/{key}"], single[f"body/{name}/{key}"],
                               rtol=0, atol=1e-14 * (1 + np.abs(single[f"body/{name}/{key}"]).max()))
    assert np.allclose(both["energy/kinetic"], only_a["energy/kinetic"] + only_b["energy/kinetic"])


def test_result_file_layout_and_every(tmp_path):
    dt, n, every = 0.01, 23, 5
    text = (time_table(dt, n * dt, every=every) + body("left", (0.0, 1.0), 10, v0=1.0)
            + body("right", (1.5, 2.0), 7) + table("contact", pair=["left", "right"]))
    r = run_text(tmp_path, text)
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
    assert r.attrs["case"] == text
    assert r.attrs["mpi_size"] == 1 and r.attrs["formulation"] == "seed"
    assert r["solver/newton_iterations"][0] == 0 and r["contact/0/force"][0] == 0
    assert np.allclose(r["body/left/v"][0], 1.0) and np.allclose(r["contact/0/gap"][0], 0.5)
    assert np.allclose(r["body/right/x"], np.linspace(1.5, 2.0, 8))
