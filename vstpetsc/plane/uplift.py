"""The uplift of a [[water]] table in an [[interface]] (interface.md,
"Water against a dam (2-D)"; docs/water.md): every pair of the interface
carries a pressure p_u that pushes its two sides apart, linear in arc
length s along the curve from p_a = rho |g| (level - y_a)+ at its end a
(the one nearest the wetted faces) to p_b = rho |g| (tailwater - y_b)+
(0 without a tailwater) at its other end b:

    p_u(s) = p_a + (p_b - p_a) s / S,    S the curve's length.

A pair's force is p_u at the pair times its tributary length L, along
its normal n (first side to second): -p_u L n on its first node, +p_u L n
on its second.  The sum over the pairs is the trapezoid rule on the
curve's nodes, exact for the linear p_u: U = (p_a + p_b) S / 2.  The
pressure is the pre-earthquake one, constant in time (g at t = 0), a
constant load of the static start and of the run.  Pure numpy."""

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from vstpetsc.plane.water import chain, face_edges


def open_piece_problem(mesh, name):
    """Why the curve ``name`` is not one open piece (words), or None."""
    edges = mesh.curves[name]
    nodes, local = np.unique(edges, return_inverse=True)
    local = local.reshape(edges.shape)
    graph = sp.coo_matrix((np.ones(len(local)), (local[:, 0], local[:, 1])),
                          shape=(nodes.size, nodes.size))
    count, _ = connected_components(graph, directed=False)
    degree = np.bincount(local.ravel(), minlength=nodes.size)
    if count != 1 or (degree == 1).sum() != 2 or (degree > 2).any():
        return (f"interface {name!r} is not one open curve ({count} pieces, "
                f"{int((degree == 1).sum())} ends): the uplift runs from one end to the other")
    return None


def check(specs, mesh):
    """The problem of the waters' uplift against the (unsplit) mesh, one
    line naming the key, or None: an interface's curve that is not one
    open piece (a curve the mesh lacks is the [[interface]]'s to report)."""
    for i, spec in enumerate(specs):
        problem = spec.uplift in mesh.curves and open_piece_problem(mesh, spec.uplift)
        if problem:
            return f"water[{i}] ({spec.name}).uplift: {problem}"
    return None


def wetted_nodes(mesh, spec):
    """The nodes of the faces' edges that reach below the level."""
    edges = face_edges(mesh, spec.faces)
    wet = mesh.coordinates[edges, 1].min(axis=1) < spec.level
    return np.unique(edges[wet])


def arc_lengths(mesh, spec):
    """(the curve's nodes in order from end a, their arc length s from a)
    of the uplift interface's curve (one open piece): a is the end nearest
    a wetted node (ties: the chain's first, its lower then left end)."""
    x = mesh.coordinates
    ordered = chain(x, mesh.curves[spec.uplift])
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(x[ordered], axis=0), axis=1))])
    wet = x[wetted_nodes(mesh, spec)]
    ends = x[ordered[[0, -1]]]
    distance = np.linalg.norm(ends[:, None, :] - wet[None, :, :], axis=2).min(axis=1)
    if distance[1] < distance[0]:
        return ordered[::-1], s[-1] - s[::-1]
    return ordered, s


def pair_pressures(mesh, spec, first_nodes, g0):
    """p_u (k,) at the pairs whose first-side nodes are ``first_nodes``,
    and (p_a, p_b, S) (the curve's nodes are the first side's in the
    split mesh)."""
    ordered, s = arc_lengths(mesh, spec)
    y = mesh.coordinates[ordered[[0, -1]], 1]
    weight = spec.rho * abs(g0)
    p_a = weight * max(spec.level - y[0], 0.0)
    p_b = 0.0 if spec.tailwater is None else weight * max(spec.tailwater - y[1], 0.0)
    at = np.full(mesh.nnodes, np.nan)
    at[ordered] = s
    total = s[-1]
    return p_a + (p_b - p_a) * at[first_nodes] / total, (p_a, p_b, total)


def uplift_push(mesh, pairs, infos, specs, g0):
    """(m, 2) p_u L n of every pair of the run (0 at the interfaces that
    no water lifts), or None when no water has uplift: rank 0's, on the
    split mesh."""
    lifting = [s for s in specs if s.uplift is not None]
    if not lifting:
        return None
    push = np.zeros((pairs.m, 2))
    for spec in lifting:                    # a case's waters: one or two
        info = next(i for i in infos if i.name == spec.uplift)
        mine = info.pairs
        p, _ = pair_pressures(mesh, spec, pairs.nodes[mine, 0], g0)
        push[mine] += (p * pairs.length[mine])[:, None] * pairs.normal[mine]
    return push


def nodal_forces(nodes, push, nnodes):
    """(nn, 2) the pairs' uplift forces on the nodes ``nodes`` (m, 2)
    (first, second) numbered up to ``nnodes``: -push on the first,
    +push on the second."""
    out = np.zeros((nnodes, 2))
    np.add.at(out, nodes[:, 0], -push)
    np.add.at(out, nodes[:, 1], push)
    return out


def owned_pattern(global_nodes, push, first, nown):
    """(2 nown,) the uplift forces on a rank's owned vertices [first,
    first + nown) of the global numbering."""
    out = np.zeros((nown, 2))
    for side, sign in ((0, -1.0), (1, 1.0)):
        local = np.asarray(global_nodes[:, side]) - first
        mine = (local >= 0) & (local < nown)
        np.add.at(out, local[mine], sign * push[mine])
    return out.ravel()
