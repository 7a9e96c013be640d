"""Water against a plane-strain dam, hydrostatic (interface.md, "Water
against a dam (2-D)"; docs/water.md): on every wetted face the pressure
p = rho |g| (level - y) where y < level (0 above) pushes on the solid,
traction -p n with n the solid's outward normal.

Along a straight edge p is linear in y where the edge is below the level
and 0 above, so each edge is cut at the level and the wet piece
integrated with two Gauss points: the consistent nodal forces
int N_a (-p n) ds are then exact (N_a p is quadratic on the piece).
The forces are a pattern per unit g (p = -rho g (level - y) for g <= 0,
[gravity] g along y), added to the weight's pattern, so they follow
g(t) in the static start and in the run.  Pure numpy and scipy."""

from dataclasses import dataclass

import numpy as np
from scipy.sparse.csgraph import breadth_first_order

from vstpetsc.plane.boundaries import edge_frames
from vstpetsc.plane.curves import edge_cells
from vstpetsc.plane.edge_graph import edge_graph

GAUSS = np.array([0.5 - 0.5 / np.sqrt(3.0), 0.5 + 0.5 / np.sqrt(3.0)])   # on [0, 1], weights 1/2


def face_edges(mesh, faces):
    """Every edge (m, 2) of the curves ``faces`` that the mesh holds."""
    parts = [mesh.curves.get(name, np.zeros((0, 2), dtype=int)) for name in faces]
    return np.concatenate(parts).astype(int) if parts else np.zeros((0, 2), dtype=int)


def outward_normals(mesh, edges):
    """The unit normal (m, 2) of each boundary edge pointing out of the
    cell that holds it (away from the cell's centroid: whatever the order
    of the cell's nodes, a convex cell's centroid lies inside it)."""
    _, normal, _ = edge_frames(mesh, edges)
    cells = mesh.cells[edge_cells(mesh, edges)]
    corner = np.where(cells < 0, cells[:, [0]], cells)         # a triangle repeats a node
    centre = mesh.coordinates[corner].mean(axis=1)
    middle = mesh.coordinates[edges].mean(axis=1)
    away = np.einsum("mc,mc->m", normal, middle - centre) > 0
    return np.where(away[:, None], normal, -normal)


def wet_pieces(y, level):
    """(s0, s1) (m,) each: the piece of each edge (parameter s in [0, 1]
    from its first end, y (m, 2) at its ends) below ``level``; s1 <= s0
    for a dry edge."""
    y0, dy = y[:, 0], y[:, 1] - y[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        cut = np.clip((level - y0) / dy, 0.0, 1.0)
    flat = dy == 0
    s0 = np.where(flat, 0.0, np.where(dy > 0, 0.0, cut))
    s1 = np.where(flat, np.where(y0 < level, 1.0, 0.0), np.where(dy > 0, cut, 1.0))
    return s0, s1


def edge_forces(xy, normal, rho, level):
    """The consistent nodal forces (m, 2 ends, 2 components) per unit g of
    the water on edges with ends ``xy`` (m, 2, 2) and outward unit
    ``normal`` (m, 2): traction -p n with p = -rho g (level - y)+, so per
    unit g rho (level - y)+ n, integrated exactly (wet_pieces, two Gauss
    points on each piece)."""
    length = np.linalg.norm(xy[:, 1] - xy[:, 0], axis=1)
    s0, s1 = wet_pieces(xy[:, :, 1], level)
    width = np.maximum(s1 - s0, 0.0)
    s = s0[:, None] + width[:, None] * GAUSS[None, :]              # (m, 2 points)
    depth = level - ((1 - s) * xy[:, 0, 1][:, None] + s * xy[:, 1, 1][:, None])
    shapes = np.stack([1 - s, s], axis=1)                          # (m, 2 ends, 2 points)
    integral = 0.5 * width[:, None] * np.einsum("map,mp->ma", shapes, depth)
    return rho * (length[:, None] * integral)[:, :, None] * normal[:, None, :]


def nodal_pattern(mesh, spec):
    """(nn, 2) the forces per unit g of the water table ``spec`` on the
    nodes of ``mesh`` (the edges of its faces that it holds)."""
    edges = face_edges(mesh, spec.faces)
    out = np.zeros((mesh.nnodes, 2))
    if len(edges):
        forces = edge_forces(mesh.coordinates[edges], outward_normals(mesh, edges), spec.rho,
                             spec.level)
        np.add.at(out, edges[:, 0], forces[:, 0])
        np.add.at(out, edges[:, 1], forces[:, 1])
    return out


def whole_pattern(mesh, specs):
    """(2 nn,) the interleaved forces per unit g of every water table on
    the whole mesh (rank 0's static solve, the mesh's numbering)."""
    out = np.zeros((mesh.nnodes, 2))
    for spec in specs:
        out += nodal_pattern(mesh, spec)
    return out.ravel()


def owned_pattern(local_mesh, owned_local, specs):
    """(2 n,) the forces per unit g of every water table on one rank's
    owned vertices ``owned_local`` (local indices in global order): its
    overlap holds every edge around them, so their sums are whole."""
    out = np.zeros((local_mesh.nnodes, 2))
    for spec in specs:
        out += nodal_pattern(local_mesh, spec)
    return out[owned_local].ravel()


def chain(x, edges):
    """The nodes of edges (m, 2) in order along each connected piece, from
    an end (the lowest, then leftmost; a closed piece from its lowest
    node), pieces by their starts' order of (y, x)."""
    g = edge_graph(edges)
    nodes, graph = g.nodes, g.graph
    xy = x[nodes]
    starts = []
    for k in range(g.count):                    # a face's pieces: one, or a few
        members, ends = g.members(k)
        candidates = ends if ends.size else members
        starts.append(candidates[np.lexsort((xy[candidates, 0], xy[candidates, 1]))[0]])
    starts = np.array(starts, dtype=int)
    starts = starts[np.lexsort((xy[starts, 0], xy[starts, 1]))]
    order = [breadth_first_order(graph, s, directed=False, return_predecessors=False)
             for s in starts]
    return nodes[np.concatenate(order)] if order else np.zeros(0, dtype=int)


@dataclass
class WaterRecord:
    """One water table's outputs (group ``water/<name>``) on rank 0's
    whole mesh: the wetted ``nodes`` in order along the faces, their
    ``depth`` (level - y)+, and ``unit_force`` (2,) the resultant per
    unit g."""

    spec: object
    nodes: np.ndarray
    depth: np.ndarray
    unit_force: np.ndarray
    dynamic: object = None      # an acoustic water's (vstpetsc.plane.reservoir.DynamicPart)

    @property
    def group(self):
        return f"water/{self.spec.name}"

    def values(self, g, v=None):
        """{pressure (m,), force (2,)} at gravity ``g`` (g <= 0), with an
        acoustic water's dynamic part from the state's velocities ``v``
        (nn, 2) (the mesh's numbering as read)."""
        out = {"pressure": self.spec.rho * -g * self.depth + 0.0,      # + 0: no -0
               "force": self.unit_force * g + 0.0}
        if self.dynamic is not None and v is not None:
            pressure, force = self.dynamic.values(v)
            out["pressure"] = out["pressure"] + pressure
            out["force"] = out["force"] + force
        return out


def water_record(mesh, spec):
    """The WaterRecord of ``spec`` on the whole mesh: the nodes of the
    faces' edges that reach below the level (those the water loads),
    face by face in order along each (a node listed once)."""
    by_face = [chain(mesh.coordinates, e[mesh.coordinates[e, 1].min(axis=1) < spec.level])
               for e in (mesh.curves[name] for name in spec.faces)]
    nodes = np.concatenate(by_face) if by_face else np.zeros(0, dtype=int)
    _, first = np.unique(nodes, return_index=True)
    nodes = nodes[np.sort(first)]
    depth = np.maximum(spec.level - mesh.coordinates[nodes, 1], 0.0)
    return WaterRecord(spec, nodes, depth, nodal_pattern(mesh, spec).sum(axis=0))


def check(specs, mesh):
    """The problem of the water tables against the (unsplit) mesh, as one
    line naming the key, or None: a face that is not a curve of the mesh
    or not on its outer boundary (an edge of one cell), two faces that
    share an edge (curves may overlap: the generated dam's "faces" holds
    its "upstream"), a level at or below every face's lowest point (no
    water on the dam)."""
    _, a, b = mesh.edges()
    keys, counts = np.unique(mesh.edge_keys(a, b), return_counts=True)
    for i, spec in enumerate(specs):
        where = f"water[{i}] ({spec.name})"
        # an acoustic water's faces lie between cells (vstpetsc.plane.reservoir.check)
        for name in spec.faces if spec.acoustic is None else ():
            if name not in mesh.curves:
                return (f"{where}.faces: {name!r} is not a curve of the mesh (curves: "
                        f"{', '.join(mesh.curves) or 'none'})")
            edges = mesh.curves[name]
            at = np.searchsorted(keys, mesh.edge_keys(edges[:, 0], edges[:, 1]))
            inner = counts[np.minimum(at, keys.size - 1)] != 1
            if inner.any():
                x, y = mesh.coordinates[edges[inner][0]].mean(axis=0)
                return (f"{where}.faces: {name!r} runs between two cells at ({x:g}, {y:g}): "
                        "water wets the outer boundary of the solid")
        shared = _shared_edge(mesh, spec.faces)
        if shared:
            (a, b), (x, y) = shared
            return (f"{where}.faces: {a!r} and {b!r} share the edge at ({x:g}, {y:g}): the "
                    "water would load it twice (name each wetted edge once)")
        lowest = min(float(mesh.coordinates[mesh.curves[n], 1].min(initial=np.inf))
                     for n in spec.faces)
        if not spec.level > lowest:
            return (f"{where}.level: {spec.level:g} is not above the faces' lowest point "
                    f"(y = {lowest:g}): the water wets nothing")
    return None


def _shared_edge(mesh, names):
    """((first name, second name), an edge's midpoint) of two of the curves
    ``names`` that share an edge, or None."""
    seen = {}
    for name in names:
        edges = mesh.curves[name]
        for key, edge in zip(mesh.edge_keys(edges[:, 0], edges[:, 1]).tolist(), edges):
            if seen.setdefault(key, name) != name:
                return (seen[key], name), tuple(mesh.coordinates[edge].mean(axis=0))
    return None
