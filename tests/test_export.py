"""`vstpetsc export`: CSV files read back equal the HDF5 datasets bit for
bit; the XDMF index, resolved by hand, gives the HDF5 rows it claims."""

import xml.etree.ElementTree as ET

import h5py
import numpy as np
import pytest

from conftest import cli, solve
from test_gauges import GAUGES, case

XI = "{http://www.w3.org/2001/XInclude}include"


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    folder = tmp_path_factory.mktemp("export")
    return solve(folder, case(every=3), "r")


def read_csv(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return dict(zip(header, data.T))


def test_csv_columns_equal_the_datasets(result, tmp_path):
    p = cli("export", result.path, "--csv", tmp_path / "csv")
    assert p.returncode == 0, p.stderr
    names = sorted(f.name for f in (tmp_path / "csv").iterdir())
    assert names == ["contact-0-events.csv", "contact-0.csv", "energy.csv", "envelope-a.csv",
                     "envelope-b.csv", "gauge.csv", "solver.csv"]
    gauges = read_csv(tmp_path / "csv" / "gauge.csv")
    assert len(gauges) == 1 + 4 * len(GAUGES)
    assert np.array_equal(gauges["time"], result.gauge("a-in").time)
    for name, _, _ in GAUGES:
        for key in ("u", "v", "stress", "strain"):
            assert np.array_equal(gauges[f"{name}.{key}"], result.gauge(name)[key])
    for file, group in (("contact-0.csv", "contact/0"), ("energy.csv", "energy"),
                        ("solver.csv", "solver")):
        columns = read_csv(tmp_path / "csv" / file)
        series = result.series(group)
        assert set(columns) == {"time", *series} and len(series) >= 4
        assert np.array_equal(columns["time"], result.time)
        for key, value in series.items():
            assert np.array_equal(columns[key], value, equal_nan=True), (file, key)
    env = read_csv(tmp_path / "csv" / "envelope-b.csv")
    b = result.body("b")
    assert np.array_equal(env["stress_min"], b.stress_min)
    assert np.array_equal(env["x_right"], b.x[1:])


def hyperslab(item, folder):
    """The array a HyperSlab DataItem selects, read from its HDF5 file."""
    select, source = item.findall("DataItem")
    start, stride, count = np.array(select.text.split(), dtype=int).reshape(3, 2)
    file, path = source.text.split(":")
    with h5py.File(folder / file, "r") as f:
        ds = f[path]
        assert ds.shape == tuple(int(d) for d in source.get("Dimensions").split())
        rows = slice(start[0], start[0] + stride[0] * count[0], stride[0])
        cols = slice(start[1], start[1] + stride[1] * count[1], stride[1])
        return ds[rows, cols]


def test_xdmf_points_at_the_rows_it_names(result, tmp_path):
    p = cli("export", result.path, "--xdmf")
    assert p.returncode == 0, p.stderr
    path = result.path[:-3] + ".xdmf"
    root = ET.parse(path).getroot()
    folder = __import__("pathlib").Path(path).parent
    collections = root.find("Domain").findall("Grid")
    assert [g.get("Name") for g in collections] == ["a", "b"]
    for body, coll in zip(("a", "b"), collections):
        steps = coll.findall("Grid")
        g = result.body(body)
        assert [float(s.find("Time").get("Value")) for s in steps] == list(result.time)
        xyz = np.array(steps[0].find("Geometry/DataItem").text.split(), float).reshape(-1, 3)
        assert np.array_equal(xyz[:, 0], g.x) and not xyz[:, 1:].any()
        cells = np.array(steps[0].find("Topology/DataItem").text.split(), int).reshape(-1, 2)
        assert np.array_equal(cells, np.c_[np.arange(g.x.size - 1), np.arange(1, g.x.size)])
        for i in (1, len(steps) // 2, len(steps) - 1):
            assert f"@Name='{body}-0'" in steps[i].find(XI).get("xpointer")
            for attr in steps[i].findall("Attribute"):
                got = hyperslab(attr.find("DataItem"), folder)
                assert np.array_equal(got[0], g[attr.get("Name")][i]), (body, i)
            assert {a.get("Name") for a in steps[i].findall("Attribute")} == {"u", "v", "stress"}


def test_export_usage_errors(result, tmp_path):
    for args, words in (((), "give --csv DIR, --xdmf or both"),
                        (("--csv", result.path), "exists and is not a folder"),
                        (("--csv",), "needs a value")):
        p = cli("export", result.path, *args)
        assert p.returncode == 2 and p.stderr.count("\n") == 1 and words in p.stderr, p.stderr
    p = cli("export", tmp_path / "none.h5", "--xdmf")
    assert p.returncode == 2 and "no such file" in p.stderr
