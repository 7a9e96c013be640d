"""The strain points of a plane-strain mesh's cells (issue 46): each linear
triangle's one point, each bilinear quadrilateral's four (2 x 2 Gauss, as
its stiffness is integrated, vstpetsc.plane.elements), gathered into one
sparse strain operator

    eps = S u        (3 np, interleaved (eps_xx, eps_yy, gamma_xy) per point)

over the mesh's interleaved unknowns, with each point's weight (area or
det J).  A yielding zone's stresses at the points become nodal forces by
S^T (w sigma), and their tangent by S^T diag(w dsigma/deps) S: the same
sums as the element stiffness, so that S^T (w D) S is the zone's linear
K (tests/test_material_points.py).  Pure numpy and scipy."""

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from vstpetsc.plane import elements
from vstpetsc.plane.assembly import dofs


@dataclass
class MaterialPoints:
    """``cell`` (np,) the cell of each point, ``weight`` (np,) its share of
    the cell's area, ``strain`` the (3 np, 2 nn) CSR operator S."""

    cell: np.ndarray
    weight: np.ndarray
    strain: sp.csr_matrix

    @property
    def count(self):
        return self.cell.size

    def strains(self, u):
        """(np, 3) the strains of the interleaved nodal field u (2 nn,)."""
        return (self.strain @ u).reshape(-1, 3)

    def forces(self, sigma):
        """(2 nn,) the nodal forces S^T (w sigma) of point stresses
        ``sigma`` (np, 3)."""
        return self.strain.T @ (self.weight[:, None] * sigma).ravel()

    def stiffness(self, tangent):
        """(2 nn, 2 nn) CSR S^T diag(w T) S of point tangents ``tangent``
        (np, 3, 3)."""
        n = self.count
        rows = np.repeat(3 * np.arange(n)[:, None] + np.arange(3), 3, axis=1)
        cols = np.tile(3 * np.arange(n)[:, None] + np.arange(3), (1, 3))
        blocks = sp.csr_matrix(((self.weight[:, None, None] * tangent).ravel(),
                                (rows.ravel(), cols.ravel())), shape=(3 * n, 3 * n))
        return sp.csr_matrix(self.strain.T @ blocks @ self.strain)


def _triangle_points(mesh, cells):
    """(cell, weight, B (n, 3, 6), nodes (n, 3)) of the triangles ``cells``."""
    nodes = mesh.cells[cells, :3]
    dN, area = elements.triangle_gradients(mesh.coordinates[nodes], area=True)
    return cells, area, elements.strain_operator(dN), nodes


def _quadrilateral_points(mesh, cells):
    """The same of the quadrilaterals ``cells``: four points a cell, cell
    by cell (the points of one cell adjacent, in elements.POINTS' order)."""
    nodes = mesh.cells[cells, :4]
    xy = mesh.coordinates[nodes]
    B, w = [], []
    for xi, eta in elements.POINTS:
        _, dN, det = elements.quadrilateral_gradients(xy, xi, eta)
        B.append(elements.strain_operator(dN))
        w.append(det)
    B, w = np.stack(B, axis=1), np.stack(w, axis=1)       # (n, 4, 3, 8), (n, 4)
    count = len(elements.POINTS)
    return (np.repeat(cells, count), w.ravel(), B.reshape(-1, 3, 8),
            np.repeat(nodes, count, axis=0))


def material_points(mesh, cells=None):
    """The MaterialPoints of ``cells`` of ``mesh`` (default: every cell),
    triangles' points first, then the quadrilaterals'."""
    cells = np.arange(mesh.ncells) if cells is None else np.asarray(cells, dtype=int)
    chosen = np.zeros(mesh.ncells, dtype=bool)
    chosen[cells] = True
    parts = [kernel(mesh, kind[chosen[kind]])
             for kind, kernel in ((mesh.triangles, _triangle_points),
                                  (mesh.quadrilaterals, _quadrilateral_points))
             if chosen[kind].any()]
    cell = np.concatenate([p[0] for p in parts]) if parts else np.zeros(0, dtype=int)
    weight = np.concatenate([p[1] for p in parts]) if parts else np.zeros(0)
    rows, cols, vals, first = [], [], [], 0
    for _, _, B, nodes in parts:
        n, _, k = B.shape
        d = dofs(nodes)                                            # (n, k)
        rows.append(np.repeat(3 * (first + np.arange(n))[:, None] + np.arange(3), k,
                              axis=1).ravel())
        cols.append(np.tile(d, (1, 3)).ravel())
        vals.append(B.ravel())
        first += n
    strain = sp.csr_matrix((np.concatenate(vals) if vals else np.zeros(0),
                            (np.concatenate(rows) if rows else np.zeros(0, dtype=int),
                             np.concatenate(cols) if cols else np.zeros(0, dtype=int))),
                           shape=(3 * cell.size, 2 * mesh.nnodes))
    return MaterialPoints(cell, weight, strain)
