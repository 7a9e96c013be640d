"""bench/opensees.py's pure helpers: the exact solutions, error norms and
the choice of the cheapest run (speed is reported by `make bench`, never
asserted). The OpenSees model itself only where openseespy is installed."""

import importlib.util
import math
import os
import sys

import numpy as np
import pytest

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "bench"))
import opensees as bench  # noqa: E402


def test_tip_of_the_standing_wave_follows_its_period():
    period = bench.wave_period()
    t = np.array([0.0, 0.25, 0.5, 1.0, 2.0]) * period
    got = bench.tip_exact(t)
    assert got[0] == bench.AMP and got[2] == -bench.AMP
    assert abs(got[1]) < 1e-15 * bench.AMP
    np.testing.assert_allclose(got[3:], bench.AMP, rtol=1e-14)


def test_relative_l2_of_a_scaled_series_is_the_scale():
    exact = np.sin(np.linspace(0.0, 3.0, 50))
    assert bench.rel_l2(1.25 * exact, exact) == pytest.approx(0.25, rel=1e-14)
    assert bench.rel_l2(exact, exact) == 0.0


def test_rebound_error_and_mean_velocity():
    masses = bench.node_masses(10)
    assert masses.sum() == pytest.approx(bench.RHO * bench.AREA * bench.LENGTH, rel=1e-14)
    assert masses[0] == masses[-1] == masses[1] / 2
    v = np.full(11, -0.9)
    v[::2] += 0.1                      # a vibration on top of the rigid motion
    expected = np.dot(v, masses) / masses.sum()
    assert bench.mean_velocity(v, masses) == pytest.approx(expected, rel=1e-14)
    assert bench.rebound_error(-1.0) == 0.0
    assert bench.rebound_error(-0.99) == pytest.approx(0.01, rel=1e-12)


def site_args(z_rock):
    s = bench.SITE
    return s["H"], s["c"], s["rho"] * s["c"], z_rock


def test_site_closed_form_on_matched_rock_is_the_doubled_pulse():
    """Rock of the soil's impedance: no reflection at the base, the free
    surface doubles the incident wave, one transit H/c later."""
    s = bench.SITE
    pulse = lambda t: bench.ricker(t, s["f"], s["t0"])     # noqa: E731
    t = np.linspace(0.0, 1.0, 1001)
    got = bench.site_surface_exact(t, pulse, *site_args(s["rho"] * s["c"]))
    lag = t - s["H"] / s["c"]
    np.testing.assert_allclose(got, np.where(lag >= 0, 2 * pulse(lag), 0.0), atol=1e-15)


def test_site_closed_form_has_the_layer_transfer_function():
    """Surface over outcrop (2 v_in) in frequency equals
    1 / sqrt(cos^2 kH + a^2 sin^2 kH), a = Z_soil / Z_rock: the textbook
    form, independent of the reflection series."""
    s = bench.SITE
    z_soil, z_rock = s["rho"] * s["c"], s["rho_rock"] * s["c_rock"]
    dt, n = 1.0e-3, 2 ** 16                       # 65 s: the reflections die out
    t = dt * np.arange(n)
    pulse = lambda x: bench.ricker(x, s["f"], s["t0"])     # noqa: E731
    surface = bench.site_surface_exact(t, pulse, *site_args(z_rock))
    freq = np.fft.rfftfreq(n, dt)
    band = (freq > 2.0) & (freq < 25.0)
    ratio = np.abs(np.fft.rfft(surface)[band] / np.fft.rfft(2 * pulse(t))[band])
    kh = 2 * math.pi * freq[band] * s["H"] / s["c"]
    a = z_soil / z_rock
    np.testing.assert_allclose(ratio, 1 / np.sqrt(np.cos(kh) ** 2 + (a * np.sin(kh)) ** 2),
                               rtol=1e-6)


def test_steps_keep_the_courant_number_and_cover_the_run():
    for n, courant in [(8, 0.5), (100, math.sqrt(0.5)), (640, 2.0)]:
        steps = bench.steps_for(1.2, n, courant, 20.0, 200.0)
        dt = 1.2 / steps
        assert 200.0 * dt / (20.0 / n) <= courant * (1 + 1e-12)
        assert 200.0 * (1.2 / (steps - 1)) / (20.0 / n) > courant


def test_cheapest_is_the_least_work_that_meets_the_target():
    rows = [{"elements": 8, "steps": 90, "error": 2e-3},
            {"elements": 16, "steps": 50, "error": 5e-4},
            {"elements": 8, "steps": 400, "error": 4e-4},
            {"elements": 4, "steps": 10, "error": None}]
    assert bench.cheapest(rows, 1e-3) is rows[1]
    assert bench.cheapest(rows, 4.5e-4) is rows[2]
    assert bench.cheapest(rows, 3e-3) is rows[0]
    assert bench.cheapest(rows, 1e-4) is None


def test_readme_section_is_replaced_and_the_rest_kept(tmp_path):
    path = tmp_path / "README.md"
    path.write_text("# Benchmarks\n\n## A\n\na\n")
    bench.write_readme(str(path), bench.SECTION + "\n\nold\n")
    path.write_text(path.read_text() + "\n## B\n\nb\n")
    bench.write_readme(str(path), bench.SECTION + "\n\nnew\n")
    assert path.read_text() == ("# Benchmarks\n\n## A\n\na\n\n" + bench.SECTION
                                + "\n\nnew\n\n## B\n\nb\n")


@pytest.mark.skipif(importlib.util.find_spec("openseespy") is None,
                    reason="openseespy is installed for `make bench` only")
def test_opensees_wave_has_newmarks_period_error():
    """Newmark average acceleration at c dt/h = r with lumped mass lengthens
    the period by delta = (kh)^2 (1/24 + r^2/12) (mass and time step alike);
    over two periods (omega t_end = 4 pi) the tip's relative L2 error is
    then 4 pi delta / sqrt(3). With consistent mass at r = 1/sqrt(2) the
    two h^2 terms cancel (the issue's Courant number)."""
    child = bench.OpenSeesChild()
    try:
        err = {m: child(bench.job_for("wave", {"mass": m}, 16, bench.SQRT_HALF))[1]["error"]
               for m in ("consistent", "lumped")}
    finally:
        child.close()
    kh = 0.5 * math.pi / 16
    delta = kh ** 2 * (1 / 24 + 0.5 / 12)
    assert err["lumped"] == pytest.approx(4 * math.pi * delta / math.sqrt(3), rel=0.05)
    assert err["consistent"] < 0.1 * err["lumped"]
