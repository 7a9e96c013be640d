"""A body's soil profile given layer by layer (docs/shear.md section 7):

    layers = [ { thickness = 5.0, Vs = 180.0, rho = 1800.0 }, ... ]

listed from the body's left end in x (as every table of a case file), the
thicknesses summing to the body's length.  Each layer is a uniform material
meshed with its own equal elements, so a node falls on every layer
boundary; the body's ``elements`` (the total) is shared among the layers
that give no ``elements`` of their own by travel time (thickness / V, V the
layer's slowest wave speed), at least one each.  G = rho Vs^2 per layer
(the shear component); the axial field takes E = rho Vp^2 or ``E`` of every
layer when given, else E := G (a pure shear column: its axial field then
carries waves at Vs).  Nothing here imports PETSc.
"""

from dataclasses import dataclass

import numpy as np

from vstpetsc.input.checker import MAGNITUDE
from vstpetsc.spacetime.history import History

KEYS = ("thickness", "Vs", "rho", "E", "Vp", "elements")
BODY_MATERIAL = ("E", "rho", "G", "Vs")   # the body's own keys that layers replace
RELATIVE_MISMATCH = 1e-9                   # of the body's length, for the thicknesses' sum


@dataclass
class Profile:
    """A body's layered material: E, rho and G as step profiles along x,
    and ``cells``, ((x_left, x_right, elements), ...) per layer."""

    E: History
    rho: History
    G: History
    cells: tuple


def read(chk, tbl, where, x, elements):
    """The :class:`Profile` of a body's ``layers``, or None after
    reporting; ``x`` and ``elements`` are the body's (None when bad)."""
    clash = [k for k in BODY_MATERIAL if k in tbl]
    if clash:
        chk.add(f"{where}.{clash[0]}", "not with layers (give it per layer)")
        return None
    rows = tbl["layers"]
    if not isinstance(rows, list) or not rows or not all(isinstance(r, dict) for r in rows):
        chk.add(f"{where}.layers", "must be a non-empty array of tables "
                "[{ thickness = ..., Vs = ..., rho = ... }, ...]")
        return None
    layers = [_layer(chk, row, f"{where}.layers[{i}]") for i, row in enumerate(rows)]
    if None in layers or not _axial_everywhere(chk, rows, where) or None in (x, elements):
        return None
    edges = _edges(chk, where, x, [lay["thickness"] for lay in layers])
    counts = _counts(chk, where, elements, layers)
    if edges is None or counts is None:
        return None
    cells = tuple((float(a), float(b), int(n)) for a, b, n in zip(edges, edges[1:], counts))
    step = lambda key: _steps(edges, [lay[key] for lay in layers])
    E = step("E") if layers[0]["E"] is not None else step("G")
    return Profile(E, step("rho"), step("G"), cells)


def _layer(chk, row, where):
    """{thickness, rho, G, E (or None), speed, elements (or None)} of one
    layer, or None after reporting."""
    chk.unknown(row, KEYS, where)
    if "E" in row and "Vp" in row:
        chk.add(f"{where}.Vp", "give E or Vp (E = rho Vp^2), not both")
        return None
    thickness, Vs, rho = (chk.number(row, k, where, positive=True) for k in KEYS[:3])
    E = chk.number(row, "E", where, positive=True) if "E" in row else None
    Vp = chk.number(row, "Vp", where, positive=True) if "Vp" in row else None
    n = chk.integer(row, "elements", where) if "elements" in row else None
    if None in (thickness, Vs, rho) or (E is None and "E" in row) or \
            (Vp is None and "Vp" in row) or (n is None and "elements" in row) or \
            set(row) - set(KEYS):
        return None
    G = _modulus(chk, f"{where}.Vs", rho, Vs)
    if Vp is not None:
        E = _modulus(chk, f"{where}.Vp", rho, Vp)
    if G is None or (E is None and Vp is not None):
        return None
    slowest = Vs if E is None else min(Vs, (E / rho) ** 0.5)
    return {"thickness": thickness, "rho": rho, "G": G, "E": E,
            "time": thickness / slowest, "elements": n}


def _modulus(chk, name, rho, speed):
    """rho speed^2, or None after reporting one that is not a normal double."""
    value = rho * speed ** 2
    if not MAGNITUDE[0] <= value <= MAGNITUDE[1]:
        chk.add(name, f"rho {name.rsplit('.', 1)[1]}^2 = {value:g} must lie in "
                f"{MAGNITUDE[0]:g} .. {MAGNITUDE[1]:g}")
        return None
    return value


def _axial_everywhere(chk, rows, where):
    """Whether every layer or none gives its axial material (E or Vp)."""
    given = ["E" in r or "Vp" in r for r in rows]
    if any(given) and not all(given):
        i = given.index(False)
        chk.add(f"{where}.layers[{i}]", "gives neither E nor Vp while layer "
                f"{given.index(True)} does (give it on every layer or on none)")
        return False
    return True


def _edges(chk, where, x, thicknesses):
    """The layer boundaries from x[0]; the last one is x[1] itself."""
    length = x[1] - x[0]
    edges = x[0] + np.concatenate(([0.0], np.cumsum(thicknesses)))
    if abs(edges[-1] - x[1]) > RELATIVE_MISMATCH * length:
        chk.add(f"{where}.layers", f"the thicknesses sum to {edges[-1] - x[0]:.12g}; "
                f"the body's x = [{x[0]:g}, {x[1]:g}] has length {length:.12g}")
        return None
    edges[-1] = x[1]
    thin = np.flatnonzero(np.diff(edges) <= 0)
    if thin.size:
        chk.add(f"{where}.layers[{thin[0]}].thickness", "too thin to place at the body's "
                "coordinates (rounds to no length)")
        return None
    return edges


def _counts(chk, where, elements, layers):
    """Elements per layer: a layer's own, the rest of the body's shared
    among the others (:func:`share`)."""
    own = [lay["elements"] for lay in layers]
    free = [i for i, n in enumerate(own) if n is None]
    rest = elements - sum(n for n in own if n is not None)
    if rest != 0 and not free:
        chk.add(f"{where}.elements", f"the layers' elements sum to {elements - rest}, "
                f"not {elements}")
        return None
    if rest < len(free):
        chk.add(f"{where}.elements", f"{elements} is too few: the layers' own elements "
                f"take {elements - rest} and each of the {len(free)} other layers needs one")
        return None
    counts = np.array([0 if n is None else n for n in own])
    if free:
        counts[free] = share(rest, np.array([layers[i]["time"] for i in free]))
    return counts


def share(total, times):
    """``total`` elements over layers of travel times ``times``: in
    proportion, at least one each, the remainder to the layers whose
    elements take longest to cross (the largest time per element)."""
    n = np.maximum(1, np.floor(total * times / times.sum())).astype(int)
    while n.sum() > total:          # only after the minimum of one raised some
        spare = np.where(n > 1, times / np.maximum(n - 1, 1), np.inf)
        n[np.argmin(spare)] -= 1
    while n.sum() < total:
        n[np.argmax(times / n)] += 1
    return n


def _steps(edges, values):
    """A History constant on each layer: a step at every inner boundary."""
    rows = [[edge, v] for a, b, v in zip(edges, edges[1:], values) for edge in (a, b)]
    return History(rows)


def node_coordinates(x, elements, cells):
    """A body's nodes: equal elements over x, or each layer's own."""
    if not cells:
        return np.linspace(x[0], x[1], elements + 1)
    parts = [np.linspace(a, b, n + 1)[:-1] for a, b, n in cells]
    return np.concatenate(parts + [[x[1]]])
