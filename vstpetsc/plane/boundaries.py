"""Boundaries of a plane-strain mesh along a named curve, per unit
thickness (interface.md, "Plane strain (2-D)", [[boundary]]).

Absorbing (Lysmer & Kuhlemeyer 1969): the curve's traction is
-(rho Vp n n^T + rho Vs t t^T) v, dashpots normal and tangential to each
edge, plus 2 (rho Vp n n^T + rho Vs t t^T) v_in for an incident plane
wave of particle velocity v_in arriving along the normal (the 1-D
absorbing end's 2 Z v_in).  Each edge gives half of its length to each
of its nodes (lumped), so a horizontal base takes rho Vs L/2 on v_x and
rho Vp L/2 on v_y at each node; a column one cell wide then has the 1-D
end's Z = rho c A.  The blocks and the incident wave's nodal patterns
are assembled per rank by vstpetsc.plane.curves.  Pure numpy."""

import numpy as np


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
