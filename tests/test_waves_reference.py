"""tests/references/waves.py, the problems of the comparison with OpenSees
and of docs/wave-accuracy.md: their exact solutions, error norms and
step counts."""

import math

import numpy as np
import pytest

from references import waves


def test_tip_of_the_standing_wave_follows_its_period():
    period = waves.wave_period()
    t = np.array([0.0, 0.25, 0.5, 1.0, 2.0]) * period
    got = waves.tip_exact(t)
    assert got[0] == waves.AMP and got[2] == -waves.AMP
    assert abs(got[1]) < 1e-15 * waves.AMP
    np.testing.assert_allclose(got[3:], waves.AMP, rtol=1e-14)


def test_relative_l2_of_a_scaled_series_is_the_scale():
    exact = np.sin(np.linspace(0.0, 3.0, 50))
    assert waves.rel_l2(1.25 * exact, exact) == pytest.approx(0.25, rel=1e-14)
    assert waves.rel_l2(exact, exact) == 0.0


def test_rebound_error_and_mean_velocity():
    masses = waves.node_masses(10)
    assert masses.sum() == pytest.approx(waves.RHO * waves.AREA * waves.LENGTH, rel=1e-14)
    assert masses[0] == masses[-1] == masses[1] / 2
    v = np.full(11, -0.9)
    v[::2] += 0.1                      # a vibration on top of the rigid motion
    expected = np.dot(v, masses) / masses.sum()
    assert waves.mean_velocity(v, masses) == pytest.approx(expected, rel=1e-14)
    assert waves.rebound_error(-1.0) == 0.0
    assert waves.rebound_error(-0.99) == pytest.approx(0.01, rel=1e-12)


def site_args(z_rock):
    s = waves.SITE
    return s["H"], s["c"], s["rho"] * s["c"], z_rock


def test_site_closed_form_on_matched_rock_is_the_doubled_pulse():
    """Rock of the soil's impedance: no reflection at the base, the free
    surface doubles the incident wave, one transit H/c later."""
    s = waves.SITE
    pulse = lambda t: waves.ricker(t, s["f"], s["t0"])     # noqa: E731
    t = np.linspace(0.0, 1.0, 1001)
    got = waves.site_surface_exact(t, pulse, *site_args(s["rho"] * s["c"]))
    lag = t - s["H"] / s["c"]
    np.testing.assert_allclose(got, np.where(lag >= 0, 2 * pulse(lag), 0.0), atol=1e-15)


def test_site_closed_form_has_the_layer_transfer_function():
    """Surface over outcrop (2 v_in) in frequency equals
    1 / sqrt(cos^2 kH + a^2 sin^2 kH), a = Z_soil / Z_rock: the textbook
    form, independent of the reflection series."""
    s = waves.SITE
    z_soil, z_rock = s["rho"] * s["c"], s["rho_rock"] * s["c_rock"]
    dt, n = 1.0e-3, 2 ** 16                       # 65 s: the reflections die out
    t = dt * np.arange(n)
    pulse = lambda x: waves.ricker(x, s["f"], s["t0"])     # noqa: E731
    surface = waves.site_surface_exact(t, pulse, *site_args(z_rock))
    freq = np.fft.rfftfreq(n, dt)
    band = (freq > 2.0) & (freq < 25.0)
    ratio = np.abs(np.fft.rfft(surface)[band] / np.fft.rfft(2 * pulse(t))[band])
    kh = 2 * math.pi * freq[band] * s["H"] / s["c"]
    a = z_soil / z_rock
    np.testing.assert_allclose(ratio, 1 / np.sqrt(np.cos(kh) ** 2 + (a * np.sin(kh)) ** 2),
                               rtol=1e-6)


def test_steps_keep_the_courant_number_and_cover_the_run():
    for n, courant in [(8, 0.5), (100, math.sqrt(0.5)), (640, 2.0)]:
        steps = waves.steps_for(1.2, n, courant, 20.0, 200.0)
        dt = 1.2 / steps
        assert 200.0 * dt / (20.0 / n) <= courant * (1 + 1e-12)
        assert 200.0 * (1.2 / (steps - 1)) / (20.0 / n) > courant
