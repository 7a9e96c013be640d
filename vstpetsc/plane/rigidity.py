"""Whether a plane-strain static problem holds every rigid motion
(issue 44): K u = f has one solution only if no part of the mesh can move
as a rigid body.  The stiffness of linear cells strains nothing under a
rigid motion of a part joined by edges, and nothing else: K's kernel is
spanned by the rigid motions (two translations, a rotation) of each
part.  The question is then small and exact: do the constraints (held
dofs, the hinges where parts share a lone node, the closed pairs' normal
springs and the sticking pairs' stick springs) leave a combination of the
parts' rigid motions free?  C, one row a constraint and three columns a
part, has full column rank iff they do not.  Its size is the number of
constraints by 3 x the parts; no factorisation of K.

Rotations are measured at the part's centroid and scaled by its radius
of gyration, so that every entry of C is of order one: an exact kernel
leaves C v at rounding (1e-16 sqrt(rows)), a part held at two points a
distance d apart has its weakest motion at (d / L)^2 of C^T C's largest
eigenvalue.  KERNEL_TOL lies between the two for any mesh whose held
points are at least 1e-5 of its size apart.  Pure numpy and scipy."""

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

KERNEL_TOL = 1e-14           # of C^T C's largest eigenvalue


def parts(mesh):
    """(number of parts, the part of each cell): cells joined across
    shared edges (two cells that share only a node are two parts)."""
    cells, a, b = mesh.edges()
    keys = mesh.edge_keys(a, b)
    order = np.argsort(keys, kind="stable")
    keys, cells = keys[order], cells[order]
    twin = np.flatnonzero(keys[1:] == keys[:-1])
    graph = sp.coo_matrix((np.ones(twin.size), (cells[twin], cells[twin + 1])),
                          shape=(mesh.ncells, mesh.ncells))
    return connected_components(graph, directed=False)


class RigidModes:
    """The rigid motions of a mesh's parts: ``modes(nodes, parts)`` gives
    each node's (x, y) displacement under each of the 3 P motions."""

    def __init__(self, mesh):
        self.mesh = mesh
        self.count, self.cell_part = parts(mesh)
        corner = mesh.cells >= 0
        node = mesh.cells[corner]
        part = np.broadcast_to(self.cell_part[:, None], mesh.cells.shape)[corner]
        pairs = np.unique(node.astype(np.int64) * self.count + part)
        self.node_of, self.part_of = pairs // self.count, pairs % self.count
        x = mesh.coordinates[self.node_of]
        weight = np.bincount(self.part_of, minlength=self.count).astype(float)
        self.centre = np.column_stack([np.bincount(self.part_of, x[:, k], self.count)
                                       for k in range(2)]) / weight[:, None]
        spread = np.bincount(self.part_of, ((x - self.centre[self.part_of]) ** 2).sum(axis=1),
                             self.count) / weight
        size = np.ptp(mesh.coordinates, axis=0).max(initial=0.0) if mesh.nnodes else 1.0
        self.radius = np.maximum(np.sqrt(spread), 1e-3 * max(size, 1e-300))
        # a node's first part (the one a pair's node is taken in)
        self.first_part = np.full(mesh.nnodes, -1)
        self.first_part[self.node_of[::-1]] = self.part_of[::-1]

    def rows(self, nodes, part, direction):
        """Rows of C: direction . (rigid motion of ``part`` at ``nodes``),
        (k, 3P) sparse for k (nodes, part, unit direction (k, 2))."""
        r = (self.mesh.coordinates[nodes] - self.centre[part]) / self.radius[part][:, None]
        rotation = direction[:, 1] * r[:, 0] - direction[:, 0] * r[:, 1]
        values = np.column_stack([direction[:, 0], direction[:, 1], rotation])
        k = np.arange(nodes.size)
        return sp.csr_matrix((values.ravel(), (np.repeat(k, 3),
                                               (3 * part[:, None] + np.arange(3)).ravel())),
                             shape=(nodes.size, 3 * self.count))


def constraint_rows(modes, held_dofs, pair_nodes, pair_directions):
    """C: a row per held dof in each part at its node, two per hinge (a
    node in two parts), one per spring (pair nodes (k, 2), the spring's
    unit direction (k, 2): the second node's motion less the first's)."""
    unit = np.eye(2)
    node, comp = held_dofs // 2, held_dofs % 2
    blocks = []
    # held: every part at the node
    at = np.searchsorted(modes.node_of, node, side="left")
    reps = np.searchsorted(modes.node_of, node, side="right") - at
    within = np.arange(reps.sum()) - np.repeat(np.cumsum(reps) - reps, reps)
    blocks.append(modes.rows(np.repeat(node, reps), modes.part_of[np.repeat(at, reps) + within],
                             unit[np.repeat(comp, reps)]))
    # hinges: consecutive parts at one node move alike
    same = np.flatnonzero(modes.node_of[1:] == modes.node_of[:-1])
    for d in range(2):
        direction = np.tile(unit[d], (same.size, 1))
        blocks.append(modes.rows(modes.node_of[same], modes.part_of[same], direction) -
                      modes.rows(modes.node_of[same + 1], modes.part_of[same + 1], direction))
    if len(pair_nodes):
        first, second = pair_nodes[:, 0], pair_nodes[:, 1]
        blocks.append(modes.rows(second, modes.first_part[second], pair_directions) -
                      modes.rows(first, modes.first_part[first], pair_directions))
    return sp.vstack(blocks).tocsr()


def free_motions(modes, C):
    """The combinations of rigid motions C leaves free: (3P, k) unit
    columns (k = 0: every part held)."""
    G = (C.T @ C).toarray()
    values, vectors = np.linalg.eigh(G)
    top = max(values[-1] if values.size else 0.0, 1.0)
    return vectors[:, values <= KERNEL_TOL * top]


def describe(modes, motion, region_names, region):
    """Words for one free motion: which part, where, how it moves."""
    amount = np.linalg.norm(motion.reshape(-1, 3), axis=1)
    part = int(np.argmax(amount))
    cells = np.flatnonzero(modes.cell_part == part)
    names = sorted({region_names[r] for r in region[cells]})
    tx, ty, rot = motion[3 * part:3 * part + 3] / amount[part]
    x, y = modes.centre[part]
    if abs(rot) > 0.5:          # about the point the motion leaves in place
        r = modes.radius[part] / rot
        how = f"rotate about ({x - r * ty:.6g}, {y + r * tx:.6g})"
    elif abs(ty) < 1e-6:
        how = "move along x"
    elif abs(tx) < 1e-6:
        how = "move along y"
    else:
        how = f"move along ({tx:.3g}, {ty:.3g})"
    regions = ", ".join(map(repr, names))
    return (f"the part of region{'s' if len(names) > 1 else ''} {regions} of {cells.size} "
            f"cells about ({x:.6g}, {y:.6g}) is free to {how}")


def free_part(mesh, held_dofs, pair_nodes=np.zeros((0, 2), int),
              pair_directions=np.zeros((0, 2))):
    """Words for a rigid motion that the held dofs and springs leave free
    in ``mesh`` (None: every part is held)."""
    modes = RigidModes(mesh)
    C = constraint_rows(modes, np.asarray(held_dofs, dtype=np.int64),
                        np.asarray(pair_nodes, dtype=np.int64).reshape(-1, 2),
                        np.asarray(pair_directions, float).reshape(-1, 2))
    free = free_motions(modes, C)
    if free.shape[1] == 0:
        return None
    more = free.shape[1] - 1
    return describe(modes, free[:, 0], mesh.region_names, mesh.region) + \
        (f" (and {more} more rigid motion{'s' if more > 1 else ''} left free)" if more else "")
