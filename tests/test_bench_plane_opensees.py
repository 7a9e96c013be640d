"""bench/plane_opensees.py: its closed form (the standing waves of a
roller-supported square solve Navier's equation and the boundary
conditions), the sample times on steps, the choice of the cheapest run,
vstpetsc's second order in h on it, and, where openseespy is installed,
the OpenSees model (speed is reported by `make bench`, never asserted)."""

import importlib.util
import math
import os
import sys

import numpy as np
import pytest

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "bench"))
import plane_opensees as bench  # noqa: E402


def mode_field(kind, m, n):
    """u(x, y, t) -> (u_x, u_y) of one mode, the amplitudes of bench.mode."""
    A, B, a, b, w = bench.mode(kind, m, n)
    return lambda x, y, t: np.array([A * np.sin(a * x) * np.cos(b * y),
                                     B * np.cos(a * x) * np.sin(b * y)]) * np.sin(w * t)


@pytest.mark.parametrize("kind,m,n", [("P", 1, 1), ("S", 2, 1), ("P", 3, 2), ("S", 1, 3)])
def test_modes_solve_navier_and_the_rollers(kind, m, n):
    """rho u_tt = (lambda + 2 mu) u_x,xx + mu u_x,yy + (lambda + mu) u_y,xy
    (and its y twin) by central differences at scattered points and times;
    u_n = 0 and sigma_xy = 0 on the four sides."""
    u, d = mode_field(kind, m, n), 1e-3
    lam, mu, rho = bench.LAM, bench.MU, bench.RHO
    w = bench.mode(kind, m, n)[4]
    rng = np.random.default_rng(7)
    x, y = rng.uniform(0, bench.LENGTH, (2, 20))
    t = rng.uniform(0, 2 * math.pi / w, 20)
    du = lambda dx, dy, dt=0.0: u(x + dx, y + dy, t + dt)
    second = lambda f, s: (f(s) - 2 * f(0.0) + f(-s)) / (s * s)
    u_xx = second(lambda s: du(s, 0), d)
    u_yy = second(lambda s: du(0, s), d)
    u_xy = (du(d, d) - du(d, -d) - du(-d, d) + du(-d, -d)) / (4 * d * d)
    u_tt = second(lambda s: du(0, 0, s), 1e-3 / w)
    navier = np.array([(lam + 2 * mu) * u_xx[0] + mu * u_yy[0] + (lam + mu) * u_xy[1],
                       (lam + 2 * mu) * u_yy[1] + mu * u_xx[1] + (lam + mu) * u_xy[0]])
    scale = rho * w * w
    assert np.abs(rho * u_tt - navier).max() <= 1e-5 * scale
    side = np.linspace(0, bench.LENGTH, 9)
    L, zero = bench.LENGTH, np.zeros(9)
    for xs, ys, normal in ((zero, side, 0), (zero + L, side, 0), (side, zero, 1),
                           (side, zero + L, 1)):
        assert np.abs(u(xs, ys, 0.3)[normal]).max() <= 1e-12
        shear = ((u(xs, ys + d, 0.3)[0] - u(xs, ys - d, 0.3)[0])
                 + (u(xs + d, ys, 0.3)[1] - u(xs - d, ys, 0.3)[1])) / (2 * d)
        assert np.abs(shear).max() <= 1e-9


def test_the_families_polarisation_and_speed():
    """P: (A, B) along the wave vector, w = Vp k; S: across it, w = Vs k."""
    for kind, speed in (("P", bench.VP), ("S", bench.VS)):
        A, B, a, b, w = bench.mode(kind, 2, 1)
        cross = A * b - B * a if kind == "P" else A * a + B * b
        assert cross == pytest.approx(0.0, abs=1e-15)
        assert w == pytest.approx(speed * math.hypot(a, b))
    assert bench.VP / bench.VS == pytest.approx(math.sqrt(3.0))


def test_sample_times_fall_on_steps_and_the_courant_number_is_kept():
    for n in (4, 11, 64, 181):
        for courant in (0.25, 1.0, 4.0):
            job = bench.job_for("vstpetsc", n, courant)
            assert job["per_sample"] * job["dt"] == pytest.approx(bench.slow_period() / 8)
            assert job["steps"] * job["dt"] == pytest.approx(bench.sample_times()[-1])
            assert job["courant"] <= courant * (1 + 1e-12)


def test_cheapest_and_the_extrapolated_mesh():
    rows = [{"n": 8, "steps": 90, "error": 2e-3, "target_courant": 1.0, "seconds": 1.0},
            {"n": 16, "steps": 50, "error": 5e-4, "target_courant": 1.0, "seconds": 2.0},
            {"n": 8, "steps": 400, "error": 4e-4, "target_courant": 0.5, "seconds": 1.0},
            {"n": 4, "steps": 10, "error": None, "target_courant": 0.5, "seconds": 1.0}]
    assert bench.cheapest(rows, 1e-3) is rows[1]
    assert bench.cheapest(rows, 4.5e-4) is rows[2]
    assert bench.cheapest(rows, 1e-4) is None
    est = bench.extrapolate(rows, 1.25e-4)         # order 2 from n = 8, 16: n = 32
    assert est["order"] == pytest.approx(2.0)
    assert est["n"] == pytest.approx(32.0)
    assert est["seconds"] == pytest.approx(2.0 * 8)     # 4 x the elements, 2 x the steps


def test_vstpetsc_converges_in_h_squared_on_the_standing_wave():
    """Bilinear quadrilaterals: the error at the nodes falls as h^2
    (dispersion); the time error is far below it at Vp dt / h = 1.5."""
    err = [bench.vst_runner(bench.job_for("vstpetsc", n, 2.0))[1] for n in (8, 16)]
    order = math.log2(err[0] / err[1])
    print("vstpetsc errors", err, "order", order)
    assert 0.005 < err[1] < 0.03
    assert 1.8 < order < 2.4


@pytest.mark.skipif(importlib.util.find_spec("openseespy") is None,
                    reason="openseespy is installed for `make bench` only")
def test_opensees_standing_wave_converges_to_the_same_closed_form():
    """OpenSees' quad (lumped) and bbarQuad (consistent) on the same
    problem: second order in h, and the lumped mass's and Newmark's period
    errors adding (quad 2-4 times bbarQuad's error)."""
    child = bench.OpenSeesChild()
    try:
        err = {m: [child(bench.job_for(m, n, 0.5))[1] for n in (8, 16)]
               for m in ("opensees quad", "opensees bbarQuad")}
    finally:
        child.close()
    print("OpenSees errors", err)
    for m, (coarse, fine) in err.items():
        assert 1.7 < math.log2(coarse / fine) < 2.4, m
    assert 2 < err["opensees quad"][1] / err["opensees bbarQuad"][1] < 4
