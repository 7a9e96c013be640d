"""Lift-off under vertical shaking: a stiff block on an interface over a
base that rises with 5 m/s^2 to 0.5 m/s at t = 0.1 s and then stops at
-50 m/s^2 (more than g): the block leaves the base at 0.1 s, flies freely
under gravity and lands where the rigid body's flight y_b(t) = y_s +
V tau - g tau^2 / 2 meets the stopped base (tau = 96.65 ms after
leaving).  While open the interface carries nothing (the slab-mean normal
force is exactly 0), the block's mean vertical velocity follows
V - g tau (within 2 % of V), and it lands within 2 ms of the rigid time."""

import numpy as np

import vstpetsc
from conftest import solve

G, V, RISE, STOP = 9.81, 0.5, 0.1, 0.01
DT, END = 5e-4, 0.3
# the rigid block lands when V tau - g tau^2 / 2 = the base's rise while stopping
LANDING = RISE + (V + np.sqrt(V * V - 2 * G * V * STOP / 2)) / G


def lift_case(folder):
    drive = [[0.0, 0.0], [RISE, V], [RISE + STOP, 0.0], [END, 0.0]]
    return vstpetsc.Case.from_dict({
        "time": {"dt": DT, "end": END},
        "mesh": {"rectangle": {"x": [0.0, 2.0], "y": [-0.25, 1.0], "nx": 8, "ny": 5,
                               "joints": {"base": 0.0}}},
        "region": [{"name": "domain", "E": 1e10, "nu": 0.2, "rho": 2000.0}],
        "boundary": [{"name": "bottom", "type": "velocity", "value": {"x": 0.0, "y": drive}}],
        "interface": [{"name": "base", "friction": 0.5}],
        "gravity": {"g": -G, "initial": "static"}}, folder=str(folder))


def test_lift_off_flight_and_landing(tmp_path):
    r = solve(tmp_path, lift_case(tmp_path), "lift")
    base = r.interface("base")
    t = r.time[:]
    N = base.normal_force[:].sum(axis=1)
    gap = base.gap[:].mean(axis=1)
    block = np.flatnonzero(r.mesh.coordinates[:, 1] > 0.0)
    vy = r.field.v[:, block, 1].mean(axis=1)
    flying = (t > RISE + STOP + DT) & (t < LANDING - 2 * DT)
    assert flying.sum() > 100 and np.all(N[flying] == 0.0) and np.all(gap[flying] > 0)
    free = V - G * (t - RISE)
    flight_error = np.abs(vy[flying] - free[flying]).max() / V
    # where the mean gap closes again after the flight (linear between rows)
    k = np.flatnonzero((t[1:] > RISE + 2 * STOP) & (gap[:-1] > 0) & (gap[1:] <= 0))[0]
    landing = t[k] + DT * gap[k] / (gap[k] - gap[k + 1])
    print("flight velocity error", flight_error, "landing", landing, LANDING,
          "numerical", r.energy["numerical"][-1] / r.energy["external"].max())
    assert flight_error <= 0.02
    # measured 0.9 ms late: the block leaves at 0.494 m/s, not 0.5 (its
    # penalty springs and its own elasticity unload in the first slab)
    assert abs(landing - LANDING) <= 4 * DT
    assert r.energy["numerical"].min() >= -1e-9 * np.abs(r.energy["external"]).max()
