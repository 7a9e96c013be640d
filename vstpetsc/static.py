"""The static initial state of ``[gravity] initial = "static"`` (docs/loads.md
section 5): (K + S) u + N(u) = F(0) with the constrained nodes and every
absorbing end held fixed, N the static forces of the nonlinear laws (a
penalty pair acts as a spring of its slab-mean stiffness).  Newton on the
whole mesh with a sparse direct solve (the system is tridiagonal; a pair's
two nodes are neighbours).  Every rank computes it alike.  numpy and scipy.
"""

import warnings

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

from vstpetsc.errors import InputError
from vstpetsc.history import History
from vstpetsc.laws.base import FieldLoad, Law, Load

MAX_NEWTON = 50


class HeldReactions(Law):
    """The reactions of the ends held during the static solve, applied as
    constant forces for the whole run."""

    def __init__(self, nodes, forces):
        self.pairs = [(int(n), float(f)) for n, f in zip(nodes, forces)]

    def loads(self):
        return [Load(n, f, History(value=1.0)) for n, f in self.pairs]

    def describe(self):
        return ("static start: reactions " +
                ", ".join(f"{f:.6g} at node {n}" for n, f in self.pairs)) if self.pairs else ""


def initial_forces(laws, nnodes):
    """The nodal forces of every load at t = 0."""
    f = np.zeros(nnodes)
    for law in laws:
        for load in law.loads():
            if isinstance(load, FieldLoad):
                f += load.vector * float(load.history(0.0))
            else:
                f[load.node] += load.weight * float(load.history(0.0))
    return f


def static_state(model):
    """(u, HeldReactions) of the static problem of ``model``."""
    n = model.mesh.nnodes
    ops = model.ops
    K = scipy.sparse.diags([ops.k_off + ops.s_off, ops.k_diag + ops.s_diag,
                            ops.k_off + ops.s_off], [-1, 0, 1], format="csr")
    F = initial_forces(model.laws, n)
    held = sorted({c.node for law in model.laws for c in law.constraints()}
                  | {node for law in model.laws for node in law.held_nodes()})
    free = np.setdiff1d(np.arange(n), held)
    u = np.zeros(n)
    for _ in range(MAX_NEWTON):
        r, J = _residual(model, K, F, u)
        du = _solve(J[free][:, free], -r[free])
        u[free] += du
        # the forces are piecewise linear in u: once the active set holds,
        # the step is exact and the next one is rounding
        if np.abs(du).max(initial=0.0) <= 1e-12 * max(np.abs(u).max(), 1e-300):
            break
    else:
        raise InputError(f"gravity.initial: the static state did not converge in "
                         f"{MAX_NEWTON} Newton iterations")
    r, _ = _residual(model, K, F, u)
    absorbing = [node for law in model.laws for node in law.held_nodes()]
    return u, HeldReactions(absorbing, r[absorbing])


def _residual(model, K, F, u):
    """K u + N(u) - F and its Jacobian (sparse)."""
    r = K @ u - F
    J = K.tolil(copy=True)
    for law in model.nonlinear:
        nodes = law.nodes
        res, tan = law.static(u[nodes])
        r[nodes] += res
        for i, a in enumerate(nodes):
            for j, b in enumerate(nodes):
                J[a, b] += tan[i, j]
    return r, J.tocsr()


def _solve(J, rhs):
    if J.shape[0] == 0:
        return np.zeros(0)
    with warnings.catch_warnings():       # a singular J is reported below
        warnings.simplefilter("ignore")
        du = scipy.sparse.linalg.spsolve(J.tocsc(), rhs)
    if not np.all(np.isfinite(du)) or np.abs(J @ du - rhs).max() > 1e-8 * max(np.abs(rhs).max(), 1e-300):
        raise InputError("gravity.initial: \"static\" needs every body held in place (by a "
                         "bc, an absorbing end, a support or foundation spring, or a contact "
                         "with a held body); some body is free to move as a whole")
    return du
