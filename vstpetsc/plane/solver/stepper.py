"""Slabs of a plane-strain model in the plain algebra of formulation.md:
A x = R (u^n, v^{n-}) with A = HM (x) M + dt HC (x) C + dt^2 HK (x) K
(vstpetsc.spacetime.slab's time algebra; stored in 4 x 4 node blocks,
vstpetsc.plane.solver.matrices), factored once; held dofs keep zero
velocity (identity rows).

On one rank the spatial matrices are whole CSR; on several each rank
gives the CSR of the rows it owns (global columns; its dofs from
``first``), vstpetsc.plane.solver.distributed.  The linear solver: options
prefix ``vst_plane_``; by default PETSc's LU (nested dissection) on one
rank, on several GMRES with ASM(ILU(0)) blocks up to Vp dt / h = 2,
beyond each rank's LU of its interior with the separator's Schur
complement (or with ``-vst_plane_whole_lu 1`` every rank's LU of the
whole matrix) up to REDUNDANT_UNKNOWNS and
MUMPS's LU above (bench/plane_solvers.py measures the choices).  A run
uses the linear solver through vstpetsc.plane.solver.slab_solver; PlaneSlabs steps
bare M, K for the tests and benches that need no case."""

import numpy as np
from petsc4py import PETSc

from vstpetsc.plane.solver.heap import give_back
from vstpetsc.plane.solver.matrices import node_matrix, slab_operator
from vstpetsc.plane.solver.redundant import factors_at_hand, whole_on_every_rank
from vstpetsc.plane.solver.separated import separated_at_hand, separated_lu

PREFIX = "vst_plane_"


def _held_rows(A, held, first):
    """The owned slab rows of the held spatial dofs ``held`` (global, the
    rank's first dof ``first``), made identities in PETSc's A."""
    rows = (2 * (np.asarray(held, dtype=int) - first)[:, None] + np.arange(2)).ravel()
    A.zeroRows((2 * first + rows).astype(PETSc.IntType), diag=1.0)
    return rows


# On several ranks, slabs of c dt / h (P wave) up to this take GMRES with
# overlapping Schwarz (ASM) blocks of ILU(0): at c dt / h = 1 it solves a
# slab 1.5 times as fast as MUMPS on two ranks and ILU keeps its 6
# iterations; beyond, its iterations grow (15 at 4, 91 at 16) while the
# factors cost the same, and an LU is the default (bench/README.md).
SCHWARZ_COURANT = 2.0
SCHWARZ_OVERLAP = 2
KRYLOV_RTOL = 1e-12
# Beyond it, up to this many slab unknowns (1e5 cells of quadrilaterals),
# each rank factors its interior and the separator
# (vstpetsc.plane.solver.separated): at 5e4 cells on two ranks 20.7 ms a
# slab against 29.7 for every rank's LU of the whole matrix
# (``-vst_plane_whole_lu 1``: vstpetsc.plane.solver.redundant, itself 15.6
# against MUMPS's 28.5 ms at 2e4 cells, 61.9 against 145.4 at 1e5, c dt /
# h = 4); larger, MUMPS (its factors shared out: at 2e5 cells 2.2 GB a
# rank against the whole LU's 3.5, set-up 15 against 63 s; the separated
# LU not measured there).
REDUNDANT_UNKNOWNS = 400_000
# preconditioners whose set-up holds what they apply (factors, blocks of
# their own): once set up they need no more of the slab matrix (a Jacobi
# takes its diagonal at its first application)
SETTLED = ("ilu", "lu", "icc", "cholesky", "asm", "bjacobi", "redundant")


def default_solver(ksp, comm, courant):
    """Set ``ksp`` to the default for ``comm``'s size and the slabs'
    Courant number (before the options database may change it)."""
    pc = ksp.getPC()
    ordering = _separated_ordering()    # (a bad value is named on one rank too)
    if comm.getSize() > 1 and courant is not None and courant <= SCHWARZ_COURANT:
        ksp.setType("gmres")
        ksp.setTolerances(rtol=KRYLOV_RTOL, atol=0.0, max_it=200)
        pc.setType("asm")
        pc.setASMOverlap(SCHWARZ_OVERLAP)
        return
    ksp.setType("preonly")
    if comm.getSize() > 1 and ksp.getOperators()[0].getSize()[0] <= REDUNDANT_UNKNOWNS:
        if PETSc.Options().getBool(PREFIX + "whole_lu", False):
            whole_on_every_rank(ksp)
        else:
            separated_lu(ksp, ordering)
        return
    pc.setType("lu")
    if comm.getSize() > 1:
        pc.setFactorSolverType("mumps")


def _separated_ordering():
    """-vst_plane_separated_ordering: the separated LU's interiors' order
    (metis, the default, or petsc); InputError for another."""
    from vstpetsc.errors import InputError
    from vstpetsc.plane.solver.separated import ORDERINGS

    chosen = PETSc.Options().getString(PREFIX + "separated_ordering", ORDERINGS[0])
    if chosen not in ORDERINGS:
        raise InputError(f"-{PREFIX}separated_ordering: {chosen!r} is not "
                         f"{' or '.join(ORDERINGS)}")
    return chosen


def linear_solver(A, comm, courant=None, operator=None):
    """The KSP of the slab matrix A (options prefix ``vst_plane_``), set up
    (factored) here, once: PETSc's LU in nested dissection on one rank; on
    several, GMRES with ASM(ILU(0)) blocks for slabs of c dt / h up to
    SCHWARZ_COURANT (``courant``, None: unknown) and beyond each rank's
    interior LU and the separator up to REDUNDANT_UNKNOWNS, MUMPS's LU
    above;
    any option of the database overrides it.  With ``operator`` (the
    slab's product without A: vstpetsc.plane.solver.slab_product) A serves
    to set up the preconditioner alone and is destroyed then (when the
    preconditioner holds its own values: SETTLED)."""
    opts = PETSc.Options()
    ksp = PETSc.KSP().create(comm=comm)
    ksp.setOptionsPrefix(PREFIX)
    ksp.setOperators(operator or A, A)
    default_solver(ksp, comm, courant)
    ksp.setFromOptions()
    pc = ksp.getPC()
    # (ASM's blocks are PETSc's default, ILU(0) with one application)
    # PETSc's own LU in nested dissection unless told otherwise (MUMPS
    # orders by itself)
    if pc.getType() == "lu" and pc.getFactorSolverType() == "petsc" and \
            not opts.hasName(PREFIX + "pc_factor_mat_ordering_type"):
        pc.setFactorOrdering("nd")
    ksp.setUp()
    if operator is not None and (pc.getType() in SETTLED or _settled_python(pc)):
        # the preconditioner is built, its factors hold their own values:
        # kept as it is while A goes (PCSetUp returns at once when reused;
        # destroyed here: petsc4py 3.18 keeps what Python lets go till
        # PETSc's garbage is cleaned)
        pc.setReusePreconditioner(True)
        ksp.setOperators(operator, operator)
        A.destroy()
        give_back()
    return ksp


def _settled_python(pc):
    """Whether ``pc`` is one of our Python preconditioners that hold their
    own values once set up."""
    return pc.getType() == "python" and getattr(pc.getPythonContext(), "settled", False)


def describe(ksp):
    """The slab solver ``ksp`` in a few words (a run's header)."""
    pc = ksp.getPC()
    kind = ksp.getType() + "/" + pc.getType()
    if pc.getType() == "lu":
        kind += f" ({pc.getFactorSolverType()})"
    elif factors_at_hand(ksp) is not None:
        kind = ksp.getType() + "/LU of the whole matrix on every rank"
    elif separated_at_hand(ksp) is not None:
        kind = ksp.getType() + "/each rank's LU of its interior, the separator's Schur complement"
    if ksp.getOperators()[0].getType() == "python":
        kind += ", matrix-free products"
    return kind


class StateProducts:
    """M v and K u of a state (u, v) (this rank's entries), in PETSc
    vectors kept for the run, and a slab's right-hand side from them:
    r = [M v - dt/2 K u, -dt/2 K u] (interleaved, formulation.md)."""

    def __init__(self, M, K):
        self.M, self.K = M, K
        self.mv, self.ku = M.createVecs()
        self.v_vec, self.u_vec = M.createVecs()

    def form(self, u, v):
        self.v_vec.setArray(v)
        self.u_vec.setArray(u)
        self.M.mult(self.v_vec, self.mv)
        self.K.mult(self.u_vec, self.ku)

    def rhs(self, r, dt):
        """r (interleaved v^1, v^2 rows) from the formed products."""
        ku = self.ku.getArray(readonly=True)
        r[0::2] = self.mv.getArray(readonly=True) - 0.5 * dt * ku
        r[1::2] = -0.5 * dt * ku


class PlaneSlabs:
    """Slabs of dt for the spatial matrices M, C (or None), K (CSR, 2
    dofs a node: whole, or a rank's owned rows from spatial dof
    ``first``); ``held`` the (global) spatial dofs whose velocity is 0."""

    def __init__(self, M, C, K, dt, held=(), comm=None, first=0):
        comm = comm or PETSc.COMM_SELF
        self.dt = dt
        self.A = slab_operator(M, C, K, dt, comm)
        self.rows = _held_rows(self.A, held, first)
        self.products = StateProducts(node_matrix(M, comm), node_matrix(K, comm))
        self.ksp = linear_solver(self.A, comm)
        self.x, self.b = self.A.createVecs()

    def step(self, u, v, forces=None):
        """(u^{n+1}, v^{(n+1)-}) from (u^n, v^{n-}), this rank's entries;
        ``forces`` the slab's nodal force integrals (2 per dof, interleaved)."""
        self.products.form(u, v)
        r = np.empty(2 * u.size)
        self.products.rhs(r, self.dt)
        if forces is not None:
            r += forces
        r[self.rows] = 0.0
        self.b.setArray(r)
        self.ksp.solve(self.b, self.x)
        x = self.x.getArray()
        v1, v2 = x[0::2], x[1::2]
        return u + 0.5 * self.dt * (v1 + v2), v2.copy()
