"""A plane-strain mesh distributed by DMPlex (vstpetsc.plane.solver.distributed)
on 1, 2 and 3 ranks (quadrilaterals, triangles, and the mixed dam
section): each rank's owned rows of M and K are the serial matrices'
(their products with a field, vertex by vertex), the regions' areas and
the curves' edges survive the distribution, and slabs of free vibration
on several ranks (the default: every rank's LU of the whole slab
matrix) reach the one-rank run (PETSc's LU) to rounding."""

import sys

import numpy as np
import pytest

from test_parallel import mpirun

pytestmark = pytest.mark.xdist_group("mpi")

SCRIPT = r'''
import sys
import numpy as np
from petsc4py import PETSc
from vstpetsc.plane import assembly, elements, mesh as plane_mesh
from vstpetsc.plane.dam_mesh import dam_mesh
from vstpetsc.plane.solver.distributed import distribute, matrices, owned_rows
from vstpetsc.plane.solver.stepper import PlaneSlabs

comm = PETSc.COMM_WORLD
mpi = comm.tompi4py()
kind = sys.argv[2]
m = dam_mesh(20.0, 4.0, 1.5, 1.5, 10.0, 80.0, 4.0) if kind == "dam" else \
    plane_mesh.rectangle((0.0, 8.0), (0.0, 6.0), 8, 6, kind == "triangles")
lam, mu = elements.lame(2e8, 0.3)
local = distribute(m, comm)
M, K = matrices(local, lam, mu, 1800.0)
order = np.argsort(local.global_vertex[local.owned])
xy = local.mesh.coordinates[local.owned][order]        # the owned vertices in global order
field = lambda p: np.column_stack([np.sin(p[:, 0]) * np.cos(p[:, 1]), p[:, 0] * p[:, 1]]).ravel()
u = M.createVecRight()
u.setArray(field(xy))
Ku, Mu = K.createVecLeft(), M.createVecLeft()
K.mult(u, Ku)
M.mult(u, Mu)
# free vibration from a smooth field, the bottom held
parts = assembly.element_matrices(local.mesh, lam, mu, 1800.0)
csr = lambda k: owned_rows(local, [(c, Ke if k == "K" else elements.MASSES["averaged"](Me))
                                   for c, Ke, Me in parts.values()])
bottom = np.flatnonzero(np.isclose(xy[:, 1], m.coordinates[:, 1].min())) + local.start
held = (2 * bottom[:, None] + np.arange(2)).ravel()
slabs = PlaneSlabs(csr("M"), None, csr("K"), 1e-3, held=held, comm=comm, first=2 * local.start)
w = 1e-3 * field(xy) * np.repeat(xy[:, 1], 2) / 6.0
v = np.zeros_like(w)
for _ in range(40):
    w, v = slabs.step(w, v)
out = [mpi.gather(a, root=0) for a in (xy, Ku.getArray().copy(), Mu.getArray().copy(), w, v)]
lm = local.mesh
areas = np.bincount(lm.region[local.owned_cells], lm.areas()[local.owned_cells],
                    minlength=len(lm.region_names))
areas = mpi.reduce(areas, root=0)
edges = {n: lm.coordinates[e].mean(axis=1) for n, e in lm.curves.items()}
edges = mpi.gather(edges, root=0)
if comm.getRank() == 0:
    mids = {n: np.unique(np.round(np.concatenate([e[n] for e in edges if n in e]), 9), axis=0)
            for n in m.curves}
    serial = {n: np.unique(np.round(m.coordinates[e].mean(axis=1), 9), axis=0)
              for n, e in m.curves.items()}
    same = all(np.array_equal(mids[n], serial[n]) for n in m.curves)
    np.savez(sys.argv[1], *[np.concatenate(a) for a in out], areas, np.array([same]))
'''


def run(tmp_path, n, kind):
    script = tmp_path / "plane.py"
    script.write_text(SCRIPT)
    out = tmp_path / f"out{n}.npz"
    p = mpirun(out, kind, n=n, program=f"{sys.executable} {script}")
    assert p.returncode == 0, p.stderr
    data = np.load(out)
    xy = data["arr_0"]
    order = np.lexsort((xy[:, 1], xy[:, 0]))             # by coordinates, any numbering
    fields = [data[f"arr_{i}"].reshape(-1, 2)[order] for i in range(5)]
    return fields + [data["arr_5"], bool(data["arr_6"][0])]


@pytest.mark.parametrize("kind", ["quadrilaterals", "triangles", "dam"])
def test_distributed_matrices_and_slabs_equal_one_rank(tmp_path, kind):
    one = run(tmp_path, 1, kind)
    for n in (2, 3):
        many = run(tmp_path, n, kind)
        assert np.array_equal(one[0], many[0])                     # the same vertices
        assert np.allclose(many[5], one[5], rtol=1e-13) and many[6]   # regions, curves
        for a, b in zip(one[1:3], many[1:3]):                      # K u, M u
            assert np.abs(a - b).max() <= 1e-14 * np.abs(a).max()
        for a, b in zip(one[3:], many[3:]):                        # u, v after 40 slabs
            assert np.abs(a - b).max() <= 1e-10 * np.abs(a).max()
