"""A plane-strain model of a case (interface.md, "Plane strain (2-D)"):
the mesh as read or generated on rank 0 (the result file's numbering),
distributed by DMPlex (vstpetsc.plane.solver.distributed), each cell's material
from its region, and each rank's rows of M, C, K with the boundaries'
dashpots, held dofs and load patterns (vstpetsc.plane.curves).

Unknowns: (v_x, v_y) of each vertex in DMPlex's global numbering; a rank
owns the vertices [start, stop).  ``owned_original`` maps them to the
numbering of the mesh as read, in which the result file, the initial
state and the gauges are given."""

import os

import numpy as np
import scipy.sparse as sp

from vstpetsc.errors import InputError
from vstpetsc.plane import acoustic, assembly, curves, elements
from vstpetsc.plane.solver import distributed, heap

OVERLAP = 0.1       # an interface's starting overlap against its cells' size


def read_mesh(spec):
    """The PlaneMesh of a [mesh] table, checked (vstpetsc.plane.mesh_checks;
    InputError naming the key)."""
    from vstpetsc.plane import mesh_checks

    where = f"mesh.file: {os.path.basename(spec.file)}" if spec.kind == "file" else \
        f"mesh.{spec.kind}"
    mesh = _built_mesh(spec)
    try:
        mesh_checks.check(mesh, cells=spec.kind != "file")      # the reader checked them
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from None
    return mesh


def _built_mesh(spec):
    from vstpetsc.plane import dam_mesh, mesh
    from vstpetsc.plane.solver import dmplex

    if spec.kind == "rectangle":
        p = spec.params
        return mesh.rectangle(p["x"], p["y"], p["nx"], p["ny"], p["triangles"],
                              p.get("joints"))
    if spec.kind == "dam":
        try:
            return dam_mesh.dam_mesh(**spec.params)
        except ValueError as exc:
            raise InputError(f"mesh.dam: {exc}") from None
    try:
        return dmplex.read_gmsh(spec.file)
    except ValueError as exc:       # ours: what the file holds that we cannot take
        raise InputError(f"mesh.file: {os.path.basename(spec.file)}: {exc}") from None
    except Exception as exc:        # PETSc's reader raises its own errors
        reason = str(exc).strip().splitlines()[-1] if str(exc).strip() else type(exc).__name__
        raise InputError(f"mesh.file: cannot read {spec.file} as a Gmsh mesh: {reason}") from None


def check_names(case, mesh):
    """InputError unless every [[region]] and [[boundary]] names a region
    or a curve of the mesh, every region of the mesh has a table and every
    [[water]] wets outer-boundary curves below its level
    (vstpetsc.plane.water.check) and lifts one open curve
    (vstpetsc.plane.uplift.check)."""
    from vstpetsc.plane import uplift, water

    from vstpetsc.plane import reservoir

    plane, regions = case.plane, mesh.region_names
    problem = reservoir.check(plane.waters, mesh, [r.name for r in plane.regions],
                              [b for b in plane.boundaries if b.name in mesh.curves])
    if problem:                 # first: a misnamed water region leaves its cells without a table
        raise InputError(problem)
    named = [r.name for r in plane.regions] + list(reservoir.stand_ins(plane.waters))
    for i, r in enumerate(plane.regions):
        if r.name not in regions:
            raise InputError(f"region[{i}] ({r.name}).name: the mesh has no region {r.name!r} "
                             f"(regions: {', '.join(regions)})")
    missing = [r for r in regions if r not in named]
    if missing:
        raise InputError(f"region: the mesh's region {missing[0]!r} has no [[region]] table")
    for i, b in enumerate(plane.boundaries):
        if b.name not in mesh.curves:
            raise InputError(f"boundary[{i}] ({b.name}).name: the mesh has no curve {b.name!r} "
                             f"(curves: {', '.join(mesh.curves) or 'none'})")
    for g in case.gauges:
        if mesh_cell(mesh, g.x) is None:
            raise InputError(f"gauge ({g.name}).x: ({g.x[0]:g}, {g.x[1]:g}) lies in no cell "
                             "of the mesh")
    problem = water.check(plane.waters, mesh) or uplift.check(plane.waters, mesh)
    if problem:
        raise InputError(problem)


def split_interfaces(case, mesh, faces=None):
    """(the mesh split along every [[interface]] and every acoustic water's
    wetted face, (infos, (nodes, normal, tangent, length)) of the
    interfaces' pairs): rank 0's (vstpetsc.plane.pairs); InputError naming
    the interface.  ``faces``: a dict given the wetted faces' couplings
    (vstpetsc.plane.reservoir), their curves turned to the solid's side."""
    from vstpetsc.plane import pairs, reservoir

    specs = case.plane.interfaces
    materials = cell_materials(regions_of(case, mesh.region_names), mesh.region)
    wetted = reservoir.wetted_names(case.plane.waters)
    try:
        mesh, infos, arrays, wet = pairs.split_all(specs, mesh, materials, case.dt, wetted)
    except ValueError as exc:
        raise InputError(str(exc)) from None
    found = reservoir.couplings(mesh, case.plane.waters, wet)
    if faces is not None:
        faces.update(found)
    return reservoir.solid_side_curves(mesh, found), (infos, arrays)


def regions_of(case, names):
    """The [[region]] of each region name, an acoustic water's region a
    stand-in (vstpetsc.plane.reservoir.stand_ins)."""
    from vstpetsc.plane.reservoir import stand_ins

    by_name = {**stand_ins(case.plane.waters), **{r.name: r for r in case.plane.regions}}
    return [by_name[n] for n in names]


def summary(case, output, mesh=None, infos=None, factors=None):
    """What a run of ``case`` solves (the run's header, and `vstpetsc run
    --dry-run`, which reads and checks the mesh here: InputError as a run
    would raise it): its size, each region's speeds and Courant number
    (a confined region's as given at p_ref, and the range of its cells'
    moduli factors when ``factors``, one per cell, are known), its
    boundaries and interfaces."""
    if mesh is None:
        mesh = read_mesh(case.plane.mesh)
        check_names(case, mesh)
        mesh, (infos, _) = split_interfaces(case, mesh)
    lines = [f"vstpetsc: {case.source}",
             f"  dt = {case.dt:g}, {case.nslabs} slabs to t = {case.nslabs * case.dt:g}; keep "
             f"every {case.every}; result: {output}",
             f"  plane strain: {mesh.ncells} cells ({mesh.triangles.size} triangles), "
             f"{mesh.nnodes} nodes"]
    size = cell_sizes(mesh)
    for r in case.plane.regions:
        h = size[mesh.region == mesh.region_names.index(r.name)]
        lines.append(f"  region {r.name}: Vp = {r.vp:.6g}, Vs = {r.vs:.6g}, rho = {r.rho:g}, "
                     f"Vp dt / h up to {r.vp * case.dt / h.min():.3g}"
                     + confined_note(r, mesh, factors))
    lines += [f"  boundary {b.name}: {b.type}" + (", incident wave" if b.incident else "")
              for b in case.plane.boundaries]
    lines += [interface_line(i) for i in infos or ()]
    lines += water_lines(case, mesh)
    return "\n".join(lines)


def water_lines(case, mesh):
    """One line per [[water]] of the summary: its level and its thrust at
    g(0) on the split mesh."""
    from vstpetsc.plane.water import water_record

    g0 = float(case.gravity.g(np.zeros(1))[0]) if case.plane.waters else 0.0
    out = []
    for spec in case.plane.waters:
        force = water_record(mesh, spec).values(g0)["force"]
        out.append(f"  water {spec.name}: level {spec.level:g}, rho {spec.rho:g}, faces "
                   f"{', '.join(spec.faces)}; hydrostatic resultant at t = 0 "
                   f"({force[0]:.6g}, {force[1]:.6g}) per unit thickness")
        if spec.acoustic is not None:
            out.append("    " + acoustic_line(case, mesh, spec))
    return out


def acoustic_line(case, mesh, spec):
    """The summary's line on an acoustic water: its region, c and c dt / h,
    its far end and bottom."""
    a = spec.acoustic
    c = a.sound(spec.rho)
    h = cell_sizes(mesh)[mesh.region == mesh.region_names.index(a.region)]
    ends = (f", far end {a.far} absorbing" if a.far else ", no far end") + \
        (f", bottom {a.bottom} alpha {a.alpha:g}" if a.bottom else "")
    return (f"acoustic: region {a.region} ({h.size} cells), bulk {a.bulk:.6g}, c = {c:.6g}, "
            f"c dt / h up to {c * case.dt / h.min():.3g}{ends}")


def confined_note(region, mesh, factors):
    """The header's note on a confined region: its cells' moduli factors
    (p / p_ref)^exponent from the static start, min to max (the speeds
    scale by their square roots); empty for an unconfined region."""
    if region.confinement is None:
        return ""
    if factors is None:
        return "; confined: moduli scaled by the static start's mean stress"
    f = factors[mesh.region == mesh.region_names.index(region.name)]
    return (f"; confined: moduli times {f.min():.3g} to {f.max():.3g} (speeds times "
            f"{np.sqrt(f.min()):.3g} to {np.sqrt(f.max()):.3g})")


def interface_line(info):
    """One line per interface of the summary."""
    friction = f", Coulomb friction {info.friction:g}, tangential stiffness " \
        f"{info.shear_stiffness:.6g}" if info.friction is not None else ", no friction"
    return (f"  interface {info.name}: {info.pairs.stop - info.pairs.start} node pairs, "
            f"{info.formulation} penalty {info.penalty:.6g} per unit length "
            f"({'given' if info.given else 'default'}){friction}")


def cell_sizes(mesh):
    """Each cell's h for a Courant number: the side of the square (a
    quadrilateral) or of the right isosceles triangle of its area."""
    return np.sqrt(np.abs(mesh.areas()) * np.where(mesh.cells[:, 3] < 0, 2.0, 1.0))


def mesh_cell(mesh, point):
    """(cell, its nodes, their weights) of the cell holding ``point`` (the
    first such), or None: the finite element field's own interpolation."""
    from vstpetsc.plane.gauges import locate
    return locate(mesh, np.asarray(point, float))


class PlaneModel:
    """The 2-D model of a case on ``comm`` (collective)."""

    dimension = 2

    def __init__(self, case, comm):
        self.case, self.comm = case, comm
        self.laws, self.recorded, self.bodies, self.soil = [], [], [], None
        self.zone = self.factors = None     # factors: confinement's (vstpetsc.plane.confinement)
        rank0 = comm.getRank() == 0
        error, mesh, split = None, None, None
        self.faces = {}                 # rank 0's acoustic waters' FaceCouplings
        if rank0:
            try:
                mesh = read_mesh(case.plane.mesh)
                check_names(case, mesh)
                mesh, split = split_interfaces(case, mesh, self.faces)
                check_overlap(case, mesh, split[0], *split[1][:2])
            except InputError as exc:
                error = str(exc)
        error = comm.tompi4py().bcast(error, root=0)
        if error:
            raise InputError(error)
        self.mesh = mesh                            # the whole mesh on rank 0, None elsewhere
        self.infos, arrays = comm.tompi4py().bcast(split, root=0)
        self.local = distributed.distribute(mesh, comm, links=arrays and arrays[0])
        self.nnodes = self.local.size
        self.ncells = comm.tompi4py().bcast(mesh.ncells if rank0 else None, root=0)
        self.regions = self._regions(self.local.mesh.region_names)
        self._owned_numbering()
        self.materials = cell_materials(self.regions, self.local.mesh.region)
        if rank0:
            self.cell_materials = cell_materials(self._regions(mesh.region_names), mesh.region)
        self.boundaries = curves.Boundaries(self, case.plane.boundaries)
        hold_water(self)
        self.pairs = self._pairs(arrays)
        self.zone = self._zone()
        if self.pairs is not None:
            from vstpetsc.plane.pairs import InterfaceRecord
            self.recorded = [InterfaceRecord(self.pairs, i) for i in self.infos]
        self.waters = self._waters(rank0)
        self.uplift = self._uplift(rank0)
        self._matrices = None
        from vstpetsc.plane.gauges import PlaneGauges
        self.gauges = PlaneGauges(self)
        heap.give_back()                # the mesh's checks' and split's temporaries

    def _waters(self, rank0):
        """The WaterRecords of the [[water]] tables (the outputs, rank 0's;
        elsewhere their shapes' stand-ins: the nodes' count, every rank's);
        sets ``water_bottoms``, each table's faces' lowest y (every rank's:
        Westergaard's H)."""
        from vstpetsc.plane.reservoir import water_records
        from vstpetsc.plane.water import WaterRecord

        from vstpetsc.plane.westergaard import faces_bottom

        specs = self.case.plane.waters
        records = water_records(self.mesh, specs, self.faces) if rank0 else None
        counts, self.water_bottoms = self.comm.tompi4py().bcast(
            ([r.nodes.size for r in records], [faces_bottom(self.mesh, s) for s in specs])
            if rank0 else None, root=0)
        return records if rank0 else [
            WaterRecord(spec, np.zeros(m, dtype=int), np.zeros(m), np.zeros(2))
            for spec, m in zip(specs, counts)]

    def _uplift(self, rank0):
        """(m, 2) each pair's uplift force p_u L n (vstpetsc.plane.uplift),
        every rank's; None when no water has uplift (collective)."""
        from vstpetsc.plane.uplift import uplift_push

        push = None
        # water needs [gravity] (the schema's check): without water, no uplift
        if rank0 and self.pairs is not None and self.case.plane.waters:
            g0 = float(self.case.gravity.g(np.zeros(1))[0])
            push = uplift_push(self.mesh, self.pairs, self.infos, self.case.plane.waters, g0)
        return self.comm.tompi4py().bcast(push, root=0)

    def _regions(self, names):
        return regions_of(self.case, names)

    def _owned_numbering(self):
        """The local vertices this rank owns in global order, and their
        numbers in the mesh as read."""
        local = self.local
        owned = np.flatnonzero(local.owned)
        owned = owned[np.argsort(local.global_vertex[owned])]
        self.owned_local = owned
        self.owned_original = local.original[owned]
        self.first = local.start

    def _pairs(self, arrays):
        """The PairSet of the interfaces (None without), with each pair's
        nodes also in the global numbering (``pairs.global_nodes``)."""
        if not self.infos:
            return None
        from vstpetsc.plane.pairs import PairSet

        pairs = PairSet(self.infos, *arrays, self.case.dt)
        global_of = self._global_of()
        numbering = None if global_of is None else global_of[pairs.nodes]
        pairs.global_nodes = self.comm.tompi4py().bcast(numbering, root=0)
        return pairs

    def _global_of(self):
        """Rank 0: each node's global number (the slab vector's order) by
        its number in the mesh as read; None elsewhere (collective)."""
        comm = self.comm.tompi4py()
        numbering = comm.gather((self.owned_original, self.first), root=0)
        if comm.Get_rank() != 0:
            return None
        global_of = np.empty(self.nnodes, dtype=np.int64)
        for original, first in numbering:
            global_of[original] = first + np.arange(original.size)
        return global_of

    def _zone(self):
        """The yielding zone of the regions with a shear_law (None without):
        its kernels on rank 0, its unknowns' global slab indices on every
        rank (collective)."""
        if all(r.shear_law is None for r in self.case.plane.regions):
            return None
        from vstpetsc.plane.yielding import YieldingZone, ZoneUnknowns, zone_cells

        global_of = self._global_of()
        zone = None
        if self.comm.getRank() == 0:
            cells, params = zone_cells(self._regions(self.mesh.region_names), self.mesh.region)
            if self.factors is not None:            # gamma_ref scaled as G
                params["gamma_ref"] = params["gamma_ref"] * self.factors[cells]
            mat = self.cell_materials
            zone = YieldingZone(self.mesh, cells, mat["lam"], mat["mu"], params, self.case.dt,
                                global_of)
        index = self.comm.tompi4py().bcast(None if zone is None else zone.slab_index, root=0)
        return zone if zone is not None else ZoneUnknowns(index)

    def matrices(self):
        """(M, C or None, K): this rank's rows (CSR, global columns),
        assembled once; M with Westergaard's added masses."""
        if self._matrices is None:
            self._matrices = self._assemble()
        return self._matrices

    def release_matrices(self):
        """Forget the assembled CSR matrices (the solver holds PETSc's
        copies; at 1e6 cells they are 1.3 GB)."""
        self._matrices = None

    def unit_weight(self):
        """The nodal pattern of a unit body force along +y on this rank's
        owned dofs: the rows of the solid's own M (without the water's
        added masses: they carry no weight)."""
        self.matrices()
        return self._unit_weight

    def _assemble(self):
        from vstpetsc.plane.loads import unit_gravity
        from vstpetsc.plane.westergaard import owned_rows

        M, C, K = spatial_matrices(self.local.mesh, self.materials, self.local)
        self._unit_weight = unit_gravity(M)
        added = owned_rows(self.local.mesh, self.owned_local, self.first, self.nnodes,
                           self.case.plane.waters, self.water_bottoms)
        if added is not None:               # inertia only: not in C = alpha M + beta K
            M = M + added
        for extra in (self.boundaries.dashpots(), water_damping(self)):
            if extra is not None:
                C = extra if C is None else C + extra
        return M, C, K

    def closed_springs(self, whole=False):
        """The interfaces' closed, sticking springs (vstpetsc.plane.pairs;
        None without): this rank's rows (CSR, global columns), or with
        ``whole`` every row in the mesh's numbering as read (rank 0's
        static solve)."""
        if self.pairs is None:
            return None
        p = self.pairs
        springs = p.springs(p.nodes if whole else p.global_nodes, self.nnodes)
        return springs if whole else \
            springs[2 * self.first:2 * (self.first + self.owned_original.size)]

    def courant(self, dt):
        """The largest Vp dt / h over every rank's cells (h: cell_sizes)."""
        mat = self.materials
        # an acoustic water's cells: c = sqrt(bulk / rho) (their lam and mu are 0)
        vp = np.sqrt((mat["lam"] + 2 * mat["mu"] + mat["bulk"]) / mat["rho"])
        local = float(np.max(vp * dt / cell_sizes(self.local.mesh), initial=0.0))
        from mpi4py import MPI
        return self.comm.tompi4py().allreduce(local, op=MPI.MAX)

    def initial_state(self):
        """(u, v) of every node (interleaved (x, y), the mesh's numbering as
        read) from the regions' u0 and v0; a node shared by regions takes
        the last region's value (collective: every rank gets them)."""
        u = v = None
        if self.comm.getRank() == 0:
            u, v, _ = region_state(self.mesh, self._regions(self.mesh.region_names))
        u, v = self.comm.tompi4py().bcast((u, v), root=0)
        return u, v


def hold_water(model):
    """Hold an acoustic water's free surface (p = 0) and every water
    node's y slot (vstpetsc.plane.acoustic) among the model's boundaries."""
    from vstpetsc.plane.acoustic import held_nodes
    from vstpetsc.plane.reservoir import acoustic_specs

    specs = acoustic_specs(model.case.plane.waters)
    if specs:
        surface, every = held_nodes(model.local.mesh, specs)
        model.boundaries.hold_still(every, 1)
        model.boundaries.hold_still(surface, 0)


def water_damping(model):
    """The acoustic waters' rows of C (vstpetsc.plane.reservoir): CSR,
    the model's owned rows, global columns; None without (collective)."""
    from vstpetsc.plane.reservoir import acoustic_specs, damping_entries

    if not acoustic_specs(model.case.plane.waters):
        return None
    global_of = model._global_of()
    entries = None
    if global_of is not None:
        rows, cols, values = damping_entries(model.mesh, model.case.plane.waters, model.faces)
        to_global = lambda d: 2 * global_of[d // 2] + d % 2
        entries = (to_global(rows), to_global(cols), values)
    rows, cols, values = model.comm.tompi4py().bcast(entries, root=0)
    first, nown = model.first, model.owned_original.size
    keep = (rows >= 2 * first) & (rows < 2 * (first + nown))
    return sp.csr_matrix((values[keep], (rows[keep] - 2 * first, cols[keep])),
                         shape=(2 * nown, 2 * model.nnodes))


def region_state(mesh, regions):
    """(u, v, the region each node takes them from) (nn, 2), (nn, 2), (nn,)
    of ``mesh`` from its ``regions``' u0 and v0: a node shared by regions
    takes the last region's value."""
    u, v = np.zeros((mesh.nnodes, 2)), np.zeros((mesh.nnodes, 2))
    source = np.zeros(mesh.nnodes, dtype=int)
    for i, r in enumerate(regions):
        nodes = mesh.cells[mesh.region == i]
        nodes = nodes[nodes >= 0]
        u[nodes], v[nodes], source[nodes] = r.u0, r.v0, i
    return u, v, source


def check_overlap(case, mesh, infos, nodes, normal):
    """InputError where the regions' u0 press an interface's two sides
    into each other deeper than OVERLAP of the cells beside it: the
    penalty stands for a compliance far smaller than the cells, and such
    a start is the mesh overlapping itself, thrown apart with the
    penalty's energy.  A shallower overlap is a joint that starts
    pressed (its penalty's energy is part of the initial energy)."""
    regions = regions_of(case, mesh.region_names)
    u, _, source = region_state(mesh, regions)
    du = u[nodes[:, 1]] - u[nodes[:, 0]]
    gap = np.einsum("mc,mc->m", normal, du)
    size = np.full(mesh.nnodes, np.inf)
    corners = mesh.cells >= 0
    np.minimum.at(size, mesh.cells[corners],
                  np.broadcast_to(cell_sizes(mesh)[:, None], mesh.cells.shape)[corners])
    deep = -gap > OVERLAP * np.minimum(size[nodes[:, 0]], size[nodes[:, 1]])
    if not deep.any():
        return
    k = int(np.argmin(np.where(deep, gap, np.inf)))
    info = next(i for i in infos if i.pairs.start <= k < i.pairs.stop)
    sides = [regions[source[n]] for n in nodes[k]]
    moved = max(sides, key=lambda r: np.abs(r.u0).max())          # the key to look at
    index = case.plane.regions.index(moved)
    against = "" if sides[0] is sides[1] else \
        f" against region {[r for r in sides if r is not moved][0].name!r}"
    x, y = mesh.coordinates[nodes[k, 0]]
    raise InputError(f"region[{index}] ({moved.name}).u0: starts interface {info.name!r} "
                     f"overlapping{against} by {-gap[k]:.6g} at ({x:.6g}, {y:.6g}), more "
                     f"than {OVERLAP:g} of the cells beside it ({int(deep.sum())} pairs): a "
                     "joint may start pressed, not interpenetrating")


CHUNK = 1 << 13         # cells assembled at once: their element matrices' memory bounded


def spatial_matrices(mesh, mat, local=None):
    """(M, Rayleigh C or None, K) of ``mesh``'s cells with their materials
    ``mat`` (cell_materials): CSR of all its nodes, or with ``local`` (a
    LocalMesh) this rank's owned rows in global columns; summed over
    chunks of CHUNK cells (at 1e6 cells the element matrices and their
    coordinate lists of all cells at once held 7 GB)."""
    rows = (lambda blocks: assembly.assemble(mesh, blocks)) if local is None else \
        (lambda blocks: distributed.owned_rows(local, blocks))
    sums = [PairwiseSum(), PairwiseSum(), PairwiseSum()]
    for first in range(0, max(mesh.ncells, 1), CHUNK):
        for total, blocks in zip(sums, _chunk_blocks(mesh, mat, (first, first + CHUNK))):
            if blocks or total is not sums[1]:
                total.add(rows(blocks))
    return tuple(total.result() for total in sums)


class PairwiseSum:
    """A sum of sparse matrices added in pairs of equal counts (a binary
    counter), so each entry is summed log2(parts) times, not once a part."""

    def __init__(self):
        self.stack = []             # (how many parts, their sum)

    def add(self, part):
        count = 1
        while self.stack and self.stack[-1][0] == count:
            done, previous = self.stack.pop()
            part, count = previous + part, count + done
        self.stack.append((count, part))

    def result(self):
        """The sum (None if nothing was added)."""
        total = None
        for _, part in reversed(self.stack):
            total = part if total is None else part + total
        return total


def _chunk_blocks(mesh, mat, within):
    """([(cells, M_e)], [(cells, C_e)] (empty without damping),
    [(cells, K_e)]) of the cells in the range ``within``: each cell's
    mass kind, Rayleigh damping, an acoustic water's Laplacian."""
    parts = assembly.element_matrices(mesh, mat["lam"], mat["mu"], mat["rho"], within)
    mass, stiff, damp = [], [], []
    for cells, Ke, Me in parts.values():
        water = mat["bulk"][cells] > 0          # an acoustic water's cells: its Laplacian
        if water.any():
            xy = mesh.coordinates[mesh.cells[cells[water], :Ke.shape[1] // 2]]
            Ke[water] = acoustic.element_stiffness(xy, mat["bulk"][cells[water]])
        Me = massed(Me, mat["mass"][cells])
        mass.append((cells, Me))
        stiff.append((cells, Ke))
        a, b = mat["alpha"][cells], mat["beta"][cells]
        if a.any() or b.any():
            damp.append((cells, a[:, None, None] * Me + b[:, None, None] * Ke))
    return mass, damp, stiff


def cell_materials(regions, region):
    """{lam, mu, rho, alpha, beta, mass} per cell from its region's spec."""
    take = lambda f: np.array([f(r) for r in regions], dtype=float)[region] if len(region) \
        else np.zeros(0)
    out = {"lam": take(lambda r: r.lam), "mu": take(lambda r: r.mu), "rho": take(lambda r: r.rho),
           "alpha": take(lambda r: r.damping[0]), "beta": take(lambda r: r.damping[1]),
           "bulk": take(lambda r: r.bulk)}          # > 0: an acoustic water's
    kinds = list(elements.MASSES)
    out["mass"] = np.array([kinds.index(r.mass) for r in regions], dtype=int)[region] \
        if len(region) else np.zeros(0, dtype=int)
    return out


def massed(Me, kind):
    """Consistent element masses Me turned into each cell's mass kind
    (indices into elements.MASSES)."""
    out = np.empty_like(Me)
    for k, transform in enumerate(elements.MASSES.values()):
        chosen = kind == k
        if chosen.any():
            out[chosen] = transform(Me[chosen])
    return out
