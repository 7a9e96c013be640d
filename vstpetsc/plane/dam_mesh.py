"""The generated dam cross-section (interface.md, "Plane strain (2-D)",
``[mesh] dam = {...}``): a trapezoidal dam of height H on a rectangular
foundation, conforming along their contact.

Geometry (y up, the foundation's top at y = 0, the crest centred on
x = 0): the foundation [-W/2, W/2] x [-D, 0]; the dam's base from
x_a = -(crest/2 + upstream H) to x_b = crest/2 + downstream H, its crest
[-crest/2, crest/2] at y = H (slopes horizontal : vertical).

Cells of about ``h``: the foundation in quadrilaterals on a grid whose
columns meet the dam's base corners; the dam in triangles, row by row
(rows h apart, each row's nodes about h apart, so cells stay near h
as the section narrows): two rows are joined by walking both at once in
the order of their nodes' x (each step one triangle).  Regions "dam", "foundation"; curves "base", "left", "right"
(the foundation's), "faces" (the dam's slopes and crest and the
foundation's top beside it), "contact" (the dam's base), and the parts
of "faces" each alone (their edges also in "faces"): "upstream" and
"downstream" (the dam's slopes, heel to crest and toe to crest),
"crest", "top_left" and "top_right" (the foundation's top left of the
heel and right of the toe)."""

import math

import numpy as np

from vstpetsc.plane.mesh import PlaneMesh


def divisions(a, b, h):
    """Points from a to b about h apart (at least one interval)."""
    return np.linspace(a, b, max(1, math.ceil(round((b - a) / h, 9))) + 1)


def _foundation(W, D, xa, xb, h):
    """(coordinates, quadrilaterals, the top row's node numbers, x grid)."""
    xs = np.concatenate([divisions(-W / 2, xa, h)[:-1], divisions(xa, xb, h)[:-1],
                         divisions(xb, W / 2, h)])
    ys = divisions(-D, 0.0, h)
    X, Y = np.meshgrid(xs, ys)
    node = np.arange(xs.size * ys.size).reshape(ys.size, xs.size)
    cells = np.column_stack([node[:-1, :-1].ravel(), node[:-1, 1:].ravel(),
                             node[1:, 1:].ravel(), node[1:, :-1].ravel()])
    return np.column_stack([X.ravel(), Y.ravel()]), cells, node, xs


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


def dam_mesh(height, crest, upstream, downstream, foundation_depth, foundation_width, h):
    """The PlaneMesh of the dam on its foundation."""
    H, W, D = height, foundation_width, foundation_depth
    xa, xb = -(crest / 2 + upstream * H), crest / 2 + downstream * H
    if not (-W / 2 < xa and xb < W / 2):
        raise ValueError("the dam's base is wider than its foundation")
    coords, quads, fnode, xs = _foundation(W, D, xa, xb, h)
    in_base = (xs >= xa - 1e-12 * W) & (xs <= xb + 1e-12 * W)
    row = fnode[-1][in_base]                               # the contact's nodes, left to right
    rows, points = [row], [coords]
    count = coords.shape[0]
    ys = divisions(0.0, H, h)
    for y in ys[1:]:
        left, right = xa + upstream * y, xb - downstream * y
        # a crest of width 0 (a triangular dam) is one node
        x = divisions(left, right, h) if right - left > 1e-9 * h else np.array([left])
        rows.append(count + np.arange(x.size))
        points.append(np.column_stack([x, np.full(x.size, y)]))
        count += x.size
    coords = np.concatenate(points)
    tris = np.concatenate([_zip_rows(lo, up, coords[lo, 0], coords[up, 0])
                           for lo, up in zip(rows[:-1], rows[1:])])
    cells = np.concatenate([quads, np.column_stack([tris, -np.ones(len(tris), int)])])
    region = np.concatenate([np.ones(len(quads), int), np.zeros(len(tris), int)])
    curves = _curves(fnode, rows, in_base)
    return PlaneMesh(coords, cells, region, ("dam", "foundation"), curves)


def _curves(fnode, rows, in_base):
    edges = lambda n: np.column_stack([n[:-1], n[1:]])
    top = fnode[-1]
    first, last = np.flatnonzero(in_base)[[0, -1]]
    upstream = np.array([r[0] for r in rows])
    downstream = np.array([r[-1] for r in rows])
    parts = {"top_left": edges(top[:first + 1]), "upstream": edges(upstream),
             "crest": edges(rows[-1]), "downstream": edges(downstream),
             "top_right": edges(top[last:])}
    # "faces" the union (an edge may lie on two curves: each is its own label)
    return {"base": edges(fnode[0]), "left": edges(fnode[:, 0]), "right": edges(fnode[:, -1]),
            "faces": np.concatenate(list(parts.values())), "contact": edges(top[first:last + 1]),
            **parts}
