"""The principal stress envelopes of a plane-strain run (issue 47, "for
dam engineers"; vstpetsc/plane/principal.py): /field/principal_max and
principal_min (ne,), each cell's largest s1 and smallest s2 of its
in-plane stress over every slab end, t = 0 included, and their times.

- the principal stresses against closed forms: pure shear and its 45
  degree rotation, any tensor rotated (the eigenvalues), and a laterally
  confined column at rest under gravity (s2 = syy = -rho g (H - y), s1 =
  sxx = K0 syy, K0 = nu / (1 - nu));
- the envelopes of a shaken dam kept at every slab against the largest
  and smallest eigenvalues of its /field/stress rows, computed here; kept
  every 5 slabs, the same envelopes bit for bit (every slab end counts);
- a yielding column's envelopes (the law's stress, on rank 0) against its
  rows the same way;
- a restart continues them bit for bit, two ranks give one rank's within
  1e-10, `info` names the largest tension, VTK's XDMF reader finds them
  bit for bit, `plot --color principal_max|principal_min` draws them."""

import h5py
import numpy as np
import pytest

from test_plane_run import DAM, mpirun_against_one_rank, run_cli
from test_plane_yielding import MKZ, column
from vstpetsc.plane.principal import DATASETS, TIME_MARGIN, principal_stresses

END = 0.15          # the dam's run: the pulse and its echoes in the dam


def dam(folder, every=1, end=END, name="dam"):
    """The shaken dam of test_plane_run on its foundation (gravity, a
    static start), kept every ``every`` slabs; the case file."""
    path = folder / f"{name}.toml"
    path.write_text(DAM.format(end=end) + f"[output]\nevery = {every}\n")
    return path


def run(path, out, *extra):
    p = run_cli("run", path, "-o", out, "-q", *extra)
    assert p.returncode == 0, p.stderr
    return out


def envelopes(out):
    """{name: the dataset} of DATASETS, /time and /field/stress."""
    with h5py.File(out, "r") as f:
        got = {name: f[f"field/{name}"][...] for name in DATASETS}
        got.update(time=f["time"][...], stress=f["field/stress"][...], dt=f.attrs["dt"])
    return got


@pytest.fixture(scope="module")
def shaken(tmp_path_factory):
    """The dam kept every slab and every 5 slabs: (folder, their files)."""
    folder = tmp_path_factory.mktemp("principal")
    return folder, run(dam(folder), folder / "one.h5"), \
        run(dam(folder, every=5, name="five"), folder / "five.h5")


def eigenvalues(stress):
    """The in-plane stress tensors' eigenvalues (..., 2), smallest first:
    numpy's, not the closed form under test."""
    tensor = np.stack([stress[..., [0, 2]], stress[..., [2, 1]]], axis=-2)
    return np.linalg.eigvalsh(tensor)


def test_principal_stresses_of_pure_shear_and_rotated_tensors():
    tau = 3.0e6
    s1, s2 = principal_stresses(np.array([[0.0, 0.0, tau], [tau, -tau, 0.0]]))
    assert np.array_equal(s1, [tau, tau]) and np.array_equal(s2, [-tau, -tau])
    rng = np.random.default_rng(47)
    stress = rng.normal(scale=1e6, size=(1000, 3))
    s1, s2 = principal_stresses(stress)
    both = eigenvalues(stress)
    error = max(np.abs(s1 - both[:, 1]).max(), np.abs(s2 - both[:, 0]).max()) / 1e6
    # the same tensors rotated by any angle: the same principal stresses
    a = rng.uniform(0.0, np.pi, size=1000)
    c, s = np.cos(a), np.sin(a)
    sxx, syy, sxy = stress.T
    rotated = np.column_stack([c * c * sxx + s * s * syy + 2 * c * s * sxy,
                               s * s * sxx + c * c * syy - 2 * c * s * sxy,
                               c * s * (syy - sxx) + (c * c - s * s) * sxy])
    r1, r2 = principal_stresses(rotated)
    turned = max(np.abs(r1 - s1).max(), np.abs(r2 - s2).max()) / 1e6
    print(f"principal stresses against eigvalsh {error:.2g}, rotated {turned:.2g} of 1e6")
    assert error <= 1e-14 and turned <= 1e-14


def test_a_confined_column_at_rest_has_k0_principal_stresses(tmp_path):
    """One cell wide, its sides holding v_x, under gravity from a static
    start: at every cell centre s2 = syy = -rho g (H - y) and s1 = sxx =
    K0 syy exactly (the centre strain of a bilinear cell is exact for the
    quadratic u_y), reached at t = 0 and kept to rounding."""
    import vstpetsc

    H, rho, nu = 10.0, 1800.0, 0.3
    case = vstpetsc.Case.from_dict({
        "time": {"dt": 1e-3, "end": 0.05},
        "mesh": {"rectangle": {"x": [0.0, 1.0], "y": [0.0, H], "nx": 1, "ny": 10}},
        "region": [{"name": "domain", "E": 2e8, "nu": nu, "rho": rho}],
        "boundary": [{"name": "bottom", "type": "absorbing"},
                     {"name": "left", "type": "velocity", "value": {"x": 0.0}},
                     {"name": "right", "type": "velocity", "value": {"x": 0.0}}],
        "gravity": {"g": -9.81, "initial": "static"}})
    out = tmp_path / "column.h5"
    vstpetsc.run(case, output=str(out), quiet=True)
    got = envelopes(out)
    y = np.arange(10) + 0.5               # the cells' centres, bottom to top
    syy = -rho * 9.81 * (H - y)
    e2 = np.abs(got["principal_min"] - syy).max() / np.abs(syy).max()
    e1 = np.abs(got["principal_max"] - nu / (1 - nu) * syy).max() / np.abs(syy).max()
    print(f"column at rest: s1 against K0 syy {e1:.2g}, s2 against syy {e2:.2g}")
    assert e1 <= 1e-12 and e2 <= 1e-12
    assert not got["principal_max_time"].any() and not got["principal_min_time"].any()


def assert_envelopes_of_rows(got):
    """``got`` (envelopes of a run kept every slab): the envelopes are the
    largest s1 and smallest s2 of the rows (eigvalsh of /field/stress); a
    time is that of a row whose value is the envelope's but for increases
    each below the margin (TIME_MARGIN of the cell's stress), and no later
    than the first row reaching the envelope (to rounding).  (the largest
    gap of the envelopes, the largest of a time's row) against the scale."""
    both = eigenvalues(got["stress"])             # (nt, ne, 2)
    s1, s2 = both[..., 1], both[..., 0]
    scale = np.abs(both).max()
    gap = max(np.abs(got["principal_max"] - s1.max(axis=0)).max(),
              np.abs(got["principal_min"] - s2.min(axis=0)).max()) / scale
    assert gap <= 1e-12, gap
    cells, cell_scale = np.arange(s1.shape[1]), np.abs(both).max(axis=(0, 2))
    short = 0.0
    for kind, values in (("max", s1), ("min", -s2)):
        row = np.rint(got[f"principal_{kind}_time"] / got["dt"]).astype(int)
        envelope = values.max(axis=0)
        short = max(short, ((envelope - values[row, cells]) / cell_scale).max())
        first = np.argmax(values >= envelope - 1e-13 * np.abs(envelope), axis=0)
        assert (row <= first).all(), kind
    assert short <= 10 * TIME_MARGIN, short
    return gap, short


def test_the_envelopes_are_the_extremes_of_every_slab_end(shaken):
    folder, one, five = shaken
    got = envelopes(one)
    assert got["time"].size == round(END / 2.5e-3) + 1          # every slab end kept
    gap, short = assert_envelopes_of_rows(got)
    tension = got["principal_max"].max()
    print(f"shaken dam: envelopes against the rows {gap:.2g} of the largest |stress|, a "
          f"time's row below its envelope by {short:.2g} of the cell's stress; "
          f"largest tension {tension:.4g}, largest compression {got['principal_min'].min():.4g}")
    assert tension > 0.0                    # the shaking pulls somewhere
    sparse = envelopes(five)
    for name in DATASETS:
        assert np.array_equal(sparse[name], got[name]), name
    # kept every 5 slabs, the rows alone miss peaks the envelopes keep
    kept = eigenvalues(sparse["stress"])[..., 1].max(axis=0)
    assert (sparse["principal_max"] > kept).any()


def test_a_yielding_columns_envelopes_take_the_laws_stress(tmp_path):
    """The zone's cells (rank 0, the law's stress as /field/stress keeps
    it) the same way as the linear cells."""
    path = column(tmp_path, end=0.2, interface=False)
    got = envelopes(run(path, tmp_path / "r.h5"))
    gap, short = assert_envelopes_of_rows(got)
    print(f"yielding column (MKZ gamma_ref {MKZ['gamma_ref']:g}): envelopes against the rows "
          f"{gap:.2g}, a time's row below its envelope by {short:.2g}")


def test_a_restart_continues_the_envelopes_bit_for_bit(shaken, tmp_path):
    folder, _, five = shaken
    out = tmp_path / "part.h5"
    run(dam(tmp_path, every=5, end=0.075, name="part"), out)
    run(dam(tmp_path, every=5, name="part"), out, "--restart", out)
    whole, part = envelopes(five), envelopes(out)
    for name in DATASETS:
        assert np.array_equal(whole[name], part[name]), name


def test_two_ranks_give_one_ranks_envelopes(tmp_path):
    two = mpirun_against_one_rank(tmp_path, dam(tmp_path, end=0.05))
    with h5py.File(two, "r") as f:
        assert all(f"field/{name}" in f for name in DATASETS)


def test_info_names_the_largest_tension(shaken):
    folder, one, _ = shaken
    got = envelopes(one)
    k = int(got["principal_max"].argmax())
    p = run_cli("info", one)
    line = next(x for x in p.stdout.splitlines() if "largest tension" in x)
    with h5py.File(one, "r") as f:
        xy, cells = f["mesh/coordinates"][...], f["mesh/cells"][...]
    x, y = xy[np.where(cells[k] < 0, cells[k, 0], cells[k])].mean(axis=0)
    assert line.strip() == (f"largest tension (principal stress) {got['principal_max'][k]:.6g} "
                            f"in cell {k} at ({x:.6g}, {y:.6g}), t = "
                            f"{got['principal_max_time'][k]:.6g} (every slab end)")


def test_xdmf_and_plot_show_the_envelopes(shaken, tmp_path):
    from test_plane_outputs import vtk_arrays, vtk_reader

    folder, _, five = shaken
    assert run_cli("export", five, "--xdmf").returncode == 0
    reader = vtk_reader(five.with_suffix(".xdmf"))
    got = envelopes(five)
    for t in (got["time"][0], got["time"][-1]):
        arrays = vtk_arrays(reader, t)
        for name in DATASETS:
            assert np.array_equal(arrays[name], got[name]), name
    for colour in ("principal_max", "principal_min"):
        png = tmp_path / f"{colour}.png"
        p = run_cli("plot", five, "--color", colour, "-o", png)
        assert p.returncode == 0 and png.stat().st_size > 10000, p.stderr


def test_a_file_without_the_envelopes(shaken, tmp_path):
    """A file of an earlier version (the datasets deleted here): `info`
    leaves the line out, `plot --color principal_max` and `--restart`
    refuse in one line (exit 2)."""
    import shutil

    folder, _, five = shaken
    old = tmp_path / "old.h5"
    shutil.copy(five, old)
    with h5py.File(old, "a") as f:
        for name in DATASETS:
            del f[f"field/{name}"]
    p = run_cli("info", old)
    assert p.returncode == 0 and "tension" not in p.stdout, p.stderr
    p = run_cli("plot", old, "--color", "principal_max", "-o", tmp_path / "p.png")
    assert p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert "principal_max" in p.stderr and not (tmp_path / "p.png").exists()
    p = run_cli("run", dam(tmp_path, every=5, end=0.2, name="old"), "-o", old, "-q",
                "--restart", old)
    assert p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert "principal stress envelopes" in p.stderr


def test_the_kept_stress_operator_gives_centre_stress(monkeypatch):
    """The rows' centre stresses through D B formed once (meshes up to
    layout.CACHED_CELLS cells) against energy.centre_stress formed anew,
    on a mesh of triangles and quadrilaterals with a material per cell:
    within 8 ulps of the largest stress (two sums of the same products)."""
    from types import SimpleNamespace

    from vstpetsc.plane import layout, mesh as plane_mesh
    from vstpetsc.plane.energy import centre_stress

    m = plane_mesh.rectangle((0.0, 24.0), (0.0, 18.0), 12, 9, triangles=True)
    quads = plane_mesh.rectangle((0.0, 24.0), (0.0, 18.0), 12, 9)
    m.cells[::3] = quads.cells[np.arange(m.ncells)[::3] // 2]
    rng = np.random.default_rng(7)
    mat = {"lam": rng.uniform(1e8, 2e9, m.ncells), "mu": rng.uniform(1e8, 1e9, m.ncells)}
    rows = object.__new__(layout.RowFiller)
    rows.model, rows.stress_operator = SimpleNamespace(mesh=m, cell_materials=mat), None
    u = rng.standard_normal(2 * m.nnodes) * 1e-3
    kept = rows._centre_stress(u)
    again = rows._centre_stress(u)
    fresh = centre_stress(m, u, mat["lam"], mat["mu"])
    assert rows.stress_operator is not None and np.array_equal(kept, again)
    assert np.abs(kept - fresh).max() <= 8 * np.finfo(float).eps * np.abs(fresh).max()
    monkeypatch.setattr(layout, "CACHED_CELLS", 10)
    rows.stress_operator = None
    assert np.array_equal(rows._centre_stress(u), fresh) and rows.stress_operator is None
