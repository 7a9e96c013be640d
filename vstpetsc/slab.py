"""The slab matrices of v-ST/FEM (formulation.md section 2) as block
tridiagonal arrays, and their rows in CSR form.  Pure numpy.

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
# r^1 = M v^{n-} - dt/2 K u^n,  r^2 = -dt/2 K u^n, acting on the state (u, v).
RM = np.array([[0.0, 1.0], [0.0, 0.0]])
RK = np.array([[-0.5, 0.0], [-0.5, 0.0]])


def node_blocks(layout, cm, ck):
    """Blocks ``cm * M_ij + ck * K_ij`` of a 2N x 2N operator.

    Returns an array (N, 3, 2, 2): ``[i, 0]`` couples node i to i-1, ``[i, 1]``
    to itself, ``[i, 2]`` to i+1 (zero where there is no such node).
    """
    n = layout.nnodes
    mb, kb = np.zeros((n, 3)), np.zeros((n, 3))
    mb[:, 1], kb[:, 1] = layout.m_diag, layout.k_diag
    mb[1:, 0], kb[1:, 0] = layout.m_off, layout.k_off
    mb[:-1, 2], kb[:-1, 2] = layout.m_off, layout.k_off
    return mb[..., None, None] * cm + kb[..., None, None] * ck


def slab_matrix(layout, dt):
    """Blocks of [A] = HM (x) M + dt^2 HK (x) K."""
    return node_blocks(layout, HM, dt * dt * HK)


def rhs_operator(layout, dt):
    """Blocks of the operator R with r = R (u^n, v^{n-})."""
    return node_blocks(layout, RM, dt * RK)


def impose_dirichlet(blocks, dofs, diagonal):
    """Zero the rows of ``dofs`` (global dof numbers); put ``diagonal`` on
    their diagonal.  Returns a modified copy."""
    out = blocks.copy()
    node, a = np.divmod(np.asarray(dofs, dtype=int), 2)
    out[node, :, a, :] = 0.0
    out[node, 1, a, a] = diagonal
    return out


def block_rows_csr(blocks, n0, n1):
    """CSR arrays (indptr, indices, data) of the dof rows of nodes n0..n1-1,
    with global column numbers, keeping explicit zeros so that every
    neighbour coupling (also between two bodies, where contact enters) has a
    slot in the matrix."""
    n = blocks.shape[0]
    nodes = np.arange(n0, n1)
    col_node = nodes[:, None] + np.array([-1, 0, 1])[None, :]          # (nl, 3)
    valid = (col_node >= 0) & (col_node < n)
    shape = (nodes.size, 2, 3, 2)                                       # row dof a, neighbour, col dof b
    cols = np.broadcast_to(2 * col_node[:, None, :, None] + np.arange(2), shape)
    mask = np.broadcast_to(valid[:, None, :, None], shape)
    data = blocks[n0:n1].transpose(0, 2, 1, 3)
    counts = mask.sum(axis=(2, 3)).ravel()
    indptr = np.concatenate(([0], np.cumsum(counts)))
    return indptr, cols[mask], data[mask]


def block_rows_bcsr(blocks, n0, n1):
    """Block CSR arrays (indptr, indices, data (nnzb, 2, 2)) of the block rows
    of nodes n0..n1-1, global block columns, explicit zero blocks kept."""
    n = blocks.shape[0]
    nodes = np.arange(n0, n1)
    col_node = nodes[:, None] + np.array([-1, 0, 1])[None, :]
    valid = (col_node >= 0) & (col_node < n)
    indptr = np.concatenate(([0], np.cumsum(valid.sum(axis=1))))
    return indptr, col_node[valid], blocks[n0:n1][valid]


def advance_blocks(nnodes, dt):
    """Per-node blocks Q of the state update Y <- mask * Y + Q X, with
    mask = (1, 0) per node: u += dt/2 (v^1 + v^2), v = v^2."""
    q = np.array([[0.5 * dt, 0.5 * dt], [0.0, 1.0]])
    return np.broadcast_to(q, (nnodes, 2, 2))
