"""A curve's edges as a graph: its nodes, its connected pieces and each
node's degree (an end of an open piece has degree 1).  Shared by the
interfaces' orientation (vstpetsc.plane.interfaces.oriented) and the
water's wetted nodes in order (vstpetsc.plane.water.chain).  Pure scipy."""

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components


@dataclass
class EdgeGraph:
    """``nodes`` (n,) the curve's node numbers; ``local`` (m, 2) its edges
    in positions among them; ``graph`` the adjacency (CSR); ``count``
    pieces, ``piece`` (n,) each node's; ``degree`` (n,)."""

    nodes: np.ndarray
    local: np.ndarray
    graph: sp.csr_matrix
    count: int
    piece: np.ndarray
    degree: np.ndarray

    def members(self, k):
        """(positions of piece k's nodes, those of them that end it)."""
        members = np.flatnonzero(self.piece == k)
        return members, members[self.degree[members] == 1]


def edge_graph(edges):
    """The EdgeGraph of edges (m, 2) (node numbers)."""
    nodes, local = np.unique(edges, return_inverse=True)
    local = local.reshape(edges.shape)
    graph = sp.coo_matrix((np.ones(len(local)), (local[:, 0], local[:, 1])),
                          shape=(nodes.size, nodes.size)).tocsr()
    count, piece = connected_components(graph, directed=False)
    degree = np.bincount(local.ravel(), minlength=nodes.size)
    return EdgeGraph(nodes, local, graph, count, piece, degree)
