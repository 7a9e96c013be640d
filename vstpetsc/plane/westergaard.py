"""Westergaard's added masses of a [[water]] table with hydrodynamic =
"westergaard" (interface.md, "Water against a dam (2-D)"; docs/water.md):
each wetted node i below the level gets

    m_i = (7/8) rho sqrt(H (level - y_i)) L_i

along its face's normal n_i, the 2 x 2 block m_i n_i n_i^T added to the
mass matrix (Westergaard 1933, with Kuo's normal for inclined faces).
H = level - the lowest y of the faces; L_i the node's tributary length:
half of the wet piece (below the level) of each adjacent face edge, so an
edge cut by the level gives half its wet piece to its end below and
nothing to its end above (whose depth, and mass, is 0 anyway); n_i the
normalised sum of the outward normals of the adjacent edges with a wet
piece.  Inertia only: the weight's pattern comes from the dry mass
matrix (vstpetsc.plane.model).  Pure numpy and scipy."""

import numpy as np
import scipy.sparse as sp

from vstpetsc.plane.boundaries import edge_frames
from vstpetsc.plane.water import face_edges, outward_normals, wet_pieces

WESTERGAARD = 7.0 / 8.0


def faces_bottom(mesh, spec):
    """The lowest y of the faces of ``spec`` that ``mesh`` holds (inf
    without): on the whole mesh, H's."""
    edges = face_edges(mesh, spec.faces)
    return float(mesh.coordinates[edges, 1].min(initial=np.inf))


def added_masses(mesh, spec, bottom):
    """(nodes (k,), m (k,), n (k, 2)) of the nodes of ``mesh`` with an
    added mass from ``spec``, its faces' lowest y ``bottom`` (the whole
    mesh's: a rank's overlap may not hold it)."""
    edges = face_edges(mesh, spec.faces)
    if not len(edges):
        return np.zeros(0, dtype=int), np.zeros(0), np.zeros((0, 2))
    length, _, _ = edge_frames(mesh, edges)
    s0, s1 = wet_pieces(mesh.coordinates[edges, 1], spec.level)
    wet = np.maximum(s1 - s0, 0.0) * length
    edges, wet, normal = edges[wet > 0], wet[wet > 0], outward_normals(mesh, edges)[wet > 0]
    share, direction = np.zeros(mesh.nnodes), np.zeros((mesh.nnodes, 2))
    for end in (0, 1):
        np.add.at(share, edges[:, end], 0.5 * wet)
        np.add.at(direction, edges[:, end], normal)
    depth = np.maximum(spec.level - mesh.coordinates[:, 1], 0.0)
    mass = WESTERGAARD * spec.rho * np.sqrt((spec.level - bottom) * depth) * share
    nodes = np.flatnonzero(mass > 0)
    n = direction[nodes] / np.linalg.norm(direction[nodes], axis=1)[:, None]
    return nodes, mass[nodes], n


def owned_rows(mesh, owned_local, first, nnodes, specs, bottoms):
    """The added masses' rows (CSR, 2 n x 2 nnodes) of a rank's owned
    vertices ``owned_local`` (local indices in global order, numbered
    first, first + 1, ...) from its local ``mesh``; None when no table is
    "westergaard"."""
    chosen = [(s, b) for s, b in zip(specs, bottoms) if s.hydrodynamic == "westergaard"]
    if not chosen:
        return None
    position = -np.ones(mesh.nnodes, dtype=int)
    position[owned_local] = np.arange(owned_local.size)
    parts = [added_masses(mesh, s, b) for s, b in chosen]
    nodes = np.concatenate([p[0] for p in parts])
    blocks = np.concatenate([p[1][:, None, None] * np.einsum("ka,kb->kab", p[2], p[2])
                             for p in parts])
    mine = position[nodes] >= 0
    pos, blocks = position[nodes[mine]], blocks[mine]
    dof = 2 * pos[:, None] + np.arange(2)
    rows = np.repeat(dof, 2, axis=1).ravel()
    cols = np.tile(dof, (1, 2)).ravel() + 2 * first
    return sp.csr_matrix((blocks.ravel(), (rows, cols)),
                         shape=(2 * owned_local.size, 2 * nnodes))
