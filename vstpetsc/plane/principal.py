"""Each cell's principal in-plane stresses at every slab end and their
envelopes over the run (issue 47: what dam engineers read for cracking;
docs/plane-strain.md, "Outputs").

A cell's stress is the one /field/stress keeps: the linear cells' at the
cell centre from u, a yielding cell's the law's (its points' mean,
vstpetsc.plane.yielding.YieldingZone.cell_stress).  Its principal
stresses s1 >= s2 of (sxx, syy, sxy) are

    s = (sxx + syy) / 2 +- sqrt(((sxx - syy) / 2)^2 + sxy^2),

and the envelopes are max s1 and min s2 over every slab end, t = 0
included, with the time each was reached.  Pure numpy: the solver keeps
them every slab (vstpetsc.plane.solver.principal)."""

import numpy as np
import scipy.sparse as sp

from vstpetsc.errors import InputError
from vstpetsc.plane import elements

DATASETS = ("principal_max", "principal_max_time", "principal_min", "principal_min_time")
# a time moves only when its envelope grows by more than this part of the
# cell's largest |principal stress| so far: a state at rest (a static
# start) repeats its stress to rounding at every slab, and one rank or two
# would otherwise pick different slabs among equal values
TIME_MARGIN = 1e-9


def principal_stresses(stress):
    """(s1, s2), s1 >= s2, of the in-plane stresses ``stress`` (n, 3):
    sigma_xx, sigma_yy, sigma_xy."""
    centre = 0.5 * (stress[:, 0] + stress[:, 1])
    radius = np.hypot(0.5 * (stress[:, 0] - stress[:, 1]), stress[:, 2])
    return centre + radius, centre - radius


CHUNK = 1 << 13         # cells whose rows are formed at once (their temporaries bounded)


def stress_operator(mesh, lam, mu, cells, dof_of_node, ncolumns):
    """CSR (3 len(cells), ncolumns): u (2 a node, x then y, at ``2
    dof_of_node[node] + c``) to sigma_xx, sigma_yy, sigma_xy at the centre
    of each of ``cells`` of ``mesh`` (Lame's ``lam``, ``mu`` per cell of the
    mesh): D B, B at the centre (exact for a linear displacement; a
    quadrilateral's at its reference centre), as energy.centre_stress;
    its rows those of stress_rows."""
    parts = list(stress_rows(mesh, lam, mu, cells, dof_of_node))
    if not parts:
        return sp.csr_matrix((0, ncolumns))
    rows = np.concatenate([np.repeat(r, v.shape[1]) for r, _, v in parts])
    columns = np.concatenate([c.ravel() for _, c, _ in parts])
    values = np.concatenate([v.ravel() for _, _, v in parts])
    return sp.csr_matrix((values, (rows, columns)), shape=(3 * len(cells), ncolumns))


def stress_rows(mesh, lam, mu, cells, dof_of_node):
    """stress_operator's entries, CHUNK cells at a time and one cell shape
    at a time: (rows (n,), columns (n, k), values (n, k)), each row a
    cell's (3 i + component for the cell cells[i]) with its k = 2 x
    corners columns."""
    cells = np.asarray(cells, dtype=np.int64)
    lam, mu = (np.broadcast_to(np.asarray(a, float), (mesh.ncells,)) for a in (lam, mu))
    for first in range(0, cells.size, CHUNK):
        part = cells[first:first + CHUNK]
        for corners, gradients in ((3, elements.triangle_gradients),
                                   (4, elements.centre_gradients)):
            where = np.flatnonzero((mesh.cells[part, 3] >= 0) == (corners == 4))
            if not where.size:
                continue
            kind = part[where]
            nodes = mesh.cells[kind, :corners]
            D = elements.elasticity(lam[kind], mu[kind])
            DB = D @ elements.strain_operator(gradients(mesh.coordinates[nodes]))
            dofs = (2 * dof_of_node[nodes][:, :, None] + np.arange(2)).reshape(kind.size, 1, -1)
            rows = 3 * (first + where)[:, None] + np.arange(3)
            yield (rows.ravel(), np.broadcast_to(dofs, DB.shape).reshape(-1, 2 * corners),
                   DB.reshape(-1, 2 * corners))


class Envelope:
    """The envelopes of the cells ``cells`` (numbers in the mesh as read):
    the largest s1 and smallest s2 so far and the times they were reached."""

    def __init__(self, cells):
        self.cells = np.asarray(cells, dtype=np.int64)
        n = self.cells.size
        self.high, self.low = np.zeros(n), np.zeros(n)
        self.high_time, self.low_time = np.zeros(n), np.zeros(n)

    def start(self, stress, t):
        """The first slab end's stress (n, 3) at time t."""
        self.high, self.low = principal_stresses(stress)
        self.high_time[:], self.low_time[:] = t, t

    def take(self, stress, t):
        """One more slab end's stress (n, 3) at time t."""
        s1, s2 = principal_stresses(stress)
        margin = TIME_MARGIN * np.maximum(np.abs(self.high), np.abs(self.low))
        self.high_time[s1 > self.high + margin] = t
        self.low_time[s2 < self.low - margin] = t
        np.maximum(self.high, s1, out=self.high)
        np.minimum(self.low, s2, out=self.low)

    def restore(self, saved):
        """The values of ``saved`` ({DATASETS name: (ne,)}) at these cells."""
        self.high = np.array(saved["principal_max"][self.cells], dtype=float)
        self.high_time = np.array(saved["principal_max_time"][self.cells], dtype=float)
        self.low = np.array(saved["principal_min"][self.cells], dtype=float)
        self.low_time = np.array(saved["principal_min_time"][self.cells], dtype=float)

    def arrays(self):
        return self.cells, np.stack([self.high, self.high_time, self.low, self.low_time])


def read_saved(f, k, field_path):
    """The envelopes a restart from slab ``k`` of open result file ``f``
    continues ({DATASETS name: (ne,), "slab": k}): written with the blocks,
    at slab k or, after a failed solve, the last slab solved (the slabs
    between are solved again, the same values).  InputError for a file
    without them (an earlier version's)."""
    names = [field_path(name) for name in DATASETS]
    if any(name not in f for name in names) or \
            int(f[names[0]].attrs.get("slab", -1)) < k:
        raise InputError(f"--restart: the file keeps no principal stress envelopes at its "
                         f"last row (slab {k}; written by an earlier vstpetsc version?); run "
                         "the case from the start")
    return {"slab": k, **{name: f[path][...] for name, path in zip(DATASETS, names)}}
