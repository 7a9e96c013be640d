"""The two ways a slab with interfaces is solved, J = A_c + E D E^T the
Newton matrix (D the pairs' blocks f'(y) - W_c, 4 x 4 per pair, zero for
a pair closed and sticking), A_c factored once:

- "dense" (default up to DENSE_PAIRS pairs): Newton on the pairs'
  coordinates (vstpetsc.plane.pair_newton) with their coupling
  S = E^T A_c^-1 E (4m x 4m, rank 0's), formed once by 4m solves with
  A_c (``coupling``), the columns A_c^-1 E kept (each rank its rows, up
  to COLUMNS_BYTES): its iterations need no solve with A_c.
- "krylov": Newton on the slab's unknowns (vstpetsc.plane.contact_newton)
  whose steps are GMRES on J applied matrix-free (A_c's product and the
  blocks), preconditioned by A_c's solver (FGMRES when that is itself
  iterative): nothing formed, but each iteration is a solve with A_c,
  and a pair that slides or opens changes J in rank 2 to 4, so the
  iterations grow with the pairs that change (bench/README.md).

``-vst_contact_steps dense|krylov`` picks one (``kind``)."""

import numpy as np
from petsc4py import PETSc

DENSE_PAIRS = 1000


def kind(pairs):
    """"dense" or "krylov": the option's, else dense up to DENSE_PAIRS."""
    from vstpetsc.errors import InputError

    chosen = PETSc.Options().getString("vst_contact_steps",
                                       "dense" if pairs.m <= DENSE_PAIRS else "krylov")
    if chosen not in ("dense", "krylov"):
        raise InputError(f"-vst_contact_steps: {chosen!r} is not dense or krylov")
    return chosen
# the columns A_c^-1 E (every rank its rows) are kept up to this many bytes a
# rank: a step then needs one solve with A_c, not two
COLUMNS_BYTES = 256 * 2 ** 20


def _land():
    from mpi4py import MPI
    return MPI.LAND


def _pair_vector(pairs, j):
    """E e_j on the pairs' dofs (m, 8): coordinate j = 4 p + (d1, d2, q1, q2)."""
    f = np.zeros((pairs.m, 4))
    f[j // 4, j % 4] = 1.0
    return pairs.to_dofs(f)


def coupling(A_c, inner, pairs, dofs, comm):
    """(S = E^T A_c^-1 E (4m, 4m) on rank 0 (None elsewhere), the columns
    A_c^-1 E (4m, this rank's rows) when they fit in COLUMNS_BYTES a rank,
    else None): 4m solves with A_c, once."""
    u, v = A_c.createVecLeft(), A_c.createVecLeft()
    rank0 = comm.getRank() == 0
    n = 4 * pairs.m
    S = np.zeros((n, n)) if rank0 else None
    local = u.getLocalSize()
    keep = comm.tompi4py().allreduce(local * n * 8 <= COLUMNS_BYTES, op=_land())
    Z = np.empty((n, local)) if keep else None          # rows: contiguous picks
    for j in range(n):
        v.zeroEntries()
        dofs.add(_pair_vector(pairs, j) if rank0 else None, v)
        inner.solve(v, u)
        if Z is not None:
            Z[j] = u.getArray(readonly=True)
        z = dofs.gather(u)
        if rank0:
            S[:, j] = pairs.coordinates(z).ravel()
    return S, Z


class _Jacobian:
    """J = A_c + E D E^T, matrix-free (petsc4py's python Mat)."""

    def __init__(self, newton):
        self.newton = newton

    def mult(self, mat, x, y):
        nw = self.newton
        nw.A_c.mult(x, y)
        z = nw.dofs.gather(x)
        values = nw.pairs.apply_difference(z, *nw.blocks) if z is not None else None
        nw.dofs.add(values, y)


class _Preconditioner:
    """A_c's own solver as GMRES's preconditioner (petsc4py's python PC)."""

    def __init__(self, inner):
        self.inner = inner

    def apply(self, pc, x, y):
        self.inner.solve(x, y)


class KrylovSteps:
    """GMRES steps preconditioned by A_c's solver (options prefix
    ``vst_contact_``)."""

    def __init__(self, newton):
        nw = newton
        J = PETSc.Mat().createPython(nw.A_c.getSizes(), context=_Jacobian(nw), comm=nw.comm)
        J.setUp()
        self.ksp = PETSc.KSP().create(comm=nw.comm)
        self.ksp.setOptionsPrefix("vst_contact_")
        self.ksp.setOperators(J)
        self.ksp.setType("gmres" if nw.inner.getType() == "preonly" else "fgmres")
        self.ksp.setTolerances(rtol=1e-12, atol=0.0, max_it=1000)
        self.ksp.setGMRESRestart(200)
        pc = self.ksp.getPC()
        pc.setType("python")
        pc.setPythonContext(_Preconditioner(nw.inner))
        self.ksp.setFromOptions()

    def solve(self, R, dx):
        from vstpetsc.errors import SolveFailed

        self.ksp.solve(R, dx)
        if self.ksp.getConvergedReason() < 0:
            raise SolveFailed(f"the interfaces' Newton step did not converge "
                              f"({self.ksp.getConvergedReason()})")
        return self.ksp.getIterationNumber()
