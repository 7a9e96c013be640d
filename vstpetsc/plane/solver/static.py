"""The static start of a plane-strain run under gravity ([gravity]
initial = "static", as in 1-D: docs/loads.md): K u = f, f the weight at
g(0) with the water's pressure (docs/water.md), the tractions constant
in time and the uplift in interfaces (constant, vstpetsc.plane.uplift),
with every held dof and every node of an absorbing curve held, solved
once; the run then starts from rest in u with the absorbing nodes'
reactions K u - f kept as constant forces (interfaces: each pair closed
or open, sticking or sliding at mu N, settled by repeated solves, vstpetsc.plane.pairs), so that (u, 0) is
an exact equilibrium of the slab equations (with v = 0 their right-hand
side is dt/2 (f - K u) on both time rows, zero everywhere).  A part of
the mesh that nothing holds is named instead (vstpetsc.plane.rigidity).

The solve is rank 0's, on the whole mesh in its numbering as read, with
PETSc's LU on one process whatever the number of ranks: the static state
is then the same bits on any number of ranks and in every run (MUMPS's
parallel factorisation is not repeatable bit for bit)."""

from dataclasses import dataclass

import numpy as np
from petsc4py import PETSc

from vstpetsc.errors import InputError
from vstpetsc.spacetime.history import History
from vstpetsc.plane.assembly import identity_rows
from vstpetsc.plane.solver.matrices import node_matrix

PREFIX = "vst_static_"
SETTLE_ROUNDS = 30


@dataclass
class PlaneStatic:
    u: np.ndarray           # (nn, 2) of every node, the mesh's numbering as read (every rank)
    reactions: tuple        # (pattern over the owned dofs, History 1): the kept forces

    @property
    def v(self):
        """At rest (the 1-D static start's v, for the time loop's sum)."""
        return np.zeros_like(self.u)


def _original_dofs(model, positions):
    """The mesh-as-read dofs of owned dof positions."""
    positions = np.asarray(positions, dtype=int)
    return 2 * model.owned_original[positions // 2] + positions % 2


def _solve_on_rank0(model, held, g0, carried):
    """u of every node (mesh as read), solved on rank 0 (None elsewhere),
    under the weight at g0 and the ``carried`` loads (dofs, forces); with
    interfaces, their pairs' states settled (``_settled``)."""
    from vstpetsc.plane.loads import whole_gravity
    from vstpetsc.plane.model import spatial_matrices

    M, _, K = spatial_matrices(model.mesh, model.cell_materials)
    rhs = whole_gravity(model, M) * g0
    np.add.at(rhs, *carried)
    rhs[held] = 0.0
    if model.pairs is None:
        _refuse_free(model.mesh, held)
        return _linear_solve(K, held, rhs)
    return _settled(model, K, held, rhs)


def _refuse_free(mesh, held, pairs=None, state=None):
    """InputError naming a part of the mesh that the held dofs and the
    pairs' springs in ``state`` (closed: normal; sticking with friction:
    tangential) leave free to move as a rigid body (vstpetsc.plane.rigidity):
    K u = f would have no single solution."""
    from vstpetsc.plane.rigidity import free_part

    nodes, directions = np.zeros((0, 2), int), np.zeros((0, 2))
    if pairs is not None:
        closed, sticking, _ = state
        along = closed & sticking & (pairs.kt > 0)
        nodes = np.concatenate([pairs.nodes[closed], pairs.nodes[along]])
        directions = np.concatenate([pairs.normal[closed], pairs.tangent[along]])
    words = free_part(mesh, held, nodes, directions)
    if words is not None:
        because = "" if pairs is None else \
            " (interfaces hold a part where their pairs are closed, and along them where " \
            f"they also stick; {_pair_states(state)})"
        raise InputError(f"gravity.initial: \"static\" needs every part of the mesh held in "
                         f"place by a fixed, velocity or absorbing curve or an interface to a "
                         f"held part{because}; {words}")


def _linear_solve(K, held, rhs):
    """u with K u = rhs (held rows identities), by PETSc's LU on rank 0."""
    A = node_matrix(identity_rows(K.tocsr(), held, 0), PETSc.COMM_SELF)
    ksp = PETSc.KSP().create(comm=PETSc.COMM_SELF)
    ksp.setOptionsPrefix(PREFIX)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorOrdering("nd")
    ksp.setFromOptions()
    x, b = A.createVecs()
    b.setArray(rhs)
    ksp.solve(b, x)
    return x.getArray(readonly=True).copy()


def _pair_states(state):
    """Words for the pairs' static states."""
    closed, sticking, _ = state
    if closed.all() and sticking.all():
        return "every pair taken closed and sticking"
    return (f"settled under the static load: {int((~closed).sum())} of {closed.size} pairs "
            f"open, {int((closed & ~sticking).sum())} sliding")


def _settled(model, K, held, rhs):
    """u under the interfaces' static laws: each pair closed (its normal
    spring) or open (nothing), sticking (its stick spring) or sliding
    (the force mu N against its tangential displacement, N from its
    normal spring): states guessed closed and sticking, then taken from
    the solution until they repeat (at most SETTLE_ROUNDS solves)."""
    from vstpetsc.plane.pairs import static_guess, static_matrix, static_state

    pairs = model.pairs
    state = static_guess(pairs)
    for _ in range(SETTLE_ROUNDS):
        _refuse_free(model.mesh, held, pairs, state)
        u = _linear_solve(K + static_matrix(pairs, state, K.shape[0] // 2), held, rhs)
        new = static_state(pairs, u.reshape(-1, 2))
        if all(np.array_equal(a, b) for a, b in zip(new, state)):
            return u
        state = new
    raise InputError("gravity.initial: the interfaces' static states did not settle in "
                     f"{SETTLE_ROUNDS} solves (pairs keep switching between sticking, "
                     "sliding and opening)")


def static_state(model, gravity_pattern):
    """The PlaneStatic of ``model`` under the load pattern of g(0), this
    rank's rows of it ``gravity_pattern`` (collective)."""
    comm, bounds = model.comm, model.boundaries
    g0 = float(model.case.gravity.g(np.array([0.0]))[0])
    held_here = np.union1d(bounds.held_dofs()[0], bounds.absorbing_dofs())
    held = comm.tompi4py().gather(_original_dofs(model, held_here), root=0)
    from vstpetsc.plane.loads import uplift_pattern

    carried = bounds.constant_loads() + uplift_pattern(model)
    loaded = np.flatnonzero(carried)
    carried_all = comm.tompi4py().gather((_original_dofs(model, loaded), carried[loaded]),
                                         root=0)
    u = error = None
    if comm.getRank() == 0:
        try:
            u = _solve_on_rank0(model, np.unique(np.concatenate(held)), g0,
                                tuple(np.concatenate(part) for part in zip(*carried_all)))
        except InputError as exc:       # every rank raises it
            error = str(exc)
    if comm.getSize() > 1:
        u, error = comm.tompi4py().bcast((u, error), root=0)
    if error is not None:
        raise InputError(error)
    # the reactions from this rank's rows of K, u in the global numbering
    local = model.local
    u_global = np.zeros(2 * model.nnodes)
    dof = (2 * local.global_vertex[:, None] + np.arange(2)).ravel()
    u_global[dof] = u.reshape(-1, 2)[local.original].ravel()
    _, _, K = model.matrices()
    springs = model.closed_springs()
    if springs is not None:             # (absorbing nodes are not a pair's in practice)
        K = K + springs
    reaction = np.zeros(K.shape[0])
    free_absorbing = np.setdiff1d(bounds.absorbing_dofs(), bounds.held_dofs()[0])
    reaction[free_absorbing] = (K @ u_global - gravity_pattern * g0 - carried)[free_absorbing]
    return PlaneStatic(u.reshape(-1, 2), (reaction, History(value=1.0)))
