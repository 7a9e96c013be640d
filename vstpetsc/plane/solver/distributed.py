"""A plane-strain mesh distributed over the ranks by PETSc's DMPlex, and
its matrices assembled in parallel.

DMPlex partitions the cells (with an overlap of one cell, so that each
rank holds every cell around the vertices it owns) and numbers the
vertices globally, each rank owning a contiguous range.  A rank computes
the element matrices of all its cells at once (vstpetsc.plane.elements)
and keeps the entries of the rows it owns: every such row is then whole,
and the rank's rows go to PETSc's parallel AIJ in one CSR call (no loop
over cells, no communication in the assembly).  The unknowns are
(v_x, v_y) of each vertex in DMPlex's global numbering.

The DMPlex is built from the mesh's cells on rank 0 (any mix of
triangles and quadrilaterals), its regions and curves as labels that
migrate with the cells."""

import os
from dataclasses import dataclass

import numpy as np
from petsc4py import PETSc

from vstpetsc.plane import assembly
from vstpetsc.plane.mesh import PlaneMesh
from vstpetsc.plane.solver.matrices import petsc_matrix


@dataclass
class LocalMesh:
    """What a rank holds: its cells (those it owns first, then the
    overlap; ``owned_cells`` marks its own), their vertices' coordinates,
    each local vertex's global number, the rank's range of owned global
    vertices."""

    mesh: PlaneMesh
    global_vertex: np.ndarray
    owned: np.ndarray
    owned_cells: np.ndarray
    start: int
    stop: int
    size: int
    comm: object
    original: np.ndarray = None
    original_cells: np.ndarray = None


def plex(mesh, comm, curve_names):
    """The DMPlex of ``mesh`` (given on rank 0; the other ranks start
    empty), interpolated, with its coordinates, a label "region" on the
    cells and a label per curve on its edges, so that both move with
    the cells when DMPlex distributes them.  Any mix of triangles and
    quadrilaterals (cones set cell by cell: set-up only)."""
    rank0 = comm.getRank() == 0
    nc, nv = (mesh.ncells, mesh.nnodes) if rank0 else (0, 0)
    dm = PETSc.DMPlex().create(comm=comm)
    dm.setDimension(2)
    dm.setChart(0, nc + nv)
    corners = (mesh.cells >= 0).sum(axis=1) if rank0 else np.zeros(0, dtype=int)
    for c in range(nc):
        dm.setConeSize(c, int(corners[c]))
    dm.setUp()
    cones = (mesh.cells + nc).astype(PETSc.IntType) if rank0 else None
    for c in range(nc):
        dm.setCone(c, cones[c, :corners[c]])
    dm.symmetrize()
    dm.stratify()
    dm.interpolate()
    _coordinates(dm, mesh.coordinates if rank0 else np.zeros((0, 2)), comm)
    dm.createLabel("region")
    label = dm.getLabel("region")
    for r in (np.unique(mesh.region) if rank0 else ()):     # a region's cells at once
        cells = np.flatnonzero(mesh.region == r).astype(PETSc.IntType)
        label.setStratumIS(int(r), PETSc.IS().createGeneral(cells, comm=PETSc.COMM_SELF))
    for name in curve_names:              # (every rank has every label)
        dm.createLabel(name)
        for a, b in (mesh.curves[name] + nc if rank0 else ()):
            dm.setLabelValue(name, int(dm.getJoin([int(a), int(b)])[0]), 1)
    return dm


def _coordinates(dm, xy, comm):
    """Vertex coordinates (2 per vertex) into the DM."""
    v0, v1 = dm.getDepthStratum(0)
    section = PETSc.Section().create(comm=comm)
    section.setNumFields(1)
    section.setFieldComponents(0, 2)
    section.setChart(v0, v1)
    for v in range(v0, v1):
        section.setDof(v, 2)
        section.setFieldDof(v, 0, 2)
    section.setUp()
    dm.setCoordinateDim(2)
    dm.getCoordinateDM().setSection(section)
    vec = PETSc.Vec().createWithArray(np.ascontiguousarray(xy, dtype=float).ravel(),
                                      comm=PETSc.COMM_SELF)
    vec.setBlockSize(2)
    dm.setCoordinatesLocal(vec)


def distribute(mesh, comm, overlap=1, names=None, links=None):
    """The LocalMesh of each rank from ``mesh`` (read on rank 0; ignored
    elsewhere) with the cells' parts of vstpetsc.plane.solver.partition
    (``links``: rank 0's interface pairs' nodes, (m, 2) or None), or
    DMPlex's own partitioner's with ``-vst_plane_partition petsc`` or
    without libmetis5; ``names``: the regions' and the curves' names
    (every rank's; default rank 0's mesh's, broadcast)."""
    rank = comm.getRank()
    chosen = partition_option()     # (every rank, one rank too: every rank raises)
    if comm.getSize() == 1:        # nothing to distribute: the mesh as it is
        every = np.arange(mesh.nnodes)
        return LocalMesh(mesh, every, np.ones(mesh.nnodes, dtype=bool),
                         np.ones(mesh.ncells, dtype=bool), 0, mesh.nnodes, mesh.nnodes, comm,
                         every, np.arange(mesh.ncells))
    if names is None:
        names = comm.tompi4py().bcast(
            (mesh.region_names, tuple(mesh.curves)) if rank == 0 else None, root=0)
    one_partitioner_thread()
    dm = plex(mesh, comm, names[1])
    p0, p1 = dm.getChart()
    point = np.arange(p0, p1, dtype=PETSc.IntType)     # rank 0's points as read
    cells0 = mesh.ncells if rank == 0 else 0
    if comm.getSize() > 1:
        if chosen == "metis":
            _balanced(dm, mesh, links, comm)
        point = _migrated(dm.distribute(overlap=overlap), point, dm.getChart())
    v0, v1 = dm.getDepthStratum(0)
    c0, c1 = dm.getHeightStratum(0)
    cells0, table = comm.tompi4py().bcast((cells0, mesh.cells if rank == 0 else None), root=0)
    original = (point[v0:v1] - cells0).astype(np.int64)
    local = _local_cells(table, point[c0:c1], original)
    xy = dm.getCoordinatesLocal().getArray().reshape(-1, 2)
    numbers = dm.getVertexNumbering().getIndices()
    owned = numbers >= 0
    global_vertex = np.where(owned, numbers, -numbers - 1)
    counts = comm.tompi4py().allgather(int(owned.sum()))
    start = int(sum(counts[:rank]))
    region, curves = _local_groups(dm, local.shape[0], len(names[0]), names[1])
    lm = PlaneMesh(np.ascontiguousarray(xy), local, region, names[0], curves)
    # a rank's ghost points are the leaves of DMPlex's point SF
    owned_cells = np.ones(c1 - c0, dtype=bool)
    leaves = dm.getPointSF().getGraph()[1] if comm.getSize() > 1 else None
    if leaves is not None and len(leaves):
        leaves = np.asarray(leaves)
        owned_cells[leaves[(leaves >= c0) & (leaves < c1)] - c0] = False
    cells = point[c0:c1].astype(np.int64)     # rank 0's cells are its points 0 .. ne - 1
    return LocalMesh(lm, global_vertex, owned, owned_cells, start, start + counts[rank],
                     sum(counts), comm, original, cells)


PARTITIONS = ("metis", "petsc")


def partition_option():
    """-vst_plane_partition: metis (the default) or petsc; InputError for
    another."""
    from vstpetsc.errors import InputError

    chosen = PETSc.Options().getString("vst_plane_partition", PARTITIONS[0])
    if chosen not in PARTITIONS:
        raise InputError(f"-vst_plane_partition: {chosen!r} is not {' or '.join(PARTITIONS)}")
    return chosen


def _balanced(dm, mesh, links, comm):
    """Give ``dm`` a shell partitioner holding rank 0's cells' parts from
    partition.balanced_parts (collective; nothing when libmetis5 is
    missing: DMPlex's own partitioner then)."""
    from vstpetsc.plane.solver.partition import balanced_parts

    size, rank0 = comm.getSize(), comm.getRank() == 0
    parts = balanced_parts(mesh.cells, size, links) if rank0 else None
    if not comm.tompi4py().bcast(parts is not None, root=0):
        return
    sizes, points = np.zeros(size, dtype=PETSc.IntType), np.zeros(0, dtype=PETSc.IntType)
    if rank0:
        sizes = np.bincount(parts, minlength=size).astype(PETSc.IntType)
        points = np.argsort(parts, kind="stable").astype(PETSc.IntType)
    partitioner = dm.getPartitioner()
    partitioner.setType("shell")
    partitioner.setShellPartition(size, sizes, points)


def _local_cells(table, cells, original):
    """(ne, 4) local vertex numbers of the cells ``cells`` (their numbers
    as read) from the mesh's cell table as read (-1 pads a triangle) and
    each local vertex's number as read ``original``: the corners in the
    order read, so that a cell's element matrices are the bits of its
    one-rank ones (DMPlex's closures, walked cell by cell, took 0.06 s a
    rank on the 1 m rockfill dam)."""
    corners = table[cells]
    local_of = np.full(int(table.max()) + 1, -1, dtype=np.int64)
    local_of[original] = np.arange(original.size)
    local = np.where(corners >= 0, local_of[np.maximum(corners, 0)], -1)
    if (local[corners >= 0] < 0).any():
        raise RuntimeError("a distributed cell's corner is not among the rank's vertices")
    return local


def one_partitioner_thread():
    """PETSc's partitioner here is PT-Scotch, and Scotch 7 splits the graph
    with as many threads as the machine has cores: its partition then
    changes from run to run (rockfill-dam on two ranks: 1386 / 1997,
    1255 / 2128 and 1729 / 1654 vertices a rank in three runs), and with
    it the global numbering, the slab solve's rounding and a restart's
    bits.  One thread (Scotch reads SCOTCH_PTHREAD_NUMBER when it
    partitions) gives one partition for a mesh and a number of ranks, on
    any machine; a value the user set is kept."""
    os.environ.setdefault("SCOTCH_PTHREAD_NUMBER", "1")


def _migrated(sf, root, chart):
    """Each distributed point's number before distribution (the migration
    SF carries rank 0's numbers to the points they became)."""
    from mpi4py import MPI

    leaf = -np.ones(chart[1] - chart[0], dtype=PETSc.IntType)
    unit = MPI.INT if np.dtype(PETSc.IntType).itemsize == 4 else MPI.INT64_T
    sf.bcastBegin(unit, root, leaf, MPI.REPLACE)
    sf.bcastEnd(unit, root, leaf, MPI.REPLACE)
    return leaf


def _local_groups(dm, ncells, nregions, curve_names):
    """(each local cell's region, {curve: its local edges (m, 2)})."""
    region = np.zeros(ncells, dtype=int)
    # (a stratum with no point on this rank has no index set: asked first)
    for r in range(nregions):
        if dm.getStratumSize("region", r):
            region[dm.getStratumIS("region", r).getIndices()] = r
    v0, _ = dm.getDepthStratum(0)
    curves = {}
    for name in curve_names:
        edges = dm.getStratumIS(name, 1).getIndices() if dm.getStratumSize(name, 1) else []
        if len(edges):
            curves[name] = np.array([dm.getCone(e) for e in edges], dtype=np.int64) - v0
    return region, curves


def owned_rows(local, blocks):
    """The rank's rows (its owned vertices' dofs) of the sum of element
    matrices [(cells, Ke)], as CSR (2 owned, 2 size) in global columns."""
    return assembly.assemble(local.mesh, blocks, local.global_vertex,
                             (local.start, local.stop), local.size)


def matrices(local, lam, mu, rho, mass="averaged"):
    """(M, K) as parallel AIJ on the ranks' owned rows."""
    from vstpetsc.plane import elements

    parts = assembly.element_matrices(local.mesh, lam, mu, rho)
    to_mass = elements.MASSES[mass]
    K = owned_rows(local, [(cells, Ke) for cells, Ke, _ in parts.values()])
    M = owned_rows(local, [(cells, to_mass(Me)) for cells, _, Me in parts.values()])
    return petsc_matrix(M, local.comm), petsc_matrix(K, local.comm)
