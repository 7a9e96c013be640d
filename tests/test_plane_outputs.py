"""The outputs of a plane-strain (2-D) result: `export --xdmf` opened by
VTK's own XDMF reader (the one ParaView uses) on mixed, all-quadrilateral
and all-triangle meshes, every array bit for bit the HDF5 dataset it
points into; `export --csv` (gauge x and y columns); `plot` (the deformed
mesh coloured by speed, its magnification, --times); `spectrum` and
`transfer --component x|y` on one-cell-wide P and S columns; and the
bad options (exit 2, one line)."""

import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import vstpetsc
from conftest import ROOT, bar, make_case, solve
from faults import one_clean_line
from test_plane_run import DAM
from vstpetsc import cli as cli_module
from vstpetsc.results.spectrum import acceleration, response_spectrum, transfer_function

VTK_TRIANGLE, VTK_QUAD = 5, 9        # VTK's cell type codes
H, VS, VP = 20.0, 200.0, 400.0       # the columns: height, wave speeds
PULSE = [[0.0, 0.0], [0.01, 0.1], [0.02, 0.0], [10.0, 0.0]]


def main(capsys, *args):
    """vstpetsc.cli.main in-process: (exit status, stdout, stderr)."""
    code = cli_module.main([str(a) for a in args])
    out = capsys.readouterr()
    return code, out.out, out.err


def rectangle(triangles):
    """A 4 x 2 plate moving up and right, its bottom held."""
    return vstpetsc.Case.from_dict({
        "time": {"dt": 1e-3, "end": 0.02},
        "mesh": {"rectangle": {"x": [0.0, 4.0], "y": [0.0, 2.0], "nx": 4, "ny": 2,
                               "triangles": triangles}},
        "region": [{"name": "domain", "Vs": VS, "Vp": VP, "rho": 2000.0, "v0": [0.1, 0.2]}],
        "boundary": [{"name": "bottom", "type": "fixed"}]})


def column(held, driven, end):
    """A one-cell-wide column of height H, its sides holding component
    ``held`` (x: a P column, y: an S column), its base driven along
    ``driven`` by a pulse; gauges at the base and the top."""
    return vstpetsc.Case.from_dict({
        "time": {"dt": 1e-3, "end": end},
        "mesh": {"rectangle": {"x": [0.0, 1.0], "y": [0.0, H], "nx": 1, "ny": 40}},
        "region": [{"name": "domain", "Vs": VS, "Vp": VP, "rho": 2000.0}],
        "boundary": [{"name": side, "type": "velocity", "value": {held: 0.0}}
                     for side in ("left", "right")]
        + [{"name": "bottom", "type": "velocity", "value": {driven: PULSE, held: 0.0}}],
        "gauge": [{"name": "base", "x": [0.5, 0.0]}, {"name": "top", "x": [0.5, H]}]})


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    """{name: Result}: the dam (triangles on quadrilaterals, two regions,
    gauges), a plate of quadrilaterals, one of triangles, the P and S
    columns, and a 1-D bar."""
    folder = tmp_path_factory.mktemp("plane-outputs")
    (folder / "dam.toml").write_text(DAM.format(end=0.05))
    out = {"dam": solve(folder, vstpetsc.Case.from_toml(folder / "dam.toml"), "dam"),
           "quads": solve(folder, rectangle(False), "quads"),
           "triangles": solve(folder, rectangle(True), "triangles"),
           "P": solve(folder, column("x", "y", 2.0), "P"),
           "S": solve(folder, column("y", "x", 2.0), "S")}
    out["bar"] = solve(folder, make_case(1e-4, 2e-3, [bar("b", (0.0, 1.0), 4, v0=1.0)],
                                         gauge=[{"name": "g", "body": "b", "x": 0.5}]), "bar")
    return out


# ---- export --xdmf, read by VTK

def vtk_reader(path):
    """VTK's vtkXdmfReader on ``path``, its time steps read."""
    xdmf = pytest.importorskip("vtkmodules.vtkIOXdmf2",
                               reason="VTK's XDMF reader (`make test` installs PyPI's vtk)")
    reader = xdmf.vtkXdmfReader()
    reader.SetFileName(str(path))
    reader.UpdateInformation()
    return reader


def vtk_arrays(reader, t):
    """What the reader gives at time ``t``: {cell_types, offsets,
    connectivity, points, and every point and cell array by name}, copied
    out of VTK (its next update overwrites them)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    reader.UpdateTimeStep(t)
    grid = reader.GetOutputDataObject(0)
    assert grid.GetClassName() == "vtkUnstructuredGrid"
    out = {"cell_types": grid.GetCellTypes(), "points": grid.GetPoints().GetData(),
           "offsets": grid.GetCells().GetOffsetsArray(),
           "connectivity": grid.GetCells().GetConnectivityArray()}
    for data in (grid.GetPointData(), grid.GetCellData()):
        out.update((data.GetArrayName(k), data.GetArray(k))
                   for k in range(data.GetNumberOfArrays()))
    return {key: vtk_to_numpy(array).copy() for key, array in out.items()}


def vtk_times(reader):
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as pipeline
    return np.array(reader.GetOutputInformation(0).Get(pipeline.TIME_STEPS()))


def assert_index_copies_no_float(path, result):
    """Every float DataItem of the XDMF file is a reference into the
    result file (the mesh's coordinates, the fields): none is inline."""
    root = ET.parse(path).getroot()
    floats = [item for item in root.iter("DataItem") if item.get("NumberType") == "Float"]
    h5 = result.path.rsplit("/", 1)[-1]
    assert floats and all(item.get("Format") == "HDF" and item.text.startswith(f"{h5}:/")
                          for item in floats)
    return root


@pytest.mark.parametrize("name, topology", [("dam", "Mixed"), ("quads", "Quadrilateral"),
                                            ("triangles", "Triangle")])
def test_xdmf_opens_in_vtk_with_the_datasets_bit_for_bit(results, capsys, name, topology):
    r = results[name]
    code, out, err = main(capsys, "export", r.path, "--xdmf")
    path = r.path[:-3] + ".xdmf"
    assert code == 0 and out == f"wrote {path}\n", err
    root = assert_index_copies_no_float(path, r)
    steps = root.findall("Domain/Grid/Grid")        # the reader would crash on no grid
    assert len(steps) == r.time.size
    assert steps[0].find("Topology").get("TopologyType") == topology
    reader = vtk_reader(path)
    assert np.array_equal(vtk_times(reader), r.time)
    mesh, field = r.mesh, r.field
    cells, coordinates = mesh.cells, mesh.coordinates
    triangle = cells[:, 3] < 0
    rows = (r.time.size // 3, r.time.size - 1)
    assert not np.array_equal(field.u[rows[0]], field.u[rows[1]])      # a row the test tells apart
    for row in rows:
        got = vtk_arrays(reader, r.time[row])
        types = got["cell_types"]
        assert types.size == len(cells)
        assert np.count_nonzero(types == VTK_TRIANGLE) == np.count_nonzero(triangle)
        assert np.count_nonzero(types == VTK_QUAD) == np.count_nonzero(~triangle)
        assert np.array_equal(np.diff(got["offsets"]), np.where(triangle, 3, 4))
        assert np.array_equal(got["connectivity"], cells[cells >= 0])
        assert np.array_equal(got["points"], np.c_[coordinates, np.zeros(len(coordinates))])
        for key in ("u", "v"):                          # 2-D vectors: VTK adds z = 0
            assert got[key].shape == (len(coordinates), 3)
            assert np.array_equal(got[key][:, :2], field[key][row]) and not got[key][:, 2].any()
        assert np.array_equal(got["stress"], field.stress[row])
        assert np.array_equal(got["region"], mesh.region)
    if name == "dam":
        assert 0 < np.count_nonzero(triangle) < len(cells)        # the mix the test is about
        assert set(mesh.region) == {0, 1}


def read_csv(path):
    """{header: column} of a CSV file of `export`, numbers as written."""
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    return dict(zip(header, np.array([row.split(",") for row in lines[1:]]).T))


def test_csv_has_the_x_and_y_columns_of_every_gauge(results, tmp_path, capsys):
    r = results["dam"]
    folder = tmp_path / "csv"
    code, out, err = main(capsys, "export", r.path, "--csv", folder)
    assert code == 0, err
    assert sorted(p.name for p in folder.iterdir()) == ["energy.csv", "gauge.csv", "solver.csv"]
    gauges = read_csv(folder / "gauge.csv")
    want = {"time": r.gauge("crest").time}
    for name in ("crest", "inside"):
        g = r.gauge(name)
        want.update((f"{name}.{key}_{axis}", g[key][:, k]) for key in ("u", "v")
                    for k, axis in enumerate("xy"))
    assert list(gauges) == list(want) and len(want["time"]) == 21
    for key, values in want.items():
        assert list(gauges[key]) == [f"{x:.17g}" for x in values], key
    assert np.abs(want["crest.v_y"]).max() > 0.01    # the incident P wave (measured 0.061)
    for file, group in (("energy.csv", "energy"), ("solver.csv", "solver")):
        columns = read_csv(folder / file)
        series = r.series(group)
        assert list(columns) == ["time", *series] and len(series) >= 4
        for key, values in {"time": r.time, **series}.items():
            assert list(columns[key]) == [f"{x:.17g}" for x in values], (file, key)


# ---- plot

PNG = b"\x89PNG\r\n\x1a\n"


def test_plot_writes_a_png_of_the_mixed_mesh(results, tmp_path, capsys):
    r = results["dam"]
    png = tmp_path / "times.png"
    p = subprocess.run([sys.executable, "-m", "vstpetsc", "plot", r.path, "-o", png,
                        "--times", f"0,{r.time[7]},{r.time[-1]}"],
                       cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and p.stdout == f"wrote {png}\n", p.stderr
    assert png.read_bytes()[:8] == PNG and png.stat().st_size > 20_000
    default = tmp_path / "default.png"
    assert main(capsys, "plot", r.path, "-o", default) == (0, f"wrote {default}\n", "")
    assert default.read_bytes()[:8] == PNG
    code, out, _ = main(capsys, "info", r.path)
    assert code == 0 and "plane strain: 193 cells (100 triangles), 174 nodes" in out


def test_the_mesh_panels_show_the_speed_on_the_magnified_mesh(results):
    """The default panels are the rows of the largest kinetic energy and
    the last; each colours its nodes by |v| of its row and moves them by
    one factor that draws the largest |u| of the panels as 5 % of the
    mesh's longer side; the figure's title states it."""
    import matplotlib.pyplot as plt

    from vstpetsc.results.plane_plot import magnification, outlines
    from vstpetsc.results.plot import result_figure

    r = results["dam"]
    rows = [int(np.argmax(r.energy["kinetic"])), r.time.size - 1]
    assert rows[0] < rows[1]                  # two distinct panels in this case
    coordinates, cells = r.mesh.coordinates, r.mesh.cells
    u, v = r.field.u[rows], r.field.v[rows]
    size = max(np.ptp(coordinates[:, 0]), np.ptp(coordinates[:, 1]))
    largest = np.sqrt(u[..., 0] ** 2 + u[..., 1] ** 2).max()
    factor = magnification(coordinates, u)
    assert factor == pytest.approx(0.05 * size / largest, rel=1e-15) and factor > 10
    fig = result_figure(r)
    assert f"magnified {factor:.4g} times" in fig._suptitle.get_text()
    for k, row in enumerate(rows):
        ax = fig.axes[k]
        assert ax.get_title() == f"(a{k + 1}) speed |v| at t = {r.time[row]:.6g} s"
        shade, edges = ax.collections
        assert np.array_equal(np.asarray(shade.get_array()),
                              np.sqrt(v[k, :, 0] ** 2 + v[k, :, 1] ** 2))
        moved = coordinates + factor * u[k]
        corners = np.array([path.vertices[:4] for path in edges.get_paths()])
        assert np.array_equal(corners, moved[outlines(cells)])
    assert [ax.get_title() for ax in fig.axes[-2:]] == [
        "(b) gauge velocities (v_x solid, v_y dashed)", "(c) energy"]
    plt.close(fig)
    fig = result_figure(r, times=[r.time[3] + 0.4 * (r.time[4] - r.time[3])])   # the nearest row
    assert fig.axes[0].get_title() == f"(a1) speed |v| at t = {r.time[3]:.6g} s"
    assert np.array_equal(np.asarray(fig.axes[0].collections[0].get_array()),
                          np.sqrt(r.field.v[3, :, 0] ** 2 + r.field.v[3, :, 1] ** 2))
    plt.close(fig)


# ---- spectrum and transfer --component

def test_gauge_acceleration_has_a_column_per_component(results):
    g = results["dam"].gauge("crest")
    dt = g.dt
    assert g.acceleration.shape == g.v.shape == (21, 2)
    for k in (0, 1):
        assert np.array_equal(g.acceleration[:, k], acceleration(g.v[:, k], dt))
    v = g.v[:, 1]
    assert np.array_equal(g.acceleration[1:-1, 1], (v[2:] - v[:-2]) / (2 * dt))


@pytest.mark.parametrize("case, component, axis", [("P", "y", 1), ("S", "x", 0)])
def test_spectrum_of_a_component_is_that_of_its_velocity_column(results, tmp_path, capsys,
                                                                case, component, axis):
    """The P column moves along y only, the S column along x only (its
    sides hold the other component): the spectrum of that component is the
    one of the gauge's v[:, axis] through vstpetsc.results.spectrum, the other
    component's a record of zeros."""
    r = results[case]
    v, dt = r.gauge("top").v, r.attrs["dt"]
    assert np.abs(v[:, axis]).max() > 0.05 and not v[:, 1 - axis].any()
    csv = tmp_path / f"{case}.csv"
    code, out, err = main(capsys, "spectrum", r.path, "--gauge", "top", "--component", component,
                          "--csv", csv)
    assert code == 0 and out == f"wrote {csv}\n", err
    want = response_spectrum(acceleration(v[:, axis], dt), dt)
    got = read_csv(csv)
    assert list(got) == ["period", "sd", "psv", "psa"] and want["psa"].max() > 0
    for key, values in want.items():
        assert list(got[key]) == [f"{x:.17g}" for x in values], key
    other = "xy"[1 - axis]
    code, out, _ = main(capsys, "spectrum", r.path, "--gauge", "top", "--component", other)
    assert code == 0 and out.startswith(f"response spectrum of gauge top, {other} acceleration")
    assert "peak acceleration 0 m/s^2" in out
    code, out, _ = main(capsys, "spectrum", r.path, "--gauge", "top")      # x by default
    assert code == 0 and out.startswith("response spectrum of gauge top, x acceleration")


@pytest.mark.parametrize("case, component, axis, speed", [("P", "y", 1, VP), ("S", "x", 0, VS)])
def test_transfer_of_a_component_peaks_at_the_columns_first_mode(results, tmp_path, capsys,
                                                               case, component, axis, speed):
    """top / base of a column driven at its base: the ratio of the Fourier
    amplitudes of that component's accelerations, largest (below 1.5 times
    it) within one frequency step of the first mode V / (4 H)."""
    r = results[case]
    dt = r.attrs["dt"]
    csv = tmp_path / f"{case}-transfer.csv"
    code, out, err = main(capsys, "transfer", r.path, "--from", "base", "--to", "top",
                          "--component", component, "--csv", csv)
    assert code == 0, err
    records = [acceleration(r.gauge(name).v[:, axis], dt) for name in ("base", "top")]
    f, amp = transfer_function(*records, dt)
    got = read_csv(csv)
    assert list(got["amplitude"]) == [f"{x:.17g}" for x in amp]
    first = speed / (4 * H)
    band = (f > 0) & (f < 1.5 * first)
    assert abs(f[band][np.nanargmax(amp[band])] - first) <= f[1] < 0.2 * first


# ---- bad options: exit 2, one line naming the option

BAD = [
    ("dam", ("plot", "--times", "9"), "--times: 9 is outside the run (0 .. 0.05)"),
    ("dam", ("plot", "--times", "-0.01"), "--times: -0.01 is outside the run"),
    ("dam", ("plot", "--times", "0.01,x"), "--times: numbers separated by commas, got '0.01,x'"),
    ("dam", ("plot", "--times", "nan"), "--times: numbers separated by commas"),
    ("dam", ("plot", "--times", "0,0,0,0,0,0,0"), "--times: 1 to 6 times, got 7"),
    ("bar", ("plot", "--times", "0"), "--times: only for a 2-D result"),
    ("dam", ("spectrum", "--gauge", "crest", "--component", "z"),
     "--component: x or y for a 2-D result, got 'z'"),
    ("dam", ("spectrum", "--gauge", "crest", "--component", "shear"),
     "--component: x or y for a 2-D result, got 'shear'"),
    ("dam", ("transfer", "--from", "inside", "--to", "crest", "--component", "axial"),
     "--component: x or y for a 2-D result, got 'axial'"),
    ("bar", ("spectrum", "--gauge", "g", "--component", "x"),
     "--component: shear or axial, got 'x' (x and y name a 2-D result's components)"),
]


@pytest.mark.parametrize("name, args, message", BAD, ids=[" ".join(b[1]) for b in BAD])
def test_bad_options_are_one_line_exit_2(results, capsys, name, args, message):
    code, out, err = main(capsys, args[0], results[name].path, *args[1:])
    assert code == 2 and out == "" and one_clean_line(err), err
    assert err.startswith(f"vstpetsc: error: {message}"), err


def test_a_bad_component_from_the_shell(results):
    p = subprocess.run([sys.executable, "-m", "vstpetsc", "spectrum", results["P"].path,
                        "--gauge", "top", "--component", "z"],
                       cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and one_clean_line(p.stderr) and "--component" in p.stderr


def test_the_mesh_panels_show_a_stress_per_cell(results, tmp_path, capsys):
    """--color sxy: each panel's cells coloured flat by sigma_xy of its
    row (the file's /field/stress column), one scale symmetric about 0
    for every panel; an unknown colour or --color on a 1-D result is one
    line, exit 2."""
    import matplotlib.pyplot as plt

    from vstpetsc.results.plot import result_figure

    r = results["dam"]
    rows = [int(np.argmax(r.energy["kinetic"])), r.time.size - 1]
    fig = result_figure(r, colour="sxy")
    stress = r.field.stress[rows][..., 2]
    top = np.abs(stress).max()
    for k, row in enumerate(rows):
        ax = fig.axes[k]
        assert ax.get_title() == f"(a{k + 1}) sigma_xy at t = {r.time[row]:.6g} s"
        shade = ax.collections[0]
        assert np.array_equal(np.asarray(shade.get_array()), stress[k])
        assert shade.get_clim() == (-top, top)
    plt.close(fig)
    png = tmp_path / "sxx.png"
    assert main(capsys, "plot", r.path, "-o", png, "--color", "sxx") == (0, f"wrote {png}\n", "")
    code, out, err = main(capsys, "plot", r.path, "-o", png, "--color", "pressure")
    assert code == 2 and err.strip().count("\n") == 0 and "--color: one of" in err
