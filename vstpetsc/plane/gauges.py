"""Gauges of a plane-strain model: u and v at points (x, y) after every
slab, interpolated in the cell that holds the point with its own shape
functions (linear on a triangle, bilinear on a quadrilateral: the finite
element field itself).  Rows of the file: /gauge/<name>/u and v, (x, y)
each.  Pure numpy."""

import numpy as np

from vstpetsc.results.layout import gauge_path

KEYS = ("u", "v")


def _triangle_weights(xy, p):
    """(n, 3) barycentric coordinates of point p in triangles xy (n, 3, 2)."""
    a, b, c = xy[:, 0], xy[:, 1], xy[:, 2]
    det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    l1 = ((p[0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (p[1] - a[:, 1])) / det
    l2 = ((b[:, 0] - a[:, 0]) * (p[1] - a[:, 1]) - (p[0] - a[:, 0]) * (b[:, 1] - a[:, 1])) / det
    return np.column_stack([1.0 - l1 - l2, l1, l2])


def _quadrilateral_weights(xy, p):
    """(4,) bilinear shape functions at p in the quadrilateral xy (4, 2)
    (Newton on the reference coordinates; exact for a parallelogram in
    one step)."""
    ref = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    s = np.zeros(2)
    for _ in range(20):
        N = 0.25 * (1 + ref[:, 0] * s[0]) * (1 + ref[:, 1] * s[1])
        dN = 0.25 * np.column_stack([ref[:, 0] * (1 + ref[:, 1] * s[1]),
                                     ref[:, 1] * (1 + ref[:, 0] * s[0])])
        step = np.linalg.solve(xy.T @ dN, p - N @ xy)
        s += step
        if np.abs(step).max() < 1e-14:
            break
    return 0.25 * (1 + ref[:, 0] * s[0]) * (1 + ref[:, 1] * s[1])


def locate(mesh, p):
    """(cell, nodes, weights) of the first cell holding point p (on its
    edges included, to rounding), or None."""
    tol = 1e-10
    tri = mesh.triangles
    if tri.size:
        w = _triangle_weights(mesh.coordinates[mesh.cells[tri, :3]], p)
        inside = np.flatnonzero((w >= -tol).all(axis=1))
        if inside.size:
            i = inside[0]
            return int(tri[i]), mesh.cells[tri[i], :3], w[i]
    quad = mesh.quadrilaterals
    if quad.size:
        xy = mesh.coordinates[mesh.cells[quad]]
        edge = np.roll(xy, -1, axis=1) - xy
        to_p = p[None, None, :] - xy
        cross = edge[..., 0] * to_p[..., 1] - edge[..., 1] * to_p[..., 0]
        scale = np.abs(edge).max(axis=(1, 2)) ** 2
        inside = np.flatnonzero((cross >= -tol * scale[:, None]).all(axis=1))
        if inside.size:
            i = inside[0]
            return int(quad[i]), mesh.cells[quad[i]], _quadrilateral_weights(xy[i], p)
    return None


class PlaneGauges:
    """The gauges of a PlaneModel (their weights on rank 0's mesh).

    ``nodes``: the nodes (the mesh's numbering as read) whose u and v the
    gauges need; :meth:`fill` turns their (n, 2) values into a row."""

    def __init__(self, model):
        specs = model.case.gauges
        self.names = [g.name for g in specs]
        self.specs = specs
        found = [locate(model.mesh, np.asarray(g.x, float)) for g in specs] \
            if model.mesh is not None else []
        found = model.comm.tompi4py().bcast(found, root=0)
        self.cells = [f[0] for f in found]
        self.nodes = np.unique(np.concatenate([f[1] for f in found])) if found \
            else np.zeros(0, dtype=int)
        self.weights = np.zeros((len(found), self.nodes.size))
        for g, (_, nodes, w) in enumerate(found):
            self.weights[g, np.searchsorted(self.nodes, nodes)] = w

    def __len__(self):
        return len(self.names)

    def series(self):
        """[(dataset name, its columns in a row of :meth:`fill`)]."""
        return [(gauge_path(name, key), np.arange(2) + 4 * g + 2 * k)
                for g, name in enumerate(self.names) for k, key in enumerate(KEYS)]

    def shapes(self):
        return [(name, (2,)) for name, _ in self.series()]

    def fill(self, u, v, out):
        """The row of every gauge from u, v (n, 2) at :attr:`nodes`."""
        rows = out.reshape(len(self.names), 2, 2)
        rows[:, 0] = self.weights @ u
        rows[:, 1] = self.weights @ v

    def attrs(self):
        return {gauge_path(g.name): {"x": np.asarray(g.x), "cell": c}
                for g, c in zip(self.specs, self.cells)}
