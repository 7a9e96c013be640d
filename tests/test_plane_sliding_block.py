"""A stiff block on a frictional interface over a base shaken by a
rectangular acceleration pulse, against Newmark's (1965) rigid block:
with yield acceleration ky g (ky = mu on a horizontal base) and a pulse
of A g for t0 (V = A g t0), the permanent slip is

    D = V^2 / (2 g ky) (1 - ky / A)

(Newmark 1965, "Effects of earthquakes on dams and embankments",
Geotechnique 15(2), the rectangular pulse).  The block rests on a row of
cells whose base is driven (a generated rectangle with a joint), starts
in static equilibrium under its weight (the joint's springs closed), and
the slip approaches D as the block (and its joint's default penalties,
which follow the cells' stiffness) stiffens."""

import numpy as np
import pytest

import vstpetsc
from conftest import solve

G, MU, A, T0 = 9.81, 0.2, 0.5, 0.2
V = A * G * T0
NEWMARK = V * V / (2 * G * MU) * (1 - MU / A)
END, DT = 0.8, 1e-3


def block_case(folder, E):
    drive = [[0.0, 0.0], [T0, V], [END, V]]
    return vstpetsc.Case.from_dict({
        "time": {"dt": DT, "end": END}, "output": {"every": 10},
        "mesh": {"rectangle": {"x": [0.0, 2.0], "y": [-0.25, 1.0], "nx": 8, "ny": 5,
                               "joints": {"base": 0.0}}},
        "region": [{"name": "domain", "E": E, "nu": 0.2, "rho": 2000.0}],
        "boundary": [{"name": "bottom", "type": "velocity", "value": {"x": drive, "y": 0.0}}],
        "interface": [{"name": "base", "friction": MU}],
        "gravity": {"g": -G, "initial": "static"}}, folder=str(folder))


def test_newmark_sliding_block(tmp_path):
    errors = []
    for E in (1e9, 1e10, 1e11):
        r = solve(tmp_path, block_case(tmp_path, E), f"block{E:g}")
        base = r.interface("base")
        slip = -base.slip[-1]                 # the block lags: negative along +x
        weight = 2000.0 * G * 2.0 * 1.0
        N = base.normal_force[1:].sum(axis=1)
        assert np.abs(N - weight).max() <= 0.05 * weight    # the weight, through the shaking
        errors.append(abs(slip.mean() - NEWMARK) / NEWMARK)
        assert np.ptp(slip) <= 0.01 * NEWMARK               # the block slides as one
        # the energy balance closes: the scheme's numerical dissipation is >= 0
        # and small beside the work put in
        work = r.energy["external"][-1]
        numerical = r.energy["numerical"]
        assert numerical.min() >= -1e-9 * work and numerical[-1] <= 1e-4 * work   # 8.1e-6 at 1e9
        # sliding dissipates about mu N |slip| (N through the shaking: its mean)
        friction = r.energy["friction"][-1]
        assert abs(friction - MU * weight * slip.mean()) <= 1e-5 * friction      # 4.0e-7 at most
        print(E, slip.mean(), NEWMARK, errors[-1], numerical[-1] / work,
              friction / (MU * weight * slip.mean()) - 1)
    # measured: 0.70 %, 0.20 %, 0.085 % at E = 1e9, 1e10, 1e11
    assert errors[0] > errors[1] > errors[2] and errors[2] <= 2e-3
