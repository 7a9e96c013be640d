"""tests/references/mkz.py, the independent reference for issue 28 (MKZ
backbone, extended Masing rules, an explicit shear column), against facts
derived here, not against vstpetsc.

Facts used.
(1) Masing branches: after a reversal at (g_k, t_k), tau = t_k + 2 F((g - g_k)/2);
    F is odd, so the branch passes through the start of the previous branch
    and, from a backbone point (g_1, t_1), through (-g_1, -t_1).
(2) The symmetric loop's area is 8 W - 4 tau_a gamma_a, W = int_0^gamma_a F.
(3) Leapfrog on one mode of circular frequency omega, from the shape with
    the dt/2 first kick: w^n = cos(Omega t_n), sin(Omega dt / 2) = omega dt / 2,
    the mean of the half-step velocities -sin(Omega t_n) sin(Omega dt) / dt.
    The fixed-free lumped chain (half mass at the top) has the exact first
    mode sin(pi x / 2H), omega = 2 Vs / h sin(pi h / 4H).
(4) d'Alembert for a uniform elastic column, free top: on a rigid base moving
    with v_b, the surface velocity is 2 sum_k (-1)^k v_b(t - (2k+1) H / Vs);
    on a matched Lysmer base (Z = rho Vs) with incident v_in it is
    2 v_in(t - H / Vs), and the wave leaves through the base.
(5) A damped oscillator (ratio zeta) at rest under a constant base
    acceleration a0 peaks first at t = pi / omega_d with
    omega^2 |u| = a0 (1 + exp(-pi zeta / sqrt(1 - zeta^2))).
"""

import math

import numpy as np
import pytest

from agreement import TRANSCENDENTAL_RTOL
from references import mkz as mr

LAW = mr.Mkz(G=8.0e7, gamma_ref=5.0e-4, beta=1.0, s=0.919)
AMPLITUDES = (1.0e-4, 1.0e-3, 1.0e-2)          # 0.2, 2 and 20 gamma_ref
F = LAW.backbone


def drive(strains, law=LAW):
    point = mr.MasingPoint(law)
    return np.array([point.strain_to(g) for g in strains])


def ramp(a, b, samples=200):
    """Strains from a to b (a excluded): one monotonic increment each."""
    return np.linspace(a, b, samples + 1)[1:]


# ---------------------------------------------------------------- one point

def test_virgin_loading_follows_the_backbone_and_linear_limit_is_elastic():
    strains = np.concatenate((ramp(0.0, 3e-3), ramp(3e-3, -1e-3), ramp(-1e-3, 2e-3)))
    # the point's scalar pow (libm) against numpy's vectorised one, whose
    # kernel the CPU picks: equal to a few ulp (tests/agreement.py)
    np.testing.assert_allclose(drive(strains[:200]), F(strains[:200]),
                               rtol=TRANSCENDENTAL_RTOL, atol=0.0)
    for linear in (mr.Mkz(8.0e7), mr.Mkz(8.0e7, gamma_ref=5e-4, beta=0.0)):
        assert np.allclose(drive(strains, linear), 8.0e7 * strains, rtol=1e-14, atol=0.0)
        assert mr.loop_damping_closed_form(linear, 1e-3) == 0.0


@pytest.mark.parametrize("gamma_a", AMPLITUDES)
def test_backbone_work_and_the_two_damping_formulas_agree(gamma_a):
    import scipy.integrate
    W, _ = scipy.integrate.quad(F, 0.0, gamma_a, epsabs=0.0, epsrel=1e-13, limit=200)
    assert mr.backbone_work(LAW, gamma_a) == pytest.approx(W, rel=1e-11)
    closed = mr.loop_damping_closed_form(LAW, gamma_a)
    assert mr.loop_damping_quadrature(LAW, gamma_a) == pytest.approx(closed, rel=1e-9)
    assert 0.0 < closed < 2.0 / math.pi


@pytest.mark.parametrize("gamma_a", AMPLITUDES)
def test_a_symmetric_strain_cycle_gives_the_closed_form_damping(gamma_a):
    """0 -> gamma_a on the backbone, then one full cycle; its loop area by
    the trapezoidal rule over the point's own stresses."""
    down, up = ramp(gamma_a, -gamma_a, 4000), ramp(-gamma_a, gamma_a, 4000)
    tau = drive(np.concatenate((ramp(0.0, gamma_a), down, up)))
    tau_a = float(F(gamma_a))
    loop_g = np.concatenate(([gamma_a], down, up))
    loop_t = np.concatenate(([tau_a], tau[200:]))
    assert tau[200 + 3999] == pytest.approx(-tau_a, rel=1e-13)   # the mirrored point
    assert tau[-1] == pytest.approx(tau_a, rel=1e-13)           # the loop closes
    area = np.trapz(loop_t, loop_g)             # the work done: loading above unloading
    D = area / (2.0 * math.pi * tau_a * gamma_a)
    assert D == pytest.approx(mr.loop_damping_closed_form(LAW, gamma_a), rel=1e-3)


def test_an_inner_unload_reload_returns_to_the_outer_loop_then_the_backbone():
    ga = 1e-3
    ta = float(F(ga))
    g1, g2 = 0.3 * ga, -0.4 * ga
    history = [ramp(0.0, ga), ramp(ga, -ga), ramp(-ga, g1), ramp(g1, g2), ramp(g2, 1.5 * ga, 800)]
    tau = drive(np.concatenate(history))
    final_g, final_t = history[-1], tau[-800:]
    outer = -ta + 2.0 * F((final_g + ga) / 2.0)
    inner = (final_g < g1)
    rejoined = (final_g >= g1) & (final_g <= ga)
    assert not np.allclose(final_t[inner], outer[inner], rtol=1e-3)   # its own branch first
    assert np.allclose(final_t[rejoined], outer[rejoined], rtol=1e-12, atol=0.0)
    assert np.allclose(final_t[final_g > ga], F(final_g[final_g > ga]), rtol=1e-12, atol=0.0)
    # the branch from the first reversal meets the backbone at the mirrored point
    first = drive(np.concatenate((ramp(0.0, ga), ramp(ga, -1.5 * ga, 500))))[-500:]
    g = ramp(ga, -1.5 * ga, 500)
    assert np.allclose(first[g >= -ga], ta + 2.0 * F((g[g >= -ga] - ga) / 2.0), rtol=1e-12)
    assert np.allclose(first[g < -ga], F(g[g < -ga]), rtol=1e-12, atol=0.0)


def test_one_increment_past_several_open_points_lands_on_the_backbone():
    ga = 1e-3
    point = mr.MasingPoint(LAW)
    for g in (ga, -ga, 0.5 * ga, -0.5 * ga, 0.25 * ga, 0.25 * ga, 2.0 * ga):
        tau = point.strain_to(g)
    assert point.reversals == []
    assert tau == float(F(2.0 * ga))
    point.strain_to(1.5 * ga)                     # a new reversal from the backbone
    assert point.reversals == [(2.0 * ga, float(F(2.0 * ga)))]


def test_masing_stress_is_the_point_over_a_history():
    strains = 1e-3 * np.sin(np.linspace(0.0, 20.0, 400)) * np.linspace(0.2, 1.5, 400)
    assert np.array_equal(mr.masing_stress(strains, LAW.G, LAW.gamma_ref, LAW.beta, LAW.s),
                          drive(strains))


# ---------------------------------------------------------------- the column

H, RHO, VS = 20.0, 2000.0, 200.0


def sin4_pulse(amplitude, duration, t_end=1.0, samples=20001):
    t = np.linspace(0.0, t_end, samples)
    return t, amplitude * np.sin(np.pi * np.clip(t / duration, 0.0, 1.0)) ** 4


def test_linear_column_oscillates_in_the_lumped_chains_exact_first_mode():
    n = 16
    column = mr.Column.uniform(H, n, RHO, VS)
    w0 = np.sin(np.pi * column.x / (2.0 * H))
    run = mr.run_column(column, mr.RigidBase([0.0], [0.0]), 0.5, courant=0.7, w0=w0)
    omega = 2.0 * VS / (H / n) * math.sin(math.pi / (4.0 * n))
    Omega = 2.0 / run.dt * math.asin(omega * run.dt / 2.0)
    exact = -np.sin(Omega * run.t) * math.sin(Omega * run.dt) / run.dt
    assert np.allclose(run.surface_velocity, exact, rtol=0.0, atol=1e-12 * np.abs(exact).max())
    assert np.all(run.base_velocity == 0.0)
    assert np.abs(run.hysteretic).max() < 1e-12 * run.stored[0]      # linear: nothing lost


def test_linear_column_converges_to_dalembert_at_second_order():
    t, v = sin4_pulse(0.1, 0.1)

    def incident(time):
        return np.interp(time, t, v, left=0.0)

    errors = {"rigid": [], "lysmer": []}
    for n in (20, 40, 80):
        column = mr.Column.uniform(H, n, RHO, VS)
        rigid = mr.run_column(column, mr.RigidBase(t, v), 0.6)
        series = sum(2.0 * (-1) ** k * incident(rigid.t - (2 * k + 1) * H / VS) for k in range(3))
        errors["rigid"].append(np.abs(rigid.surface_velocity - series).max())
        lysmer = mr.run_column(column, mr.LysmerBase(RHO * VS, t, v), 0.6)
        doubled = 2.0 * incident(lysmer.t - H / VS)
        errors["lysmer"].append(np.abs(lysmer.surface_velocity - doubled).max())
    for e in errors.values():
        assert e[0] / e[1] > 3.5 and e[1] / e[2] > 3.5                 # order 2
        assert e[2] < 0.01 * 0.2
    # the matched base took the whole wave: only O(h^2) is left in the column
    assert lysmer.kinetic[-1] + lysmer.stored[-1] < 1e-5 * lysmer.input[-1]


LAYERS = [(10.0, 2100.0, 400.0, 1.0e-3, 1.0, 0.919),      # from the base up
          (10.0, 1900.0, 300.0, 6.0e-4, 1.0, 0.919),
          (10.0, 1800.0, 200.0, 4.0e-4, 1.0, 0.919)]
Z_ROCK = 2300.0 * 700.0


def site_input(amplitude=0.06, duration=0.25):
    """An incident velocity: a 8 Hz sine under a sin^4 window of 0.25 s."""
    t = np.linspace(0.0, 2.0, 8001)
    window = np.sin(np.pi * np.clip(t / duration, 0.0, 1.0)) ** 4
    return t, amplitude * window * np.sin(4.0 * np.pi * t / duration)


def nonlinear_run(h_max, courant=0.5, t_end=1.0, rigid=False, **kw):
    """On rock with the incident wave, or on a rigid base moving with twice
    it (the outcrop motion) when rigid."""
    column = mr.Column.layered(LAYERS, h_max)
    t, v = site_input()
    base = mr.RigidBase(t, 2.0 * v) if rigid else mr.LysmerBase(Z_ROCK, t, v)
    return mr.run_column(column, base, t_end, courant=courant, **kw)


@pytest.mark.parametrize("rigid", [False, True])
def test_energy_balance_closes_at_order_dt_squared(rigid):
    residuals = []
    for courant in (0.8, 0.4, 0.2):
        run = nonlinear_run(1.25, courant, rigid=rigid)
        residuals.append(np.abs(run.energy_residual()).max() / run.input[-1])
        assert run.hysteretic[-1] > 0.2 * run.input[-1]               # the law dissipates
        assert run.hysteretic.min() > -1e-3 * run.input[-1]
        assert run.peak_strain.max() > 1.5 * 4.0e-4                 # into the nonlinear range
    assert 3.5 < residuals[0] / residuals[1] < 4.5
    assert 3.5 < residuals[1] / residuals[2] < 4.5
    assert residuals[2] < 2e-4


def test_recorded_element_stress_is_the_masing_point_on_its_strain():
    run = nonlinear_run(2.5, record=(7, 11))
    G = 1800.0 * 200.0 ** 2
    assert np.max(run.peak_strain[8:]) > 4e-4
    for e in (7, 11):
        law = (G, 4.0e-4, 1.0, 0.919) if e >= 8 else (1900.0 * 300.0 ** 2, 6.0e-4, 1.0, 0.919)
        assert np.array_equal(run.stress[e], mr.masing_stress(run.strain[e], *law))
        assert np.abs(run.strain[e]).max() == run.peak_strain[e]


def test_surface_motion_converges_under_mesh_refinement():
    """The peak surface velocity and the 5 % response spectrum (periods
    0.1 to 1 s) converge; the raw peak acceleration does in the linear
    column, at order 2 (in the nonlinear one it carries grid-scale ringing
    from the reversals, which the lossless explicit scheme keeps)."""
    periods = [0.1, 0.2, 0.5, 1.0]
    spectra, peaks = [], []
    for h_max in (2.5, 1.25, 0.625):
        run = nonlinear_run(h_max, t_end=1.5)
        spectra.append(mr.response_spectrum(run.t, run.surface_acceleration, periods))
        peaks.append(np.abs(run.surface_velocity).max())
    change = [np.abs(spectra[k + 1] / spectra[k] - 1.0).max() for k in range(2)]
    assert change[1] < 0.5 * change[0] and change[1] < 0.015
    assert abs(peaks[2] - peaks[1]) < 0.5 * abs(peaks[1] - peaks[0])
    linear = [(thickness, rho, vs, math.inf, 1.0, 1.0) for thickness, rho, vs, *_ in LAYERS]
    pga = []
    for h_max in (2.5, 1.25, 0.625):
        column = mr.Column.layered(linear, h_max)
        run = mr.run_column(column, mr.LysmerBase(Z_ROCK, *site_input(0.02)), 0.8)
        pga.append(np.abs(run.surface_acceleration).max())
    assert abs(pga[0] - pga[1]) / abs(pga[1] - pga[2]) > 3.0


def test_response_spectrum_of_a_constant_acceleration():
    zeta, period, a0 = 0.05, 0.5, 2.0
    omega = 2.0 * math.pi / period
    first_peak = math.pi / (omega * math.sqrt(1.0 - zeta ** 2))
    t = np.linspace(0.0, 2.0 * first_peak, 401)        # the peak is a sample
    psa = mr.response_spectrum(t, np.full_like(t, a0), [period], zeta)
    overshoot = math.exp(-math.pi * zeta / math.sqrt(1.0 - zeta ** 2))
    assert psa[0] == pytest.approx(a0 * (1.0 + overshoot), rel=1e-10)


def test_bad_step_and_layers_are_refused():
    column = mr.Column.uniform(H, 10, RHO, VS)
    with pytest.raises(ValueError, match=r"^dt: must be in \(0, 0.9 min"):
        mr.run_column(column, mr.RigidBase([0.0], [0.0]), 1.0, dt=0.95 * column.dt_limit())
    with pytest.raises(ValueError, match=r"^gamma_ref: must be > 0"):
        mr.Column.uniform(H, 10, RHO, VS, gamma_ref=0.0)
