"""The slab solver of a plane-strain run, with the protocol of the 1-D
SlabSolver that the shared time loop and recorder use (``rhs``,
``solve``, ``advance``, ``set_state``, ``gather_state``, ``totals``,
``restart``, ``describe``, ``space``).

Each slab in the plain algebra of formulation.md: r from (u^n, v^{n-})
by two parallel products (M v, K u), A x = r + int T_a f dt solved with A
factored once (with interfaces: A_c, the interfaces closed and sticking,
and Newton, vstpetsc.plane.solver.contact_newton)
(vstpetsc.plane.solver.stepper's linear solver, options prefix
``vst_plane_``), u^{n+1} = u^n + dt/2 (v^1 + v^2).  Held dofs have
identity rows carrying their prescribed (v^1, v^2).  The energy terms of
each slab are summed per rank (docs/loads.md section 4): the dashpots'
and Rayleigh's int v^T C v dt, the loads' work and, at moving held dofs,
the reactions' work (A x - r on their rows)."""

import numpy as np
from petsc4py import PETSc

from vstpetsc.errors import InputError, SolveFailed
from vstpetsc.native import library
from vstpetsc.petsc.ranks import Ranks
from vstpetsc.plane.solver.principal import PrincipalStresses
from vstpetsc.plane.solver.heap import give_back
from vstpetsc.plane.solver.matrices import node_matrix, slab_operator
from vstpetsc.plane.solver.newton_terms import slab_newton
from vstpetsc.plane.solver.slab_product import run_operators
from vstpetsc.plane.solver.stepper import StateProducts, describe, linear_solver
from vstpetsc.results import layout

SUMS = ("damping", "external", "contact", "friction")


class NoLaws:
    """A plane-strain run has no nonlinear laws yet (issue 38)."""

    def finish_slab(self, t0, dt):
        pass


class PlaneSolver:
    serial = property(lambda self: self.comm.getSize() == 1)
    native = False

    def __init__(self, model, dt, comm, loads):
        self.model, self.dt, self.comm, self.loads = model, dt, comm, loads
        self.space = Ranks(comm)
        self.laws = NoLaws()
        M, C, K = model.matrices()
        first = model.first
        springs = model.closed_springs()        # interfaces: A_c = A + dt^2 HK (x) springs
        held = loads.held
        self.rows = (2 * held[:, None] + np.arange(2)).ravel()
        A = slab_operator(M, C, K if springs is None else K + springs, dt, comm)
        self.M, self.K = node_matrix(M, comm), node_matrix(K, comm)
        self.C = None if C is None else node_matrix(C, comm)
        n = M.shape[0]
        del M, C, K             # the CSR copies go before the factors come
        model.release_matrices()
        give_back()
        # the unconstrained rows' product gives the reactions of moving held
        # dofs (on every rank when any rank has some: the copy is collective)
        from mpi4py import MPI
        moving = comm.tompi4py().allreduce(not loads.all_fixed, op=MPI.LOR)
        self.A, P, self.A_free = run_operators(A, (self.M, self.C, self.K), springs, dt,
                                               self.rows, first, moving, comm)
        del A, springs
        self.ax = None if self.A_free is None else self.A_free.createVecLeft()
        self.courant = model.courant(dt)
        self.ksp = linear_solver(P, comm, self.courant, None if P is self.A else self.A)
        del P
        self.x, self.b = self.A.createVecs()
        self.products = StateProducts(self.M, self.K)
        self.mv, self.ku = self.products.mv, self.products.ku
        self.v_vec, self.u_vec = self.products.v_vec, self.products.u_vec
        self.c1, self.c2 = self.M.createVecs()
        self.u, self.v = np.zeros(n), np.zeros(n)
        self.sums = np.zeros(len(SUMS))
        self.forces = None
        self._products_fresh = False
        self.restart = PlaneRestart(self)
        self.to_rank0 = gather_to_rank0(model, comm)
        self.pairs, self.zone = model.pairs, model.zone
        if hasattr(self.zone, "use_native") and PETSc.Options().getBool("vst_native", True):
            self.zone.use_native(library())
        self.principal = PrincipalStresses(model, dt, comm)
        self.newton = None if self.pairs is None and self.zone is None else \
            slab_newton(self, comm)

    def describe(self):
        return f"plane strain, {describe(self.ksp)}, Vp dt / h up to {self.courant:.3g}"

    def set_state(self, u, v, envelopes=None):
        """Start from u, v (nn, 2) of every node (the mesh's numbering as
        read): the principal stress envelopes from u at t = 0, or a
        restart's ``envelopes`` (layout.read_envelopes)."""
        self._take_state(u, v)
        self.principal.start(self.u, envelopes)

    def _take_state(self, u, v):
        own = self.model.owned_original
        self.u[:] = np.asarray(u).reshape(-1, 2)[own].ravel()
        self.v[:] = np.asarray(v).reshape(-1, 2)[own].ravel()
        self._products_fresh = False

    def _state_products(self):
        """M v and K u of the state (u, v), in ``mv`` and ``ku``: formed once
        per state, for a slab's right-hand side and a kept row's energies
        alike."""
        if self._products_fresh:
            return
        self.products.form(self.u, self.v)
        self._products_fresh = True

    def rhs(self, forces, velocities, fields=None):
        self._state_products()
        r = self.b.getArray()
        self.products.rhs(r, self.dt)
        if forces is not None:
            r += forces.ravel()
        self.forces = forces
        if self.A_free is not None:
            self.r_free = r[self.rows].copy()
        r[self.rows] = np.asarray(velocities).ravel()

    def solve(self, k):
        if self.newton is not None:
            # Newton starts from the state's velocity on the whole slab: a
            # function of the state alone, so that a restart repeats it
            self.x.setArray(np.repeat(self.v, 2))
            its = self.newton.solve(self.b, self.x, k)
            if not np.isfinite(self.x.getArray(readonly=True)).all():
                raise SolveFailed(f"slab {k}: the solution is not finite")
            return its
        self.ksp.solve(self.b, self.x)
        if self.ksp.getConvergedReason() < 0:
            raise SolveFailed(f"slab {k}: the linear solver did not converge "
                              f"({self.ksp.getConvergedReason()})")
        x = self.x.getArray(readonly=True)
        if not np.isfinite(x).all():
            raise SolveFailed(f"slab {k}: the solution is not finite")
        return 0, self.ksp.getIterationNumber()

    def advance(self):
        """Close the slab: its energy terms, then u and v."""
        x = self.x.getArray(readonly=True)
        v1, v2 = x[0::2], x[1::2]
        if self.C is not None:
            self.sums[0] += self.dt * self._damping(v1, v2) / 3.0
        if self.forces is not None:
            self.sums[1] += float(self.forces[:, 0] @ v1 + self.forces[:, 1] @ v2)
        if self.A_free is not None:
            self.sums[1] += self._reaction_work(x)
        if self.newton is not None and self.comm.getRank() == 0:
            if self.pairs is not None:
                self.sums[2:4] += self.pairs.finish_slab()
            if self.zone is not None:
                self.zone.finish_slab()
            self.sums[1] += self.newton.held_work()
        self.u += 0.5 * self.dt * (v1 + v2)
        self.v[:] = v2
        self._products_fresh = False
        self.principal.after_slab(self.u)

    def _damping(self, v1, v2):
        """This rank's v1 C v1 + (v1 C v2 + v2 C v1) / 2 + v2 C v2 (rows it
        owns): 3 / dt times the work of C's symmetric part (an acoustic
        water's skew coupling does none)."""
        self._products_fresh = False          # v_vec holds v1, v2 now
        self.v_vec.setArray(v1)
        self.C.mult(self.v_vec, self.c1)
        self.v_vec.setArray(v2)
        self.C.mult(self.v_vec, self.c2)
        c1, c2 = self.c1.getArray(readonly=True), self.c2.getArray(readonly=True)
        return float(v1 @ c1 + 0.5 * (v1 @ c2 + v2 @ c1) + v2 @ c2)

    def _reaction_work(self, x):
        """The held dofs' reactions' work in the slab: (A x - r) . x on their rows."""
        self.A_free.mult(self.x, self.ax)
        reaction = self.ax.getArray(readonly=True)[self.rows] - self.r_free
        return float(reaction @ x[self.rows])

    def totals(self):
        """The energy sums and the state's kinetic and strain energy over
        every rank (collective)."""
        self._state_products()
        kinetic, strain = 0.5 * self.mv.dot(self.v_vec), 0.5 * self.ku.dot(self.u_vec)
        out = dict(zip(SUMS, map(float, self.space.sum_over_ranks(self.sums))))
        out.update(kinetic=float(kinetic), strain=float(strain))
        if self.zone is not None:       # rank 0's, on every rank
            beyond = self.zone.energies() if self.comm.getRank() == 0 else None
            beyond = self.comm.tompi4py().bcast(beyond, root=0)
            out.update(strain_beyond_linear=beyond[0], hysteretic=beyond[1])
        return out

    def held_energies(self, u, v):
        """(kinetic, strain) of the state u, v (nn, 2) (collective)."""
        keep = self.u.copy(), self.v.copy()
        self._take_state(u, v)
        totals = self.totals()
        self.u[:], self.v[:] = keep
        self._products_fresh = False
        return totals["kinetic"], totals["strain"]

    def gather_state(self):
        """(u, v), (nn, 2) each in the mesh's numbering as read, on rank 0
        (None elsewhere)."""
        if self.serial:
            return self.u.reshape(-1, 2), self.v.reshape(-1, 2)
        u, v = self.to_rank0(self.u), self.to_rank0(self.v)
        return None if u is None else (u.reshape(-1, 2), v.reshape(-1, 2))

    def state_energies(self):
        return None

    def elongation(self):
        return None

    def envelopes(self, nelements):
        """(the principal stress envelopes on rank 0, None): what the
        layout's envelope_snapshots writes (collective)."""
        return self.principal.gathered(), None

    def probe(self, nodes):
        """A callable giving (u, v) (n, 2) at ``nodes`` (the mesh's numbering)
        on rank 0 (None elsewhere)."""
        if self.serial:
            nodes = np.asarray(nodes)
            return lambda: (self.u.reshape(-1, 2)[nodes], self.v.reshape(-1, 2)[nodes])
        gather = gather_to_rank0(self.model, self.comm, nodes)
        return lambda: _pair(gather(self.u), gather(self.v))


def _pair(u, v):
    return None if u is None else (u.reshape(-1, 2), v.reshape(-1, 2))


def gather_to_rank0(model, comm, nodes=None):
    """A callable taking this rank's owned values (2 a node, global order)
    and giving, on rank 0, those of every node (or of ``nodes``) in the
    mesh's numbering as read (None elsewhere): one PETSc scatter."""
    if comm.getSize() == 1:
        return None
    own = model.owned_original
    gdof = 2 * (model.first + np.arange(own.size))[:, None] + np.arange(2)
    odof = 2 * own[:, None] + np.arange(2)
    total = 2 * model.nnodes
    if nodes is not None:          # only these nodes, in their order
        where = -np.ones(model.nnodes, dtype=int)
        where[np.asarray(nodes)] = np.arange(len(nodes))
        keep = where[own] >= 0
        gdof, odof = gdof[keep], 2 * where[own[keep]][:, None] + np.arange(2)
        total = 2 * len(nodes)
    rank0 = comm.getRank() == 0
    target = PETSc.Vec().createMPI((total if rank0 else 0, total), comm=comm)
    source = PETSc.Vec().createMPI((2 * own.size, PETSc.DECIDE), comm=comm)
    scatter = PETSc.Scatter().create(
        source, PETSc.IS().createGeneral(gdof.ravel().astype(PETSc.IntType), comm=comm),
        target, PETSc.IS().createGeneral(odof.ravel().astype(PETSc.IntType), comm=comm))

    def gather(values):
        source.setArray(values)
        scatter.scatter(source, target, addv=PETSc.InsertMode.INSERT,
                        mode=PETSc.ScatterMode.FORWARD)
        return target.getArray(readonly=True).copy() if rank0 else None
    return gather


class PlaneRestart:
    """What a restart keeps beyond (u, v): each rank's energy sums, so
    that a continued run sums as the uninterrupted one did."""

    def __init__(self, solver):
        self.solver = solver

    def saved(self):
        parts = self.solver.space.gather_on_rank0(self.solver.sums.copy())
        if parts is None:
            return None
        out = {layout.ENERGY_STATE: np.array(parts)}
        if self.solver.zone is not None:         # a yielding zone's points (rank 0's)
            out[layout.SOIL_STATE] = self.solver.zone.snapshot()
        return out

    def restore(self, state):
        zone = self.solver.zone
        if zone is not None:
            # rank 0 holds the zone; its refusal of the file is every rank's
            # (one rank raising alone would leave the others in the run)
            problem = None
            if self.solver.comm.getRank() == 0:
                try:
                    zone.restore(state[layout.SOIL_STATE])
                except InputError as exc:
                    problem = str(exc)
            problem = self.solver.comm.tompi4py().bcast(problem, root=0)
            if problem is not None:
                raise InputError(problem)
        parts = state.get(layout.ENERGY_STATE) if state else None
        if parts is not None and parts.shape[1] < len(SUMS):    # written before interfaces
            parts = np.pad(parts, ((0, 0), (0, len(SUMS) - parts.shape[1])))
        space = self.solver.space
        if parts is not None and len(parts) == self.solver.comm.getSize():
            self.solver.sums[:] = parts[self.solver.comm.getRank()]
        elif parts is not None:           # another number of ranks: rank 0 takes them all
            self.solver.sums[:] = np.sum(parts, axis=0) if space.comm.getRank() == 0 else 0.0
