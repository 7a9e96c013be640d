"""A plane-strain mesh: nodes in the (x, y) plane (y up), cells of three
(linear triangles) or four (bilinear quadrilaterals) nodes counter-
clockwise, each in one named region, and named curves as lists of edges.

Cells are one (ne, 4) array with -1 padding a triangle's fourth node (the
result file's layout, interface.md "Plane strain (2-D)"), so that every
kernel works on all cells of one kind at once.
"""

from dataclasses import dataclass, field

import numpy as np


@dataclass
class PlaneMesh:
    """Nodes, cells, regions and curves.

    Attributes
    ----------
    coordinates : (nn, 2) node coordinates.
    cells : (ne, 4) node indices counter-clockwise; -1 pads a triangle.
    region : (ne,) index of each cell's region in ``region_names``.
    region_names : tuple of the regions' names.
    curves : {name: (m, 2) edges as node pairs}.
    """

    coordinates: np.ndarray
    cells: np.ndarray
    region: np.ndarray
    region_names: tuple = ("domain",)
    curves: dict = field(default_factory=dict)

    @property
    def nnodes(self):
        return self.coordinates.shape[0]

    @property
    def ncells(self):
        return self.cells.shape[0]

    @property
    def triangles(self):
        """Indices of the triangular cells."""
        return np.flatnonzero(self.cells[:, 3] < 0)

    @property
    def quadrilaterals(self):
        return np.flatnonzero(self.cells[:, 3] >= 0)

    def edges(self):
        """(cells (k,), first node (k,), second node (k,)) of every cell's
        edges, counter-clockwise: a triangle's three, a quadrilateral's four."""
        corners = np.where(self.cells[:, 3] < 0, 3, 4)
        valid = np.arange(4)[None, :] < corners[:, None]
        following = np.where(np.arange(4)[None, :] + 1 < corners[:, None], np.arange(1, 5), 0)
        b = np.take_along_axis(self.cells, following, axis=1)
        cells = np.broadcast_to(np.arange(self.ncells)[:, None], self.cells.shape)
        return cells[valid], self.cells[valid], b[valid]

    def edge_keys(self, a, b):
        """One integer per undirected edge (a, b)."""
        n = max(self.nnodes, 1)
        return np.minimum(a, b).astype(np.int64) * n + np.maximum(a, b)

    def curve_nodes(self, name):
        """The sorted nodes of a named curve."""
        return np.unique(self.curves[name])

    def region_mesh(self, name):
        """The mesh of one region's cells alone (nodes renumbered in their
        order; curves keep the edges whose nodes both remain)."""
        cells = self.cells[self.region == self.region_names.index(name)]
        used = np.unique(cells[cells >= 0])
        new = -np.ones(self.nnodes, dtype=int)
        new[used] = np.arange(used.size)
        renumbered = np.where(cells >= 0, new[np.maximum(cells, 0)], -1)
        curves = {}
        for curve, edges in self.curves.items():
            kept = edges[(new[edges] >= 0).all(axis=1)]
            if kept.size:
                curves[curve] = new[kept]
        return PlaneMesh(self.coordinates[used], renumbered,
                         np.zeros(len(cells), dtype=int), (name,), curves)

    def split_curve(self, curve, name, inside):
        """The mesh with the edges of ``curve`` whose both nodes satisfy
        ``inside(x, y)`` moved to a new curve ``name`` (a load's patch on a
        surface, for instance); the rest keep ``curve``'s name."""
        edges = self.curves[curve]
        xy = self.coordinates[edges]
        mine = inside(xy[..., 0], xy[..., 1]).all(axis=1)
        curves = {k: v for k, v in self.curves.items() if k != curve}
        curves[curve], curves[name] = edges[~mine], edges[mine]
        return PlaneMesh(self.coordinates, self.cells, self.region, self.region_names, curves)

    def areas(self):
        """(ne,) cell areas (shoelace; positive for counter-clockwise cells)."""
        n = np.where(self.cells < 0, self.cells[:, [2]], self.cells)   # a triangle repeats a node
        x, y = self.coordinates[n, 0], self.coordinates[n, 1]
        return 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)


def rectangle(x, y, nx, ny, triangles=False, joints=None):
    """The structured mesh of [x0, x1] x [y0, y1] with nx x ny quadrilaterals
    (each split into two triangles along its rising diagonal when
    ``triangles``): region "domain", curves "left", "right", "bottom", "top",
    and ``joints`` {name: k}: grid row k (0 < k < ny) as an inner curve
    drawn from left to right (an interface's curve; the cells above are
    its second side)."""
    xs, ys = np.linspace(x[0], x[1], nx + 1), np.linspace(y[0], y[1], ny + 1)
    X, Y = np.meshgrid(xs, ys)                     # node (i, j) = j * (nx + 1) + i
    coordinates = np.column_stack([X.ravel(), Y.ravel()])
    node = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1)
    a, b = node[:-1, :-1].ravel(), node[:-1, 1:].ravel()      # a cell's lower left, right
    c, d = node[1:, 1:].ravel(), node[1:, :-1].ravel()        # upper right, left
    if triangles:
        pad = -np.ones_like(a)
        cells = np.column_stack([np.column_stack([a, b, c, pad]),
                                 np.column_stack([a, c, d, pad])]).reshape(-1, 4)
    else:
        cells = np.column_stack([a, b, c, d])
    edges = lambda nodes: np.column_stack([nodes[:-1], nodes[1:]])
    curves = {"bottom": edges(node[0]), "top": edges(node[-1]),
              "left": edges(node[:, 0]), "right": edges(node[:, -1])}
    curves.update({name: edges(node[k]) for name, k in (joints or {}).items()})
    return PlaneMesh(coordinates, cells, np.zeros(cells.shape[0], dtype=int), ("domain",),
                     curves)
