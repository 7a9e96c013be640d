"""The fixed cost of a run (issue 29; bench/run_overhead.py times it): what
the cuts must not change.  A tiny run's file reads back whole, with chunks
sized to it and no block thread; a restart continues such a file far; the
low-level objects and attributes are those h5py's high level makes; the
reader's outline is that of h5py's walk; ``import vstpetsc`` loads no heavy
module."""

import subprocess
import sys

import h5py
import numpy as np
import pytest

import vstpetsc
from vstpetsc import bundled
from vstpetsc.results import blocks, reader
from vstpetsc.results.hdf5 import Growing, set_attrs
from vstpetsc.results.writer import CHUNK_FLOOR


def bar_wall(slabs):
    case = vstpetsc.Case.from_toml(bundled.path("bar-wall"))
    return case.with_value("time.end", slabs * case.dt)


def walked(path):
    """{name: (kind, rows)} of every object of a file, by h5py's high level."""
    out = {}

    def note(name, obj):
        if not isinstance(obj, h5py.Dataset):
            out[name] = ("group", None)
        elif not (obj.maxshape and obj.maxshape[0] is None):
            out[name] = ("dataset", obj.shape[0] if obj.shape else None)
        else:
            out[name] = ("series" if obj.ndim == 1 else "table", obj.shape[0])
    with h5py.File(path, "r") as f:
        f.visititems(note)
    return out


def loaded_after(code):
    """The sorted modules of interest loaded by ``code`` in a new process."""
    code += ("; import sys; print(sorted(m for m in sys.modules if m.split('.')[0] in "
             "('matplotlib', 'scipy', 'h5py', 'petsc4py', 'mpi4py', 'threadpoolctl') or "
             "m in ('vstpetsc.runner.driver', 'vstpetsc.input.case', 'vstpetsc.results.reader')))")
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True).stdout.strip()


def test_import_loads_no_heavy_module():
    assert loaded_after("import vstpetsc") == "[]"
    assert loaded_after("import vstpetsc.cli") == "[]"


def test_public_names_load_on_demand():
    assert loaded_after("import vstpetsc; vstpetsc.Case") == "['vstpetsc.input.case']"
    assert "'vstpetsc.runner.driver'" in loaded_after("from vstpetsc import run")
    for name in vstpetsc.__all__:
        assert name in dir(vstpetsc) and getattr(vstpetsc, name) is not None
    assert vstpetsc.sweep.__module__ == "vstpetsc.runner.sweep"      # the function, not the module
    assert vstpetsc.results.reader.Result is vstpetsc.Result   # submodules as before
    with pytest.raises(AttributeError):
        vstpetsc.no_such_name


def test_tiny_run_reads_back_whole_without_a_block_thread(tmp_path, monkeypatch):
    def no_thread(self, write):
        raise AssertionError("a tiny run's blocks go to the file at once")
    monkeypatch.setattr(blocks.BlockThread, "start", no_thread)
    case = bar_wall(2)
    result = vstpetsc.run(case, tmp_path / "tiny.h5", quiet=True)
    assert result.status == "completed"
    assert list(result.time) == [0.0, case.dt, 2 * case.dt]
    assert list(result.solver["slab"]) == [0, 1, 2]
    files = walked(tmp_path / "tiny.h5")
    assert {name: kind for name, (kind, _) in files.items()} == result._names
    for name, (kind, rows) in files.items():
        if kind in ("series", "table") and not name.endswith("events"):
            assert rows == 3 and result[name].shape[0] == 3, name
    with h5py.File(tmp_path / "tiny.h5", "r") as f:
        assert f.attrs["complete_rows"] == 3
        chunks = {f[n].chunks[0] for n, (kind, _) in files.items()
                  if kind == "series" and not n.endswith("events")}
    assert chunks == {CHUNK_FLOOR}          # a chunk holds the run, no more


def test_restart_continues_a_tiny_run_far_as_one_run(tmp_path):
    """Small chunks do not limit a file: a 2-slab run continued to 300
    slabs equals the 300-slab run (wall times apart)."""
    out, straight = tmp_path / "grown.h5", tmp_path / "straight.h5"
    vstpetsc.run(bar_wall(2), out, quiet=True)
    grown = vstpetsc.run(bar_wall(300), out, quiet=True, restart=True)
    whole = vstpetsc.run(bar_wall(300), straight, quiet=True)
    assert grown._names == whole._names and grown._rows == whole._rows == 301
    for name, kind in whole._names.items():
        if kind != "group" and name != "solver/wall_time":
            np.testing.assert_array_equal(grown[name], whole[name], err_msg=name)


@pytest.mark.parametrize("name", ["nonlinear-site", "sliding-block", "site-response"])
def test_outline_is_that_of_h5pys_walk(tmp_path, name):
    case = vstpetsc.Case.from_toml(bundled.path(name))
    path = tmp_path / "r.h5"
    vstpetsc.run(case.with_value("time.end", 3 * case.dt), path, quiet=True)
    files = walked(path)
    with h5py.File(path, "r") as f:
        assert reader._walk(f) == [(n, kind, rows) for n, (kind, rows) in files.items()]


def test_low_level_objects_are_those_of_the_high_level(tmp_path):
    values = {"text": "a case\nwith lines", "empty": "", "count": 7, "dt": 2e-6,
              "numpy": np.float64(1.5), "array": np.arange(3.0), "flag": True,
              "names": ["a", "b"], "unsigned": np.uint32(5)}
    with h5py.File(tmp_path / "a.h5", "w") as f:
        high, low = f.create_group("high"), f.create_group("low")
        for key, value in values.items():
            high.attrs[key] = value
        set_attrs(low, values)
        set_attrs(low, {"count": 8})                       # an existing name
        high.attrs["count"] = 8
        high.create_dataset("s", shape=(0, 3), maxshape=(None, 3), chunks=(64, 3), dtype="i8")
        high.create_dataset("x", shape=(5,), dtype="f8")
        made = Growing(f)
        made.add("low/s", (3,), 64, "i8")
        made.fixed("low/x", (5,), "f8")
        for key in values:
            a, b = high.attrs.get_id(key), low.attrs.get_id(key)
            assert (a.dtype, a.shape) == (b.dtype, b.shape), key
            np.testing.assert_array_equal(high.attrs[key], low.attrs[key])
        for key in ("s", "x"):
            a, b = high[key], low[key]
            assert (a.shape, a.maxshape, a.chunks, a.dtype, a.fillvalue) == \
                (b.shape, b.maxshape, b.chunks, b.dtype, b.fillvalue), key
