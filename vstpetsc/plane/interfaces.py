"""The mesh split along an interface curve (interface.md, "Plane strain
(2-D)", [[interface]]): every node of the curve is doubled, one per side,
and the two sides touch through node pairs, each with the curve's unit
normal (from the first side to the second), its tangent and its
tributary length (half of each adjacent curve edge).

Which side is which: the second side is the one the curve's left normal
points into (n = (-t_y, t_x) for an edge drawn along t: a curve drawn
from left to right has its second side above).  Around each node of the
curve the cells fall into groups joined across edges that are not on the
curve: two groups, and the node is doubled, the second side's cells
taking the new node; one group (the curve ends inside the mesh, a crack's
tip), and the node stays single, welded.  The groups come from one
connected-components call on the cells' corners at the curve's nodes (no
loop over nodes or cells).  Pure numpy and scipy."""

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from vstpetsc.plane.boundaries import edge_frames
from vstpetsc.plane.curves import edge_cells
from vstpetsc.plane.mesh import PlaneMesh


@dataclass
class NodePairs:
    """An interface's node pairs in a split mesh: ``nodes`` (m, 2) (first
    side, second side), unit ``normal`` and ``tangent`` (m, 2) (t = the
    normal turned clockwise: (n_y, -n_x)), tributary ``length`` (m,)."""

    name: str
    nodes: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    length: np.ndarray


def _inner_check(mesh, name, edges):
    """ValueError unless every edge of the curve lies between two cells."""
    _, a, b = mesh.edges()
    keys, counts = np.unique(mesh.edge_keys(a, b), return_counts=True)
    twice = counts[np.searchsorted(keys, mesh.edge_keys(edges[:, 0], edges[:, 1]))] == 2
    if not twice.all():
        x, y = mesh.coordinates[edges[~twice][0]].mean(axis=0)
        raise ValueError(f"curve {name!r} runs along the mesh's boundary at ({x:g}, {y:g}): "
                         "an interface lies between two cells")


def corner_sides(mesh, edges):
    """Per corner (cell, node) at a node of the curve: its group's label
    (corners joined across edges that are not on the curve); returns
    (corner cells, corner nodes, labels)."""
    nodes = np.unique(edges)
    on_curve = np.zeros(mesh.nnodes, dtype=bool)
    on_curve[nodes] = True
    flat = mesh.cells.ravel()
    cell_of = np.repeat(np.arange(mesh.ncells), 4)
    mine = (flat >= 0) & on_curve[np.maximum(flat, 0)]
    corners_cell, corners_node = cell_of[mine], flat[mine]
    n = max(mesh.nnodes, 1)
    key = corners_cell.astype(np.int64) * n + corners_node
    order = np.argsort(key)
    # two cells sharing an edge (p, q) that is not on the curve join their
    # corners at p and at q
    cells, a, b = mesh.edges()
    ek = mesh.edge_keys(a, b)
    curve_keys = np.sort(mesh.edge_keys(edges[:, 0], edges[:, 1]))
    hit = np.searchsorted(curve_keys, ek)
    along = (hit < curve_keys.size) & (curve_keys[np.minimum(hit, curve_keys.size - 1)] == ek)
    keep = ~along & (on_curve[a] | on_curve[b])
    cells, a, b, ek = cells[keep], a[keep], b[keep], ek[keep]
    by_edge = np.argsort(ek, kind="stable")
    ek, cells, a, b = ek[by_edge], cells[by_edge], a[by_edge], b[by_edge]
    shared = np.flatnonzero(ek[1:] == ek[:-1])          # the edge's two cells: i, i + 1
    rows, cols = [], []
    for p in (a, b):
        first = shared[on_curve[p[shared]]]
        c1, c2, node = cells[first], cells[first + 1], p[first]
        rows.append(_corner(key, order, c1, node, n))
        cols.append(_corner(key, order, c2, node, n))
    rows, cols = np.concatenate(rows), np.concatenate(cols)
    graph = sp.coo_matrix((np.ones(rows.size), (rows, cols)), shape=(key.size, key.size))
    _, labels = connected_components(graph, directed=False)
    return corners_cell, corners_node, labels


def _corner(key, order, cells, nodes, n):
    """Positions of the corners (cells, nodes) in the corner arrays."""
    return order[np.searchsorted(key[order], cells.astype(np.int64) * n + nodes)]


def split(mesh, name):
    """(the mesh split along curve ``name``, its NodePairs); ValueError for
    a curve the mesh has not or one on the mesh's boundary."""
    if name not in mesh.curves:
        raise ValueError(f"the mesh has no curve {name!r}")
    edges = mesh.curves[name]
    _inner_check(mesh, name, edges)
    corner_cell, corner_node, labels = corner_sides(mesh, edges)
    second = _second_side_groups(mesh, edges, corner_cell, corner_node, labels)
    moved = second[labels]                                 # corners taking the new node
    doubled = np.unique(corner_node[moved])
    new = np.full(mesh.nnodes, -1)
    new[doubled] = mesh.nnodes + np.arange(doubled.size)
    cells = mesh.cells.copy()
    slot = np.argmax(mesh.cells[corner_cell] == corner_node[:, None], axis=1)
    cells[corner_cell[moved], slot[moved]] = new[corner_node[moved]]
    coordinates = np.concatenate([mesh.coordinates, mesh.coordinates[doubled]])
    split_mesh = PlaneMesh(coordinates, cells, mesh.region, mesh.region_names,
                           _renumbered_curves(mesh, cells, name, new))
    return split_mesh, _pairs(mesh, name, edges, doubled, new)


def _second_side_groups(mesh, edges, corner_cell, corner_node, labels):
    """Whether each group is on the second side: the groups of the corners
    of the cells left of the curve's edges, where a node has two groups."""
    n = max(mesh.nnodes, 1)
    left = _left_cells(mesh, edges)
    key = corner_cell.astype(np.int64) * n + corner_node
    order = np.argsort(key)
    second = np.zeros(labels.max() + 1, dtype=bool)
    for p in (edges[:, 0], edges[:, 1]):
        second[labels[_corner(key, order, left, p, n)]] = True
    # a node whose corners are all in one group (a tip) is not doubled
    groups = np.unique(np.column_stack([corner_node, labels]), axis=0)
    count = np.bincount(groups[:, 0], minlength=mesh.nnodes)
    single = count[groups[:, 0]] < 2
    second[groups[single, 1]] = False
    return second


def _left_cells(mesh, edges):
    """The cell on the left of each directed edge (a, b)."""
    cells, a, b = mesh.edges()
    n = max(mesh.nnodes, 1)
    # a cell's counter-clockwise edge (a, b) has the cell on its left
    directed = a.astype(np.int64) * n + b
    order = np.argsort(directed)
    want = edges[:, 0].astype(np.int64) * n + edges[:, 1]
    at = np.searchsorted(directed[order], want)
    return cells[order[np.minimum(at, order.size - 1)]]


def _renumbered_curves(mesh, cells, name, new):
    """Every curve's edges in the split mesh: the interface's own on the
    first side (old nodes); another curve's edge touching a doubled node
    takes the nodes of the cell that holds it."""
    out = {}
    for curve, edges in mesh.curves.items():
        if curve == name or not (new[edges] >= 0).any():
            out[curve] = edges
            continue
        holder = cells[edge_cells(mesh, edges)]
        pick = lambda p: np.where((holder == new[p][:, None]).any(axis=1) & (new[p] >= 0),
                                  new[p], p)
        out[curve] = np.column_stack([pick(edges[:, 0]), pick(edges[:, 1])])
    return out


def _pairs(mesh, name, edges, doubled, new):
    """The NodePairs: per doubled node, the length-weighted mean of its
    curve edges' left normals, and half their lengths."""
    length, _, t = edge_frames(mesh, edges)
    left = np.column_stack([-t[:, 1], t[:, 0]]) * length[:, None]
    normal = np.zeros((mesh.nnodes, 2))
    share = np.zeros(mesh.nnodes)
    for p in (edges[:, 0], edges[:, 1]):
        np.add.at(normal, p, left)
        np.add.at(share, p, 0.5 * length)
    normal = normal[doubled] / np.linalg.norm(normal[doubled], axis=1)[:, None]
    tangent = np.column_stack([normal[:, 1], -normal[:, 0]])
    return NodePairs(name, np.column_stack([doubled, new[doubled]]), normal, tangent,
                     share[doubled])


def spring_matrix(pairs, normal_stiffness, tangent_stiffness, nnodes):
    """The stiffness (2 nn, 2 nn CSR) of linear springs joining each pair's
    two nodes, per unit length along the normal and the tangent (one value
    or one per pair; times the pair's tributary length): a closed,
    sticking interface's linear part (the pairs' penalty and stick
    springs), to be added to K, so that such an interface costs no more
    per slab than the welded mesh."""
    length = np.asarray(pairs.length, float)
    return pair_matrix(pairs.nodes, spring_blocks(pairs.normal, pairs.tangent,
                                                  np.multiply(normal_stiffness, length),
                                                  np.multiply(tangent_stiffness, length)),
                       nnodes)


def spring_blocks(normal, tangent, kn, kt):
    """Each pair's 2 x 2 spring block kn n n^T + kt t t^T (kn, kt one value
    or one per pair)."""
    kn, kt = (np.reshape(np.asarray(k, float), (-1, 1, 1)) for k in (kn, kt))
    return kn * np.einsum("ma,mb->mab", normal, normal) + \
        kt * np.einsum("ma,mb->mab", tangent, tangent)


def pair_matrix(nodes, block, nnodes):
    """The (2 nn, 2 nn) CSR that gives each pair (first, second) of
    ``nodes`` the forces B (u_first - u_second) on its first node and
    B (u_second - u_first) on its second: 2 x 2 blocks ``block`` (m, 2, 2)
    B on the diagonal, -B across (a spring's pattern)."""
    first, second = nodes[:, 0], nodes[:, 1]
    rows, cols, vals = [], [], []
    for p, q, sign in ((first, first, 1.0), (second, second, 1.0),
                       (first, second, -1.0), (second, first, -1.0)):
        dp = 2 * p[:, None] + np.arange(2)
        dq = 2 * q[:, None] + np.arange(2)
        rows.append(np.repeat(dp, 2, axis=1).ravel())
        cols.append(np.tile(dq, (1, 2)).ravel())
        vals.append(sign * block.ravel())
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(2 * nnodes, 2 * nnodes))
