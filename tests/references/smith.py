"""The peer for pile driving: the classical lumped-mass wave-equation
algorithm of Smith (1960), explicit, the engine of the usual pile-driving
programs, written here from its published recurrence:

    D_m(t) = D_m(t - dt) + V_m(t - dt) dt                displacements
    C_m = D_m - D_{m+1}, F_m = K_m C_m                     springs (the cushion: no
                                                           tension, unloading K / e^2)
    R_m = static (elastic-plastic, quake q, slip D'_m) + damping,  soil
    V_m(t) = V_m(t - dt) + (F_{m-1} - F_m - R_m) dt / M_m  velocities

Masses: the ram and the pile cut into segments of length dx, each lumped
at one point; the soil acts on the pile's masses (the shaft share by
length, the toe on the last mass); damping R_s J |v| with v the previous
velocity (Smith's explicit choice), written as in vstpetsc (R_s + J |R_s| v,
the toe's total clipped at 0).  dt = ``courant`` dx / c.

It reads the blow from a vstpetsc Case (its bodies, soil and cushion) and
imports nothing of vstpetsc.  Used by tests/test_examples.py (the bundled
`pile`) and the pile benchmarks (bench/pile_blow.py, bench/pile_speed.py).
"""

import time

import numpy as np


def setup(case, segments):
    """Masses, springs and soil of a vstpetsc pile Case (a ram body, a pile
    body with one [[soil]], a cushion between them) with the pile cut into
    ``segments`` and the ram into proportionally many (at least 2)."""
    ram, pile = case.bodies
    soil, cushion = case.soils[0], case.contacts[0].params
    parts, masses, springs = [], [], []
    for body, n in ((ram, max(2, round(segments * (ram.x[1] - ram.x[0])
                                       / (pile.x[1] - pile.x[0])))), (pile, segments)):
        x0, x1 = body.x
        dx = (x1 - x0) / n
        E, rho, A = (float(h(0.5 * (x0 + x1))) for h in (body.E, body.rho, body.area))
        parts.append((len(masses), n, dx, np.sqrt(E / rho)))
        masses += [rho * A * dx] * n
        springs += [E * A / dx] * (n - 1) + [None]
    head = parts[1][0]
    springs[head - 1] = cushion["stiffness"]          # the ram's last mass on the pile head
    return {"M": np.array(masses), "K": np.array(springs[:-1], dtype=float), "head": head,
            "cushion": (head - 1, cushion["stiffness"], cushion["restitution"]),
            "soil": _soil(soil, head, segments, pile), "dx": min(p[2] for p in parts),
            "c": max(p[3] for p in parts), "v0": float(ram.v0(ram.x[0])),
            "area": float(pile.area(pile.x[0])), "E": float(pile.E(pile.x[0]))}


def _soil(soil, head, n, pile):
    """(R_u, k, J, toe) per mass (arrays over every mass; 0 off the pile)."""
    Ru = np.zeros(head + n)
    shaft_ru = (1.0 - soil.toe_share) * soil.capacity
    x0, x1 = pile.x
    edges = np.linspace(x0, x1, n + 1)
    inside = np.clip(np.minimum(edges[1:], soil.shaft["to"])
                     - np.maximum(edges[:-1], soil.shaft["from"]), 0.0, None)
    Ru[head:] = shaft_ru * inside / inside.sum()
    q = np.full(head + n, soil.shaft["quake"])
    J = np.full(head + n, soil.shaft["damping"])
    toe = head + n - 1
    return {"Ru": Ru, "q": q, "J": J, "toe": (toe, soil.toe_share * soil.capacity,
                                               soil.toe["quake"], soil.toe["damping"])}


def run(case, segments, end, courant=0.5):
    """Integrate one blow to time ``end``: set, largest compressive and
    tensile pile stresses, energy transferred at the head, wall time."""
    s = setup(case, segments)
    M, K, head = s["M"], s["K"], s["head"]
    ic, kc, e = s["cushion"]
    soil = s["soil"]
    toe, toe_ru, toe_q, toe_j = soil["toe"]
    dt = courant * s["dx"] / s["c"]
    D, V = np.zeros(M.size), np.zeros(M.size)
    V[:head] = s["v0"]
    slip, toe_slip, cmax = np.zeros(M.size), 0.0, 0.0
    lo = hi = transferred = 0.0
    start = time.perf_counter()
    for _ in range(int(round(end / dt))):
        D += V * dt
        C = D[:-1] - D[1:]
        F = K * C
        cmax = max(cmax, C[ic]) if C[ic] > 0.0 else 0.0      # apart: the next contact is fresh
        F[ic] = 0.0 if C[ic] <= 0.0 else max(0.0, kc * cmax - kc / e ** 2 * (cmax - C[ic]))
        R, slip, toe_slip = _resistance(D, V, slip, toe_slip, soil, toe, toe_ru, toe_q, toe_j)
        net = np.zeros(M.size)
        net[1:] += F
        net[:-1] -= F
        V += (net - R) * dt / M
        transferred += F[ic] * V[head] * dt
        stress = F[head:] / s["area"]                     # compression positive here
        lo, hi = min(lo, -stress.max(initial=0.0)), max(hi, -stress.min(initial=0.0))
    return {"set": toe_slip, "stress_min": lo, "stress_max": hi, "transferred": transferred,
            "wall": time.perf_counter() - start, "dt": dt, "steps": int(round(end / dt))}


def _resistance(D, V, slip, toe_slip, soil, toe, toe_ru, toe_q, toe_j):
    """Smith's soil on every mass at displacements D (previous velocities V)."""
    Ru, q, J = soil["Ru"], soil["q"], soil["J"]
    k = np.divide(Ru, q)
    slip = np.clip(slip, D - q, D + q)                  # plastic flow moves the slip
    Rs = k * (D - slip)
    R = Rs + J * np.abs(Rs) * V
    # the toe: compression only, its own quake and damping
    toe_slip = max(toe_slip, D[toe] - toe_q)
    Rs_toe = min(max(toe_ru / toe_q * (D[toe] - toe_slip), 0.0), toe_ru) if toe_ru else 0.0
    R[toe] += max(0.0, Rs_toe * (1.0 + toe_j * V[toe]))
    return R, slip, toe_slip
