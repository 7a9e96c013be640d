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
