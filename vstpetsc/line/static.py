"""The static initial state of ``[gravity] initial = "static"`` (docs/loads.md
section 5): the state that the slab equations which follow keep unchanged.

1. The static problem (K + S) u + N(u) = F: F the static loads
   (``Law.static_loads``: the weight at g(0) and every load constant in
   time), N the laws' static forces (``Law.static``), every constrained
   node and every absorbing end held.  Newton on the whole mesh with a
   sparse direct solve; converged when the residual is rounding against the
   largest term that enters it (a backward error: the system's condition
   grows like the square of the element count, so a test relative to F
   alone never passes on fine meshes).  A part of the mesh that nothing
   holds is named instead of solved.
2. The fixed point of the slab map.  A state that repeats from slab to
   slab has u^{n+1} = u^n, so v^{n+} = w and v^{(n+1)-} = -w at every node
   for some w, with v^{n-} = -w.  The sum and the difference of a node's
   two slab equations (formulation.md section 2) then read

       (K + S)(u + dt w / 6) + (N^1 + N^2) / dt = F        (the slab mean)
       (2 M / dt + C / 3) w  + (N^1 - N^2) / dt = 0

   with N^a the laws' slab terms (``Law.force``) for that motion.  A law
   whose force at rest weighs the two time levels alike (power penalty,
   cushion, Smith soil: forces tested with T_a) has N^1 = N^2 at w = 0, and
   step 1 is already the fixed point.  The seed penalty tests the gap with
   I_a, which weighs them 2 : 1, so its fixed point has the contact nodes
   move inside every slab and come back (w != 0): Newton on (u, w) from
   step 1's u, the laws' u-derivatives by central differences.

Every rank computes it alike.  numpy and scipy.
"""

from dataclasses import dataclass

import numpy as np
import scipy.sparse
import scipy.sparse.csgraph
import scipy.sparse.linalg

from vstpetsc.errors import InputError
from vstpetsc.spacetime.history import History
from vstpetsc.line.laws.base import FieldLoad, Law, Load

MAX_NEWTON = 50
RESIDUAL_TOL = 1e-12      # of the largest term that enters the residual
FLOATING_TOL = 1e-12      # a part's row sums against its diagonal: rounding
FD_STEP = 1e-7            # relative step of the laws' u-derivatives


class HeldReactions(Law):
    """The reactions of the ends held during the static solve, applied as
    constant forces for the whole run: the rock below an absorbing end
    carries the static load, its dashpot only what moves."""

    def __init__(self, nodes, forces):
        self.pairs = [(int(n), float(f)) for n, f in zip(nodes, forces)]

    def loads(self):
        return [Load(n, f, History(value=1.0)) for n, f in self.pairs]

    def describe(self):
        return ("static start: reactions " +
                ", ".join(f"{f:.6g} at node {n}" for n, f in self.pairs)) if self.pairs else ""


@dataclass
class StaticStart:
    """Displacements and velocities v^{0-} to start from, and the held ends'
    reactions (a law to add to the model)."""

    u: np.ndarray
    v: np.ndarray
    reactions: HeldReactions


def static_state(model, dt):
    """The StaticStart of ``model`` for slabs of length ``dt``."""
    problem = StaticProblem(model, dt)
    u = problem.rest()
    u, w = problem.stationary(u)
    reactions = problem.reactions(u, w)
    for law in problem.laws:       # the slab terms of the last evaluation: none yet
        law.last = None
    return StaticStart(u, -w, HeldReactions(problem.absorbing, reactions))


def static_forces(laws, nnodes):
    """The nodal forces of the static loads (their values at t = 0)."""
    f = np.zeros(nnodes)
    for law in laws:
        for load in law.static_loads():
            if isinstance(load, FieldLoad):
                f += load.vector * float(load.history(0.0))
            else:
                f[load.node] += load.weight * float(load.history(0.0))
    return f


def band_matrix(diag, off):
    return scipy.sparse.diags([off, diag, off], [-1, 0, 1], format="csr")


class StaticProblem:
    """The two steps of the module docstring on ``model``'s mesh."""

    def __init__(self, model, dt):
        ops, n = model.ops, model.mesh.nnodes
        self.model, self.dt, self.n = model, dt, n
        self.K = band_matrix(ops.k_diag + ops.s_diag, ops.k_off + ops.s_off)
        self.D = band_matrix(2.0 * ops.m_diag / dt + ops.c_diag / 3.0,
                             2.0 * ops.m_off / dt + ops.c_off / 3.0)
        self.F = static_forces(model.laws, n)
        # the static state is the axial field's: the shear field (nodes from
        # axial_nodes on) starts from its own initial state, held here
        axial = model.mesh.axial_nodes
        self.laws = [law for law in model.nonlinear if law.nodes.max() < axial]
        constrained = [c.node for law in model.laws for c in law.constraints()]
        self.absorbing = sorted({node for law in model.laws for node in law.held_nodes()
                                 if node < axial})
        self.u_free = np.ones(n, dtype=bool)
        self.u_free[constrained + self.absorbing] = False
        self.u_free[axial:] = False
        self.w_free = self.u_free.copy()
        self.w_free[self.absorbing] = True

    # step 1: the static problem ------------------------------------------
    def rest(self):
        """u of the static problem (held nodes at 0)."""
        u = np.zeros(self.n)
        free = np.flatnonzero(self.u_free)
        for _ in range(MAX_NEWTON):
            r, J, scale = self._rest_residual(u)
            Jf = J[free][:, free].tocsc()
            # also without a static load: u = 0 is then one of many states
            self._check_held(Jf, free, u)
            if np.abs(r[free]).max(initial=0.0) <= RESIDUAL_TOL * scale:
                return u
            u[free] -= _lu(Jf).solve(r[free])
        self._not_converged(u, np.abs(r[free]).max() / scale)

    def _rest_residual(self, u):
        """(K u + N(u) - F, its Jacobian, the largest term's size)."""
        r = self.K @ u - self.F
        size = abs(self.K) @ np.abs(u) + np.abs(self.F)
        blocks = []
        for law in self.laws:
            nodes = law.nodes
            res, tan = law.static(u[nodes])
            np.add.at(r, nodes, res)
            np.add.at(size, nodes, np.abs(res))
            blocks.append((nodes, nodes, tan))
        return r, with_blocks(self.K, blocks), max(size.max(initial=0.0), 1e-300)

    def _check_held(self, J, free, u):
        """InputError naming what leaves a part of the mesh free to move."""
        loose = free[floating(J)]
        if loose.size == 0:
            return
        for law in self.laws:
            if np.isin(law.nodes, loose).any():
                line = law.static_limit(u[law.nodes])
                if line:
                    raise InputError(line)
        mesh = self.model.mesh
        names = [b.name for i, b in enumerate(self.model.case.bodies)
                 if np.isin(np.arange(mesh.first[i], mesh.first[i + 1]), loose).any()]
        raise InputError(
            "gravity.initial: \"static\" needs every body held in place (by a bc, an "
            "absorbing end, a support or foundation spring, soil, or a closed contact with "
            f"a held body); {_listed('body', names)} free to move as a whole")

    def _not_converged(self, u, residual):
        for law in self.laws:
            line = law.static_limit(u[law.nodes])
            if line:
                raise InputError(line)
        raise InputError(f"gravity.initial: the static state did not converge in {MAX_NEWTON} "
                         f"Newton iterations (residual {residual:.2g} of the largest force)")

    # step 2: the fixed point of the slab map ------------------------------
    def stationary(self, u):
        """(u, w) of the slab map's fixed point, from step 1's u."""
        w = np.zeros(self.n)
        mask = np.concatenate([self.u_free, self.w_free])
        for _ in range(MAX_NEWTON):
            r, scale = self._slab_residual(u, w)
            if np.abs(r[mask]).max(initial=0.0) <= RESIDUAL_TOL * scale:
                return u, w
            J = self._slab_jacobian(u, w)[mask][:, mask].tocsc()
            step = np.zeros(2 * self.n)
            step[mask] = _lu(J).solve(r[mask])
            u, w = u - step[:self.n], w - step[self.n:]
        self._not_converged(u, np.abs(r[mask]).max() / scale)

    def _terms(self, law, u, w):
        """The law's force() output for the slab motion (u, w), or None."""
        nodes = law.nodes
        law.start_slab(u[nodes], self.dt)
        y = float(law.signs @ w[nodes])
        return law.force(y, -y)

    def _law_terms(self, u, w):
        """The laws' (N^1 + N^2) / dt and (N^1 - N^2) / dt per node for the
        slab motion (u, w), and their sizes."""
        dt, n = self.dt, self.n
        total, diff, size = np.zeros(n), np.zeros(n), np.zeros(n)
        for law in self.laws:
            out = self._terms(law, u, w)
            if out is not None:
                nodes, c = law.nodes, law.signs
                np.add.at(total, nodes, c * (out[0] + out[1]) / dt)
                np.add.at(diff, nodes, c * (out[0] - out[1]) / dt)
                np.add.at(size, nodes, (abs(out[0]) + abs(out[1])) / dt)
        return total, diff, size

    def _slab_residual(self, u, w):
        """(the sum rows then the difference rows, the largest term's size)."""
        total, diff, size = self._law_terms(u, w)
        mean = u + self.dt * w / 6.0
        r = np.concatenate([self.K @ mean - self.F + total, self.D @ w + diff])
        big = np.concatenate([abs(self.K) @ np.abs(mean) + np.abs(self.F) + size,
                              abs(self.D) @ np.abs(w) + size])
        return r, max(big.max(initial=0.0), 1e-300)

    def _slab_jacobian(self, u, w):
        """The linear blocks [[K, dt K / 6], [0, D]] plus the laws' terms:
        d/dw from their tangents (y^2 = -y^1 = -sum c_k w_k), d/du by
        central differences."""
        dt, n = self.dt, self.n
        h = FD_STEP * max(np.abs(u).max(initial=0.0), 1e-300)
        blocks = []
        for law in self.laws:
            nodes, c = law.nodes, law.signs
            out = self._terms(law, u, w)
            dw = np.zeros((2, nodes.size, nodes.size))       # (sum, diff), node, node
            if out is not None:
                dy = np.array([(out[2] + out[4]) - (out[3] + out[5]),
                               (out[2] - out[4]) - (out[3] - out[5])]) / dt
                dw = dy[:, None, None] * np.outer(c, c)
            du = np.zeros_like(dw)
            for j, b in enumerate(nodes):
                plus, minus = u.copy(), u.copy()
                plus[b] += h
                minus[b] -= h
                du[:, :, j] = (self._rows_of(law, plus, w) - self._rows_of(law, minus, w)) / (2 * h)
            blocks += [(nodes, nodes, du[0]), (nodes + n, nodes, du[1]),
                       (nodes, nodes + n, dw[0]), (nodes + n, nodes + n, dw[1])]
        J = scipy.sparse.bmat([[self.K, self.K * (dt / 6.0)], [None, self.D]], format="csr")
        return with_blocks(J, blocks)

    def _rows_of(self, law, u, w):
        """One law's ((N^1 + N^2) / dt, (N^1 - N^2) / dt) on its nodes (2, n)."""
        out = self._terms(law, u, w)
        if out is None:
            return np.zeros((2, law.nodes.size))
        return np.outer([out[0] + out[1], out[0] - out[1]], law.signs) / self.dt

    def reactions(self, u, w):
        """The forces the held absorbing ends carry in the fixed point."""
        total, _, _ = self._law_terms(u, w)
        r = self.K @ (u + self.dt * w / 6.0) - self.F + total
        return r[self.absorbing]


def with_blocks(J, blocks):
    """J plus dense blocks: (row indices, column indices, block) triples."""
    if not blocks:
        return J
    rows = np.concatenate([np.repeat(r, c.size) for r, c, _ in blocks])
    cols = np.concatenate([np.tile(c, r.size) for r, c, _ in blocks])
    vals = np.concatenate([np.ravel(b) for _, _, b in blocks])
    return J + scipy.sparse.csr_matrix((vals, (rows, cols)), shape=J.shape)


def floating(J):
    """Indices of the rows of J in connected parts that nothing holds: a
    part's rows sum to zero (up to rounding) when it can move as a whole."""
    if J.shape[0] == 0:
        return np.zeros(0, dtype=int)
    count, labels = scipy.sparse.csgraph.connected_components(J, directed=False)
    rowsum = np.abs(J @ np.ones(J.shape[0]))
    held = (np.bincount(labels, rowsum, count)
            > FLOATING_TOL * np.bincount(labels, np.abs(J.diagonal()), count))
    return np.flatnonzero(~held[labels])


def _lu(J):
    try:
        return scipy.sparse.linalg.splu(J)
    except RuntimeError:                  # exactly singular
        raise InputError("gravity.initial: the static state's equations are singular "
                         "(a body or node that nothing holds)") from None


def _listed(word, names):
    if len(names) == 1:
        return f"{word} {names[0]!r} is"
    return f"{word.replace('y', 'ie')}s {', '.join(map(repr, names))} are"
