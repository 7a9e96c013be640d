"""The slab solver of one run (constant dt) on PETSc.

Unknowns and rows are mixed per node (slab.recurrence: unknowns
z = dt/2 (v^2 - v^1, v^1 + v^2), rows by W) so that the right-hand side is a
running sum: a slab without an active law costs one solve with A's factors,
one product with a sparse matrix of three entries a row (b += G z) and one
vector sum (u += z_2); the state (u, v) is formed only for output.  A below
is that transformed slab matrix, X the unknowns z.

Per slab: one solve gives the law-free solution; if no nonlinear law is
active anywhere in the slab for it, it is the answer (the laws' terms
vanish); otherwise Newton (:mod:`vstpetsc.line.solver.newton`) starts from it.
The slab's energy terms (docs/loads.md section 4) are summed as it closes.
"""

import math

import numpy as np

from vstpetsc.spacetime import slab

from vstpetsc.line import bands
from vstpetsc.line.envelope import StressEnvelope
from vstpetsc.errors import SolveFailed
from vstpetsc.line.loading import SlabLoads
from vstpetsc.line.native.closing import SlabClose
from vstpetsc.line.solver import material_newton
from vstpetsc.line.solver.energy_sums import EnergySums
from vstpetsc.line.solver.fields import FieldTerms
from vstpetsc.line.solver.law_solver import LawSolver
from vstpetsc.line.solver.linear import LinearSolver
from vstpetsc.line.solver.matrices import block_matrix
from vstpetsc.line.solver.reactions import Reactions
from vstpetsc.line.solver.restart import RestartState
from vstpetsc.line.solver.slab_end import SlabEnd
from vstpetsc.line.solver.slab_forces import SlabForces
from vstpetsc.line.solver.space import Halo, Space
from vstpetsc.line.solver.work import DampingWork


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

    Its parts: the slab matrix A and its factors (:meth:`_linear_system`:
    LinearSolver), the terms of a slab's right-hand side and their work
    (:meth:`_slab_terms`: SlabForces, FieldTerms, Reactions, DampingWork,
    EnergySums), the state between slabs and the end of a slab
    (:meth:`_slab_state`: the envelopes, SlabClose or SlabEnd), and the
    nonlinear laws (LawSolver, a soil's material Newton); what a restart
    keeps of it (RestartState).  A slab is :meth:`rhs`, :meth:`solve` and
    :meth:`advance`.

    Parameters
    ----------
    model : vstpetsc.line.model.Model
    dt : float
    comm : PETSc communicator
    options : vstpetsc.petsc.options.SolverOptions
    loads : vstpetsc.line.loading.SlabLoads, optional
        The model's loads (built from its laws when not given).
    """

    def __init__(self, model, dt, comm, options, loads=None):
        loads = SlabLoads(model.laws, dt) if loads is None else loads
        self.dt, self.ops, self.fixed_nodes = dt, model.ops, loads.fixed_nodes
        self.space = Space(model.mesh.nnodes, comm, options.ownership)
        self.serial, self.native = comm.getSize() == 1, options.native
        # unknowns and rows mixed per node (slab.recurrence), and the carry
        # of a term of the running sum into the next slab's
        self.W, self.V, _, _ = slab.recurrence(dt)
        self.carry = self.W @ (slab.CARRY - np.eye(2)) @ np.linalg.inv(self.W)
        self._linear_system(model, options)
        self._slab_terms(loads, options)
        self._slab_state(model, options)
        self.nonlinear = LawSolver(model, options, self)
        self.laws = self.nonlinear.laws
        self.material = material_newton.of(model, self, options)
        self.restart = RestartState(self)

    def _linear_system(self, model, options):
        """A, its factors (the linear solver, set up here) and the vectors
        of a slab: the running right-hand side b (W r) and the unknowns X
        (z per node), both stored in numpy arrays of ours (br, x: the
        per-slab numpy work uses the arrays, PETSc the vectors)."""
        self.A = block_matrix(self.matrix_blocks(), self.space.nodes, self.space.comm,
                              options.mat_type)
        self.linear = LinearSolver(self.A, self.space, schwarz_overlap(model.mesh, self.dt))
        (self.b, self.br), (self.X, self.x) = self.linear.vectors(self.space)

    def _slab_terms(self, loads, options):
        """The terms of a slab's right-hand side beyond the running sum,
        and the sums of their work."""
        self.fields = FieldTerms(self.space, loads, self.W, self.V, self.dt)
        self.reactions = None if loads.all_fixed else \
            Reactions(self.space, self.ops, self.dt, self.W, self.V, loads.fixed_nodes)
        self.forces = SlabForces(self.space.nodes, self.W, self.V, self.reactions)
        self.damping = DampingWork(self.space, self.ops, self.dt, self.V, options.mat_type)
        self.sums = EnergySums(self.space, self.damping, self.fields, self.forces,
                               self.reactions)

    def _slab_state(self, model, options):
        """The state between slabs (this rank's u, the v^2 formed for
        output, the envelopes) and the end of a slab that updates it: in
        compiled code, G's product included (on several ranks with the
        neighbours' z through a halo), or numpy's."""
        n0, n1 = nodes = self.space.nodes
        self.Y, self.y = self.space.array_vector()    # (u, v) per node, for output
        self.u = np.zeros(n1 - n0)      # displacement of the owned nodes
        self.v = np.zeros(n1 - n0)      # v^2 of the owned nodes, formed for output
        self.u_ghost = np.zeros(1)      # u of node n1 (the next rank's first), if any
        self.envelope = StressEnvelope(model.mesh, nodes)
        halo = None if self.serial else Halo(self.X, nodes, model.mesh.nnodes)
        self.end = SlabClose.of(self, self.ops, options.native, halo) or \
            SlabEnd(self, self.ops)

    def matrix_blocks(self):
        """The block bands (N, 3, 2, 2) of A: the slab matrix in the mixed
        unknowns and rows, prescribed rows replaced by identities."""
        fixed = (2 * self.fixed_nodes[:, None] + np.arange(2)).ravel()
        return bands.impose_dirichlet(bands.slab_matrix(self.ops, self.dt, self.W, self.V),
                                     fixed, 1.0)

    def describe(self):
        soil = "" if self.material is None else self.material.describe()
        return self.linear.describe() + self.nonlinear.describe() + soil

    def rhs(self, forces, velocities, fields):
        """Add the slab's nodal force integrals and body forces to the
        running b and set the prescribed velocities: (nodes, values (n, 2))
        pairs in the velocity basis, global node numbers (nodes not owned
        are skipped); ``fields`` the integrals of the body forces."""
        self.forces.add(self.br, forces)
        if fields.size:
            self.fields.add(self.br, fields)
        self.forces.prescribe(self.br, velocities)

    def solve(self, slab_index):
        """Solve the slab for the current b; returns (Newton its, linear its)."""
        count = self.linear.count
        self.linear.solve(self.b, self.X, slab_index)
        newton = 0
        if self.material is not None:
            newton = self.material.solve(self.X, self.b, slab_index)
        if self.nonlinear.active and not self.nonlinear.hosted:
            newton = self.nonlinear.solve(self.X, self.b, self.dt, slab_index)
        if not self.linear.finite(self.X, self.x):
            raise SolveFailed(f"slab {slab_index}: the solution is not finite")
        return newton, self.linear.count - count

    def advance(self):
        """Close the slab: its energy terms, b += G z (the running sum)
        minus the force terms, u += z_2 (slab.recurrence)."""
        arr = self.br
        if self.reactions is not None:
            self.reactions.solved(self.X)
        self.sums.add_slab(self.X, self.x)       # the laws' share: in their solvers
        if self.reactions is not None:
            self.reactions.carry(arr)
        self.end.close()
        self.forces.carry(arr)
        self.fields.carry(arr)
        if self.reactions is not None:
            self.reactions.carry_after(arr)
        if self.nonlinear.active:
            self.nonlinear.advance(self.X, self.b)
        if self.material is not None:
            self.material.advance(self.b)

    def totals(self):
        """The summed energy terms over every rank (collective)."""
        return self.sums.totals(self.nonlinear, self.material)

    def set_state(self, u, v, envelope=None):
        """Start from displacements u and velocities v (global node arrays):
        b = W R (u, v) (every row in the same order on any number of ranks)
        plus the constant body forces; ``envelope`` (lo, hi) of every
        element continues a restart's envelopes."""
        n0, n1 = self.space.nodes
        R = bands.rhs_operator(self.ops, self.dt, self.W)
        self.br[:] = bands.apply_blocks(R, np.column_stack([u, v]), n0, n1).ravel()
        self.fields.fold(self.br)
        self.u[:] = u[n0:n1]
        self.forces.open = None
        self.nonlinear.set_state(u)
        if self.material is not None:
            self.material.soil.start(u)
        self.u_ghost[0] = u[n1] if self.envelope.ghost else 0.0
        el = self.envelope.elements
        restored = None if envelope is None else (envelope[0][el], envelope[1][el])
        self.envelope.start(self.u, self.u_ghost[0], restored)

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
        close summed them (None: the LineEnergyBook sums them)."""
        return self.end.energies()

    def elongation(self):
        """u_{i+1} - u_i of every node pair after the last slab, on one rank
        (the envelopes' own; None on several ranks)."""
        return self.envelope.buf if self.serial else None

    def probe(self, nodes):
        """A callable giving (u, v) at the global ``nodes`` on rank 0 (None
        elsewhere), between slabs: the gauges' values."""
        from vstpetsc.line.solver.probe import NodeValues
        return NodeValues(self, nodes)

    def envelopes(self, nelements):
        """Elongation envelopes (lo, hi) of every element on rank 0 (None
        elsewhere)."""
        return self.space.assemble_on_rank0(nelements, *self.envelope.local())
