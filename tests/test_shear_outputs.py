"""The shear field in the outputs (issue 36 item 4): a sweep's summary.csv
columns `strain_max` and `hysteretic`, `vstpetsc info`'s shear peaks and
`vstpetsc export --xdmf`'s shear attributes, each checked against the
result file's own raw datasets (shear/u, shear/v, shear/stress, the
envelopes, /energy/hysteretic) recomputed here.

The case: two shear columns side by side, not touching ("a" of MKZ soil,
"b" linear), each shaken at its base by a shear velocity pulse, and an
axial bar "c" without a shear component; every slab kept. The sweep
drives "b" weakly, then strongly, so that the largest strain is a's in
the first run and b's in the second.
"""

import re
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np
import pytest

import vstpetsc
from conftest import bar, cli, make_case, solve
from vstpetsc.runner.sweep import quantities, read_summary

MKZ = {"model": "mkz", "gamma_ref": 1.0e-4, "beta": 1.0, "s": 0.9}
B_PULSE = "bc.1.value"
WEAK, STRONG = 0.01, 1.0          # b's peak base velocity (Vs = 200 m/s: strain ~ v / Vs)


def pulse(peak):
    return [[0.0, 0.0], [0.02, peak], [0.04, 0.0]]


def column_case(b_peak=WEAK):
    soil = dict(E=1.0e8, rho=2000.0)
    bodies = [bar("a", [0.0, 10.0], 10, Vs=100.0, shear_law=MKZ, **soil),
              bar("b", [20.0, 30.0], 8, Vs=200.0, **soil),
              bar("c", [40.0, 41.0], 2)]
    bcs = [dict(body=name, end="left", type="velocity", component="shear", value=pulse(v))
           for name, v in (("a", 0.05), ("b", b_peak))]
    return make_case(1.0e-3, 0.15, bodies, bcs=bcs, every=1)


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    """(rows, summary.csv's header and data, [Result]) of the sweep over
    b's pulse."""
    folder = tmp_path_factory.mktemp("shear-sweep")
    rows = vstpetsc.sweep(column_case(), {B_PULSE: [pulse(WEAK), pulse(STRONG)]},
                          str(folder))
    header, data = read_summary(str(folder / "summary.csv"))
    results = [vstpetsc.Result(str(folder / row["file"])) for row in rows]
    return rows, header, data, results


def kept_strain(r, body):
    """|dw/dx| of every element at every kept row, from shear/u and x."""
    g = r.body(body)
    return np.abs(np.diff(g.shear.u, axis=1) / np.diff(g.x))


def test_summary_strain_max_is_the_largest_strain_of_any_body(swept):
    rows, header, data, results = swept
    assert {"strain_max", "hysteretic"} <= set(header)
    largest = []
    for i, r in enumerate(results):
        assert r.status == "completed"
        assert "shear" not in r.body("c").keys()
        per_body = {b: kept_strain(r, b).max() for b in ("a", "b")}
        # every = 1: the envelope over every slab end is the kept rows' largest
        for b in ("a", "b"):
            assert r.body(b).shear.strain_max.max() == pytest.approx(per_body[b], rel=1e-12)
        assert data["strain_max"][i] == pytest.approx(max(per_body.values()), rel=1e-12)
        assert rows[i]["strain_max"] == data["strain_max"][i]
        largest.append(max(per_body, key=per_body.get))
    assert largest == ["a", "b"]            # the max is taken over the bodies


def test_summary_hysteretic_is_the_last_hysteretic_energy(swept):
    _, _, data, results = swept
    for i, r in enumerate(results):
        e = r.energy["hysteretic"]
        assert data["hysteretic"][i] == e[-1]
        assert e[-1] > 0.0                  # a's soil went round loops
    # only a dissipates by hysteresis, shaken alike in both runs (b is
    # linear, c has no shear component)
    assert data["hysteretic"][1] == pytest.approx(data["hysteretic"][0], rel=1e-6)


def test_no_shear_component_no_shear_columns(tmp_path):
    """A run without a shear component has neither column (empty cells
    in a sweep that mixes both kinds)."""
    case = make_case(1.0e-5, 1.0e-4, [bar("bar", [0.0, 1.0], 10, v0=1.0)])
    q = quantities(solve(tmp_path, case))
    assert "strain_max" not in q and "hysteretic" not in q and "numerical_energy" in q


def info_block(text, body):
    """`vstpetsc info`'s lines of ``body`` (its heading line to the next
    body's or section's)."""
    lines = text.splitlines()
    start = next(i for i, x in enumerate(lines) if x.startswith(f"    {body} "))
    end = next(i for i in range(start + 1, len(lines)) if not lines[i].startswith("      "))
    return "\n".join(lines[start + 1:end])


def info_numbers(block, label):
    m = re.search(rf"{re.escape(label)} (\S+) at x = (\S+), t = (\S+)", block)
    assert m, (label, block)
    return [float(v) for v in m.groups()]


def test_info_prints_the_shear_peaks_of_each_body(swept):
    _, _, _, results = swept
    r = results[1]
    p = cli("info", r.path)
    assert p.returncode == 0, p.stderr
    assert "shear" not in info_block(p.stdout, "c")
    t = r.time
    for body in ("a", "b"):
        block = info_block(p.stdout, body)
        g = r.body(body)
        x, mid = g.x, 0.5 * (g.x[1:] + g.x[:-1])
        stress = g.shear.stress                      # the law's stress at the kept rows
        row, e = np.unravel_index(np.argmax(np.abs(stress)), stress.shape)
        value, where, when = info_numbers(block, "largest shear stress")
        assert value == pytest.approx(stress[row, e], rel=1e-5)
        assert (where, when) == (pytest.approx(mid[e], rel=1e-5), pytest.approx(t[row], abs=1e-9))
        strain = kept_strain(r, body)
        row, e = np.unravel_index(np.argmax(strain), strain.shape)
        value, where, when = info_numbers(block, "largest shear strain |dw/dx|")
        assert value == pytest.approx(strain[row, e], rel=1e-5)
        assert (where, when) == (pytest.approx(mid[e], rel=1e-5), pytest.approx(t[row], abs=1e-9))
        v = g.shear.v
        row, node = np.unravel_index(np.argmax(np.abs(v)), v.shape)
        value, where, when = info_numbers(block, "largest shear velocity")
        assert value == pytest.approx(v[row, node], rel=1e-5)
        assert (where, when) == (pytest.approx(x[node], rel=1e-5, abs=1e-9),
                                 pytest.approx(t[row], abs=1e-9))


def test_xdmf_carries_the_shear_field(swept):
    _, _, _, results = swept
    r = results[0]
    p = cli("export", r.path, "--xdmf")
    assert p.returncode == 0, p.stderr
    path = Path(r.path).with_suffix(".xdmf")
    domain = ET.parse(path).getroot().find("Domain")
    grids = {g.get("Name"): g.findall("Grid") for g in domain.findall("Grid")}
    assert list(grids) == ["a", "b", "c"]
    want = {"u": "u", "v": "v", "stress": "stress",
            "shear_u": "shear/u", "shear_v": "shear/v", "shear_stress": "shear/stress"}
    with h5py.File(r.path, "r") as f:
        for body, steps in grids.items():
            nn = f[f"body/{body}/x"].shape[0]
            names = set(want) if body != "c" else {"u", "v", "stress"}
            assert len(steps) == f["time"].shape[0]
            for i in (0, len(steps) // 2, len(steps) - 1):
                attrs = {a.get("Name"): a for a in steps[i].findall("Attribute")}
                assert set(attrs) == names
                for name, a in attrs.items():
                    select, source = a.find("DataItem").findall("DataItem")
                    file, dataset = source.text.split(":")
                    assert (path.parent / file).resolve() == Path(r.path).resolve()
                    assert dataset == f"/body/{body}/{want[name]}"
                    ds = f[dataset]
                    width = nn if a.get("Center") == "Node" else nn - 1
                    assert ds.shape == (f["time"].shape[0], width)
                    assert tuple(map(int, source.get("Dimensions").split())) == ds.shape
                    start, stride, count = np.array(select.text.split(), int).reshape(3, 2)
                    assert list(start) == [i, 0] and list(count) == [1, width]
                    assert list(stride) == [1, 1]
                    assert float(steps[i].find("Time").get("Value")) == f["time"][i]
