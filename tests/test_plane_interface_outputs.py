"""The outputs of a plane-strain result with an interface (the dam on its
foundation across "contact", tests/test_plane_interface_runs.py, sliding
and lifting by 0.3 s): `plot`'s row per interface (slip and opening along
the curve at the mesh panels' times, the largest |slip|, the largest
opening and the length open over time) drawn from the file's datasets;
the order of the pairs along a curve (the dam's, one drawn in reverse, a
shuffled arc); `export --xdmf`'s grid per interface read by VTK's
vtkXdmfReader (ParaView's), its values the HDF5 datasets bit for bit."""

import io

import numpy as np
import pytest

import vstpetsc
from test_plane_interface_runs import dam_text
from test_plane_outputs import PNG, assert_index_copies_no_float, main, vtk_reader, vtk_times
from vstpetsc.results.interface_plot import curve_order, curve_segments, interface_order

VTK_POLY_VERTEX = 2
PAIR_FIELDS = ("gap", "normal_force", "shear_force", "slip")


@pytest.fixture(scope="module")
def dam(tmp_path_factory):
    """The dam with its interface "contact", run to 0.3 s (121 kept rows)."""
    folder = tmp_path_factory.mktemp("interface-outputs")
    (folder / "dam.toml").write_text(dam_text(0.3))
    return vstpetsc.run(vstpetsc.Case.from_toml(folder / "dam.toml"),
                        output=str(folder / "dam.h5"), quiet=True, out=io.StringIO())


# ---- the order along the curve

def assert_monotone(points, order, distance):
    """distance: 0 at the first pair, rising by the length of each step."""
    steps = np.linalg.norm(np.diff(points[order], axis=0), axis=1)
    assert distance[0] == 0.0 and np.all(steps > 0)
    assert np.array_equal(distance, np.concatenate([[0.0], np.cumsum(steps)]))


def test_the_dams_pairs_are_ordered_along_the_curve(dam):
    g = dam.interface("contact")
    first, tangent = g.nodes[:][:, 0], g.tangent[:]
    points = dam.mesh.coordinates[first]
    segments = curve_segments(dam.mesh.cells, first)
    assert len(segments) == len(first) - 1                  # one open polyline
    order, distance = curve_order(points, tangent, segments)
    assert_monotone(points, order, distance)
    assert np.all(np.diff(points[order, 0]) > 0) and not points[:, 1].any()   # left to right
    assert distance[-1] == pytest.approx(np.ptp(points[:, 0]), rel=1e-14)
    assert np.array_equal(interface_order(dam, "contact")[0], order)
    shuffled = np.random.default_rng(3).permutation(len(first))
    again, d = curve_order(points[shuffled], tangent[shuffled],
                           curve_segments(dam.mesh.cells, first[shuffled]))
    assert np.array_equal(first[shuffled][again], first[order]) and np.array_equal(d, distance)
    # the curve drawn in reverse (right to left: the tangents turned round)
    back, d = curve_order(points[::-1], -tangent[::-1], segments=None)
    assert np.array_equal(first[::-1][back], first[order][::-1])
    assert_monotone(points[::-1], back, d)


SWEEP = 1.5 * np.pi         # the arc: three quarters of a circle


def arc(n=13):
    """Three quarters of the unit circle, n nodes (0 .. n-1) from angle 0
    to SWEEP, their tangents along it, and cells beside it: a triangle
    (i, i+1, n+i) on each edge, every other one a quadrilateral
    (i, i+1, n+i, n+i-1) (the outer nodes n.. off the curve)."""
    angle = np.linspace(0.0, SWEEP, n)
    curve = np.c_[np.cos(angle), np.sin(angle)]
    outside = 1.3 * np.c_[np.cos(angle[:-1] + 0.1), np.sin(angle[:-1] + 0.1)]
    k = np.arange(n - 1)
    cells = np.c_[k, k + 1, n + k, np.full(n - 1, -1)]
    cells[1::2, 3] = n + k[1::2] - 1
    return np.vstack([curve, outside]), np.c_[-np.sin(angle), np.cos(angle)], cells


@pytest.mark.parametrize("reverse", [False, True])
def test_a_shuffled_arc_is_walked_along_its_polyline(reverse):
    """The shuffled pairs of the arc come back in the curve's order, in
    the direction of its tangents (drawn in reverse: the other way),
    where the projections on the mean tangent would mix them."""
    coordinates, tangent, cells = arc()
    n = len(tangent)
    sign = -1.0 if reverse else 1.0
    first = np.random.default_rng(7).permutation(n)
    points = coordinates[first]
    order, distance = curve_order(points, sign * tangent[first], curve_segments(cells, first))
    want = np.arange(n)[::-1] if reverse else np.arange(n)
    assert np.array_equal(first[order], want)
    assert_monotone(points, order, distance)
    chord = 2 * np.sin(SWEEP / (n - 1) / 2)
    assert np.allclose(np.diff(distance), chord, rtol=1e-12, atol=0)
    projected = np.argsort(points @ (sign * tangent[first]).sum(axis=0))
    assert not np.array_equal(first[projected], want)       # the walk is needed here


def test_branching_edges_fall_back_on_the_projection(dam):
    g = dam.interface("contact")
    first = g.nodes[:][:, 0]
    points = dam.mesh.coordinates[first]
    branch = np.array([[0, 1], [0, 2], [0, 3]])             # a point with three neighbours
    order, distance = curve_order(points, g.tangent[:], branch)
    assert np.array_equal(order, np.argsort(points[:, 0], kind="stable"))
    assert_monotone(points, order, distance)


# ---- plot

def test_plot_draws_a_row_per_interface(dam, tmp_path, capsys):
    """(d1): per chosen time the slip (solid) and the gap (dashed) of the
    pairs in their order along the curve; (d2): the largest |slip|, the
    largest gap and the length open ((gap > 0) @ length) per kept row."""
    import matplotlib.pyplot as plt

    from vstpetsc.results.plot import result_figure

    r, g = dam, dam.interface("contact")
    png = tmp_path / "dam.png"
    assert main(capsys, "plot", r.path, "-o", png, "--times", "0.1,0.3") == (
        0, f"wrote {png}\n", "")
    assert png.read_bytes()[:8] == PNG
    rows = [40, 120]
    fig = result_figure(r, times=r.time[rows])
    titles = [ax.get_title() for ax in fig.axes]
    along = fig.axes[titles.index("(d1) interface contact along the curve: slip solid, "
                                  "opening dashed")]
    timed = fig.axes[titles.index("(d2) interface contact over time")]
    assert titles.index("(c) energy") < titles.index("(d2) interface contact over time")
    order, distance, _ = interface_order(r, "contact")
    slip, gap, length = g.slip[:], g.gap[:], g.length[:]
    lines = along.get_lines()
    for k, row in enumerate(rows):
        for line, values in zip(lines[2 * k:2 * k + 2], (slip[row], gap[row])):
            assert np.array_equal(line.get_xdata(), distance)
            assert np.array_equal(line.get_ydata(), values[order])
    largest, opening = timed.get_lines()[:2]
    assert np.array_equal(largest.get_ydata(), np.abs(slip).max(axis=1))
    assert np.array_equal(opening.get_ydata(), gap.max(axis=1))
    opened = [ax for ax in fig.axes if ax.get_ylabel() == "length open [m]"][0].get_lines()[0]
    assert np.array_equal(opened.get_ydata(), (gap > 0) @ length)
    assert opened.get_ydata().max() > 0 and np.abs(slip).max() > 1e-3      # it lifts and slides
    plt.close(fig)


# ---- export --xdmf

def blocks(reader, t):
    """{grid name: vtkUnstructuredGrid} of the reader's output at time t."""
    reader.UpdateTimeStep(t)
    out = reader.GetOutputDataObject(0)
    assert out.GetClassName() == "vtkMultiBlockDataSet"
    return {out.GetMetaData(k).Get(out.NAME()): out.GetBlock(k)
            for k in range(out.GetNumberOfBlocks())}


def test_xdmf_has_a_grid_per_interface_bit_for_bit(dam, capsys):
    r, g = dam, dam.interface("contact")
    code, out, err = main(capsys, "export", r.path, "--xdmf")
    path = r.path[:-3] + ".xdmf"
    assert code == 0 and out == f"wrote {path}\n", err
    root = assert_index_copies_no_float(path, r)
    assert [grid.get("Name") for grid in root.findall("Domain/Grid")] == [
        "mesh", "interface-contact"]
    reader = vtk_reader(path)                      # skips without VTK
    from vtkmodules.util.numpy_support import vtk_to_numpy as numpy

    assert np.array_equal(vtk_times(reader), r.time)
    first, coordinates = g.nodes[:][:, 0], r.mesh.coordinates
    rows = (40, 120)
    assert not np.array_equal(g.slip[rows[0]], g.slip[rows[1]])
    for row in rows:
        got = blocks(reader, r.time[row])
        assert list(got) == ["mesh", "interface-contact"]
        mesh, pairs = got["mesh"], got["interface-contact"]
        assert np.array_equal(numpy(mesh.GetPointData().GetArray("u"))[:, :2], r.field.u[row])
        assert np.array_equal(numpy(pairs.GetCellTypes()), np.full(len(first), VTK_POLY_VERTEX))
        assert np.array_equal(numpy(pairs.GetCells().GetConnectivityArray()), first)
        assert np.array_equal(numpy(pairs.GetPoints().GetData()),
                              np.c_[coordinates, np.zeros(len(coordinates))])
        cells = pairs.GetCellData()
        assert np.array_equal(numpy(cells.GetArray("length")), g.length[:])
        for key in PAIR_FIELDS:
            assert np.array_equal(numpy(cells.GetArray(key)), g[key][row]), key
