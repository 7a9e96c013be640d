"""Boundaries of a plane-strain mesh along a named curve, per unit
thickness (interface.md, "Plane strain (2-D)", [[boundary]]).

Absorbing (Lysmer & Kuhlemeyer 1969): the curve's traction is
-(rho Vp n n^T + rho Vs t t^T) v, dashpots normal and tangential to each
edge, plus 2 (rho Vp n n^T + rho Vs t t^T) v_in for an incident plane
wave of particle velocity v_in arriving along the normal (the 1-D
absorbing end's 2 Z v_in).  Each edge gives half of its length to each
of its nodes (lumped), so a horizontal base takes rho Vs L/2 on v_x and
rho Vp L/2 on v_y at each node; a column one cell wide then has the 1-D
end's Z = rho c A.  Pure numpy and scipy."""

import numpy as np
import scipy.sparse as sp


def edge_frames(mesh, edges):
    """(lengths (m,), normals (m, 2), tangents (m, 2)) of edges (m, 2)."""
    d = np.diff(mesh.coordinates[edges], axis=1)[:, 0]
    length = np.linalg.norm(d, axis=1)
    t = d / length[:, None]
    return length, np.column_stack([t[:, 1], -t[:, 0]]), t


def dashpot_blocks(mesh, edges, rho, vp, vs):
    """(nodes, (n, 2, 2) blocks): per node of the edges (m, 2) of a curve,
    the sum over its edges of L/2 (rho Vp n n^T + rho Vs t t^T); rho, vp,
    vs per edge or one value."""
    length, n, t = edge_frames(mesh, edges)
    rho, vp, vs = (np.broadcast_to(np.asarray(a, float), length.shape) for a in (rho, vp, vs))
    block = 0.5 * length[:, None, None] * (
        (rho * vp)[:, None, None] * np.einsum("ma,mb->mab", n, n)
        + (rho * vs)[:, None, None] * np.einsum("ma,mb->mab", t, t))
    nodes, slot = np.unique(edges, return_inverse=True)
    out = np.zeros((nodes.size, 2, 2))
    np.add.at(out, slot.reshape(-1, 2)[:, 0], block)
    np.add.at(out, slot.reshape(-1, 2)[:, 1], block)
    return nodes, out


def block_diagonal(nnodes, nodes, blocks):
    """The (2 nn, 2 nn) sparse matrix of 2 x 2 blocks on the given nodes."""
    dof = 2 * nodes[:, None] + np.arange(2)
    rows = np.repeat(dof, 2, axis=1).ravel()
    cols = np.tile(dof, (1, 2)).ravel()
    return sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(2 * nnodes, 2 * nnodes))


class AbsorbingBoundary:
    """Lysmer's dashpots along a curve and the forces of an incident wave
    (``incident``: (x history, y history) of its particle velocity, or
    None)."""

    def __init__(self, mesh, curve, rho, vp, vs, incident=None):
        self.nodes, self.blocks = dashpot_blocks(mesh, mesh.curves[curve], rho, vp, vs)
        self.nnodes = mesh.nnodes
        self.incident = incident

    def damping(self):
        return block_diagonal(self.nnodes, self.nodes, self.blocks)

    def forces(self, dt, k0, k1):
        """(k1 - k0, 2 nn, 2): each slab's int T_a f dt on every dof,
        f = 2 blocks v_in (exact: the histories' own slab integrals)."""
        out = np.zeros((k1 - k0, 2 * self.nnodes, 2))
        if self.incident is None:
            return out
        hx, hy = (h.slab_integrals(dt, k0, k1) for h in self.incident)     # (K, 2) each
        v = np.stack([hx, hy], axis=1)                                     # (K, 2 comps, 2 a)
        f = 2.0 * np.einsum("nij,kja->knia", self.blocks, v)              # (K, n, 2, 2)
        dof = (2 * self.nodes[:, None] + np.arange(2)).ravel()
        out[:, dof, :] = f.reshape(k1 - k0, -1, 2)
        return out
