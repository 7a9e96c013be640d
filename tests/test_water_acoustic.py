"""The acoustic reservoir ([[water]] hydrodynamic = "acoustic", issue 47,
docs/water.md section 4): the coupled dam and water third order in time
against the semi-discrete solution of the same M, C, K (matrix
exponential), its energy balance (the face's skew coupling does no work,
the far end and the bottom absorb), a dam at rest under its reservoir
stays at rest, and the bad inputs (exit 2, one line naming the key).
Chopra's closed form and the far end's absorption:
tests/test_water_acoustic_chopra.py."""

import io

import h5py
import numpy as np
import pytest
import scipy.linalg

import vstpetsc
from acoustic_cases import free_dam_case, reservoir_case, shaken_case
from test_plane_run import run_cli

END = 0.2


def run(path, tmp_path, name="out"):
    out = tmp_path / f"{name}.h5"
    vstpetsc.run(vstpetsc.Case.from_toml(path), output=str(out), quiet=True, out=io.StringIO())
    return out


def semi_discrete(path, t):
    """(u, v) (nn, 2) at t of M v' + C v + K u = 0 with the model's own
    matrices (its held dofs at zero), from its initial state: the matrix
    exponential of the first-order system."""
    from petsc4py import PETSc
    from vstpetsc.plane.model import PlaneModel

    model = PlaneModel(vstpetsc.Case.from_toml(path), PETSc.COMM_WORLD)
    M, C, K = (m.toarray() for m in model.matrices())
    free = np.setdiff1d(np.arange(M.shape[0]), model.boundaries.held_dofs()[0])
    M, C, K = (A[np.ix_(free, free)] for A in (M, C, K))
    m = free.size
    solve = np.linalg.solve
    A = np.block([[np.zeros((m, m)), np.eye(m)], [-solve(M, K), -solve(M, C)]])
    order = model.owned_original                    # global position -> node as read
    u0, v0 = (s[order].ravel()[free] for s in model.initial_state())
    z = scipy.linalg.expm(A * t) @ np.concatenate([u0, v0])
    out = []
    for part in (z[:m], z[m:]):
        full = np.zeros(M.shape[0] + 0 * m + (2 * order.size - M.shape[0]))
        full[free] = part
        node = np.zeros((order.size, 2))
        node[order] = full.reshape(-1, 2)
        out.append(node)
    return out


def test_third_order_in_time_with_the_water_coupled(tmp_path):
    """A free dam thrown at its reservoir (far end, half-absorbing bottom):
    the final u and v against the semi-discrete solution; the fitted
    order of both over dt = 4, 2, 1 ms is 3 (measured 2.96 / 3.02 for v,
    2.9 / 3.0 for u); numerical energy >= 0, falling as dt^3."""
    U, V = semi_discrete(free_dam_case(tmp_path, 1e-3, END, "m"), END)
    errors, numerical = [], []
    for dt in (4e-3, 2e-3, 1e-3):
        with h5py.File(run(free_dam_case(tmp_path, dt, END, f"d{dt:g}"), tmp_path)) as f:
            u, v = f["field/u"][-1], f["field/v"][-1]
            energy = {k: f[f"energy/{k}"][:] for k in f["energy"]}
        errors.append([np.abs(u - U).max() / np.abs(U).max(),
                       np.abs(v - V).max() / np.abs(V).max()])
        numerical.append(energy["numerical"][-1])
        assert energy["numerical"].min() >= -1e-9 * energy["kinetic"][0]
        assert energy["damping"][-1] > 0.1 * energy["kinetic"][0]      # the far end absorbs
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert (orders > 2.75).all() and (orders < 3.3).all(), orders
    assert numerical[0] / numerical[-1] > 30, numerical


def test_a_dam_at_rest_under_its_reservoir_stays_at_rest(tmp_path):
    """A rigid face held still, the reservoir's static start: the water
    stays at rest (|v| = 0 exactly: nothing loads it) and the pressure on
    the face is rho g (level - y) at every kept time."""
    path = reservoir_case(tmp_path, 10.0, 20.0, 8, 4, 1e-3, 0.05, "0.0", initial="static")
    with h5py.File(run(path, tmp_path)) as f:
        assert np.abs(f["field/v"][:]).max() == 0.0
        y = f["mesh/coordinates"][:, 1][f["water/reservoir/nodes"][:]]
        assert np.allclose(f["water/reservoir/pressure"][:], 1000.0 * 9.81 * (10.0 - y),
                           rtol=0, atol=1e-9 * 1000 * 9.81 * 10)
        assert np.allclose(f["water/reservoir/force"][:], [[-1000 * 9.81 * 50.0, 0.0]],
                           rtol=1e-12)


BAD = [
    ("no region", ('region = "water"\n', ""), "water[0] (reservoir).region: missing"),
    ("unknown region", ('region = "water"', 'region = "lake"'),
     "water[0] (reservoir).region: the mesh has no region 'lake'"),
    ("region with a table", ("[gravity]", '[[region]]\nname = "water"\nE = 1e9\nnu = 0.2\n'
                             'rho = 1000.0\n[gravity]'),
     "water[0] (reservoir).region: 'water' has a [[region]] table"),
    ("face on the outside", ('faces = ["face"]', 'faces = ["far"]'),
     "water[0] (reservoir).faces: 'far' at"),
    ("far inside", ('far = "far"', 'far = "face"'),
     "water[0] (reservoir).far: 'face' is not on the water region's outer boundary"),
    ("level off the top", ("level = 10.0", "level = 9.0"),
     "water[0] (reservoir).level: 9, but the water region 'water' reaches y = 10"),
    ("alpha beyond 1", ('far = "far"', 'far = "far"\nbottom = { name = "bottom", alpha = 1.5 }'),
     "water[0] (reservoir).bottom.alpha: must be <= 1"),
    ("acoustic key elsewhere", ('hydrodynamic = "acoustic"', 'hydrodynamic = "westergaard"'),
     "water[0] (reservoir).region: is the acoustic water's"),
    ("bulk NaN", ("bulk = 2250000000.0", "bulk = nan"), "water[0] (reservoir).bulk"),
    ("boundary on the water", ("[gravity]", '[[boundary]]\nname = "far"\ntype = "fixed"\n'
                               '[gravity]'),
     "boundary[2] (far).name: runs along the acoustic water's region only"),
]


@pytest.mark.parametrize("label, change, message", BAD, ids=[b[0] for b in BAD])
def test_bad_acoustic_input_is_one_line_and_exit_2(tmp_path, label, change, message):
    path = reservoir_case(tmp_path, 10.0, 20.0, 4, 2, 1e-3, 0.01, "0.0")
    text = path.read_text()
    assert change[0] in text, change
    path.write_text(text.replace(change[0], change[1]))
    out = tmp_path / "bad.h5"
    p = run_cli("run", path, "-o", out, "-q")
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], p.stderr
    assert not out.exists()


def test_two_ranks_equal_one_with_an_acoustic_reservoir(tmp_path):
    """Every dataset within 1e-10 of its largest (the face's couplings
    and the water's dashpots across the ranks' rows)."""
    from test_plane_run import mpirun_against_one_rank

    two = mpirun_against_one_rank(tmp_path, shaken_case(tmp_path, 0.1))
    with h5py.File(two) as f:
        dynamic = f["water/reservoir/pressure"][:] - f["water/reservoir/pressure"][0]
        assert np.abs(dynamic).max() > 100.0             # the water answered the dam


def test_a_restart_with_an_acoustic_reservoir_is_bit_for_bit(tmp_path):
    from test_water_hydrostatic import restarted_as_whole

    names = restarted_as_whole(tmp_path, lambda end, name: shaken_case(tmp_path, end, name), 0.1)
    assert "water/reservoir/pressure" in names


def test_info_prints_the_lowest_pressure_on_the_faces(tmp_path):
    """`vstpetsc info` names the lowest total pressure on the faces, its
    node and time (the dataset's own minimum), and says when it is below
    zero (the water pulls: no cavitation)."""
    out = run(shaken_case(tmp_path, 0.1), tmp_path)
    with h5py.File(out) as f:
        p, nodes, time = (f[k][:] for k in ("water/reservoir/pressure", "water/reservoir/nodes",
                                            "time"))
    k, j = np.unravel_index(p.argmin(), p.shape)
    text = run_cli("info", out).stdout
    line = next(x for x in text.splitlines() if "lowest pressure" in x)
    assert f"{p[k, j]:.6g} at node {nodes[j]}, t = {time[k]:.6g}" in line
    assert ("cavitate" in line) == (p[k, j] < 0)


def test_the_water_matrices_of_a_rectangle(tmp_path):
    """The reservoir beside a rigid face (H = 10, L = 20, alpha 0.5): C's
    symmetric part is the far end's dashpot rho c H plus the bottom's
    rho c L (1 - alpha) / (1 + alpha), on the water's w alone; its skew
    part couples the face's solid x rows to the water's w with sum
    -rho c H (the solid's outward normal +x, the face H long), nothing
    along y; the water's K is bulk times a Laplacian (no w of a constant,
    bulk |grad w|^2 A of a linear field: exact on quadrilaterals of a
    rectangle); its y slots carry mass only."""
    from petsc4py import PETSc
    from acoustic_cases import BULK, RHO_W
    from vstpetsc.plane.model import PlaneModel

    path = reservoir_case(tmp_path, 10.0, 20.0, 8, 4, 1e-3, 0.01, "0.0", alpha=0.5)
    model = PlaneModel(vstpetsc.Case.from_toml(path), PETSc.COMM_WORLD)
    M, C, K = (m.toarray() for m in model.matrices())
    impedance = RHO_W * np.sqrt(BULK / RHO_W)
    nodes = model.owned_original                   # global position -> node as read
    region = model.mesh.region
    cells = model.mesh.cells[region == model.mesh.region_names.index("water")]
    water_nodes = np.zeros(model.mesh.nnodes, dtype=bool)
    water_nodes[cells[cells >= 0]] = True
    water = water_nodes[nodes]
    sym, skew = (C + C.T) / 2, (C - C.T) / 2
    w_dofs = 2 * np.flatnonzero(water)
    assert np.isclose(np.trace(sym), impedance * (10.0 + 20.0 * 0.5 / 1.5), rtol=1e-13)
    assert np.abs(sym).sum() == pytest.approx(np.trace(sym[np.ix_(w_dofs, w_dofs)]), rel=1e-13)
    solid_x = 2 * np.flatnonzero(~water)
    assert skew[np.ix_(solid_x, w_dofs)].sum() == pytest.approx(-impedance * 10.0, rel=1e-13)
    assert np.abs(skew[np.ix_(solid_x + 1, w_dofs)]).max() == 0.0
    Kw = K[np.ix_(w_dofs, w_dofs)]
    x, y = (model.mesh.coordinates[nodes[water], k] for k in range(2))
    assert np.abs(Kw.sum(axis=1)).max() < 1e-12 * np.abs(Kw).max()
    field = 0.3 * x - 0.7 * y
    assert field @ Kw @ field == pytest.approx(BULK * (0.09 + 0.49) * 200.0, rel=1e-12)
    y_slots = w_dofs + 1
    assert np.abs(K[y_slots]).max() == 0.0 and np.abs(C[y_slots]).max() == 0.0
    assert M[y_slots, y_slots].min() > 0
