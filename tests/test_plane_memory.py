"""What the plane-strain room stores (issue 48, docs/parallel.md "Memory"):
the slab matrix in 4 x 4 node blocks (PETSc's BAIJ) holds the same values
as vstpetsc.spacetime.slab's sparse Kronecker form, bit for bit (each
value the same sum in the same order), with one column index per 16
values; the spatial matrices assembled over chunks of cells equal the
whole assembly to rounding; a solver stores what the design says and no
more: the slab matrix, M, K and C, their nonzeros counted."""

import numpy as np
import pytest
import scipy.sparse as sp
from petsc4py import PETSc

import vstpetsc
from vstpetsc.plane.solver.matrices import slab_matrix
from vstpetsc.spacetime.slab import sparse_slab_matrix


def as_dense(A):
    indptr, indices, values = A.convert("aij").getValuesCSR()
    return sp.csr_matrix((values, indices, indptr), shape=A.getSize()).toarray()


@pytest.mark.parametrize("damped", [True, False])
def test_the_blocked_slab_matrix_is_the_kronecker_form_bit_for_bit(damped):
    """Random symmetric M, C, K of 30 dofs (15 nodes; patterns unlike a
    mesh's: blocks partly empty, C sparser), formed 4 node rows at a time
    and all at once: every entry equal."""
    rng = np.random.default_rng(3)
    pick = lambda density: (lambda A: sp.csr_matrix(A + A.T))(
        sp.random(30, 30, density=density, random_state=rng))
    M, K, C = pick(0.2), pick(0.3), pick(0.05) if damped else None
    dt = 0.0137
    reference = sparse_slab_matrix(M, C, K, dt).toarray()
    for rows in (4, 1 << 15):           # node rows formed at once: several chunks, one
        blocked = slab_matrix(M, C, K, dt, PETSc.COMM_SELF, rows)
        assert blocked.getBlockSize() == 4
        assert np.array_equal(as_dense(blocked), reference)


def test_chunks_of_cells_assemble_the_whole_matrices(monkeypatch):
    """A 24 x 18 mesh of triangles and quadrilaterals in chunks of 7 cells
    against one chunk: M, K, C within 4 ulps of their largest entries."""
    from vstpetsc.plane import mesh as plane_mesh, model
    from vstpetsc.plane.model import cell_materials, spatial_matrices
    from vstpetsc.plane.schema import RegionSpec

    m = plane_mesh.rectangle((0.0, 24.0), (0.0, 18.0), 12, 9, triangles=True)
    quads = plane_mesh.rectangle((0.0, 24.0), (0.0, 18.0), 12, 9)
    m.cells[::3] = quads.cells[np.arange(m.ncells)[::3] // 2]   # some quadrilaterals: the same nodes
    region = RegionSpec("domain", 2.0e9, 1.0e9, 2000.0, damping=(0.3, 1e-3))
    mat = cell_materials([region], np.zeros(m.ncells, dtype=int))
    whole = spatial_matrices(m, mat)
    monkeypatch.setattr(model, "CHUNK", 7)
    chunked = spatial_matrices(m, mat)
    for a, b in zip(whole, chunked):
        a, b = a.toarray(), b.toarray()
        assert np.abs(a - b).max() <= 4 * np.finfo(float).eps * np.abs(a).max()


def test_a_node_matrix_multiplies_as_its_csr():
    """K of a small mesh as BAIJ(2): K x equal to scipy's K @ x within 18
    ulps of the largest |K||x| (a row holds at most 18 products, which the
    two sum in different orders: the bound on any CPU)."""
    from vstpetsc.plane import mesh as plane_mesh
    from vstpetsc.plane.model import cell_materials, spatial_matrices
    from vstpetsc.plane.schema import RegionSpec
    from vstpetsc.plane.solver.matrices import node_matrix

    m = plane_mesh.rectangle((0.0, 6.0), (0.0, 4.0), 6, 4, triangles=True)
    mat = cell_materials([RegionSpec("domain", 2.0e9, 1.0e9, 2000.0)],
                         np.zeros(m.ncells, dtype=int))
    _, _, K = spatial_matrices(m, mat)
    x = np.random.default_rng(5).standard_normal(K.shape[0])
    B = node_matrix(K)
    y = B.createVecLeft()
    B.mult(PETSc.Vec().createWithArray(x), y)
    scale = (abs(K) @ np.abs(x)).max()
    assert B.getBlockSize() == 2
    assert np.abs(y.getArray() - K @ x).max() <= 18 * np.finfo(float).eps * scale


def test_a_solver_stores_what_the_design_says(tmp_path):
    """A 12 x 8 square of quadrilaterals (117 nodes), absorbing base: the
    solver keeps the slab matrix as BAIJ(4) with one 4 x 4 block per pair
    of nodes sharing a cell (9 a node inside, fewer at the edges: the
    count from the mesh's own node-to-node adjacency), M and K as BAIJ(2)
    on the same node pairs, C (the base's dashpots) on the base's nodes
    alone, the stress operator 3 rows a cell; the model has let its CSR
    copies go; no other PETSc matrix is held by the solver."""
    from petsc4py import PETSc
    from vstpetsc.plane.loads import plane_loads
    from vstpetsc.plane.model import PlaneModel
    from vstpetsc.plane.solver.slab_solver import PlaneSolver

    case = vstpetsc.Case.from_dict({
        "time": {"dt": 1e-3, "end": 0.01},
        "mesh": {"rectangle": {"x": [0.0, 12.0], "y": [0.0, 8.0], "nx": 12, "ny": 8}},
        "region": [{"name": "domain", "Vs": 200.0, "Vp": 400.0, "rho": 2000.0}],
        "boundary": [{"name": "bottom", "type": "absorbing"}]})
    comm = PETSc.COMM_SELF
    model = PlaneModel(case, comm)
    solver = PlaneSolver(model, case.dt, comm, plane_loads(model, case.dt))
    cells = model.local.mesh.cells
    pairs = sp.csr_matrix((np.ones(cells.size * 4), (np.repeat(cells, 4, axis=1).ravel(),
                                                     np.tile(cells, (1, 4)).ravel())))
    blocks = pairs.nnz                          # node pairs sharing a cell (each node with itself)
    assert blocks == 9 * 77 + 6 * 36 + 4 * 4    # inner nodes, edge nodes, corners
    held = {name: getattr(solver, name) for name in ("A", "M", "K", "C", "A_free")}
    assert held["A_free"] is None and model._matrices is None
    info = lambda A: (A.getType(), A.getBlockSize(), int(A.getInfo()["nz_used"]))
    assert info(held["A"]) == ("seqbaij", 4, 16 * blocks)
    assert info(held["M"]) == info(held["K"]) == ("seqbaij", 2, 4 * blocks)
    base = 13                                   # the dashpots' nodes: one 2 x 2 block each
    assert info(held["C"]) == ("seqbaij", 2, 4 * base)
    assert solver.principal.B.getSize()[0] == 3 * 96
    mats = [v for v in vars(solver).values() if isinstance(v, PETSc.Mat)]
    assert len(mats) == 4, [m.getType() for m in mats]      # A, M, K, C


def test_the_stress_operator_in_chunks_is_the_whole(monkeypatch):
    """The centre-stress operator of 60 mixed cells formed 7 cells at a time
    equals the one formed at once, bit for bit (each row its own cell's)."""
    from vstpetsc.plane import mesh as plane_mesh, principal

    m = plane_mesh.rectangle((0.0, 6.0), (0.0, 5.0), 6, 5, triangles=True)
    lam, mu = np.linspace(1e9, 2e9, m.ncells), np.linspace(5e8, 9e8, m.ncells)
    cells = np.random.default_rng(2).permutation(m.ncells)
    whole = principal.stress_operator(m, lam, mu, cells, np.arange(m.nnodes), 2 * m.nnodes)
    monkeypatch.setattr(principal, "CHUNK", 7)
    chunked = principal.stress_operator(m, lam, mu, cells, np.arange(m.nnodes), 2 * m.nnodes)
    assert np.array_equal(whole.toarray(), chunked.toarray())


def _solver(case, matrix_free):
    from vstpetsc.plane.loads import plane_loads
    from vstpetsc.plane.model import PlaneModel
    from vstpetsc.plane.solver.slab_solver import PlaneSolver

    opts = PETSc.Options()
    opts["vst_plane_matrix_free"] = int(matrix_free)
    try:
        model = PlaneModel(case, PETSc.COMM_SELF)
        return PlaneSolver(model, case.dt, PETSc.COMM_SELF, plane_loads(model, case.dt))
    finally:
        opts.delValue("vst_plane_matrix_free")


@pytest.mark.parametrize("name", ["gravity-dam", "plane-column"])
def test_the_matrix_free_product_is_the_slab_matrix(tmp_path, name):
    """-vst_plane_matrix_free: the slab's product from M, C, K (and the
    interfaces' closed springs: gravity-dam) against the assembled slab
    matrix's for a random x, within 32 ulps of |A| |x| row by row (a row
    sums at most 9 node blocks' 4 products of each of 4 matrices, in
    another order); the held rows identities in both, and their free
    product (the reactions') alike; the solver holds no slab matrix."""
    from vstpetsc import bundled

    case = vstpetsc.Case.from_toml(bundled.path(name))
    if name == "plane-column":          # its left side moves: the reactions' product
        case = case.with_value("boundary.left.value.y", 0.01)
    free, assembled = _solver(case, True), _solver(case, False)
    A = assembled.A
    x = A.createVecRight()
    x.setArray(np.random.default_rng(7).standard_normal(x.getSize()))
    magnitude = lambda B: abs(sp.csr_matrix(B.convert("aij").getValuesCSR()[::-1],
                                            shape=B.getSize()))
    for shell, matrix in ((free.A, A), (free.A_free, assembled.A_free)):
        if matrix is None:
            assert shell is None
            continue
        y, z = shell.createVecLeft(), matrix.createVecLeft()
        shell.mult(x, y)
        matrix.mult(x, z)
        bound = 32 * np.finfo(float).eps * (magnitude(matrix) @ np.abs(x.getArray()))
        assert (np.abs(y.getArray() - z.getArray()) <= bound).all()
    assert (name == "plane-column") == (assembled.A_free is not None)
    assert free.A.getType() == "python"
    mats = [v for v in vars(free).values() if isinstance(v, PETSc.Mat)]
    assert sorted(m.getType() for m in mats) == sorted(
        ["python"] * (2 if free.A_free is not None else 1) + ["seqbaij"] * 3)
    operator, pmat = free.ksp.getOperators()
    assert operator.getType() == pmat.getType() == "python"     # the factors' own values


def test_a_matrix_free_run_is_the_assembled_one(tmp_path):
    """gravity-dam-reservoir (interfaces, uplift, the static start) by
    GMRES + ILU(0) with the slab matrix assembled and matrix-free: every
    dataset within 1e-9 of its largest (GMRES stops at 1e-12 of the
    residual; the two products differ in rounding)."""
    from agreement import assert_runs_agree
    from conftest import cli

    path = tmp_path / "case.toml"
    assert cli("example", "gravity-dam-reservoir", "-o", path).returncode == 0  # with its record
    case = vstpetsc.Case.from_toml(path)
    path.write_text(case.with_value("time.end", 0.05).to_toml())
    krylov = ["-vst_plane_ksp_type", "gmres", "-vst_plane_pc_type", "ilu",
              "-vst_plane_ksp_rtol", "1e-13"]
    for name, extra in (("a", []), ("b", ["-vst_plane_matrix_free", "1"])):
        p = cli("run", path, "-o", tmp_path / f"{name}.h5", "--quiet", *krylov, *extra)
        assert p.returncode == 0, p.stderr
    assert_runs_agree(tmp_path / "a.h5", tmp_path / "b.h5", rtol=1e-9)


RELEASE = """
import sys, numpy as np
from petsc4py import PETSc
from vstpetsc.petsc import release
from vstpetsc.plane.solver.heap import give_back
rss = lambda: int(open("/proc/self/statm").read().split()[1]) * 4096
n = 4_000_000
r = np.arange(n, dtype=PETSc.IntType)
give_back()
base = rss()
A = PETSc.Mat().createAIJ((n, n), nnz=1, comm=PETSc.COMM_SELF)
A.setValuesRCV(r[:, None], r[:, None], np.ones((n, 1)))
A.assemble()
held = rss()
del A
if sys.argv[1] == "release":
    release(PETSc.COMM_SELF)
give_back()
print((held - rss()) / (held - base))
"""


def test_what_python_lets_go_is_released(tmp_path):
    """petsc4py 3.18 keeps a matrix Python let go (4e6 rows: its resident
    memory mostly kept: less than half returned) until vstpetsc.petsc.release destroys PETSc's garbage: a run
    calls it at its start and end, so a process that runs case after
    case does not keep every run's matrices."""
    import subprocess
    import sys

    script = tmp_path / "release.py"
    script.write_text(RELEASE)
    freed = {how: float(subprocess.run([sys.executable, script, how], capture_output=True,
                                       text=True, check=True).stdout)
             for how in ("release", "del")}
    assert freed["release"] > 0.9 and freed["del"] < 0.5, freed


def test_the_stress_matrix_is_the_stress_operator():
    """The solver's centre-stress matrix, set into PETSc a chunk of cells
    at a time (chunks of 7 cells here), holds stress_operator's entries
    bit for bit, and its rows' entry counts are its cells' (no room
    preallocated beyond them)."""
    from vstpetsc.plane import principal
    from vstpetsc.plane.model import PlaneModel
    from vstpetsc.plane.solver.principal import PrincipalStresses

    case = vstpetsc.Case.from_dict({
        "time": {"dt": 1e-3, "end": 0.01},
        "mesh": {"rectangle": {"x": [0.0, 6.0], "y": [0.0, 5.0], "nx": 6, "ny": 5,
                               "triangles": True}},
        "region": [{"name": "domain", "Vs": 200.0, "Vp": 400.0, "rho": 2000.0}]})
    model = PlaneModel(case, PETSc.COMM_SELF)
    saved, principal.CHUNK = principal.CHUNK, 7
    try:
        B = PrincipalStresses(model, case.dt, PETSc.COMM_SELF).B
    finally:
        principal.CHUNK = saved
    local = model.local
    cells = np.arange(local.mesh.ncells)
    whole = principal.stress_operator(local.mesh, model.materials["lam"], model.materials["mu"],
                                      cells, local.global_vertex, 2 * local.size)
    assert np.array_equal(as_dense(B), whole.toarray())
    assert int(B.getInfo()["nz_allocated"]) == whole.nnz == 3 * 6 * cells.size


AFTER_RUNS = """
import sys
import vstpetsc
from vstpetsc import bundled
import vstpetsc.petsc
if sys.argv[1] == "kept":                  # the release a run calls: undone
    vstpetsc.petsc.release = lambda comm, collect=True: None
case = vstpetsc.Case.from_toml(bundled.path("plane-column")).with_value("time.end", 0.02)
for k in range(2):
    vstpetsc.run(case, sys.argv[2], quiet=True)
import gc
gc.collect()                               # (what Python still holds in cycles let go)
from petsc4py import PETSc
PETSc.garbage_view(PETSc.COMM_WORLD)
"""


def test_a_run_leaves_no_petsc_garbage(tmp_path):
    """Two plane-strain runs through the API in one process: after them
    PETSc's garbage is empty (each run released what it let go); without
    the release it holds the runs' objects."""
    import re
    import subprocess
    import sys

    script = tmp_path / "runs.py"
    script.write_text(AFTER_RUNS)
    entries = {}
    for how in ("released", "kept"):
        out = subprocess.run([sys.executable, script, how, tmp_path / f"{how}.h5"],
                             capture_output=True, text=True, check=True).stdout
        entries[how] = int(re.search(r"Total entries: (\d+)", out).group(1))
    assert entries["released"] == 0 and entries["kept"] > 10, entries
