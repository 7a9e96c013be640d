"""The slab solver of one run (constant dt) on PETSc.

Unknowns and rows are mixed per node (slab.recurrence: unknowns
z = dt/2 (v^2 - v^1, v^1 + v^2), rows by W) so that the right-hand side is a
running sum: a slab without an active law costs one solve with A's factors,
one product with a sparse matrix of three entries a row (b += G z) and one
vector sum (u += z_2); the state (u, v) is formed only for output.  A below
is that transformed slab matrix, X the unknowns z.

Per slab: one solve gives the law-free solution; if no nonlinear law is
active anywhere in the slab for it, it is the answer (the laws' terms
vanish); otherwise Newton (:mod:`vstpetsc.petsc.newton`) starts from it.
The slab's energy terms (docs/loads.md section 4) are summed as it closes.
"""

import math

import numpy as np

from vstpetsc import slab
from vstpetsc.energy import SUMS, SUMS_BEFORE_FRICTION
from vstpetsc.envelope import StressEnvelope
from vstpetsc.errors import SolveFailed
from vstpetsc.loading import SlabLoads
from vstpetsc.native.closing import SlabClose
from vstpetsc.petsc.fields import FieldTerms
from vstpetsc.petsc import material_newton
from vstpetsc.petsc.law_solver import LawSolver
from vstpetsc.petsc.linear import LinearSolver
from vstpetsc.petsc.matrices import block_matrix
from vstpetsc.petsc.reactions import Reactions
from vstpetsc.petsc.slab_end import SlabEnd
from vstpetsc.petsc.space import Space
from vstpetsc.petsc.work import DampingWork


def schwarz_overlap(mesh, dt):
    """Nodes of overlap for the parallel solve: 32 per unit of the largest
    Courant number c dt / h, at least 32 (a slab's coupling decays by about
    0.3 per element at c dt/h <= 1, 0.6 at 4: docs/parallel.md)."""
    if mesh.h.size == 0:
        return 32
    courant = float(np.max(np.sqrt(mesh.E / mesh.rho) * dt / mesh.h))
    return 32 * max(1, math.ceil(courant))


class SlabSolver:
    """Assembles and solves the slab equations of ``model`` (laws included).

    Parameters
    ----------
    model : vstpetsc.model.Model
    dt : float
    comm : PETSc communicator
    options : vstpetsc.petsc.options.SolverOptions
    loads : vstpetsc.loading.SlabLoads, optional
        The model's loads (built from its laws when not given).
    """

    def __init__(self, model, dt, comm, options, loads=None):
        self.dt = dt
        loads = SlabLoads(model.laws, dt) if loads is None else loads
        ops = model.ops
        self.space = Space(model.mesh.nnodes, comm, options.ownership)
        n0, n1 = nodes = self.space.nodes
        self.W, self.V, _, _ = slab.recurrence(dt)
        self.Vinv = np.linalg.inv(self.V)
        self.WT = self.W @ slab.CARRY                     # W T
        self.carry = self.W @ (slab.CARRY - np.eye(2)) @ np.linalg.inv(self.W)
        self.ops = ops
        self.fixed_nodes = loads.fixed_nodes
        self.A = block_matrix(self.matrix_blocks(), nodes, comm, options.mat_type)
        # vectors stored in numpy arrays of ours (the per-slab numpy work
        # uses the arrays, PETSc the vectors)
        self.Y, self.y = self.space.array_vector()    # (u, v) per node, for output
        self.X, self.x = self.space.array_vector()    # slab unknowns z per node
        self.b, self.br = self.space.array_vector()   # W r: the running right-hand side
        self.v = np.zeros(n1 - n0)      # v^2 of the owned nodes, formed for output
        self.serial = comm.getSize() == 1
        self.native = options.native
        self.u = np.zeros(n1 - n0)      # displacement of the owned nodes
        self._loads = None              # (local dofs, -W T f, f) of the open slab
        self._row_cache = {}
        self.linear = LinearSolver(self.A, self.space, schwarz_overlap(model.mesh, dt))
        self.fields = FieldTerms(self.space, loads, self.W, self.V, dt)
        self.reactions = None if loads.all_fixed else \
            Reactions(self.space, ops, dt, self.W, self.V, loads.fixed_nodes)
        self.damping = DampingWork(self.space, ops, dt, self.V, options.mat_type)
        self.envelope = StressEnvelope(model.mesh, nodes)
        self.u_ghost = 0.0
        # one rank: the slab's end in compiled code, G's product included
        self.end = SlabClose.of(self, ops, options.native) or SlabEnd(self, ops)
        self.nonlinear = LawSolver(model, options, self)
        self.laws = self.nonlinear.laws
        self.material = material_newton.of(model, self, options)
        self.work = {"damping": 0.0}       # sums, the same on every rank
        self.local_work = 0.0          # this rank's share of the external work

    def matrix_blocks(self):
        """The block bands (N, 3, 2, 2) of A: the slab matrix in the mixed
        unknowns and rows, prescribed rows replaced by identities."""
        fixed = (2 * self.fixed_nodes[:, None] + np.arange(2)).ravel()
        return slab.impose_dirichlet(slab.slab_matrix(self.ops, self.dt, self.W, self.V),
                                     fixed, 1.0)

    def describe(self):
        soil = "" if self.material is None else self.material.describe()
        return self.linear.describe() + self.nonlinear.describe() + soil

    def rhs(self, forces, velocities, fields):
        """Add the slab's nodal force integrals and body forces to the
        running b and set the prescribed velocities: (nodes, values (n, 2))
        pairs in the velocity basis, global node numbers (nodes not owned
        are skipped); ``fields`` the integrals of the body forces."""
        arr = self.br
        self._loads = None
        nodes, per = forces
        if nodes.size:
            idx, own = self._rows(nodes)
            arr[idx] += (per[own] @ self.W.T).ravel()
            self._loads = (idx, -(per[own] @ self.WT.T).ravel(), per[own])   # for advance()
        if fields.size:
            self.fields.add(arr, fields)
        nodes, vals = velocities
        if nodes.size:
            idx, own = self._rows(nodes)
            if self.reactions is not None:
                self.reactions.hold(arr)
                arr[idx] = (vals @ self.Vinv.T)[own].ravel()
            else:                              # fixed nodes: zero velocities
                arr[idx] = 0.0

    def _rows(self, nodes):
        """(local dofs of the owned ones among ``nodes``, their mask), cached
        per node array (the loads' and constraints' nodes never change)."""
        key = id(nodes)
        if key not in self._row_cache:
            n0, n1 = self.space.nodes
            own = (nodes >= n0) & (nodes < n1)
            self._row_cache[key] = ((2 * (nodes[own] - n0)[:, None] + np.arange(2)).ravel(), own)
        return self._row_cache[key]

    def solve(self, slab_index):
        """Solve the slab for the current b; returns (Newton its, linear its)."""
        count = self.linear.count
        self.linear.solve(self.b, self.X, slab_index)
        newton = 0
        if self.material is not None:
            newton = self.material.solve(self.X, self.b, slab_index)
        if self.nonlinear.active:
            newton = self.nonlinear.solve(self.X, self.b, self.dt, slab_index)
        if not self.linear.finite(self.X, self.x):
            raise SolveFailed(f"slab {slab_index}: the solution is not finite")
        return newton, self.linear.count - count

    def advance(self):
        """Close the slab: its energy terms, b += G z (the running sum)
        minus the force terms, u += z_2 (slab.recurrence)."""
        self._slab_work()
        arr = self.br
        if self.reactions is not None:
            self.reactions.carry(arr)
        self.end.close()
        if self._loads is not None:
            arr[self._loads[0]] += self._loads[1]
            self._loads = None
        self.fields.carry(arr)
        if self.reactions is not None:
            self.reactions.carry_after(arr)
        if self.nonlinear.active:
            self.nonlinear.advance(self.X, self.b)
        if self.material is not None:
            self.material.advance(self.b)

    def _slab_work(self):
        """Dashpots and external forces over the slab (the laws' share is
        summed in _solve_laws)."""
        if self.damping.D is not None:
            self.work["damping"] += self.damping(self.X)
        x = self.x
        if self.fields.active:
            self.local_work += self.fields.work(x)
        if self._loads is not None:
            idx, _, per = self._loads
            self.local_work += float(np.sum(per * (x[idx].reshape(-1, 2) @ self.V.T)))
        if self.reactions is not None:
            self.reactions.solved(self.X)
            self.local_work += self.reactions.work(x)

    def totals(self):
        """The summed energy terms over every rank (collective)."""
        laws = dict(self.nonlinear.work)
        # a moving wall's work through friction is external, the same on every
        # rank, and so is the work of supports against a soil's stress
        beyond = laws.get("wall", 0.0)
        if self.material is not None:
            soil = self.material.soil
            laws["strain_beyond_linear"], laws["hysteretic"] = soil.energies()
            beyond += soil.support_work
        return {**self.work, **laws,
                "external": self.space.sum_over_ranks(self.local_work) + beyond}

    def set_state(self, u, v, envelope=None):
        """Start from displacements u and velocities v (global node arrays):
        b = W R (u, v) (every row in the same order on any number of ranks)
        plus the constant body forces; ``envelope`` (lo, hi) of every
        element continues a restart's envelopes."""
        n0, n1 = self.space.nodes
        R = slab.rhs_operator(self.ops, self.dt, self.W)
        self.br[:] = slab.apply_blocks(R, np.column_stack([u, v]), n0, n1).ravel()
        self.fields.fold(self.br)
        self.u[:] = u[n0:n1]
        self._loads = None
        self.nonlinear.set_state(u)
        if self.material is not None:
            self.material.soil.start(u)
        self.u_ghost = float(u[n1]) if self.envelope.ghost else 0.0
        el = self.envelope.elements
        restored = None if envelope is None else (envelope[0][el], envelope[1][el])
        self.envelope.start(self.u, self.u_ghost, restored)

    def set_restart_state(self, state):
        """Continue from the running right-hand side saved by rhs_state()
        (a global array), the Newton state of the last slab and the energy
        sums of energy_sums() ({layout name: array}, from the file), after
        set_state: the restart is then bit for bit."""
        from vstpetsc.results.layout import ENERGY_STATE, NEWTON_STATE, RHS_STATE, SOIL_STATE

        n0, n1 = self.space.nodes
        if RHS_STATE in state:
            self.br[:] = state[RHS_STATE][2 * n0:2 * n1]
        if NEWTON_STATE in state:
            self.nonlinear.set_newton_state(state[NEWTON_STATE])
        if ENERGY_STATE in state:
            self._restore_sums(state[ENERGY_STATE])
        if SOIL_STATE in state and self.material is not None:
            saved = state[SOIL_STATE]
            size = self.material.soil.snapshot().size
            self.material.soil.restore(saved[:size])
            self.material.restore(saved[size:])

    def soil_state(self):
        """A hysteretic soil's state and its Newton's start (None without
        one; the same on every rank)."""
        if self.material is None:
            return None
        return np.concatenate([self.material.soil.snapshot(), self.material.state()])

    def energy_sums(self):
        """The running sums of the energy terms (energy.SUMS order), then
        every rank's share of the external work, on rank 0 (None
        elsewhere; collective)."""
        shares = self.space.gather_on_rank0(self.local_work)
        if shares is None:
            return None
        sums = {**self.work, **self.nonlinear.work}
        return np.array([sums.get(key, 0.0) for key in SUMS] + list(shares))

    def _restore_sums(self, saved):
        """Take back the sums of :meth:`energy_sums`; on another number of
        ranks rank 0 takes the whole external work (equal to rounding)."""
        rank, size = self.space.comm.getRank(), self.space.comm.getSize()
        names = SUMS if saved.size != len(SUMS_BEFORE_FRICTION) + size else SUMS_BEFORE_FRICTION
        sums, shares = saved[:len(names)], saved[len(names):]
        for key, value in zip(names, sums.tolist()):
            for work in (self.work, self.nonlinear.work):
                if key in work:
                    work[key] = value
        if shares.size == size:
            self.local_work = float(shares[rank])
        else:
            self.local_work = float(shares.sum()) if rank == 0 else 0.0

    def gather_state(self):
        """(u, v) of all nodes on rank 0 (None elsewhere); v = v^2 of the
        last slab.  On one rank these are the solver's own arrays, valid
        until the next slab."""
        self.end.velocities()
        if self.serial:
            return self.u, self.v
        y = self.y.reshape(-1, 2)
        y[:, 0] = self.u
        y[:, 1] = self.v
        y = self.space.to_rank0(self.Y)
        return None if y is None else (y[0::2].copy(), y[1::2].copy())

    def state_energies(self):
        """(kinetic, strain) energy after the last slab when the compiled
        close summed them (None: the EnergyBook sums them)."""
        return self.end.energies()

    def elongation(self):
        """u_{i+1} - u_i of every node pair after the last slab, on one rank
        (the envelopes' own; None on several ranks)."""
        return self.envelope.buf if self.serial else None

    def rhs_state(self):
        """The running right-hand side of all dofs on rank 0 (None
        elsewhere), between slabs."""
        return self.space.to_rank0(self.b)

    def envelopes(self, nelements):
        """Elongation envelopes (lo, hi) of every element on rank 0 (None
        elsewhere)."""
        return self.space.assemble_on_rank0(nelements, *self.envelope.local())
