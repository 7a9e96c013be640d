"""The acoustic reservoir against Chopra's closed form (issue 47, docs/water.md
section 4): a rigid vertical face shaken harmonically along x against a
reservoir of depth H on a rigid or partly absorbing bottom, truncated at
L = 3H by the plane-wave dashpot: the heel's steady pressure amplitude
(fitted over the last periods, after a smooth start) against the same
reservoir's closed form (tests/references/chopra_reservoir.py, derived
from the wave equation, (b) and (c)) below the first cut-off pi c / (2H)
and above it (the first mode radiating), converging as h^2; and the far
end's absorption of a high-frequency pulse (the energy left behind)."""

import io

import h5py
import numpy as np
import pytest

import vstpetsc
from acoustic_cases import BULK, RHO_W, reservoir_case
from references import chopra_reservoir as chopra

H, L = 10.0, 30.0
C = np.sqrt(BULK / RHO_W)
FIRST = np.pi * C / (2 * H)                 # the first cut-off, rad/s
A0, RAMP = 1.0, 4                           # the face's acceleration, its smooth start (periods)


def face_velocity(omega, end):
    """v_x(t) of the face (a TOML history, 200 points a period): its
    acceleration A0 cos(omega t) after a half-cosine ramp over RAMP
    periods (its spectrum narrow: the reservoir's own modes stay quiet)."""
    rise = RAMP * 2 * np.pi / omega
    t = np.arange(0.0, end + 0.01, 2 * np.pi / omega / 200)
    ramp = np.where(t < rise, 0.5 - 0.5 * np.cos(np.pi * t / rise), 1.0)
    v = ramp * A0 / omega * np.sin(omega * t)
    return "[" + ", ".join(f"[{a!r}, {b!r}]" for a, b in zip(t, v)) + "]"


def heel_amplitude(tmp_path, ratio, cells, alpha=None, periods=8, name="heel"):
    """The complex amplitude of the heel's dynamic pressure (its total less
    rho g H), least squares over the last 4 of ``periods`` periods after
    the ramp (slabs of a 120th of a period), and the energy balance's
    (numerical, external) at the end."""
    omega = ratio * FIRST
    period = 2 * np.pi / omega
    end = (RAMP + periods) * period
    path = reservoir_case(tmp_path, H, L, 3 * cells, cells, period / 120, end,
                          face_velocity(omega, end), name=name, alpha=alpha)
    out = tmp_path / f"{name}.h5"
    vstpetsc.run(vstpetsc.Case.from_toml(path), output=str(out), quiet=True, out=io.StringIO())
    with h5py.File(out) as f:
        t = f["time"][:]
        p = f["water/reservoir/pressure"][:, 0] - RHO_W * 9.81 * H
        energy = {k: f[f"energy/{k}"][-1] for k in ("numerical", "external")}
    last = t >= end - 4 * period - 1e-12
    X = np.column_stack([np.cos(omega * t[last]), np.sin(omega * t[last])])
    (a, b), *_ = np.linalg.lstsq(X, p[last], rcond=None)
    return a - 1j * b, energy


@pytest.mark.parametrize("ratio, periods, within", [(0.5, 8, 1e-3), (1.5, 20, 2e-2)])
def test_the_heel_pressure_against_chopra(tmp_path, ratio, periods, within):
    """Below the cut-off (0.5: every mode evanescent; measured 1.7e-3 at
    h = H / 5, 1.7e-4 at H / 10) and above it (1.5: the first mode travels
    to the far end, whose dashpot sends back part of it; 3.7e-2, 1.0e-2,
    after 20 periods: the reflections die slowly): the heel's amplitude
    against the truncated reservoir's closed form, the error falling by 3
    or more from h = H / 5 to H / 10; the energy balance closes."""
    omega = ratio * FIRST
    exact = chopra.pressure_truncated(0.0, 0.0, H, L, RHO_W, C, omega, A0)
    errors = []
    for cells in (5, 10):
        z, energy = heel_amplitude(tmp_path, ratio, cells, periods=periods, name=f"h{cells}")
        errors.append(abs(z - exact) / abs(exact))
        assert 0 <= energy["numerical"] < 1e-3 * abs(energy["external"])
    assert errors[1] < within and errors[0] / errors[1] > 3.0, errors


def test_a_partly_absorbing_bottom_against_fenves_and_chopra(tmp_path):
    """alpha = 0.5 at 0.8 of the cut-off: the heel's amplitude within 1 %
    of the closed form with Fenves and Chopra's bottom (complex vertical
    modes; measured 2.4e-3), which differs from the rigid bottom's by far
    more."""
    omega = 0.8 * FIRST
    exact = chopra.pressure_truncated(0.0, 0.0, H, L, RHO_W, C, omega, A0, alpha=0.5)
    rigid = chopra.pressure_truncated(0.0, 0.0, H, L, RHO_W, C, omega, A0)
    z, _ = heel_amplitude(tmp_path, 0.8, 10, alpha=0.5)
    assert abs(z - exact) < 1e-2 * abs(exact)
    assert abs(rigid - exact) > 5e-2 * abs(exact)


def test_the_truncated_reservoir_is_chopras_infinite_one_below_the_cut_off():
    """At L = 3H and half the cut-off the truncation changes the heel's
    pressure by less than 1e-3 (so the FE runs above measure Chopra's
    reservoir); above the cut-off the dashpot's reflection of the
    travelling first mode is what they include."""
    omega = 0.5 * FIRST
    truncated = chopra.pressure_truncated(0.0, 0.0, H, L, RHO_W, C, omega, A0)
    infinite = chopra.pressure_infinite(0.0, 0.0, H, RHO_W, C, omega, A0)
    assert abs(truncated - infinite) < 1e-3 * abs(infinite)


def pulse_velocity(omega, end):
    """A face pulse exp(-((t - t0) / tau)^2) sin(omega (t - t0)) (a TOML
    history, 40 points a period): its spectrum about omega, tau = 4 / omega."""
    tau, t0 = 4 / omega, 12 / omega
    t = np.arange(0.0, end + 1e-3, 2 * np.pi / omega / 40)
    v = np.exp(-((t - t0) / tau) ** 2) * np.sin(omega * (t - t0))
    return "[" + ", ".join(f"[{a!r}, {b!r}]" for a, b in zip(t, v)) + "]", t0 + 4 * tau


@pytest.mark.parametrize("far", [True, False])
def test_the_far_end_absorbs_what_reaches_it(tmp_path, far):
    """A pulse of ten times the cut-off frequency (its modes near plane
    waves) sent from the face: once it has crossed the reservoir 1.5 times,
    the energy left in the water is 2.9 % of the work put in with the far
    end's dashpot (the rest went out through it: the damping's work), and
    95 % with a rigid far end (no damping work; the slabs' numerical
    dissipation takes the other 5 %)."""
    omega = 10 * FIRST
    velocity, gone = pulse_velocity(omega, 1.0)
    end = gone + 1.5 * L / C
    path = reservoir_case(tmp_path, H, L, 75, 25, 2 * np.pi / omega / 20, end, velocity,
                          far=far, every=5)
    out = tmp_path / "pulse.h5"
    vstpetsc.run(vstpetsc.Case.from_toml(path), output=str(out), quiet=True, out=io.StringIO())
    with h5py.File(out) as f:
        e = {k: f[f"energy/{k}"][-1] for k in ("kinetic", "strain", "external", "damping",
                                                  "numerical")}
    left = (e["kinetic"] + e["strain"]) / e["external"]
    assert e["numerical"] >= 0
    if far:
        assert left < 0.05 and e["damping"] > 0.9 * e["external"], e
    else:
        assert left > 0.9 and abs(e["damping"]) < 1e-12 * e["external"], e
