"""What every contact law shares: a pair of facing ends (or an end and a
rigid wall), its gap, the running contact totals and the result group
``/contact/<k>``.  A formulation (penalty.py, ...) adds the force law."""

import math

import numpy as np

from vstpetsc.line.laws.base import Law

# running totals over every slab (exact whatever `every` is)
TOTALS = ("impulse_total", "contact_time", "episodes", "force_peak", "first_contact",
          "event_count")
WALL = "wall"


class PairLaw(Law):
    """Pair ``index`` of the case: nodes ``n_k`` with signs ``c_k`` (+1 for
    the body on the left of the gap, -1 for the one on its right; a wall
    pair has one node), initial gap ``g0``."""

    series = ("gap", "force", "impulse") + TOTALS

    def __init__(self, spec, index, case, mesh):
        nodes, signs = [], []
        if spec.left is not None:
            nodes.append(mesh.right_node(spec.left))
            signs.append(1.0)
        if spec.right is not None:
            nodes.append(mesh.left_node(spec.right))
            signs.append(-1.0)
        self.nodes, self.signs = np.array(nodes), np.array(signs)
        self._terms = list(zip(nodes, signs))
        bodies = case.bodies
        if spec.left is None:
            self.g0 = bodies[spec.right].x[0] - spec.wall
        elif spec.right is None:
            self.g0 = spec.wall - bodies[spec.left].x[1]
        else:
            self.g0 = bodies[spec.right].x[0] - bodies[spec.left].x[1]
        self.names = tuple(WALL if b is None else bodies[b].name
                           for b in (spec.left, spec.right))
        self.wall = spec.wall
        self.index, self.group = index, f"contact/{index}"
        self.formulation = spec.formulation
        self.dt = case.dt
        self.impulse = 0.0
        self.totals = dict.fromkeys(TOTALS, 0.0)
        self.totals["first_contact"] = np.nan
        self.on = False
        self.closed = False     # whether the pair is closed at the end of the last slab
        self.events = []        # [(t, +1 close / -1 open)] not yet taken by the recorder

    def start_slab(self, u, dt):
        """Gap at t^n from the displacements of the pair's nodes."""
        self.gn = float(self.g0 - self.signs @ u)

    def add_impulse(self, impulse, t0, dt):
        """Record the slab's impulse in the running totals."""
        self.impulse = impulse
        on = impulse > 0
        if not on and not self.on:          # nothing changes (most slabs)
            return
        t = self.totals
        t["episodes"] += on and not self.on
        self.on = on
        t["impulse_total"] += impulse
        t["contact_time"] += dt * on
        t["force_peak"] = max(t["force_peak"], impulse / dt)
        if on and math.isnan(t["first_contact"]):
            t["first_contact"] = t0

    def track(self, t0, dt, intervals):
        """Events of the slab [t0, t0 + dt] from the ordered pieces
        [(p, q)] of [0, 1] where the pair acts: a close at p, an open at q
        inside the slab; a piece reaching a slab end continues the state
        across it (no open and close at the boundary while in contact), and
        an open followed by a close within the slab is no event."""
        events, before = self.events, len(self.events)
        self._track(t0, dt, intervals)
        _drop_openings_within(events, before)
        # the count of events with every kept row: a restart cuts the
        # events dataset there (a block killed midway may hold later ones)
        self.totals["event_count"] += len(events) - before

    def _track(self, t0, dt, intervals):
        closed, events = self.closed, self.events
        if not intervals:
            if closed:              # it acted up to the end of the last slab
                events.append((t0, -1.0))
                self.closed = False
            return
        for p, q in intervals:
            if closed and p > 0.0:  # (rounding) the gap opened at the slab's start
                events.append((t0, -1.0))
                closed = False
            if not closed:
                events.append((t0 + p * dt, 1.0))
            closed = q == 1.0
            if not closed:
                events.append((t0 + q * dt, -1.0))
        self.closed = closed

    def take_events(self):
        """The events since the last call, as an (m, 2) array."""
        out = np.array(self.events, dtype=np.float64).reshape(-1, 2)
        self.events = []
        return out

    def gap(self, u):
        """Gap for the displacements ``u`` of all nodes (the signs are +-1,
        so the products are exact and the sum rounds once)."""
        terms = self._terms
        if len(terms) == 1:
            (n, s), = terms
            return self.g0 - s * u[n]
        (n0, s0), (n1, s1) = terms
        return self.g0 - (s0 * u[n0] + s1 * u[n1])

    def static(self, u):
        """(residual (n,), tangent (n, n)) of the pair as a spring of the
        formulation's ``static_stiffness``, for the displacements u of its
        nodes; a closed gap (g <= 0) is active."""
        g = self.g0 - self.signs @ u
        k = self.static_stiffness
        res = -self.signs * k * min(0.0, g)
        tangent = np.outer(self.signs, self.signs) * k * (g <= 0.0)
        return res, tangent

    def stored_energy(self, u):
        """1/2 k min(0, g)^2 for the displacements u of all nodes."""
        return 0.5 * self.static_stiffness * min(0.0, self.gap(u)) ** 2

    def values(self, u):
        return {"gap": self.gap(u), "impulse": self.impulse,
                "force": self.impulse / self.dt, **self.totals}

    def restore(self, values):
        self.totals = {k: float(values[k]) for k in TOTALS}
        self.on = values["impulse"] > 0
        self.closed = bool(values.get("closed", False))

    def attrs(self):
        return {"pair": ",".join(self.names), "formulation": self.formulation,
                "initial_gap": self.g0, "wall": np.nan if self.wall is None else self.wall}

    def describe(self):
        return f"contact[{self.index}] {self.names[0]} | {self.names[1]}: gap {self.g0:g}"


def _drop_openings_within(events, start):
    """Remove from ``events[start:]`` (one slab's, alternating) every open
    followed by a close: the pair is in contact on both sides of such an
    opening and passes force in its slab.  The seed formulation's fixed
    point at rest moves the contact node inside each slab and its gap
    opens for part of every slab (an open and a close per slab), as it does
    within nearly every slab of an impact: none of it changes the pair's
    state across a slab end (docs/contact-formulations.md).  A close
    followed by an open inside a slab (a touch shorter than the slab)
    stays: an impulse passed."""
    kept = []
    for event in events[start:]:
        if event[1] > 0 and kept and kept[-1][1] < 0:
            kept.pop()
        else:
            kept.append(event)
    events[start:] = kept
