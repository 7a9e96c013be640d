"""A zoned rockfill dam's cross-section on its foundation: a central clay
core between two rockfill shells, conforming along the core's faces and
along the dam's base (the mesh of the rockfill-dam example's Gmsh file,
docs/make_example_meshes.py).

Geometry (y up, the foundation's top at y = 0, everything centred on
x = 0): the foundation [-W/2, W/2] x [-D, 0]; the dam a trapezoid of
height H, its crest [-crest/2, crest/2] at y = H, its faces sloping
``upstream`` and ``downstream`` (horizontal : vertical) down to its base
[x_a, x_b]; the core a trapezoid inside it, its crest [-core_crest/2,
core_crest/2] at y = H, its faces sloping ``core_slope`` outward going
down; the upstream shell between the upstream face and the core, the
downstream shell between the core and the downstream face.

Cells of about ``h``, as in vstpetsc.plane.dam_mesh: the foundation in
quadrilaterals on a grid whose columns meet the dam's two base corners
and the core's two; the dam in triangles row by row (rows h apart), each
row's nodes holding the exact x of the four boundaries (upstream face,
the core's two faces, downstream face) and points about h apart between
them.  Two rows are joined zone by zone (each of the three strips by the
walk of dam_mesh._zip_rows), so that every triangle lies in one zone,
the core's faces are edges of the mesh and each triangle's region is its
zone's (no test of centroids needed).

Regions "core", "upstream_shell", "downstream_shell", "foundation".
Curves: "base", "left", "right" (the foundation's bottom, left to right,
and sides, bottom to top); "faces" (the free surface: the dam's slopes
and crest and the foundation's top beside it); "contact" (the dam's
base, left to right: the dam on its second side, above); "core_upstream"
and "core_downstream" (the core's faces, bottom to top, from the base to
the crest: the second side of "core_upstream" is the upstream shell, that
of "core_downstream" the core).  The three inner curves each lie between
two cells everywhere, and touch the outer boundary only at their end
nodes (the dam's toes; the crest), where vstpetsc.plane.interfaces.split
doubles the node like any other."""

from dataclasses import dataclass

import numpy as np

from vstpetsc.plane.dam_mesh import _zip_rows, divisions
from vstpetsc.plane.mesh import PlaneMesh

REGIONS = ("core", "upstream_shell", "downstream_shell", "foundation")
ZONE_REGION = np.array([1, 0, 2])     # the strips left to right: upstream shell, core, downstream


@dataclass(frozen=True)
class Section:
    """The dam's and the core's outline (see the module's docstring)."""

    height: float
    crest: float
    upstream: float
    downstream: float
    core_crest: float
    core_slope: float

    def breaks(self, y):
        """The x of the upstream face, the core's upstream and downstream
        faces and the downstream face at height y (0 <= y <= H)."""
        below = self.height - y
        core = self.core_crest / 2 + self.core_slope * below
        return np.array([-(self.crest / 2 + self.upstream * below), -core, core,
                         self.crest / 2 + self.downstream * below])

    def check(self, W):
        """ValueError unless the core lies strictly inside the dam, with a
        positive width (both are linear in y: their ends decide) and the
        dam's base inside the foundation's top."""
        top, bottom = self.breaks(self.height), self.breaks(0.0)
        for b in (top, bottom):
            if not (b[0] < b[1] < b[2] < b[3]):
                raise ValueError("the core must lie strictly inside the dam, with a positive "
                                 f"width: breaks {b.tolist()} at its crest or base")
        if not (-W / 2 < bottom[0] and bottom[3] < W / 2):
            raise ValueError("the dam's base is wider than its foundation")


def _row(breaks, h):
    """(x, positions of the breaks in x): each break exactly and points
    about h apart between successive breaks (dam_mesh.divisions), so that
    a row and the foundation's top agree wherever their breaks do."""
    parts = [divisions(a, b, h) for a, b in zip(breaks[:-1], breaks[1:])]
    x = np.concatenate([p[:-1] for p in parts] + [parts[-1][-1:]])
    at = np.concatenate([[0], np.cumsum([p.size - 1 for p in parts])])
    return x, at


def _foundation(W, D, base, h):
    """(coordinates, quadrilaterals, node grid (rows bottom to top), the
    positions of the dam's breaks ``base`` in the top row): the grid's
    columns meet the base's four breaks."""
    xs, at = _row(np.concatenate([[-W / 2], base, [W / 2]]), h)
    ys = divisions(-D, 0.0, h)
    X, Y = np.meshgrid(xs, ys)
    node = np.arange(xs.size * ys.size).reshape(ys.size, xs.size)
    cells = np.column_stack([node[:-1, :-1].ravel(), node[:-1, 1:].ravel(),
                             node[1:, 1:].ravel(), node[1:, :-1].ravel()])
    return np.column_stack([X.ravel(), Y.ravel()]), cells, node, at[1:-1]


def _dam_rows(section, h, base, base_marks, start):
    """The dam's rows: (the coordinates of the nodes above the base, each
    row's node numbers (the first the base's, ``base``, the foundation's
    top nodes from x_a to x_b), each row's break positions (the base's
    ``base_marks``)).  The new nodes are numbered from ``start``."""
    rows, marks, points, count = [base], [base_marks], [], start
    for y in divisions(0.0, section.height, h)[1:]:
        x, at = _row(section.breaks(y), h)
        rows.append(count + np.arange(x.size))
        marks.append(at)
        points.append(np.column_stack([x, np.full(x.size, y)]))
        count += x.size
    return np.concatenate(points), rows, marks


def _join(rows, marks, x):
    """(triangles (k, 3), their zone 0, 1, 2): each pair of rows joined
    strip by strip (between successive breaks), counter-clockwise."""
    tris, zone = [], []
    for lo, up, lm, um in zip(rows[:-1], rows[1:], marks[:-1], marks[1:]):
        for z in range(3):
            a, b = lo[lm[z]:lm[z + 1] + 1], up[um[z]:um[z + 1] + 1]
            t = _zip_rows(a, b, x[a], x[b])
            tris.append(t)
            zone.append(np.full(len(t), z))
    return np.concatenate(tris), np.concatenate(zone)


def rockfill_mesh(height=40.0, crest=8.0, upstream=2.0, downstream=1.8, core_crest=4.0,
                  core_slope=0.25, foundation_depth=30.0, foundation_width=300.0, h=2.0):
    """The PlaneMesh of the zoned dam on its foundation (module docstring);
    ValueError for a core not strictly inside the dam or a base wider than
    the foundation."""
    section = Section(height, crest, upstream, downstream, core_crest, core_slope)
    section.check(foundation_width)
    coords, quads, fnode, at = _foundation(foundation_width, foundation_depth,
                                           section.breaks(0.0), h)
    base = fnode[-1][at[0]:at[-1] + 1]                   # the contact's nodes, left to right
    points, rows, marks = _dam_rows(section, h, base, at - at[0], coords.shape[0])
    coords = np.concatenate([coords, points])
    tris, zone = _join(rows, marks, coords[:, 0])
    cells = np.concatenate([quads, np.column_stack([tris, -np.ones(len(tris), int)])])
    region = np.concatenate([np.full(len(quads), REGIONS.index("foundation")),
                             ZONE_REGION[zone]])
    return PlaneMesh(coords, cells, region, REGIONS, _curves(fnode, at, rows, marks))


def _curves(fnode, at, rows, marks):
    """The named curves (module docstring), each an (m, 2) edge list."""
    edges = lambda n: np.column_stack([n[:-1], n[1:]])
    top = fnode[-1]
    column = lambda k: np.array([r[m[k]] for r, m in zip(rows, marks)])   # bottom to top
    faces = np.concatenate([edges(top[:at[0] + 1]), edges(top[at[-1]:]), edges(column(0)),
                            edges(column(3)), edges(rows[-1])])
    return {"base": edges(fnode[0]), "left": edges(fnode[:, 0]), "right": edges(fnode[:, -1]),
            "faces": faces, "contact": edges(top[at[0]:at[-1] + 1]),
            "core_upstream": edges(column(1)), "core_downstream": edges(column(2))}
