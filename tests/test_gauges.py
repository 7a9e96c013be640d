"""Gauges ([[gauge]]): a row every slab whatever `every` is, equal to the
full field interpolated where both exist; buffered and unbuffered files
identical; bad gauge tables named."""

import h5py
import numpy as np
import pytest

import vstpetsc
from conftest import bar, cli, make_case, solve, write_case
from vstpetsc.results import writer

# two bars in contact, 10 elements each (h = 0.1 and 0.125): gauges at a
# body's left end, inside elements, at an interior node, at a right end
GAUGES = [("a-left", "a", 0.0), ("a-in", "a", 0.237), ("a-node", "a", 0.5),
          ("a-right", "a", 1.0), ("b-left", "b", 1.02), ("b-in", "b", 1.9013)]
E = {"a": 1.0, "b": 2.0}


def case(every=1, end=2.9, gauges=GAUGES):
    return make_case(0.01, end, [bar("a", (0.0, 1.0), 10, E=E["a"], rho=1.0, v0=1.0),
                                 bar("b", (1.02, 2.27), 10, E=E["b"], rho=1.0)],
                     contacts=[dict(pair=["a", "b"], formulation="power")], every=every,
                     gauge=[{"name": n, "body": b, "x": x} for n, b, x in gauges])


def field_at(result, body, x):
    """(u, v, stress) at x over the kept rows, from the body's series: u, v
    by np.interp, stress of the element holding x (left at a node)."""
    g = result.body(body)
    xs = g.x
    e = max(0, int(np.sum(xs < x)) - 1)
    u = np.array([np.interp(x, xs, row) for row in g.u])
    v = np.array([np.interp(x, xs, row) for row in g.v])
    return u, v, g.stress[:, e]


@pytest.mark.parametrize("every", [1, 3, 7])
def test_gauges_equal_the_interpolated_field_every_slab(tmp_path, every):
    c = case(every)
    r = solve(tmp_path, c)
    kept = r.solver["slab"]
    assert r.gauges == sorted(n for n, _, _ in GAUGES)
    assert r.time.size == (c.nslabs - 1) // every + 2 or every == 1
    for name, body, x in GAUGES:
        g = r.gauge(name)
        assert g.attrs["body"] == body and g.attrs["x"] == x
        for key in ("u", "v", "stress", "strain"):
            assert g[key].shape == (c.nslabs + 1,), (name, key)
        u, v, stress = field_at(r, body, x)
        for got, want in ((g.u[kept], u), (g.v[kept], v), (g.stress[kept], stress)):
            scale = np.abs(want).max()
            assert scale > 0 and np.abs(got - want).max() <= 1e-12 * scale, name
        assert np.allclose(g.strain * E[body], g.stress, rtol=1e-14, atol=1e-14 * scale)
        assert np.array_equal(g.time, np.arange(c.nslabs + 1) * c.dt)


def test_gauge_rows_do_not_depend_on_every_or_on_the_buffer(tmp_path, monkeypatch):
    """Rows between kept slabs (here a buffer of 16 gauge rows fills 18
    times before the one kept slab) are written alone and equal those of
    every = 1."""
    one = solve(tmp_path, case(1), "one")
    monkeypatch.setattr(writer, "BUFFER_ROWS", 16)
    sparse = solve(tmp_path, case(1000), "sparse")
    assert sparse.time.size == 2
    for name, _, _ in GAUGES:
        for key in ("u", "v", "stress", "strain"):
            assert np.array_equal(one.gauge(name)[key], sparse.gauge(name)[key]), (name, key)


def datasets(path):
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: out.__setitem__(name, obj[()])
                     if isinstance(obj, h5py.Dataset) else None)
        attrs = dict(f.attrs)
    return out, attrs


@pytest.mark.parametrize("other", ["unbuffered", "no thread"])
def test_buffered_and_unbuffered_files_are_identical(tmp_path, monkeypatch, other):
    """Blocks written by wall time on the writer's thread (default), a
    flush after every kept row (-vst_flush_interval 0), or every block
    written at once (one set of buffers, as for huge rows): every dataset
    equal bit for bit."""
    c = case(2)
    solve(tmp_path, c, "buffered")
    options = ["-vst_flush_interval", "0"]
    if other == "no thread":
        monkeypatch.setattr(writer, "THREAD_ROWS", 1 << 30)
        options = ["-vst_flush_interval", "0.0001"]
    solve(tmp_path, c, "other", options=options)
    a, attrs_a = datasets(tmp_path / "buffered.h5")
    b, attrs_b = datasets(tmp_path / "other.h5")
    assert set(a) == set(b) and any(k.startswith("gauge/") for k in a)
    for key in a:
        if key != "solver/wall_time":
            assert a[key].dtype == b[key].dtype and np.array_equal(a[key], b[key], equal_nan=True), key
    varying = {"wall_time", "setup_time", "petsc_options"}
    assert {k: v for k, v in attrs_a.items() if k not in varying} == \
        {k: v for k, v in attrs_b.items() if k not in varying}


@pytest.mark.parametrize("gauge, key, words", [
    ({"name": "g", "body": "a", "x": 1.5}, "gauge[0] (g).x", "outside body 'a'"),
    ({"name": "g", "body": "c", "x": 0.5}, "gauge[0] (g).body", "unknown body 'c'"),
    ({"name": "g/1", "body": "a", "x": 0.5}, "gauge[0] (g/1).name", "letters, digits"),
    ({"name": "g", "body": "a"}, "gauge[0] (g).x", "missing"),
    ({"name": "g", "body": "a", "x": 0.5, "y": 1}, "gauge[0].y", "unknown key"),
])
def test_bad_gauge_tables_are_named(tmp_path, gauge, key, words):
    c = case()
    doc = c.to_dict()
    doc["gauge"] = [gauge]
    path = tmp_path / "bad.toml"
    path.write_text(vstpetsc.input.toml_text.dumps(doc))
    p = cli("run", path, "-o", tmp_path / "r.h5")
    assert p.returncode == 2 and p.stderr.count("\n") == 1, p.stderr
    assert key in p.stderr and words in p.stderr, p.stderr


def test_duplicate_gauge_names_and_unknown_gauge(tmp_path):
    twice = [("g", "a", 0.1), ("g", "a", 0.2)]
    with pytest.raises(vstpetsc.CaseError, match=r"gauge\[1\] \(g\).name: duplicate"):
        case(gauges=twice)
    r = solve(tmp_path, case(end=0.1, gauges=GAUGES[:1]))
    with pytest.raises(KeyError, match="no gauge 'x'"):
        r.gauge("x")
    assert case(gauges=GAUGES[:2]).with_value("gauge.a-in.x", 0.3).gauges[1].x == 0.3
    assert write_case(tmp_path, case()).read_text().count("[[gauge]]") == len(GAUGES)
