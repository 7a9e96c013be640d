"""The slab matrix solved by each rank's interior LU and the separator's
Schur complement (vstpetsc.plane.solver.separated), the default on
several ranks beyond the Schwarz default's Courant number: on 2 and 3
ranks a dam section's slab matrix (its base held) solves to rounding
(the backward error, and the whole matrix's one-rank LU within 1e-12),
the compiled sweeps and scipy's triangular solves agree to rounding, no
interior node couples with another rank's interior, and each rank holds
a part of the factors (on two ranks under 0.6 of the whole matrix's
LU's); three right-hand sides solved at once (the interfaces' coupling
columns) are their three solves alone, bit for bit; the interiors in
METIS's order and in PETSc's solve alike.  METIS's nested dissection
(vstpetsc.native.metis_order) is a permutation, the same for the same
graph, and on a grid its LU holds a fraction of the banded order's
values.  A bad -vst_plane_separated_ordering ends the run in one line."""

import sys

import numpy as np
import pytest

from test_parallel import mpirun

pytestmark = pytest.mark.xdist_group("mpi")

SCRIPT = r'''
import sys
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from petsc4py import PETSc
from vstpetsc.plane import assembly, elements
from vstpetsc.plane.dam_mesh import dam_mesh
from vstpetsc.plane.solver.distributed import distribute, owned_rows
from vstpetsc.plane.solver.matrices import slab_operator
from vstpetsc.plane.solver.separated import separated_lu, separator, _node_pattern, _submatrix
from vstpetsc.plane.solver.stepper import _held_rows

comm = PETSc.COMM_WORLD
mpi = comm.tompi4py()
m = dam_mesh(20.0, 4.0, 1.5, 1.5, 10.0, 80.0, 2.0)
lam, mu = elements.lame(2e8, 0.3)
local = distribute(m, comm)
parts = assembly.element_matrices(local.mesh, lam, mu, 1800.0)
csr = lambda k: owned_rows(local, [(c, Ke if k == "K" else elements.MASSES["averaged"](Me))
                                   for c, Ke, Me in parts.values()])
xy = local.mesh.coordinates[local.owned][np.argsort(local.global_vertex[local.owned])]
bottom = np.flatnonzero(np.isclose(xy[:, 1], m.coordinates[:, 1].min())) + local.start
A = slab_operator(csr("M"), None, csr("K"), 0.01, comm)
_held_rows(A, (2 * bottom[:, None] + np.arange(2)).ravel(), local.start)
ksp = PETSc.KSP().create(comm=comm)
ksp.setOperators(A)
ksp.setType("preonly")
separated_lu(ksp, sys.argv[2] if len(sys.argv) > 2 else "metis")
ksp.setUp()
b, x = A.createVecLeft(), A.createVecRight()
lo, hi = A.getOwnershipRange()
b.setArray(np.random.default_rng(5).standard_normal(A.getSize()[0])[lo:hi])
ksp.solve(b, x)
r = A.createVecLeft()
A.mult(x, r)
r.axpy(-1.0, b)
whole = A.getRedundantMatrix(comm.getSize())
indptr, indices, values = whole.convert("aij").getValuesCSR()
W = sp.csr_matrix((values, indices, indptr), shape=whole.getSize())
xw = spla.spsolve(W.tocsc(), np.random.default_rng(5).standard_normal(W.shape[0]))
xs = np.concatenate(mpi.allgather(x.getArray().copy()))
scale = (abs(W) @ np.abs(xs)).max()
# the separator: no interior row couples with another rank's interior
nodes = A.getSize()[0] // 4
pattern = _node_pattern(_submatrix(A, np.arange(lo // 4, hi // 4), np.arange(nodes)), nodes)
ranges = mpi.allgather((lo // 4, hi // 4))
S, interior = separator(pattern, lo // 4, ranges, comm)
rows = pattern[interior - lo // 4]
inside = (rows.indices >= lo // 4) & (rows.indices < hi // 4)
apart = bool(np.isin(rows.indices[~inside], S).all())
whole_lu = PETSc.KSP().create(comm=PETSc.COMM_SELF)
whole_lu.setOperators(whole)
whole_lu.setType("preonly")
whole_lu.getPC().setType("lu")
whole_lu.getPC().setFactorOrdering("nd")
whole_lu.setUp()
context = ksp.getPC().getPythonContext()
held = context.part.stored()
loads = np.random.default_rng(6 + comm.getRank()).standard_normal((hi - lo, 3))
together = context.solve_many(loads)
alone = np.column_stack([context.solve_many(loads[:, c].copy()) for c in range(3)])
out = dict(residual=r.norm(PETSc.NormType.INFINITY) / scale,
           error=np.abs(xs - xw).max() / np.abs(xw).max(), apart=apart,
           share=held / whole_lu.getPC().getFactorMatrix().getInfo()["nz_used"],
           separator=S.size, together=bool(np.array_equal(together, alone)))
out = mpi.gather(out, root=0)
if comm.getRank() == 0:
    np.save(sys.argv[1], np.array(out, dtype=object), allow_pickle=True)
    np.save(sys.argv[1] + ".x.npy", xs)
'''


def solve(tmp_path, n, *options, ordering="metis"):
    script = tmp_path / "separated.py"
    script.write_text(SCRIPT)
    out = tmp_path / f"out{n}{len(options)}{ordering}.npy"
    p = mpirun(out, ordering, *options, n=n, program=f"{sys.executable} {script}")
    assert p.returncode == 0, p.stderr
    return list(np.load(out, allow_pickle=True)), np.load(f"{out}.x.npy")


@pytest.mark.parametrize("n", [2, 3])
def test_the_separated_lu_solves_the_slab_matrix(tmp_path, n):
    ranks, x = solve(tmp_path, n)
    eps = np.finfo(float).eps
    for r in ranks:
        assert r["separator"] > 0 and r["apart"] and r["together"]
        assert r["residual"] <= 100 * eps
        assert r["error"] <= 1e-12
        assert r["share"] < (0.6 if n == 2 else 0.5), r["share"]
    scipy_path, x_scipy = solve(tmp_path, n, "-vst_native", "0")
    assert np.abs(x - x_scipy).max() <= 1e-12 * np.abs(x).max()
    if n == 2:                          # (one count of ranks is enough for the order)
        petsc, x_petsc = solve(tmp_path, n, ordering="petsc")
        assert all(r["residual"] <= 100 * eps for r in petsc)
        assert np.abs(x - x_petsc).max() <= 1e-12 * np.abs(x).max()


def test_metis_orders_a_grid_by_nested_dissection():
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from vstpetsc.native import metis_order

    n = 40
    line = sp.diags([1.0, 1.0], [-1, 1], shape=(n, n))
    graph = (sp.kron(sp.eye(n), line) + sp.kron(line, sp.eye(n))).tocsr()
    graph.sort_indices()
    order = metis_order(graph)
    if order is None:
        pytest.skip("no libmetis.so.5")
    assert np.array_equal(np.sort(order), np.arange(n * n))
    assert np.array_equal(order, metis_order(graph.copy()))
    A = (graph + 5.0 * sp.eye(n * n)).tocsc()

    def fill(p):
        lu = spla.splu(A[p][:, p].tocsc(), permc_spec="NATURAL", diag_pivot_thresh=0.0)
        return lu.L.nnz + lu.U.nnz

    assert fill(order) < 0.5 * fill(np.arange(n * n)), (fill(order), fill(np.arange(n * n)))


def test_a_bad_separated_ordering_is_named(tmp_path):
    from test_plane_ranks import assert_bad_option_named

    assert_bad_option_named(tmp_path, "vst_plane_separated_ordering", "amd")


def test_the_compiled_correction_subtracts_row_by_row():
    """pair_newton.subtract_rows (x - w @ Z[rows], the pairs' correction
    from the kept coupling columns): compiled, the bits of subtracting
    the rows one by one in their order; numpy's product to rounding."""
    from vstpetsc.native import library
    from vstpetsc.plane.solver.pair_newton import subtract_rows

    rng = np.random.default_rng(3)
    Z = rng.standard_normal((40, 1003))
    for k in (1, 4, 7, 13):
        rows, w, x = rng.choice(40, k, replace=False), rng.standard_normal(k), \
            rng.standard_normal(1003)
        one_by_one = x.copy()
        for i in range(k):
            one_by_one -= w[i] * Z[rows[i]]
        compiled = subtract_rows(x.copy(), w, Z, rows, library())
        assert np.array_equal(compiled, one_by_one)
        numpy_path = subtract_rows(x.copy(), w, Z, rows, None)
        # (each path within k ulps of the sum's magnitudes: gamma_k)
        bound = 2 * (k + 1) * np.finfo(float).eps * (np.abs(w) @ np.abs(Z[rows]) + np.abs(x))
        assert (np.abs(numpy_path - one_by_one) <= bound).all()
