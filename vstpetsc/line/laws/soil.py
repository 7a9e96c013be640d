"""Smith soil on a body ([[soil]], docs/pile-driving.md): a nonlinear law
per soil node (:class:`SoilNode`, its slab integrals in
:mod:`vstpetsc.kernels.smith`) and one law that reports the table's totals
(:class:`SoilReport`, the result group ``/soil/<k>``).

A shaft node's share of the shaft capacity (1 - toe_share) R_u is the part
of its tributary length inside [from, to]; the toe node (the body's end
``toe.end``, which moves into the ground) takes toe_share R_u.  "Into the
ground" is +x for a toe at the right end, -x at the left.
"""

import math
from dataclasses import dataclass

import numpy as np

from vstpetsc.line.laws.base import Law
from vstpetsc.kernels.gap import closed_somewhere
from vstpetsc.kernels.smith import smith_integrals

KEYS = ("body", "capacity", "toe_share", "shaft", "toe")
SHAFT_KEYS = ("quake", "damping", "from", "to")
TOE_KEYS = ("quake", "damping", "end")


@dataclass
class SoilSpec:
    """A [[soil]] table, validated (body number, forces, lengths, times per length)."""

    body: int
    capacity: float
    toe_share: float
    shaft: dict
    toe: dict


def read(chk, tbl, where, bodies, names):
    """A SoilSpec, or None after reporting."""
    chk.unknown(tbl, KEYS, where)
    name = chk.string(tbl, "body", where)
    if name is not None and name not in names:
        chk.add(f"{where}.body", f"unknown body {name!r} (bodies: {', '.join(names) or 'none'})")
        name = None
    capacity = chk.number(tbl, "capacity", where, minimum=0.0)
    share = chk.number(tbl, "toe_share", where, minimum=0.0, maximum=1.0)
    body = None if name is None else bodies[names[name]]
    # a part is needed when it carries some of the capacity
    shaft = _part(chk, tbl, "shaft", where, SHAFT_KEYS, share is not None and share < 1.0)
    toe = _part(chk, tbl, "toe", where, TOE_KEYS, share is not None and share > 0.0)
    if toe is not None and "toe" in tbl:
        toe["end"] = chk.string(tbl["toe"], "end", f"{where}.toe", required=False,
                                default="right", choices=("left", "right"))
    if shaft is not None and body is not None and "shaft" in tbl:
        lo = chk.number(tbl["shaft"], "from", f"{where}.shaft", required=False,
                        default=body.x[0])
        hi = chk.number(tbl["shaft"], "to", f"{where}.shaft", required=False,
                        default=body.x[1])
        if None not in (lo, hi) and not body.x[0] <= lo < hi <= body.x[1]:
            chk.add(f"{where}.shaft", f"from = {lo:g}, to = {hi:g} must satisfy "
                    f"{body.x[0]:g} <= from < to <= {body.x[1]:g} (body {name!r})")
            lo = None
        shaft.update({"from": lo, "to": hi})
    elif shaft is not None and body is not None:
        shaft.update({"from": body.x[0], "to": body.x[1]})
    if toe is not None:
        toe.setdefault("end", "right")
    parts = (body, capacity, share, shaft, toe)
    if any(v is None for v in parts) or None in shaft.values() or None in toe.values():
        return None
    return SoilSpec(names[name], capacity, share, shaft, toe)


def _part(chk, tbl, key, where, keys, needed):
    """{quake, damping} of the inline table ``key``: quake > 0 (length),
    damping J >= 0 (time per length); an unused part may be left out."""
    if key not in tbl and not needed:
        return {"quake": 1.0, "damping": 0.0}
    sub = chk.table(tbl, key, f"{where}.{key}", required=True)
    if not isinstance(tbl.get(key), dict):
        return None                     # reported
    chk.unknown(sub, keys, f"{where}.{key}")
    # a part that carries no capacity may give only its range or its end
    return {"quake": chk.number(sub, "quake", f"{where}.{key}", positive=True,
                                required=needed, default=1.0),
            "damping": chk.number(sub, "damping", f"{where}.{key}", required=False,
                                  default=0.0, minimum=0.0)}


def shaft_shares(x, lo, hi):
    """Each node's tributary length inside [lo, hi] over the total (the
    nodes ``x`` of one body)."""
    mid = np.concatenate([[x[0]], 0.5 * (x[1:] + x[:-1]), [x[-1]]])
    inside = np.clip(np.minimum(mid[1:], hi) - np.maximum(mid[:-1], lo), 0.0, None)
    return inside / inside.sum()


class SoilNode(Law):
    """The Smith resistance on one node: capacity ``Ru``, quake ``q``,
    damping ``J``; ``toe`` resists only motion into the ground."""

    energy_key = "soil"

    def __init__(self, node, direction, Ru, q, J, toe, dt):
        self.nodes, self.signs = np.array([node]), np.array([direction])
        self.Ru, self.k, self.J, self.toe, self.dt = Ru, Ru / q, J, toe, dt
        self.p = 0.0                   # plastic slip into the ground
        self.tally = [0.0]             # energy its table's nodes took (shared, see SoilReport)
        self.impulse = 0.0
        self.last = None
        self.where = "soil"             # the table, for messages (set by build)
        self.report = None              # its table's SoilReport (set by it)

    def start_slab(self, u, dt):
        self.wn = float(self.signs[0] * u[0])

    def acts(self, y1, y2):
        if not self.toe:
            return self.wn != self.p or y1 != 0.0 or y2 != 0.0
        # the toe presses where w - p > 0: where the "gap" p - w is negative
        return closed_somewhere(self.p - self.wn, -self.dt * y1, -0.5 * self.dt * (y2 - y1))

    def force(self, y1, y2):
        out = smith_integrals(self.wn, self.p, y1, y2, self.dt, self.k, self.Ru, self.J,
                              self.toe)
        self.last = None if out is None else (out, y1, y2)
        return None if out is None else out[:6]

    @staticmethod
    def force_batch(laws, y1, y2):
        """``[law.force(y1[i], y2[i])]`` for many soil nodes at once: the
        nodes whose slab is one smooth piece (no turn, no yield, no sign
        change of R_s, the toe's damping factor positive) in numpy, the
        others one by one (docs/pile-driving.md)."""
        y1, y2 = np.asarray(y1, dtype=float), np.asarray(y2, dtype=float)
        par = _batch_params(laws)
        simple, out = _smooth_slabs(par, y1, y2)
        results = [None] * len(laws)
        for i, law in enumerate(laws):
            if simple[i]:
                row = out[i]
                law.last = ((*row, law.p), float(y1[i]), float(y2[i]))
                results[i] = row
            else:
                results[i] = law.force(float(y1[i]), float(y2[i]))
        return results

    def static(self, u):
        """(residual, tangent) of the static resistance at displacement u
        (elastic about the slip, clipped at the capacity; the slip itself
        is not moved: a static state needs the soil elastic)."""
        s = self.signs[0]
        Rs = self.k * (s * u[0] - self.p)
        lo = 0.0 if self.toe else -self.Ru
        clipped = min(max(Rs, lo), self.Ru)
        return np.array([s * clipped]), np.array([[self.k * (clipped == Rs)]])

    def static_limit(self, u):
        """A line when the node's static resistance is at its capacity."""
        Rs = self.k * (self.signs[0] * u[0] - self.p)
        if Rs < self.Ru and (self.toe or Rs > -self.Ru):
            return None
        return (f"{self.where}.capacity: the soil cannot carry the static load: it yields "
                f"at node {int(self.nodes[0])} (capacity {self.Ru:.6g} there); a static "
                "start needs the soil elastic, so the capacity must exceed the pile's "
                "share of the static load with a margin")

    def finish_slab(self, t0, dt):
        if self.last is None:
            self.impulse = 0.0
            return
        out, y1, y2 = self.last
        self.impulse = out[0] + out[1]
        self.tally[0] += out[0] * y1 + out[1] * y2
        self.p = out[6]


class SoilReport(Law):
    """The totals of soil table ``index``: group ``/soil/<index>``."""

    series = ("toe_force", "shaft_force", "energy", "toe_slip", "slip")

    def __init__(self, index, shaft, toe, dt):
        self.index, self.group = index, f"soil/{index}"
        self.shaft, self.toe, self.dt = shaft, toe, dt
        self.nodes_all = shaft + ([toe] if toe else [])
        if not self.nodes_all:          # capacity 0: no soil nodes, no slips to keep
            self.series = tuple(k for k in SoilReport.series if k != "slip")
        # one running sum, added to node by node in a fixed order, so that
        # a restart continues it bit for bit
        self.tally = [0.0]
        for node in self.nodes_all:
            node.tally, node.report = self.tally, self
        # a compiled path keeping the nodes' state in arrays writes it back
        # to them before a read (native/smith_slab.py SmithBank)
        self.before_read = None

    def series_shape(self, key):
        return (len(self.nodes_all),) if key == "slip" else ()

    def values(self, u):
        if self.before_read is not None:
            self.before_read()
        return {"toe_force": self.toe.impulse / self.dt if self.toe else 0.0,
                "shaft_force": sum(n.impulse for n in self.shaft) / self.dt,
                "energy": self.tally[0],
                "toe_slip": self.toe.p if self.toe else 0.0,
                "slip": np.array([n.p for n in self.nodes_all])}

    def restore(self, values):
        for n, p in zip(self.nodes_all, np.atleast_1d(values.get("slip", []))):
            n.p = float(p)
        self.tally[0] = float(values["energy"])

    def final_attrs(self):
        """``set`` (the toe's plastic slip: the blow's permanent set) and
        ``blow_count`` (1 / set; inf at refusal)."""
        if self.before_read is not None:
            self.before_read()
        s = self.toe.p if self.toe else 0.0
        return {"set": s, "blow_count": 1.0 / s if s > 0.0 else math.inf}

    def attrs(self):
        return {"nodes": len(self.nodes_all), "toe": int(self.toe is not None)}

    def describe(self):
        return (f"soil[{self.index}]: {len(self.shaft)} shaft nodes"
                + (", a toe" if self.toe else ""))


def build(spec, index, case, mesh):
    """The node laws of one [[soil]] table and its report (the report last)."""
    b = spec.body
    nodes = np.arange(mesh.nodes(b).start, mesh.nodes(b).stop)
    toe_end = spec.toe["end"]
    direction = 1.0 if toe_end == "right" else -1.0
    shaft_ru = (1.0 - spec.toe_share) * spec.capacity
    shares = shaft_shares(mesh.x[nodes], spec.shaft["from"], spec.shaft["to"])
    shaft = [SoilNode(int(n), direction, shaft_ru * s, spec.shaft["quake"],
                      spec.shaft["damping"], False, case.dt)
             for n, s in zip(nodes, shares) if shaft_ru * s > 0.0]
    toe_ru = spec.toe_share * spec.capacity
    toe = None
    if toe_ru > 0.0:
        toe = SoilNode(mesh.end_node(b, toe_end), direction, toe_ru, spec.toe["quake"],
                       spec.toe["damping"], True, case.dt)
    report = SoilReport(index, shaft, toe, case.dt)
    for node in report.nodes_all:
        node.where = f"soil[{index}]"
    return shaft + ([toe] if toe else []) + [report]


def mark_head(laws, spec, mesh):
    """Mark the contact pair at the pile's head (the end opposite its toe)
    so that its work on the pile is reported as ``/energy/transferred``."""
    head = mesh.end_node(spec.body, "left" if spec.toe["end"] == "right" else "right")
    for law in laws:
        if law.group and law.group.startswith("contact/") and head in law.nodes:
            law.transfer_node = int(np.flatnonzero(law.nodes == head)[0])


_GAUSS = np.array([(0.5 - 0.5 * np.sqrt(0.6), 5.0 / 18.0), (0.5, 8.0 / 18.0),
                   (0.5 + 0.5 * np.sqrt(0.6), 5.0 / 18.0)])


def _batch_params(laws):
    """(wn, p, k, q, J, toe, dt) of the laws as arrays."""
    return (np.array([law.wn for law in laws]), np.array([law.p for law in laws]),
            np.array([law.k for law in laws]), np.array([law.Ru / law.k for law in laws]),
            np.array([law.J for law in laws]), np.array([law.toe for law in laws]),
            laws[0].dt)


def _smooth_slabs(par, y1, y2):
    """(mask of the nodes whose slab is one smooth elastic piece, their
    (f1, f2, J11, J12, J21, J22) as rows): the scalar kernel's Gauss rule
    on [0, 1], over all nodes at once."""
    wn, p, k, q, J, toe, dt = par
    b1, b2 = dt * y1, 0.5 * dt * (y2 - y1)
    e0, e1 = wn - p, wn - p + b1 + b2                    # w - p at the slab's ends
    with np.errstate(divide="ignore", invalid="ignore"):
        vertex = np.where(b2 != 0.0, -b1 / (2.0 * b2), -1.0)
    sign = np.where(e0 > 0.0, 1.0, -1.0)
    factor0, factor1 = 1.0 + J * y1, 1.0 + J * y2
    simple = (~((vertex > 0.0) & (vertex < 1.0)) & (e0 * e1 > 0.0)
              & (np.abs(e0) < q * (1.0 - 1e-12)) & (np.abs(e1) < q * (1.0 - 1e-12))
              & (~toe | ((e0 > 0.0) & (factor0 > 0.0) & (factor1 > 0.0))))
    sign = np.where(toe, 1.0, sign)
    t, weight = _GAUSS[:, 0], _GAUSS[:, 1]
    e = e0[:, None] + t * (b1[:, None] + t * b2[:, None])            # (n, 3)
    v = y1[:, None] + (y2 - y1)[:, None] * t
    fac = 1.0 + (J * sign)[:, None] * v
    R = k[:, None] * e * fac
    half = 0.5 * t * t
    dR = [k[:, None] * dt * I * fac + (k * J * sign)[:, None] * e * T
          for I, T in (((t - half), 1.0 - t), (half, t))]
    w = dt * weight
    out = np.empty((y1.size, 6))
    for a, T in enumerate((1.0 - t, t)):
        out[:, a] = (R * T) @ w
        out[:, 2 + 2 * a] = (dR[0] * T) @ w
        out[:, 3 + 2 * a] = (dR[1] * T) @ w
    return simple, out.tolist()
