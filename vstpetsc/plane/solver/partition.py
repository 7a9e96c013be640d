"""The cells' parts for DMPlex's distribution when the slab is solved by
each rank's interior LU (vstpetsc.plane.solver.separated): METIS's
recursive bisection of the cells' graph, each cell weighted by its share
of its nodes, so that the ranks own about as many nodes (each rank's
factors, and its sweeps, follow its nodes, not its cells).

The graph joins two cells that share an edge, and the cells of an
interface pair's two nodes (the split mesh no longer joins them, the
pair's springs do: a cut along an interface is no cheaper than elsewhere).
PT-Scotch, DMPlex's own partitioner, balances cells: on the 1 m rockfill
dam (6808 triangles, 9000 quadrilaterals) its two ranks owned 6104 and
6838 nodes, and the larger's factors held 16 % more values."""

import ctypes

import numpy as np

from vstpetsc.native import METIS_OK, metis_defaults, metis_library

SCALE = 60          # a node's weight split among up to 6 cells stays whole


def cell_graph(cells, links=None):
    """The cells' adjacency (CSR: indptr, indices, int32) of the cells
    ``cells`` (ne, 4; -1 pads a triangle): cells that share an edge, and
    for each node pair of ``links`` (m, 2) a cell of each node."""
    ne = cells.shape[0]
    corners = (cells >= 0).sum(axis=1)
    nxt = np.where(np.arange(4) + 1 < corners[:, None], np.roll(cells, -1, axis=1), cells[:, :1])
    a, b = cells.ravel(), nxt.ravel()
    owner = np.repeat(np.arange(ne), 4)
    real = a >= 0
    a, b, owner = a[real], b[real], owner[real]
    nodes = cells.max() + 1
    cell_of = np.full(nodes, -1)
    cell_of[a] = owner                      # a cell of each node (any serves a link)
    key = np.minimum(a, b).astype(np.int64) * nodes + np.maximum(a, b)
    order = np.argsort(key, kind="stable")
    key, owner = key[order], owner[order]
    twin = np.flatnonzero(key[1:] == key[:-1])
    first, second = owner[twin], owner[twin + 1]
    if links is not None and len(links):
        joined = cell_of[links]
        joined = joined[(joined >= 0).all(axis=1) & (joined[:, 0] != joined[:, 1])]
        first, second = np.concatenate([first, joined[:, 0]]), np.concatenate([second, joined[:, 1]])
    rows = np.concatenate([first, second])
    cols = np.concatenate([second, first])
    pairs = np.unique(rows.astype(np.int64) * ne + cols)
    rows, cols = pairs // ne, pairs % ne
    indptr = np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=ne))])
    return indptr.astype(np.int32), cols.astype(np.int32)


def node_shares(cells):
    """Each cell's share of its nodes (int32, SCALE for a whole node): a
    node's weight split evenly among its cells."""
    real = cells >= 0
    count = np.bincount(cells[real], minlength=cells.max() + 1)
    share = np.where(real, 1.0 / np.maximum(count[np.where(real, cells, 0)], 1), 0.0)
    return np.maximum(np.rint(SCALE * share.sum(axis=1)), 1).astype(np.int32)


def balanced_parts(cells, parts, links=None):
    """Each cell's part (0 .. parts - 1) by METIS's recursive bisection of
    cell_graph weighted by node_shares, or None without libmetis5."""
    lib = metis_library()
    if lib is None or parts < 2 or cells.shape[0] < parts:
        return None
    indptr, indices = cell_graph(cells, links)
    weights = node_shares(cells)
    n = cells.shape[0]
    options = metis_defaults(lib)
    part, cut = np.zeros(n, dtype=np.int32), ctypes.c_int32(0)
    P = ctypes.c_void_p
    status = lib.METIS_PartGraphRecursive(
        ctypes.byref(ctypes.c_int32(n)), ctypes.byref(ctypes.c_int32(1)),
        indptr.ctypes.data_as(P), indices.ctypes.data_as(P), weights.ctypes.data_as(P),
        None, None, ctypes.byref(ctypes.c_int32(parts)), None, None,
        options.ctypes.data_as(P), ctypes.byref(cut), part.ctypes.data_as(P))
    if status != METIS_OK:
        raise RuntimeError(f"METIS_PartGraphRecursive failed ({status})")
    return part.astype(np.int64)
