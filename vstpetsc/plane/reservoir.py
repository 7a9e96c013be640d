"""The acoustic waters of a plane-strain model on rank 0's whole mesh
(vstpetsc.plane.acoustic for the physics): their checks against the
mesh, the mesh split along their wetted faces (with the interfaces, at
once: vstpetsc.plane.pairs.split_all), and the entries they add to C in
the mesh's numbering as read.  Pure numpy."""

from dataclasses import dataclass

import numpy as np

from vstpetsc.plane import acoustic
from vstpetsc.plane.schema import RegionSpec


def acoustic_specs(specs):
    """The [[water]] tables with hydrodynamic = "acoustic"."""
    return [s for s in specs if s.acoustic is not None]


def stand_ins(specs):
    """{region name: RegionSpec} standing for each acoustic water's region
    in what reads the regions' materials: its density, no elastic moduli
    (no stress, no strain energy of its own outside its K), and ``bulk``
    (cell_materials' "bulk": the cells whose matrices are the water's)."""
    out = {}
    for spec in acoustic_specs(specs):
        out[spec.acoustic.region] = RegionSpec(spec.acoustic.region, 0.0, 0.0, spec.rho,
                                               mass="averaged", bulk=spec.acoustic.bulk)
    return out


def wetted_names(specs):
    """The curves the acoustic waters wet (split from their water)."""
    return [name for s in acoustic_specs(specs) for name in s.faces]


def _cells_beside(mesh, edges):
    """(m, 2) the regions of the cells on the two sides of each edge (-1:
    none, the mesh's boundary)."""
    cells, a, b = mesh.edges()
    keys = mesh.edge_keys(a, b)
    order = np.argsort(keys, kind="stable")
    keys, cells = keys[order], cells[order]
    want = mesh.edge_keys(edges[:, 0], edges[:, 1])
    at = np.searchsorted(keys, want)
    first = mesh.region[cells[at]]
    nxt = np.minimum(at + 1, keys.size - 1)
    second = np.where(keys[nxt] == want, mesh.region[cells[nxt]], -1)
    second[at + 1 >= keys.size] = -1
    return np.column_stack([first, second])


def check(specs, mesh, tables, boundaries=()):
    """The problem of the acoustic waters against the unsplit mesh as one
    line naming the key, or None (``tables``: the [[region]] names;
    ``boundaries``: the [[boundary]] tables, none of which may hold a
    curve that only the water's cells hold)."""
    seen = {}
    for i, spec in enumerate(specs):
        if spec.acoustic is None:
            continue
        where, a = f"water[{i}] ({spec.name})", spec.acoustic
        problem = _region_problem(where, a, mesh, tables, seen) or \
            _faces_problem(where, spec, mesh) or _ends_problem(where, spec, mesh)
        if problem:
            return problem
    return _boundary_problem(specs, mesh, boundaries)


def _boundary_problem(specs, mesh, boundaries):
    """A [[boundary]] on a curve of an acoustic water's alone (its unknown
    is no velocity: its boundaries are the free surface, far and bottom)."""
    water = [mesh.region_names.index(s.acoustic.region) for s in acoustic_specs(specs)]
    for i, b in enumerate(boundaries):
        edges = mesh.curves.get(b.name)
        if not water or edges is None or not len(edges):
            continue
        sides = _cells_beside(mesh, edges)
        if np.isin(sides, water + [-1]).all(axis=1).any():
            return (f"boundary[{i}] ({b.name}).name: runs along the acoustic water's region "
                    "only: the water's boundaries are its free surface, far and bottom "
                    "(docs/water.md)")
    return None


def _region_problem(where, a, mesh, tables, seen):
    if a.region not in mesh.region_names:
        return (f"{where}.region: the mesh has no region {a.region!r} (regions: "
                f"{', '.join(mesh.region_names)})")
    if a.region in tables:
        return (f"{where}.region: {a.region!r} has a [[region]] table: the acoustic water's "
                "region is water (remove its [[region]] table)")
    if a.region in seen:
        return f"{where}.region: {a.region!r} is also {seen[a.region]}'s"
    seen[a.region] = where
    return None


def _faces_problem(where, spec, mesh):
    """Every wetted face's edges between a cell of the water and a solid's."""
    water = mesh.region_names.index(spec.acoustic.region)
    for name in spec.faces:
        if name not in mesh.curves:
            return (f"{where}.faces: {name!r} is not a curve of the mesh (curves: "
                    f"{', '.join(mesh.curves) or 'none'})")
        edges = mesh.curves[name]
        sides = _cells_beside(mesh, edges)
        good = ((sides == water).sum(axis=1) == 1) & (sides >= 0).all(axis=1)
        if not good.all():
            x, y = mesh.coordinates[edges[~good][0]].mean(axis=0)
            return (f"{where}.faces: {name!r} at ({x:g}, {y:g}) does not run between the "
                    f"water region {spec.acoustic.region!r} and a solid's cell: an acoustic "
                    "water wets the curves where it meets the solid")
    return None


def _ends_problem(where, spec, mesh):
    """far and bottom: curves of the water's outer boundary; the water's
    top at the level (its free surface)."""
    a = spec.acoustic
    water = mesh.region_names.index(a.region)
    for key, name in (("far", a.far), ("bottom.name", a.bottom)):
        if name is None:
            continue
        if name not in mesh.curves:
            return (f"{where}.{key}: {name!r} is not a curve of the mesh (curves: "
                    f"{', '.join(mesh.curves) or 'none'})")
        sides = _cells_beside(mesh, mesh.curves[name])
        if not ((sides[:, 0] == water) & (sides[:, 1] < 0)).all():
            return (f"{where}.{key}: {name!r} is not on the water region's outer boundary "
                    f"(the water's cells on one side, nothing on the other)")
    nodes = acoustic.water_nodes(mesh, [water])
    top = float(mesh.coordinates[nodes, 1].max())
    if abs(top - spec.level) > acoustic.surface_tolerance(spec.level):
        return (f"{where}.level: {spec.level:g}, but the water region {a.region!r} reaches "
                f"y = {top:g}: the acoustic water's top is its free surface")
    return None


def solid_side_curves(mesh, couplings):
    """The split mesh with each wetted face's curve on its solid side
    (``couplings`` {face: FaceCoupling}): the hydrostatic pressure and the
    records read the solid's nodes."""
    for name, face in couplings.items():
        to_solid = np.arange(mesh.nnodes)
        to_solid[face.water] = face.solid
        mesh.curves[name] = to_solid[mesh.curves[name]]
    return mesh


def couplings(mesh, specs, wet_pairs):
    """{face: FaceCoupling} of every acoustic water's faces from the split
    mesh and its {face: NodePairs}."""
    out = {}
    for spec in acoustic_specs(specs):
        index = mesh.region_names.index(spec.acoustic.region)
        wet = acoustic.water_nodes(mesh, [index])
        c = spec.acoustic.sound(spec.rho)
        for name in spec.faces:
            out[name] = acoustic.face_coupling(wet_pairs[name], wet, spec.rho, c)
    return out


def damping_entries(mesh, specs, faces):
    """(rows, columns, values) the acoustic waters add to C in the split
    mesh's dofs: the faces' skew couplings, the far ends' and bottoms'
    dashpots."""
    parts = [acoustic.coupling_entries(face) for face in faces.values()]
    for spec in acoustic_specs(specs):
        a = spec.acoustic
        impedance = spec.rho * a.sound(spec.rho)
        for name, factor in ((a.far, 1.0), (a.bottom, (1.0 - a.alpha) / (1.0 + a.alpha))):
            if name is not None and factor > 0:
                dofs, values = acoustic.edge_dashpots(mesh, mesh.curves[name], impedance * factor)
                parts.append((dofs, dofs, values))
    if not parts:
        return np.zeros(0, int), np.zeros(0, int), np.zeros(0)
    return tuple(np.concatenate(p) for p in zip(*parts))


@dataclass
class DynamicPart:
    """An acoustic water's dynamic pressure on its record's nodes: each
    node's ``partner`` water node, the water's ``impedance`` rho c, and
    its faces' couplings' ``water`` nodes and ``push`` (the forces the
    solid feels, push w)."""

    partner: np.ndarray
    impedance: float
    water: np.ndarray
    push: np.ndarray

    def values(self, v):
        """(p (m,) at the record's nodes, the resultant (2,) on the solid)
        of the velocities v (nn, 2): p = -rho c w, force = sum push w."""
        w = v[:, 0]
        return acoustic.dynamic_pressure(self.impedance, w[self.partner]), \
            self.push.T @ w[self.water] + 0.0


def dynamic_part(spec, nodes, faces):
    """The DynamicPart of the acoustic [[water]] ``spec`` whose record lists
    the solid ``nodes``, from the {face: FaceCoupling}."""
    mine = [faces[name] for name in spec.faces]
    solid = np.concatenate([f.solid for f in mine])
    water = np.concatenate([f.water for f in mine])
    order = np.argsort(solid, kind="stable")
    partner = water[order[np.searchsorted(solid[order], nodes)]]
    return DynamicPart(partner, spec.rho * spec.acoustic.sound(spec.rho), water,
                       np.concatenate([f.push for f in mine]))


def water_records(mesh, specs, faces):
    """The WaterRecord of every [[water]] on rank 0's split mesh, an
    acoustic water's with its DynamicPart (``faces``: {face:
    FaceCoupling})."""
    from vstpetsc.plane.water import water_record

    records = [water_record(mesh, spec) for spec in specs]
    for record in records:
        if record.spec.acoustic is not None:
            record.dynamic = dynamic_part(record.spec, record.nodes, faces)
    return records
