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
from scipy.sparse.csgraph import breadth_first_order, connected_components

from vstpetsc.plane.boundaries import edge_frames
from vstpetsc.plane.curves import edge_cells
from vstpetsc.plane.edge_graph import edge_graph
from vstpetsc.plane.mesh import PlaneMesh

LEVEL = 1e-9        # ends at one height, against the curve's extent


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
    """(the mesh split along curve ``name``, its NodePairs) (split_along)."""
    split_mesh, (pairs,) = split_along(mesh, [name])
    return split_mesh, pairs


def split_along(mesh, names):
    """(the mesh split along the curves ``names`` at once, a NodePairs per
    curve); ValueError for a curve the mesh has not, one on its boundary,
    or an edge in two of them.

    Around each node of the curves, the cells fall into groups joined
    across edges on none of them; each group has its copy of the node
    (one group: a crack's tip, the node stays single).  The group on the
    first side of the node's edge of lowest key (edge_keys) keeps its
    number, the others take new ones in the order of (node, group).  A
    pair joins the copies on the two sides of a curve's edges at a node:
    one per side of a crossing or a junction, each with its edges'
    normal and half their length.  So a node where curves meet or cross
    is split the same whatever the order of ``names``."""
    if not names:
        return mesh, []
    edges, curve = _curve_edges(mesh, names)
    corner_cell, corner_node, labels = corner_sides(mesh, edges)
    key = corner_cell.astype(np.int64) * max(mesh.nnodes, 1) + corner_node
    order = np.argsort(key)
    group = lambda cells, nodes: labels[_corner(key, order, cells, nodes, max(mesh.nnodes, 1))]
    first, second = _left_cells(mesh, edges[:, ::-1]), _left_cells(mesh, edges)
    label_node = _label_nodes(mesh, edges, corner_node, labels, group(first[:, None], edges))
    cells = mesh.cells.copy()
    slot = np.argmax(mesh.cells[corner_cell] == corner_node[:, None], axis=1)
    cells[corner_cell, slot] = label_node[labels]
    coordinates = np.concatenate([mesh.coordinates, mesh.coordinates[
        _original_of(mesh, label_node, corner_node, labels)]])
    copies = lambda holder, nodes: label_node[group(holder, nodes)]
    split_mesh = PlaneMesh(coordinates, cells, mesh.region, mesh.region_names,
                           _renumbered_curves(mesh, cells, {n: (edges[curve == i], first[curve == i])
                                                            for i, n in enumerate(names)}))
    pairs = []
    for i, name in enumerate(names):
        mine = curve == i
        ends = [(copies(first[mine], edges[mine, k]), copies(second[mine], edges[mine, k]))
                for k in range(2)]
        pairs.append(_pairs(mesh, name, edges[mine], ends))
    return split_mesh, pairs


def _curve_edges(mesh, names):
    """(every edge of the curves (m, 2), the index of its curve (m,))."""
    for name in names:
        if name not in mesh.curves:
            raise ValueError(f"the mesh has no curve {name!r}")
        _inner_check(mesh, name, mesh.curves[name])
    parts = [oriented(mesh.coordinates, mesh.curves[name]) for name in names]
    edges = np.concatenate(parts) if parts else np.zeros((0, 2), dtype=int)
    curve = np.repeat(np.arange(len(parts)), [len(e) for e in parts])
    keys = mesh.edge_keys(edges[:, 0], edges[:, 1])
    unique, first, counts = np.unique(keys, return_index=True, return_counts=True)
    if (counts > 1).any():
        k = first[np.argmax(counts > 1)]
        other = curve[(keys == keys[k]) & (np.arange(keys.size) != k)][0]
        x, y = mesh.coordinates[edges[k]].mean(axis=0)
        raise ValueError(f"curves {names[curve[k]]!r} and {names[other]!r} share the edge at "
                         f"({x:g}, {y:g}): an edge is one interface's")
    return edges, curve


def oriented(x, edges):
    """A curve's edges (m, 2) turned to run one way along each of its
    pieces: from its lower end to its upper (from left to right where the
    ends are level: within LEVEL of the curve's extent), a closed piece
    counter-clockwise.  The direction a mesh file's edges come in is the
    reader's (DMPlex takes each edge from the first cell that holds it),
    so it tells nothing; the second side is then the left of this one."""
    g = edge_graph(edges)
    nodes, local, piece = g.nodes, g.local, g.piece
    extent = float(np.ptp(x[nodes], axis=0).max(initial=0.0))
    out = local.copy()
    for k in range(g.count):                    # a curve's pieces: one, or a few
        members, ends = g.members(k)
        mine = piece[local[:, 0]] == k
        out[mine] = _piece_oriented(x[nodes], local[mine], ends if ends.size else members,
                                    closed=not ends.size, level=LEVEL * extent)
    return nodes[out]


def _piece_oriented(x, edges, candidates, closed, level):
    """One connected piece's edges run away from its start (the lowest of
    ``candidates``; a closed piece opened at its start and then turned
    counter-clockwise)."""
    y = x[candidates, 1]
    low = candidates[y <= y.min() + level]
    start = low[np.argmin(x[low, 0])]
    n = x.shape[0]
    keep = np.ones(len(edges), dtype=bool)
    if closed:                                  # open the loop at one edge of its start
        keep[np.flatnonzero((edges == start).any(axis=1))[0]] = False
    graph = sp.coo_matrix((np.ones(keep.sum()), (edges[keep, 0], edges[keep, 1])),
                          shape=(n, n)).tocsr()
    _, before = breadth_first_order(graph, start, directed=False)
    forward = before[edges[:, 1]] == edges[:, 0]
    backward = before[edges[:, 0]] == edges[:, 1]
    out = np.where((forward | ~(forward | backward))[:, None], edges, edges[:, ::-1])
    if closed:
        cut = np.flatnonzero(~keep)[0]          # the loop's last edge returns to the start
        out[cut] = [edges[cut][edges[cut] != start][0], start]
        a, b = x[out[:, 0]], x[out[:, 1]]
        if np.sum(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]) < 0:      # clockwise
            out = out[:, ::-1]
    return out


def _label_nodes(mesh, edges, corner_node, labels, first_side):
    """The node number of each group: the original for the group on the
    first side of the lowest edge at its node (``first_side`` (m, 2): the
    group of each edge end on its first side), new numbers for the others
    in the order of (node, group)."""
    ends = edges.T.ravel()                          # the edges' first ends, then their second
    keeper_of = np.full(mesh.nnodes, -1)
    # by node, then by the edge's own key: not by the curves' order
    at_end = np.lexsort((np.tile(mesh.edge_keys(edges[:, 0], edges[:, 1]), 2), ends))
    ends, side = ends[at_end], first_side.T.ravel()[at_end]
    lead = np.r_[True, ends[1:] != ends[:-1]]
    keeper_of[ends[lead]] = side[lead]
    groups = np.unique(np.column_stack([corner_node, labels]), axis=0)   # by node, then group
    keeps = keeper_of[groups[:, 0]] == groups[:, 1]
    label_node = np.empty(labels.max(initial=-1) + 1, dtype=int)
    label_node[groups[keeps, 1]] = groups[keeps, 0]
    label_node[groups[~keeps, 1]] = mesh.nnodes + np.arange(int((~keeps).sum()))
    return label_node


def _original_of(mesh, label_node, corner_node, labels):
    """The original node of each new node (numbered from nnodes on)."""
    out = np.zeros(label_node.max(initial=mesh.nnodes - 1) + 1, dtype=int)
    out[label_node[labels]] = corner_node
    return out[mesh.nnodes:]


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


def _renumbered_curves(mesh, cells, interfaces):
    """Every curve's edges in the split mesh: an interface's (``interfaces``
    {name: (its edges, turned; their first sides' cells)}) on its first
    side; another curve's edge takes the nodes of the cell that holds it."""
    out = {}
    for curve, edges in mesh.curves.items():
        edges, holder = interfaces.get(curve) or (edges, edge_cells(mesh, edges))
        slot = lambda p: np.argmax(mesh.cells[holder] == p[:, None], axis=1)
        out[curve] = np.column_stack([cells[holder, slot(edges[:, k])] for k in range(2)])
    return out


def _pairs(mesh, name, edges, ends):
    """The NodePairs of a curve: per (first copy, second copy) of a node
    (``ends``: those of the edges' first ends, then of their second), the
    length-weighted mean of its edges' left normals, and half their
    lengths; none where both copies are one node (a tip)."""
    length, _, t = edge_frames(mesh, edges)
    left = np.column_stack([-t[:, 1], t[:, 0]]) * length[:, None]
    a = np.concatenate([ends[0][0], ends[1][0]])
    b = np.concatenate([ends[0][1], ends[1][1]])
    split_here = a != b
    node = np.concatenate([edges[:, 0], edges[:, 1]])[split_here]
    a, b = a[split_here], b[split_here]
    keys, at = np.unique(np.column_stack([node, a, b]), axis=0, return_inverse=True)
    at = at.ravel()
    normal, share = np.zeros((len(keys), 2)), np.zeros(len(keys))
    np.add.at(normal, at, np.concatenate([left, left])[split_here])
    np.add.at(share, at, np.concatenate([0.5 * length, 0.5 * length])[split_here])
    normal = normal / np.linalg.norm(normal, axis=1)[:, None]
    tangent = np.column_stack([normal[:, 1], -normal[:, 0]])
    return NodePairs(name, keys[:, 1:].copy(), normal, tangent, share)


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
