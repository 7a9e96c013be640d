"""A plane-strain mesh distributed by DMPlex (vstpetsc.plane.distributed)
on 1, 2 and 3 ranks: each rank's owned rows of M and K are the serial
matrices' (their products with a field, vertex by vertex), and slabs of
free vibration on two ranks (MUMPS's LU) reach the one-rank run (PETSc's
LU) to rounding."""

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
from vstpetsc.plane.distributed import distribute, matrices, owned_rows
from vstpetsc.plane.stepper import PlaneSlabs

comm = PETSc.COMM_WORLD
mpi = comm.tompi4py()
triangles = sys.argv[2] == "triangles"
m = plane_mesh.rectangle((0.0, 8.0), (0.0, 6.0), 8, 6, triangles)
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
bottom = np.flatnonzero(np.isclose(xy[:, 1], 0.0)) + local.start
held = (2 * bottom[:, None] + np.arange(2)).ravel()
slabs = PlaneSlabs(csr("M"), None, csr("K"), 1e-3, held=held, comm=comm, first=2 * local.start)
w = 1e-3 * field(xy) * np.repeat(xy[:, 1], 2) / 6.0
v = np.zeros_like(w)
for _ in range(40):
    w, v = slabs.step(w, v)
out = [mpi.gather(a, root=0) for a in (xy, Ku.getArray().copy(), Mu.getArray().copy(), w, v)]
if comm.getRank() == 0:
    np.savez(sys.argv[1], *[np.concatenate(a) for a in out])
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
    return [data[f"arr_{i}"].reshape(-1, 2)[order] for i in range(5)]


@pytest.mark.parametrize("kind", ["quadrilaterals", "triangles"])
def test_distributed_matrices_and_slabs_equal_one_rank(tmp_path, kind):
    one = run(tmp_path, 1, kind)
    for n in (2, 3):
        many = run(tmp_path, n, kind)
        assert np.array_equal(one[0], many[0])                     # the same vertices
        for a, b in zip(one[1:3], many[1:3]):                      # K u, M u
            assert np.abs(a - b).max() <= 1e-14 * np.abs(a).max()
        for a, b in zip(one[3:], many[3:]):                        # u, v after 40 slabs
            assert np.abs(a - b).max() <= 1e-10 * np.abs(a).max()
