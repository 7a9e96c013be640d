"""Accuracy by mass matrix, formulation and penalty (issue 26's study,
first part; docs/accuracy.md).

Impact: a steel bar (1 m, 100 elements unless given) hits a rigid wall at
1 m/s; per variant and Courant number c dt/h, the peak and median contact
force over Z v0 (exact: 1), the rebound velocity error (the bar's mean
velocity after release against -v0) and the energy error after the impact.
Standing wave: the clamped-free steel bar started in its first mode (nodal
values exact), the tip displacement's relative L2 error over two periods
against the continuous solution.

    .venv/bin/python studies/impact_study.py [impact|mesh|moved|wave|cost]

``moved``: the defaults (power penalty 0.5 E A / h, averaged mass) and the
same with ``redistribute_mass``, against the mesh and c dt/h.
"""

import io
import os
import sys
import tempfile

import numpy as np

import vstpetsc
from vstpetsc.line import model as model_mod

E, RHO, L, V0, GAP = 2e11, 7850.0, 1.0, 1.0, 0.001
C = np.sqrt(E / RHO)
Z = RHO * C


def bar_wall_case(n, courant, pair=(), body=()):
    """The bar-wall Case at n elements and c dt/h = ``courant``, with the
    extra keys ``pair`` of its [[contact]] and ``body`` of its [[body]]."""
    dt = courant * L / n / C
    return vstpetsc.Case.from_dict({
        "time": {"dt": dt, "end": GAP / V0 + 2.5 * L / C}, "output": {"every": 1},
        "body": [{"name": "bar", "x": [0.0, L], "elements": n, "E": E, "rho": RHO, "v0": V0,
                  **dict(body)}],
        "contact": [{"pair": ["bar", "wall"], "wall": L + GAP, **dict(pair)}]})


def bar_wall(n, courant, mass, formulation, beta, folder, moved=False):
    """(peak, plateau, rebound error, energy error) of one variant
    (``moved``: the contact node's mass moved inward)."""
    pair = {"formulation": formulation}
    if moved:
        pair["redistribute_mass"] = True
    if beta is not None:
        k = beta * E * n / L                      # beta E A / h
        pair["penalty"] = k if formulation == "power" else 2.0 * k / (courant * L / n / C)
    case = bar_wall_case(n, courant, pair, {"mass": mass})
    r = vstpetsc.run(case, output=os.path.join(folder, "r.h5"), quiet=True, out=io.StringIO())
    force = r.contact(0).force[:] / (Z * V0)
    ops = model_mod.build_model(case).ops            # the masses the run used
    momentum = np.sum(model_mod.band_mult(ops.m_diag, ops.m_off, r.body("bar").v[-1]))
    mean_v = float(momentum) / (RHO * L)
    e0 = 0.5 * RHO * L * V0 ** 2
    energy = r.energy["kinetic"][-1] + r.energy["strain"][-1]
    return (force.max(), np.median(force[force > 1e-3]), (-mean_v - V0) / V0,
            (energy - e0) / e0)


def slab_costs(variant, courant, folder, n=100, reps=5):
    """(mean and largest Newton iterations per contact slab, median wall
    time of a contact slab and of a free slab in s, the best of ``reps``
    runs) of bar-wall: the defaults, "moved" (the contact node's mass
    moved inward) or "seed" (the seed penalty with the consistent mass)."""
    pair, body = {"seed": ({"formulation": "seed"}, {"mass": "consistent"}),
                  "moved": ({"redistribute_mass": True}, {})}.get(variant, ({}, {}))
    case = bar_wall_case(n, courant, pair, body)
    contact = free = np.inf
    for _ in range(reps):
        r = vstpetsc.run(case, output=os.path.join(folder, "c.h5"), quiet=True,
                         out=io.StringIO())
        newton = r.solver["newton_iterations"][1:]
        on = r.contact(0).impulse[1:] > 0
        wall = np.diff(r.solver["wall_time"][:])
        contact, free = min(contact, np.median(wall[on])), min(free, np.median(wall[~on]))
    return newton[on].mean(), int(newton.max()), contact, free


def standing_wave(n, mass, courant, folder):
    """The tip's relative L2 error over two periods of the first mode."""
    omega = np.pi * C / (2.0 * L)
    period = 2.0 * np.pi / omega
    slabs = int(round(2.0 * period / (courant * L / n / C)))
    x = np.linspace(0.0, L, n + 1)
    doc = {"time": {"dt": 2.0 * period / slabs, "end": 2.0 * period},
           "body": [{"name": "bar", "x": [0.0, L], "elements": n, "E": E, "rho": RHO,
                     "mass": mass, "u0": [[a, 1e-4 * np.sin(omega * a / C)] for a in x]}],
           "bc": [{"body": "bar", "end": "left", "type": "fixed"}]}
    r = vstpetsc.run(vstpetsc.Case.from_dict(doc), output=os.path.join(folder, "w.h5"),
                     quiet=True, out=io.StringIO())
    exact = 1e-4 * np.cos(omega * r.time[:])
    return np.sqrt(np.mean((r.body("bar").u[:, -1] - exact) ** 2) / np.mean(exact ** 2))


def main(part):
    with tempfile.TemporaryDirectory() as folder:
        if part == "wave":
            for mass in ("consistent", "averaged", "lumped"):
                for n in (10, 20, 40):
                    for courant in (1.0, 0.25, 0.0625):
                        error = standing_wave(n, mass, courant, folder)
                        print(f"wave {mass:10s} elements {n:3d} c dt/h={courant:6.4f} "
                              f"tip L2 {error:.2e}", flush=True)
            return
        if part == "cost":
            for variant in ("defaults", "moved", "seed"):
                for courant in (1.0, 0.5):
                    mean, most, contact, free = slab_costs(variant, courant, folder)
                    print(f"{variant:8s} c dt/h={courant:4.2f} Newton per contact slab "
                          f"{mean:.2f} (max {most}), contact slab {1e6 * contact:.0f} us, "
                          f"free slab {1e6 * free:.0f} us", flush=True)
            return
        if part == "moved":          # the defaults, and with the contact node's mass moved
            for moved in (False, True):
                for courant in (1.0, 0.5, 0.25):
                    for n in (50, 100, 200, 400):
                        peak, plateau, rebound, energy = bar_wall(
                            n, courant, "averaged", "power", None, folder, moved=moved)
                        print(f"defaults{' mass moved' if moved else ''} c dt/h={courant:4.2f} "
                              f"elements {n} peak {peak:.3f} rebound {rebound:+.4%} "
                              f"energy {energy:+.4%}", flush=True)
            return
        if part == "mesh":
            for beta in (0.25, 0.5, 1.0):
                for n in (50, 100, 200, 400):
                    peak, plateau, rebound, energy = bar_wall(n, 1.0, "averaged", "power",
                                                              beta, folder)
                    print(f"power averaged beta={beta} elements {n} peak {peak:.3f} "
                          f"rebound {rebound:+.4%} energy {energy:+.4%}", flush=True)
            return
        for formulation, beta in (("seed", None), ("power", 50.0), ("power", 0.5)):
            for mass in ("consistent", "averaged", "lumped"):
                for courant in (1.0, 0.5, 0.25):
                    peak, plateau, rebound, energy = bar_wall(100, courant, mass, formulation,
                                                              beta, folder)
                    print(f"{formulation:6s} beta={beta} {mass:10s} c dt/h={courant:4.2f} "
                          f"peak {peak:.3f} plateau {plateau:.4f} rebound {rebound:+.4%} "
                          f"energy {energy:+.4%}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "impact")
