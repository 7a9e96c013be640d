"""The time algebra of v-ST/FEM (formulation.md section 2), for any
geometry: the time matrices, the slab matrix of any sparse M, C, K, the
advance of a slab and the running-sum recurrence.  Pure numpy (the 1-D
room's banded form: vstpetsc.line.bands).

Unknowns are interleaved per node: dof ``2 i`` is v_i^{n+} (time node 1),
dof ``2 i + 1`` is v_i^{(n+1)-} (time node 2).  The state carried from slab to
slab is interleaved the same way: dof ``2 i`` is u_i^n, dof ``2 i + 1`` is
v_i^{n-}.
"""

import numpy as np

# int T_a dT_b/dt dt plus the upwind jump term at t^n+ (row a = test function).
HM = np.array([[0.5, 0.5], [-0.5, 0.5]])
# int T_a I_b dt / dt^2.
HK = np.array([[1.0 / 8.0, 1.0 / 24.0], [5.0 / 24.0, 1.0 / 8.0]])
# int T_a T_b dt / dt (damping).
HC = np.array([[1.0 / 3.0, 1.0 / 6.0], [1.0 / 6.0, 1.0 / 3.0]])
# r^1 = M v^{n-} - dt/2 K u^n,  r^2 = -dt/2 K u^n, acting on the state (u, v).
RM = np.array([[0.0, 1.0], [0.0, 0.0]])
RK = np.array([[-0.5, 0.0], [-0.5, 0.0]])


def sparse_slab_matrix(M, C, K, dt, w=np.eye(2), v=np.eye(2)):
    """[A] = HM (x) M + dt HC (x) C + dt^2 HK (x) K for sparse spatial
    matrices of any geometry (scipy.sparse; C None: undamped), unknowns
    interleaved per spatial dof as the bands' are per node: index
    2 d + a is time node a of dof d."""
    import scipy.sparse as sp

    A = sp.kron(M, w @ HM @ v) + sp.kron(K, dt * dt * w @ HK @ v)
    if C is not None:
        A = A + sp.kron(C, dt * w @ HC @ v)
    return A.tocsr()


def advance_block(dt):
    """The per-node block Q of the state update Y <- mask * Y + Q X, with
    mask = (1, 0) per node: u += dt/2 (v^1 + v^2), v = v^2."""
    return np.array([[0.5 * dt, 0.5 * dt], [0.0, 1.0]])


# R (mask * Y) = T R Y: after a slab, the right-hand side keeps only its
# K u part, which both rows share (r^1 and r^2 both carry -dt/2 K u).
CARRY = np.array([[0.0, 1.0], [0.0, 1.0]])


def recurrence(dt):
    """Per-node transforms that make the right-hand side a running sum.

    Folding the state update into r = R Y and using A x^n = r^n + f^n (f^n:
    the nodal forces of slab n, contact included),

        r^{n+1} = r^n + (XM (x) M + XK (x) K) x^n - (T - I) f^n,

    with T = CARRY, Q the state update, XM = (T - I) HM + RM Q and
    XK = dt^2 (T - I) HK + dt RK Q, both of rank one.  New unknowns per node,
    z = V^{-1} x = dt/2 (v^2 - v^1, v^1 + v^2), and test functions mixed by W
    make the increment diagonal: one tridiagonal product per dof row,

        W r^{n+1} = W r^n + (gm M z_1, gk K z_2) - W (T - I) f^n,

    and z_2 is the displacement increment u^{n+1} - u^n.  The state (u, v)
    is no longer needed per slab.  Returns (W, V, gm, gk)."""
    eye = np.eye(2)
    q = advance_block(dt)
    xm = (CARRY - eye) @ HM + RM @ q
    xk = dt * dt * (CARRY - eye) @ HK + dt * RK @ q
    a = np.column_stack([xm[:, np.abs(xm).max(axis=0).argmax()],
                         xk[:, np.abs(xk).max(axis=0).argmax()]])
    w = np.linalg.inv(a / np.abs(a).max(axis=0))
    v = np.linalg.inv(0.5 * dt * np.array([[-1.0, 1.0], [1.0, 1.0]]))
    gm, gk = w @ xm @ v, w @ xk @ v
    assert np.allclose(gm, np.diag([gm[0, 0], 0.0]), rtol=0, atol=1e-12 * abs(gm[0, 0]))
    assert np.allclose(gk, np.diag([0.0, gk[1, 1]]), rtol=0, atol=1e-12 * abs(gk[1, 1]))
    return w, v, gm[0, 0], gk[1, 1]


