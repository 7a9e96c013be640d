"""The two ways a slab with interfaces is solved, J = A_c + E D E^T the
Newton matrix (D the pairs' blocks f'(y) - W_c, 4 x 4 per pair, zero for
a pair closed and sticking), A_c factored once:

- "dense" (default up to DENSE_PAIRS pairs): Newton on the pairs'
  coordinates (vstpetsc.plane.solver.pair_newton) with their coupling
  S = E^T A_c^-1 E (4m x 4m, rank 0's), each pair's four columns formed
  by four solves with A_c the first time it opens or slides
  (``Coupling``), the columns A_c^-1 E kept (each rank its rows, up to
  COLUMNS_BYTES): its iterations need no solve with A_c.
- "krylov": Newton on the slab's unknowns (vstpetsc.plane.solver.contact_newton)
  whose steps are GMRES on J applied matrix-free (A_c's product and the
  blocks), preconditioned by A_c's solver (FGMRES when that is itself
  iterative): nothing formed, but each iteration is a solve with A_c,
  and a pair that slides or opens changes J in rank 2 to 4, so the
  iterations grow with the pairs that change (bench/README.md).

``-vst_contact_steps dense|krylov`` picks one (``kind``)."""

import numpy as np
from petsc4py import PETSc

from vstpetsc.plane.solver.redundant import factors_at_hand
from vstpetsc.plane.solver.separated import separated_at_hand

DENSE_PAIRS = 1000
FORM = "form"           # rank 0's word to the other ranks: form these pairs' columns


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
COLUMNS_BYTES = 2 ** 30


def _land():
    from mpi4py import MPI
    return MPI.LAND


def _pair_vector(pairs, j):
    """E e_j on the pairs' dofs (m, 8): coordinate j = 4 p + (d1, d2, q1, q2)."""
    f = np.zeros((pairs.m, 4))
    f[j // 4, j % 4] = 1.0
    return pairs.to_dofs(f)


class Coupling:
    """The pairs' coupling S = E^T A_c^-1 E (4m x 4m, rank 0's) and the
    columns A_c^-1 E (each rank its rows, when they fit in COLUMNS_BYTES
    a rank; else ``Z`` is None), formed a pair at a time (4 solves with
    A_c) the first time a pair leaves the closed, sticking state: a pair
    that never does costs nothing (rank 0 asks, ``ensure``; the other
    ranks take part, ``serve``)."""

    def __init__(self, A_c, inner, pairs, dofs, comm):
        self.inner, self.pairs, self.dofs, self.comm = inner, pairs, dofs, comm
        self.u, self.v = A_c.createVecLeft(), A_c.createVecLeft()
        self.rank0 = comm.getRank() == 0
        n = 4 * pairs.m
        # S by its columns: ST[j] = S e_j (a step's and a residual's picks
        # of columns are then rows: 0.2 s less in the 1 m rockfill dam's run)
        self.ST = np.zeros((n, n)) if self.rank0 else None
        local = self.u.getLocalSize()
        keep = comm.tompi4py().allreduce(local * n * 8 <= COLUMNS_BYTES, op=_land())
        # rows: contiguous picks; only a formed column's row is ever read
        # (a correction's, after its pair's columns were formed): left
        # unwritten, not zeroed (np.zeros cleared recycled heap: 0.1 s a rank
        # on the 1 m rockfill dam's 980 x 26 000)
        self.Z = np.empty((n, local)) if keep else None
        self.known = np.zeros(pairs.m, dtype=bool)
        self.solves = 0
        # beside each column a collective solve: the columns dealt to the
        # ranks when each holds the whole factors, solved together when each
        # holds its part (the factors read once for all)
        self.by_ranks = None
        if comm.getSize() > 1 and factors_at_hand(inner) is not None:
            self.by_ranks = DealtColumns(factors_at_hand(inner), dofs, self.u, comm)
        elif separated_at_hand(inner) is not None:
            self.by_ranks = ColumnsTogether(separated_at_hand(inner), dofs, self.u, comm)

    def ensure(self, wanted):
        """Rank 0: form the columns of the pairs ``wanted`` not formed yet,
        the other ranks called in (``serve``) only then."""
        new = np.unique(wanted)
        new = new[~self.known[new]]
        if not new.size:
            return
        self.tell((FORM, new))
        self._form(new)

    def tell(self, word):
        """Rank 0: send ``word`` to the other ranks' ``serve``."""
        if self.comm.getSize() > 1:
            self.comm.tompi4py().bcast(word, root=0)

    def serve(self):
        """The other ranks: form columns as rank 0 asks (``ensure``) until
        it sends another word; returns that word."""
        while True:
            word = self.comm.tompi4py().bcast(None, root=0)
            if word[0] != FORM:
                return word
            self._form(word[1])

    def _form(self, new):
        """The columns of the pairs ``new`` (collective)."""
        columns = [4 * int(p) + c for p in new for c in range(4)]
        if self.by_ranks is not None:
            self.by_ranks.form(columns, self)
        else:
            self._collective(columns)
        self.known[new] = True
        self.solves += len(columns)

    def _collective(self, columns):
        """The ``columns``, each a solve of every rank."""
        for j in columns:
            self.v.zeroEntries()
            self.dofs.add(_pair_vector(self.pairs, j) if self.rank0 else None, self.v)
            self.inner.solve(self.v, self.u)
            self.keep(j, self.u.getArray(readonly=True), self.dofs.gather(self.u))

    def keep(self, j, rows, z):
        """Column j: this rank's ``rows`` into Z (if kept; None: already
        there), its values ``z`` at the pairs' unknowns into S (rank 0's;
        None elsewhere)."""
        if self.Z is not None and rows is not None:
            self.Z[j] = rows
        if z is not None:
            self.ST[j] = self.pairs.coordinates(z).ravel()


class _ColumnsByRanks:
    """What both ways of forming columns by the ranks share: the pairs'
    unknowns (rank 0's, every rank's copy) and the columns' loads."""

    def __init__(self, dofs, comm):
        self.dofs, self.comm = dofs, comm.tompi4py()
        self.index = self.comm.bcast(dofs.index if dofs.rank0 else None, root=0)

    def loads(self, pairs, columns):
        """Every rank's list of each column's load (global unknowns,
        values): a unit load at one pair coordinate."""
        loads = None
        if self.comm.Get_rank() == 0:
            free = self.dofs.free
            loads = [(self.index[j // 4], _pair_vector(pairs, j)[j // 4] * free[j // 4])
                     for j in columns]
        return self.comm.bcast(loads, root=0)


class ColumnsTogether(_ColumnsByRanks):
    """The coupling's columns A_c^-1 E e_j solved at once by the ranks'
    separated LU (vstpetsc.plane.solver.separated: each rank sweeps its
    factors once for all the columns; every column the bits of its own
    solve); each rank keeps its rows (Z), rank 0 gets every column's
    values at the pairs' unknowns (S)."""

    def __init__(self, separated, dofs, vec, comm):
        super().__init__(dofs, comm)
        self.separated = separated
        self.lo, self.hi = vec.getOwnershipRange()

    def form(self, columns, coupling):
        """Columns ``columns`` into coupling.Z and coupling.ST (collective)."""
        loads = self.loads(coupling.pairs, columns)
        B = np.zeros((self.hi - self.lo, len(columns)))
        for k, (index, values) in enumerate(loads):
            mine = (index >= self.lo) & (index < self.hi)
            np.add.at(B[:, k], index[mine] - self.lo, values[mine])
        X = self.separated.solve_many(B)
        if coupling.Z is not None:
            coupling.Z[columns] = X.T
        flat = self.index.ravel()
        mine = np.flatnonzero((flat >= self.lo) & (flat < self.hi))
        parts = self.comm.gather((mine, X[flat[mine] - self.lo]), root=0)
        if parts is None:
            return
        at_pairs = np.empty((flat.size, len(columns)))
        for where, values in parts:
            at_pairs[where] = values
        for k, j in enumerate(columns):
            coupling.keep(j, None, at_pairs[:, k].reshape(self.index.shape))


class DealtColumns(_ColumnsByRanks):
    """The coupling's columns A_c^-1 E e_j dealt to the ranks, each rank
    solving its share alone with its factors of the whole matrix
    (vstpetsc.plane.solver.redundant): the same solves as the collective
    ones (the same load, the same factors), so the same bits; each rank
    gets its rows of every column (Z) and rank 0 every column's values at
    the pairs' unknowns (S)."""

    def __init__(self, whole, dofs, vec, comm):
        super().__init__(dofs, comm)
        self.whole = whole
        self.rank, self.size = comm.getRank(), comm.getSize()
        self.ranges = self.comm.allgather(vec.getOwnershipRange())

    def form(self, columns, coupling):
        """Columns ``columns`` into coupling.Z (each rank's rows, if kept)
        and coupling.ST (rank 0's) (collective)."""
        loads = self.loads(coupling.pairs, columns)
        sent = [[] for _ in range(self.size)]
        for k in range(self.rank, len(columns), self.size):
            full = self.whole.solve_alone(*loads[k])
            for r, (lo, hi) in enumerate(self.ranges):
                sent[r].append((k, full[lo:hi], full[self.index] if r == 0 else None))
        for part in self.comm.alltoall(sent):
            for k, rows, z in part:
                coupling.keep(columns[k], rows, z)


class _Jacobian:
    """J = A_c + each term's E D E^T, matrix-free (petsc4py's python Mat)."""

    def __init__(self, newton):
        self.newton = newton

    def mult(self, mat, x, y):
        nw = self.newton
        nw.A_c.mult(x, y)
        for term in nw.terms:
            z = term.dofs.gather(x)
            term.dofs.add(term.apply(z) if z is not None else None, y)


class _Preconditioner:
    """A_c's own solver as GMRES's preconditioner (petsc4py's python PC)."""

    def __init__(self, inner):
        self.inner = inner

    def apply(self, pc, x, y):
        self.inner.solve(x, y)


ZONE_RTOL = 1e-6


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
        # with a yielding zone each step need not be exact (the Newton's own
        # tolerance decides): 1e-6 took 14 solves a slab where 1e-12 took
        # 21, the iterations the same (rockfill-dam with MKZ, 1.3x faster);
        # pairs alone keep 1e-12 (their runs as they were)
        exact = all(term.exact_steps for term in nw.terms)
        self.ksp.setTolerances(rtol=1e-12 if exact else ZONE_RTOL, atol=0.0, max_it=1000)
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
