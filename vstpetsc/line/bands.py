"""The slab matrices of bodies on a line (formulation.md section 2) as block
tridiagonal arrays, and their rows in CSR form: the 1-D room's banded
form of the shared time algebra (vstpetsc.spacetime.slab).  Pure numpy.

Unknowns are interleaved per node: dof ``2 i`` is v_i^{n+} (time node 1),
dof ``2 i + 1`` is v_i^{(n+1)-} (time node 2).
"""

import numpy as np

from vstpetsc.spacetime.slab import HC, HK, HM, RK, RM, recurrence


def bands(ops, which):
    """(diagonal, off-diagonal) of M, C or the stiffness K + S."""
    if which == "k":
        return ops.k_diag + ops.s_diag, ops.k_off + ops.s_off
    return getattr(ops, f"{which}_diag"), getattr(ops, f"{which}_off")


def node_blocks(ops, **coefficients):
    """Blocks ``sum_w c_w * W_ij`` of a 2N x 2N operator, over the spatial
    matrices named by the keywords (m: M, c: C, k: K + S) with 2 x 2 time
    coefficients.

    Returns an array (N, 3, 2, 2): ``[i, 0]`` couples node i to i-1, ``[i, 1]``
    to itself, ``[i, 2]`` to i+1 (zero where there is no such node).
    """
    n = ops.m_diag.size
    out = np.zeros((n, 3, 2, 2))
    for which, coef in coefficients.items():
        diag, off = bands(ops, which)
        band = np.zeros((n, 3))
        band[:, 1], band[1:, 0], band[:-1, 2] = diag, off, off
        out += band[..., None, None] * coef
    return out


def slab_matrix(ops, dt, w=np.eye(2), v=np.eye(2)):
    """Blocks of [A] = HM (x) M + dt HC (x) C + dt^2 HK (x) (K + S); with
    per-node transforms, of (W (x) I) A (V (x) I) (test functions mixed by W,
    unknowns x = V z)."""
    return node_blocks(ops, m=w @ HM @ v, c=dt * w @ HC @ v, k=dt * dt * w @ HK @ v)


def rhs_operator(ops, dt, w=np.eye(2)):
    """Blocks of the operator R with r = R (u^n, v^{n-}) (or of W R)."""
    return node_blocks(ops, m=w @ RM, k=dt * w @ RK)


def apply_blocks(blocks, y, n0, n1):
    """Rows n0..n1-1 of the block band ``blocks`` times ``y`` (N, 2): each
    row sums its six products left to right with separately rounded
    multiplications and additions (elementwise ufuncs; einsum may fuse
    them, differently for different array offsets), so every rank of a run
    computes its rows exactly as one rank would."""
    pad = np.zeros((1, 2))
    ext = np.concatenate([pad, y, pad])                # ext[i + 1] = y[i]
    out = np.zeros((n1 - n0, 2))
    for j in range(3):                                 # the neighbours i-1, i, i+1
        yj = ext[n0 + j:n1 + j]
        for a in range(2):
            for b in range(2):
                out[:, a] += blocks[n0:n1, j, a, b] * yj[:, b]
    return out


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
    return node_rows_csr(blocks, np.arange(n0, n1))


def node_rows_csr(blocks, nodes):
    """CSR arrays of the dof rows of the given nodes (any order), global
    column numbers, explicit zeros kept."""
    n = blocks.shape[0]
    nodes = np.asarray(nodes, dtype=int)
    col_node = nodes[:, None] + np.array([-1, 0, 1])[None, :]
    valid = (col_node >= 0) & (col_node < n)
    shape = (nodes.size, 2, 3, 2)
    cols = np.broadcast_to(2 * col_node[:, None, :, None] + np.arange(2), shape)
    mask = np.broadcast_to(valid[:, None, :, None], shape)
    data = blocks[nodes].transpose(0, 2, 1, 3)
    indptr = np.concatenate(([0], np.cumsum(mask.sum(axis=(2, 3)).ravel())))
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


def increment_bands(ops, dt, n0, n1):
    """The rows of the running-sum increment G of nodes n0..n1-1 in
    difference form, (nl, 2, 3): row a of node i adds

        [i, a, 0] (z_{i-1} - z_i) + [i, a, 1] z_i + [i, a, 2] (z_{i+1} - z_i)

    of the z_1 (a = 0: gm (M + dt/6 C)) or the z_2 (a = 1: gk (K + S)) of
    the nodes: the off-diagonal entries and the row sum.  The bars' K
    sums to zero in every row (sum_e E A / h [[1, -1], [-1, 1]]), so its
    product is formed from the elongation increments alone: the plain
    product k_ii z_i + k_ij z_j of a body moving nearly as a whole rounds
    relative to z (the displacement increment), and that rounding,
    summed into b slab after slab, did work that no term of the energy
    balance holds (docs/loads.md section 4).  Entries outside the mesh
    are zero.

    Damping enters the first rows only: (T - I) dt HC = (dt / 6) (T - I) HM
    + ... has the pattern of XM (docs/loads.md section 3)."""
    _, _, gm, gk = recurrence(dt)
    nodes = np.arange(n0, n1)
    pad = np.zeros(1)
    md, mo = ops.m_diag, ops.m_off
    if ops.damped:
        md, mo = md + dt / 6.0 * ops.c_diag, mo + dt / 6.0 * ops.c_off
    ko = ops.k_off + ops.s_off
    side = lambda off: (np.r_[pad, off][nodes], np.r_[off, pad][nodes])
    (ml, mr), (kl, kr), (sl, sr) = side(mo), side(ko), side(ops.s_off)
    m = np.column_stack([ml, md[nodes] + ml + mr, mr])
    k = np.column_stack([kl, ops.s_diag[nodes] + sl + sr, kr])
    return np.stack([gm * m, gk * k], axis=1)
