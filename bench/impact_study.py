"""Impact accuracy by mass matrix, formulation and penalty (issue 26's study,
first part): a steel bar (1 m, 100 elements) hits a rigid wall at 1 m/s.
Prints, per variant and Courant number c dt/h, the peak and median contact
force over Z v0 (exact: 1), the rebound velocity error (the bar's mean
velocity after release against -v0) and the energy error after the impact.

    .venv/bin/python bench/impact_study.py
"""

import io
import os
import tempfile

import numpy as np

import vstpetsc

E, RHO, L, V0, GAP = 2e11, 7850.0, 1.0, 1.0, 0.001
C = np.sqrt(E / RHO)
Z = RHO * C


def bar_wall(n, courant, mass, formulation, beta, folder):
    """(peak, plateau, rebound error, energy error) of one variant."""
    dt = courant * L / n / C
    pair = {"pair": ["bar", "wall"], "wall": L + GAP, "formulation": formulation}
    if beta is not None:
        k = beta * E * n / L                      # beta E A / h
        pair["penalty"] = k if formulation == "power" else 2.0 * k / dt
    doc = {"time": {"dt": dt, "end": GAP / V0 + 2.5 * L / C}, "output": {"every": 1},
           "body": [{"name": "bar", "x": [0.0, L], "elements": n, "E": E, "rho": RHO,
                     "v0": V0, "mass": mass}],
           "contact": [pair]}
    r = vstpetsc.run(vstpetsc.Case.from_dict(doc), output=os.path.join(folder, "r.h5"),
                     quiet=True, out=io.StringIO())
    force = r.contact(0).force[:] / (Z * V0)
    bar = r.body("bar")
    mean_v = np.trapz(bar.v[-1], bar.x[:]) / L
    e0 = 0.5 * RHO * L * V0 ** 2
    energy = r.energy["kinetic"][-1] + r.energy["strain"][-1]
    return (force.max(), np.median(force[force > 1e-3]), (-mean_v - V0) / V0,
            (energy - e0) / e0)


def main():
    with tempfile.TemporaryDirectory() as folder:
        for formulation, beta in (("seed", None), ("power", None), ("power", 0.5)):
            for mass in ("consistent", "averaged", "lumped"):
                for courant in (1.0, 0.5, 0.25):
                    peak, plateau, rebound, energy = bar_wall(100, courant, mass, formulation,
                                                              beta, folder)
                    print(f"{formulation:6s} beta={beta} {mass:10s} c dt/h={courant:4.2f} "
                          f"peak {peak:.3f} plateau {plateau:.4f} rebound {rebound:+.4%} "
                          f"energy {energy:+.4%}", flush=True)


if __name__ == "__main__":
    main()
