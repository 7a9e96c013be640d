"""The generated dam cross-section (interface.md, "Plane strain (2-D)",
``[mesh] dam = {...}``): a dam of height H on a rectangular foundation,
conforming along their contact, and optionally its reservoir's water as
a third region, conforming with both.

Geometry (y up, the foundation's top at y = 0): the foundation
[-W/2, W/2] x [-D, 0]; the dam between its upstream face (left) and its
downstream face (right), from its base [x_a, x_b] at y = 0 to its crest
at y = H.  A face is a slope (horizontal : vertical, a straight face) or
a polyline: [x, y] points, y rising strictly from 0 (the heel or the toe)
to H (the crest's corner).  Two slopes: the crest [-crest/2, crest/2]
centred on x = 0, x_a = -(crest/2 + upstream H), x_b = crest/2 +
downstream H (the trapezoid).  One polyline: the slope's crest corner
``crest`` from the polyline's.  Two polylines: the crest is theirs
(``crest``, if given, must agree).

The reservoir ``{level, length}``: water from the upstream face out to
x_far = x_a - length, from the foundation's top (y = 0) up to y = level
(0 < level <= H).

Cells of about ``h``: the foundation in quadrilaterals on a grid whose
columns meet the dam's base corners (and x_far); the dam in triangles,
row by row: the rows' heights hold the faces' breaks and the level
exactly, rows about h apart between them; each row from face to face,
its nodes about h apart (so cells stay near h as the section narrows);
two rows joined by walking both at once in the order of their nodes' x
(each step one triangle).  The water row by row at the dam's row heights
up to the level, each row from x_far to the face, its nodes about h
apart, its last node the dam's row's first, its bottom row the
foundation's top from x_far to the heel; two rows joined by
quadrilaterals where their x's agree (beside a vertical face), else by
triangles as in the dam.

Regions "dam", "foundation" (and "water").  Curves "base", "left",
"right" (the foundation's), "faces" (the dam's faces and crest and the
foundation's top beside it), "contact" (the dam's base), and the parts of
"faces" each alone (their edges also in "faces"): "upstream" and
"downstream" (the dam's faces, heel to crest and toe to crest),
"crest", "top_left" and "top_right" (the foundation's top left of the
heel and right of the toe).  With a reservoir these keep their whole
length (part of "upstream" and of "top_left" then lies between the
water's cells and the solid's) and four more: "wet" (the upstream face
from the heel up to the level, between the dam and the water), "floor"
(the foundation's top from x_far to the heel, between the foundation and
the water), "far" (the water's far end x = x_far, y from 0 to the level,
on the outer boundary) and "surface" (the free surface y = level, from
x_far to the face).  Each curve but "faces" runs left to right or bottom
to top."""

import math
import numbers
from dataclasses import dataclass

import numpy as np

from vstpetsc.plane.mesh import PlaneMesh

REGIONS = ("dam", "foundation", "water")
# how far apart two crest widths may be and still agree (of the height)
AGREE = 1e-9


class ProfileError(ValueError):
    """A profile that cannot be meshed: ``key`` the dam's key to blame
    ("upstream", "reservoir.level", ...), ``message`` why."""

    def __init__(self, key, message):
        super().__init__(f"{key}: {message}")
        self.key, self.message = key, message


@dataclass(frozen=True)
class Face:
    """One face of the dam, base to crest: ``points`` (k, 2) [x, y], y
    rising from 0 to H; ``run`` its dx/dy when it was given as a slope
    (None for a polyline)."""

    points: np.ndarray
    run: float | None = None

    def x(self, y):
        """The face's x at heights y (0 <= y <= H)."""
        if self.run is not None:       # as straight faces always were: the same mesh to the bit
            return self.points[0, 0] + self.run * y
        return np.interp(y, self.points[:, 1], self.points[:, 0])

    @property
    def heights(self):
        """The heights of its breaks (0 and H included)."""
        return self.points[:, 1]


def divisions(a, b, h):
    """Points from a to b about h apart (at least one interval)."""
    return np.linspace(a, b, max(1, math.ceil(round((b - a) / h, 9))) + 1)


def through(breaks, h):
    """(points through every one of the increasing ``breaks``, about h
    apart between successive ones; the breaks' positions among them)."""
    parts = [divisions(a, b, h) for a, b in zip(breaks[:-1], breaks[1:])]
    points = np.concatenate([p[:-1] for p in parts] + [parts[-1][-1:]])
    return points, np.concatenate([[0], np.cumsum([p.size - 1 for p in parts])])


def _polyline(key, points, H):
    """The polyline face ``key`` of the points given; ProfileError unless y
    rises strictly from 0 to H."""
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 2 or not np.isfinite(p).all():
        raise ProfileError(key, "must be a slope (a number) or a list of at least two [x, y] "
                           "points (finite numbers)")
    if not (p[0, 1] == 0.0 and p[-1, 1] == H and (np.diff(p[:, 1]) > 0).all()):
        ys = ", ".join(f"{v:g}" for v in p[:, 1])
        raise ProfileError(key, f"points must rise from y = 0 to y = height ({H:g}), y strictly "
                           f"increasing, got y = {ys}")
    return Face(p)


def faces(height, crest, upstream, downstream):
    """(upstream Face, downstream Face) of the profile (module docstring);
    ProfileError for polylines that do not rise from 0 to H, a crest
    missing or disagreeing, or faces that cross."""
    H = height
    slope = {k: isinstance(v, numbers.Real) for k, v in (("upstream", upstream),
                                                         ("downstream", downstream))}
    if not any(slope.values()):
        up, down = _polyline("upstream", upstream, H), _polyline("downstream", downstream, H)
        implied = down.points[-1, 0] - up.points[-1, 0]
        if crest is not None and abs(crest - implied) > AGREE * H:
            raise ProfileError("crest", f"the polylines' crest is {implied:g} wide, not "
                               f"{crest:g} (leave crest out, or make it agree)")
    elif crest is None:
        raise ProfileError("crest", "missing (needed unless both faces are polylines)")
    elif all(slope.values()):
        xa, xb = -(crest / 2 + upstream * H), crest / 2 + downstream * H
        up = Face(np.array([[xa, 0.0], [-crest / 2, H]]), upstream)
        down = Face(np.array([[xb, 0.0], [crest / 2, H]]), -downstream)
    elif slope["downstream"]:          # the slope hangs from the crest's far corner
        up = _polyline("upstream", upstream, H)
        corner = up.points[-1, 0] + crest
        down = Face(np.array([[corner + downstream * H, 0.0], [corner, H]]), -downstream)
    else:
        down = _polyline("downstream", downstream, H)
        corner = down.points[-1, 0] - crest
        up = Face(np.array([[corner - upstream * H, 0.0], [corner, H]]), upstream)
    _check_apart(up, down, H, "upstream" if slope["downstream"] else "downstream")
    return up, down


def _check_apart(up, down, H, key):
    """ProfileError (naming ``key``) unless the downstream face lies right
    of the upstream one below the crest (they may meet at it): both are
    linear between their breaks, so the breaks decide."""
    y = np.union1d(up.heights, down.heights)
    gap = down.x(y) - up.x(y)
    bad = np.flatnonzero(np.append(gap[:-1] <= 0, gap[-1] < -AGREE * H))
    if bad.size:
        k = bad[0]
        raise ProfileError(key, f"the faces cross at y = {y[k]:g} (the upstream face at x = "
                           f"{up.x(y[k]):g}, the downstream at x = {down.x(y[k]):g})")


def check_fit(up, down, foundation_width, reservoir=None):
    """ProfileError unless the dam's base (and the reservoir's water) lies
    on the foundation's top and the reservoir's level and far end fit."""
    W, H = foundation_width, up.heights[-1]
    xa, xb = up.points[0, 0], down.points[0, 0]
    if not (-W / 2 < xa and xb < W / 2):
        raise ProfileError("foundation_width", f"the dam's base [{xa:g}, {xb:g}] is wider than "
                           f"its foundation [{-W / 2:g}, {W / 2:g}]")
    if reservoir is None:
        return
    level, x_far = reservoir["level"], xa - reservoir["length"]
    if not 0 < level <= H:
        raise ProfileError("reservoir.level", f"must lie in (0, height = {H:g}], got {level:g}")
    if x_far < -W / 2:
        raise ProfileError("reservoir.length", f"the water's far end x = {x_far:g} lies beyond "
                           f"the foundation's left end x = {-W / 2:g}")
    y = np.append(up.heights[up.heights < level], level)
    bad = np.flatnonzero(up.x(y) <= x_far)
    if bad.size:
        raise ProfileError("reservoir.length", f"the upstream face reaches x = "
                           f"{up.x(y[bad[0]]):g} at y = {y[bad[0]]:g}, at or beyond the "
                           f"water's far end x = {x_far:g}")


def areas(up, down, reservoir=None):
    """(the dam's area, the water's): both faces are linear between their
    breaks, so the trapezoid rule on the breaks is exact."""
    trapezoid = lambda f, y: float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(y)))
    y = np.union1d(up.heights, down.heights)
    dam = trapezoid(down.x(y) - up.x(y), y)
    if reservoir is None:
        return dam, 0.0
    level, x_far = reservoir["level"], up.points[0, 0] - reservoir["length"]
    y = np.append(up.heights[up.heights < level], level)
    return dam, trapezoid(up.x(y) - x_far, y)


def _foundation(W, D, columns, h):
    """(coordinates, quadrilaterals, node grid (rows bottom to top), the
    positions of ``columns`` in a row): the grid's columns meet every one
    of the increasing ``columns`` (-W/2 first, W/2 last)."""
    xs, at = through(columns, h)
    ys = divisions(-D, 0.0, h)
    X, Y = np.meshgrid(xs, ys)
    node = np.arange(xs.size * ys.size).reshape(ys.size, xs.size)
    cells = np.column_stack([node[:-1, :-1].ravel(), node[:-1, 1:].ravel(),
                             node[1:, 1:].ravel(), node[1:, :-1].ravel()])
    return np.column_stack([X.ravel(), Y.ravel()]), cells, node, at


def _zip_rows(lower, upper, s_lower, s_upper):
    """Triangles (k, 3) joining two rows of nodes (numbers ``lower``,
    ``upper``, their x ``s_lower``, ``s_upper``), counter-clockwise with
    the lower row below: each step advances the row whose next node comes
    first along x (the shorter sides)."""
    # the order of the steps: each row's interior steps by position
    steps = np.concatenate([s_lower[1:], s_upper[1:]])
    which = np.concatenate([np.zeros(lower.size - 1, int), np.ones(upper.size - 1, int)])
    order = np.lexsort((which, steps))
    which = which[order]
    i = np.concatenate([[0], np.cumsum(which == 0)])        # lower index before each step
    j = np.concatenate([[0], np.cumsum(which == 1)])
    i0, j0, i1, j1 = i[:-1], j[:-1], i[1:], j[1:]
    low = which == 0
    # a lower step: (l_i, l_i+1, u_j); an upper step: (l_i, u_j+1, u_j)
    a = lower[i0]
    b = np.where(low, lower[np.minimum(i1, lower.size - 1)], upper[np.minimum(j1, upper.size - 1)])
    c = upper[j0]
    return np.column_stack([a, b, c])


def _rows(ends, y, h, start, last=None):
    """(the coordinates of new rows' nodes, each row's node numbers): the
    rows at heights ``y`` from x = ends[0][k] to ends[1][k], nodes about h
    apart, numbered from ``start``; ``last`` (if given) the number of each
    row's node at ends[1][k], a node already there."""
    rows, points, count = [], [], start
    for k, (a, b) in enumerate(zip(*ends)):
        # a crest of width 0 (a triangular dam) is one node
        x = divisions(a, b, h) if b - a > 1e-9 * h else np.array([a])
        if last is not None:
            x = x[:-1]
        new = count + np.arange(x.size)
        rows.append(new if last is None else np.append(new, last[k]))
        points.append(np.column_stack([x, np.full(x.size, y[k])]))
        count += x.size
    return np.concatenate(points), rows


def _join(lower, upper, x):
    """Cells (k, 4) joining two rows counter-clockwise, the lower row
    below: quadrilaterals where both rows have the same x's (beside a
    vertical face), else triangles (_zip_rows, -1 padded)."""
    if lower.size == upper.size and np.array_equal(x[lower], x[upper]):
        return np.column_stack([lower[:-1], lower[1:], upper[1:], upper[:-1]])
    tris = _zip_rows(lower, upper, x[lower], x[upper])
    return np.column_stack([tris, -np.ones(len(tris), int)])


def dam_mesh(height, crest, upstream, downstream, foundation_depth, foundation_width, h,
             reservoir=None):
    """The PlaneMesh of the dam on its foundation, with its reservoir's
    water when ``reservoir`` is {"level": y, "length": m} (module
    docstring); ProfileError (a ValueError naming the key) for a profile
    that cannot be meshed.  ``crest`` may be None with two polylines."""
    W, D = foundation_width, foundation_depth
    up, down = faces(height, crest, upstream, downstream)
    check_fit(up, down, W, reservoir)
    xa, xb = up.points[0, 0], down.points[0, 0]
    level = None if reservoir is None else reservoir["level"]
    x_far = None if reservoir is None else xa - reservoir["length"]
    # the foundation's columns meet the heel and the toe, and the water's far end
    far = [x_far] if x_far is not None and x_far > -W / 2 else []
    coords, quads, fnode, at = _foundation(W, D, np.array([-W / 2, *far, xa, xb, W / 2]), h)
    heel, toe = at[-3], at[-2]
    # the rows' heights hold the faces' breaks exactly (the faces exact) and the
    # level (the water's rows end on the dam's)
    exact = [up.heights, down.heights] + ([] if level is None else [[level]])
    ys, _ = through(np.unique(np.concatenate(exact)), h)
    left = up.x(ys)
    points, rows = _rows((left[1:], down.x(ys[1:])), ys[1:], h, len(coords))
    rows = [fnode[-1][heel:toe + 1]] + rows          # the dam's base is the foundation's top
    coords = np.concatenate([coords, points])
    tris = np.concatenate([_zip_rows(lo, hi, coords[lo, 0], coords[hi, 0])
                           for lo, hi in zip(rows[:-1], rows[1:])])
    cells = [quads, np.column_stack([tris, -np.ones(len(tris), int)])]
    region = [np.ones(len(quads), int), np.zeros(len(tris), int)]
    curves = _curves(fnode, rows, heel, toe)
    if reservoir is None:
        return PlaneMesh(coords, np.concatenate(cells), np.concatenate(region), REGIONS[:2],
                         curves)
    floor = fnode[-1][at[1] if far else 0:heel + 1]
    coords, water, water_cells = _water(coords, floor, rows, ys, left, x_far, level, h)
    curves.update(_water_curves(rows, water))
    return PlaneMesh(coords, np.concatenate(cells + [water_cells]),
                     np.concatenate(region + [np.full(len(water_cells), REGIONS.index("water"))]),
                     REGIONS, curves)


def _water(coords, floor, rows, ys, left, x_far, level, h):
    """(the coordinates with the water's nodes added, the water's rows, its
    cells (k, 4)): its floor the foundation's top nodes ``floor`` from
    x_far to the heel; above, a row at each of the dam's heights ``ys`` up
    to the level, from x_far to the upstream face (at x = ``left``), its
    last node the dam's row's first."""
    top = int(np.searchsorted(ys, level))           # ys holds the level exactly
    points, water = _rows((np.full(top, x_far), left[1:top + 1]), ys[1:top + 1], h,
                          len(coords), [r[0] for r in rows[1:top + 1]])
    water = [floor] + water
    coords = np.concatenate([coords, points])
    cells = np.concatenate([_join(lo, hi, coords[:, 0]) for lo, hi in zip(water[:-1], water[1:])])
    return coords, water, cells


def _edges(nodes):
    return np.column_stack([nodes[:-1], nodes[1:]])


def _curves(fnode, rows, heel, toe):
    """The dam's and the foundation's curves (module docstring): ``rows``
    the dam's rows bottom to top, ``heel`` and ``toe`` the base's ends'
    positions in the foundation's top row."""
    top = fnode[-1]
    upstream = np.array([r[0] for r in rows])
    downstream = np.array([r[-1] for r in rows])
    parts = {"top_left": _edges(top[:heel + 1]), "upstream": _edges(upstream),
             "crest": _edges(rows[-1]), "downstream": _edges(downstream),
             "top_right": _edges(top[toe:])}
    # "faces" the union (an edge may lie on two curves: each is its own label)
    return {"base": _edges(fnode[0]), "left": _edges(fnode[:, 0]),
            "right": _edges(fnode[:, -1]), "faces": np.concatenate(list(parts.values())),
            "contact": _edges(top[heel:toe + 1]), **parts}


def _water_curves(rows, water):
    """"wet", "floor", "far", "surface" (module docstring): ``rows`` the
    dam's rows, ``water`` the water's (the first its floor, each row's
    last node the dam's row's first)."""
    return {"wet": _edges(np.array([r[0] for r in rows[:len(water)]])),
            "floor": _edges(water[0]), "far": _edges(np.array([r[0] for r in water])),
            "surface": _edges(water[-1])}
