"""Readers of a file being written (issue 25, item 10) and the energy
change a run and `vstpetsc info` print (item 6)."""

import os
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np
import pytest

import faults
import vstpetsc
from conftest import bar, cli, make_case, run_and_info, write_case
from vstpetsc import Result
from vstpetsc.results import layout
from vstpetsc.results.files import OutputLock
from vstpetsc.results.hdf5 import swmr_format

RESTART = ("solver/rhs_state", "solver/newton_state", "solver/energy_sums")


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """(folder, a short completed result of faults.long_case, its case file)."""
    folder = tmp_path_factory.mktemp("readers")
    case = write_case(folder, faults.long_case(end=0.4, every=10), "short")
    out = folder / "done.h5"
    p = cli("run", case, "-o", out, "--quiet")
    assert p.returncode == 0, p.stderr
    return folder, out, case


def series_names(path):
    """(kept-row series, gauge series) of a result file."""
    kept, gauges = [], []
    with h5py.File(path, "r", locking=False) as f:
        f.visititems(lambda name, obj: (gauges if layout.every_slab(name) else kept).append(name)
                     if isinstance(obj, h5py.Dataset) and obj.maxshape[0] is None else None)
    return kept, gauges


def half_written(done, path, grown, rows=3):
    """A copy of ``done`` as a run leaves it in the middle of a block: the
    datasets ``grown`` have ``rows`` more rows (garbage), the others and the
    counts of complete rows not yet."""
    path.write_bytes(done.read_bytes())
    with h5py.File(path, "a", locking=False) as f:
        f.attrs["status"] = "running"
        for name in grown:
            ds = f[name]
            ds.resize(ds.shape[0] + rows, axis=0)
            ds[-rows:] = -7.0
    return path


@pytest.mark.parametrize("which", ["some", "all"])
def test_readers_of_a_block_half_written(written, tmp_path, which):
    """Stubbed writer mid-block (the file held as by a running run): some or
    all series (and gauges) grown; Result, info, export --csv and plot read
    the complete rows only, every series as long as /time, values those of
    the completed file."""
    folder, done, _ = written
    kept, gauges = series_names(done)
    grown = kept[::2] + gauges[::2] if which == "some" else kept + gauges
    path = half_written(done, tmp_path / "running.h5", grown)
    lock = OutputLock(str(path))
    lock.existing()                                   # a run holds it
    try:
        ref = Result(done)
        ok, detail = faults.consistent(path)
        assert ok, detail
        r = Result(path)
        assert r.status == "running"
        for name in kept + gauges:
            assert np.array_equal(r[name], ref[name], equal_nan=True), name
        assert np.array_equal(r.read("body/a/u", np.s_[-1, :]), ref.body("a").u[-1])
        assert np.array_equal(r.read("body/a/v", np.s_[[0, -1], 3]), ref.body("a").v[[0, -1], 3])
        with pytest.raises(IndexError):
            r.read("time", ref.time.size)
        for k in range(3):
            ok, detail = faults.command_reads(str(path), k)
            assert ok, detail
        assert set(faults._csv_lengths(f"{path}.csv1").values()) == {ref.time.size + 1}
    finally:
        lock.release()


def test_read_racing_a_write_is_retried(written, tmp_path, monkeypatch):
    """A file of the format before SWMR (a restart continues it without
    SWMR): an HDF5 error while a run holds it (a read that met a write half
    done) is retried; on a file nobody writes it is raised after one more
    read (the run may have let go of the file since the error)."""
    _, done, _ = written
    path = tmp_path / "held.h5"
    with h5py.File(done, "r") as src, h5py.File(path, "w", libver="earliest") as old:
        for name in src:
            src.copy(src[name], old, name)
        old.attrs.update(src.attrs)
    assert not swmr_format(path) and swmr_format(done)
    r = Result(path)
    failures = []
    real_open = Result._open

    def flaky(self):
        if len(failures) < 2:
            failures.append(1)
            raise OSError("Unable to open object (wrong B-tree signature)")
        return real_open(self)

    monkeypatch.setattr(Result, "_open", flaky)
    lock = OutputLock(str(path))
    lock.existing()
    try:
        assert np.array_equal(r.time, Result(done).time) and len(failures) == 2
    finally:
        lock.release()
    failures.clear()
    with pytest.raises(OSError):
        r.time


# a run's last moments on file argv[1]: SWMR writing until a line on stdin,
# then (as ResultWriter.close) closed, opened plainly, the status written,
# and held so for half a second
ENDING_RUN = r"""
import sys, time, h5py
from vstpetsc.results.files import OutputLock
lock = OutputLock(sys.argv[1])
lock.existing()
f = h5py.File(sys.argv[1], "a", libver="latest", locking=False)
f.swmr_mode = True
print("swmr", flush=True)
sys.stdin.readline()
f.close()
f = h5py.File(sys.argv[1], "a", libver="latest", locking=False)
f.attrs["status"] = "completed"
f.flush()
print("plain", flush=True)
time.sleep(0.5)
f.close()
lock.release()
"""


def test_the_end_of_a_run_is_waited_for(written, tmp_path):
    """A run writes its status once its file has left SWMR mode (and a
    restart writes before SWMR starts): HDF5 then refuses to open the file
    ("file is already open for write"), and a Result made in SWMR mode may
    meet stale metadata.  Its reads, a session's too, are retried until
    the run has let go of the file (before: the session's open failed in
    20 of 30 trials of readers across the end of a run)."""
    _, done, _ = written
    path = tmp_path / "ending.h5"
    shutil.copy(done, path)
    with h5py.File(path, "a", locking=False) as f:
        f.attrs["status"] = "running"
    run = subprocess.Popen([sys.executable, "-c", ENDING_RUN, str(path)], text=True,
                           stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    try:
        assert run.stdout.readline().strip() == "swmr"
        r = Result(path)
        assert r._swmr and r.status == "running"
        run.stdin.write("\n")
        run.stdin.flush()
        assert run.stdout.readline().strip() == "plain"
        with r.session():
            assert r.status == "completed"
            assert np.array_equal(r.time, Result(done).time)
    finally:
        run.communicate(timeout=60)
    assert run.returncode == 0


def test_completed_file_counts(written):
    """The writer's counts of complete rows equal the datasets' lengths."""
    _, done, _ = written
    with h5py.File(done, "r", locking=False) as f:
        assert f.attrs[layout.COMPLETE_ROWS] == f["time"].shape[0]
        assert f.attrs[layout.COMPLETE_GAUGE_ROWS] == f["gauge/a-mid/u"].shape[0]


def test_restart_keeps_counts(written, tmp_path):
    """A restart (from a run stopped early) ends with the counts of its
    whole file: the gauges cut back to the last kept slab and grown again."""
    folder, done, case = written
    part = tmp_path / "part.h5"
    short = write_case(tmp_path, faults.long_case(end=0.2, every=10), "part")
    assert cli("run", short, "-o", part, "--quiet").returncode == 0
    p = cli("run", case, "--restart", part, "--quiet")
    assert p.returncode == 0, p.stderr
    with h5py.File(part, "r", locking=False) as f:
        assert f.attrs[layout.COMPLETE_ROWS] == f["time"].shape[0]
        assert f.attrs[layout.COMPLETE_GAUGE_ROWS] == f["gauge/a-mid/u"].shape[0]
    ok, detail = faults.consistent(part)
    assert ok, detail


def made_in_swmr_mode(monkeypatch):
    """[(module, name)] of every dataset, attribute and group made (through
    h5py, high or low level) in a file open for SWMR writing, filled while
    the test runs."""
    made = []
    for module in (h5py.h5d, h5py.h5a, h5py.h5g):
        def spy(loc, name, *args, _real=module.create, _module=module.__name__, **kwargs):
            if h5py.h5i.get_file_id(loc).get_intent() & h5py.h5f.ACC_SWMR_WRITE:
                made.append((_module, name))
            return _real(loc, name, *args, **kwargs)
        monkeypatch.setattr(module, "create", spy)
    return made


def test_nothing_made_in_swmr_mode(tmp_path, monkeypatch):
    """HDF5's SWMR covers a writer growing datasets and writing their data,
    not making objects: blocks that made /solver/rhs_state, newton_state
    and energy_sums turned /solver's links into a fractal heap that a
    reader met half written ("wrong fractal heap header signature", in the
    soak below on a loaded machine).  A run writing a block per kept row,
    and a restart of a file without the restart state (a run killed before
    its first block), make every object before the file goes into SWMR mode;
    the restart state made at the start is stamped -1, so a restart does
    not take it."""
    made = made_in_swmr_mode(monkeypatch)
    out = str(tmp_path / "r.h5")
    fast = ["-vst_flush_interval", "0"]
    vstpetsc.run(faults.long_case(end=0.05, every=10, elements=20), out, fast, quiet=True)
    with h5py.File(out, "a", locking=False) as f:
        assert all(f[name].attrs["slab"] == 50 for name in RESTART)
        for name in RESTART:                           # as a run killed early leaves it
            del f[name]
    vstpetsc.run(faults.long_case(end=0.1, every=10, elements=20), out, fast, quiet=True,
                 restart=True)
    assert made == []
    with h5py.File(out, "r", locking=False) as f:
        assert all(f[name].attrs["slab"] == 100 for name in RESTART)


def test_reads_while_a_run_writes(tmp_path):
    """A soak: 1000 Result reads and info, export --csv, plot of a file a run
    writes a block per kept row into (HDF5's SWMR mode), the other core
    busy: every read a consistent prefix of the final file."""
    ok, detail = faults.read_while_running(str(tmp_path))
    assert ok, detail


# -- item 6: the energy change printed at the end of a run and by info --

def resting_on_cushion(initial):
    """A short bar against a wall through a cushion, gravity pressing it
    there; ``initial`` "static": at rest in the pressed state from t = 0."""
    return make_case(1e-3, 0.3, [bar("ram", (0.0, 0.1), 4, E=1e4, rho=1.0)],
                     contacts=[dict(pair=["ram", "wall"], wall=0.1, formulation="cushion",
                                    stiffness=1.0, restitution=0.7)],
                     gravity={"g": 10.0, "initial": initial})


def energy_lines(tmp_path, case, name):
    """(the run's last line, the energy line of `vstpetsc info`, Result)."""
    last, info, r = run_and_info(tmp_path, case, name)
    return last, [l for l in info.splitlines() if l.startswith("  energy: ")][0], r


def test_pressed_cushion_at_rest_loses_nothing(tmp_path):
    """A body at rest on a pressed cushion (static start under gravity):
    the run's line and info print the energy the bodies and the cushion
    hold at the start and at the end (the same terms, the file's first and
    last rows), equal to rounding (it printed -100 % when the cushion's
    stored energy counted at the start only), no work, nothing
    dissipated."""
    run_line, info_line, r = energy_lines(tmp_path, resting_on_cushion("static"), "pressed")
    e = r.energy
    holds = e["kinetic"] + e["strain"] + e["spring"] + e["contact"]
    assert e["strain"][0] > 0 and r.contact(0).gap[0] < 0          # pressed, holding energy
    e0, e1, work, dissipated = re.search(
        r"energy (\S+) -> (\S+); work in (\S+); dissipated (\S+) by", run_line).groups()
    assert (float(e0), float(e1)) == (float(f"{holds[0]:.6g}"), float(f"{holds[-1]:.6g}"))
    assert float(e1) == pytest.approx(float(e0), rel=1e-6)
    assert abs(float(work)) <= 1e-9 * float(e0) and float(dissipated) == 0.0
    assert info_line == "  energy: " + run_line.split("; energy ")[1].split("; result: ")[0]


@pytest.mark.parametrize("name, case", [
    ("gravity", resting_on_cushion("rest")),
    ("traction", make_case(1e-3, 0.3, [bar("bar", (0.0, 1.0), 10, E=1.0, rho=1.0)],
                           bcs=[dict(body="bar", end="left", type="fixed"),
                                dict(body="bar", end="right", type="traction", value=1.0)]))])
def test_start_with_no_energy_prints_no_nan(tmp_path, name, case):
    """A body at rest loaded by gravity or a traction (initial energy 0):
    no nan; the numerical energy relative to the largest total energy
    (initial + external work) the run reached, from the file."""
    run_line, info_line, r = energy_lines(tmp_path, case, name)
    assert "nan" not in run_line + info_line
    e = r.energy
    peak = np.abs(r.summary()["energy_initial"] + e["external"]).max()
    for line in (run_line, info_line):
        share, reference = re.search(r"\((\S+) % of the largest total energy (\S+)\)",
                                     line).groups()
        assert float(reference) == float(f"{peak:.6g}")
        assert float(share) == float(f"{100 * e['numerical'][-1] / peak:.3g}")


def test_no_energy_at_all(tmp_path):
    """Nothing moves and nothing loads: no share of nothing."""
    run_line, info_line, _ = energy_lines(
        tmp_path, make_case(1e-3, 0.01, [bar("bar", (0.0, 1.0), 4, E=1.0, rho=1.0)]), "still")
    for line in (run_line, info_line):
        assert "nan" not in line and "energy 0 -> 0; work in 0;" in line.replace(":", "") \
            and "(no energy in the run)" in line


def older_format(path):
    """Result file ``path`` rewritten in HDF5's format before SWMR (as
    vstpetsc wrote it before SWMR), every object and attribute kept."""
    new = path.with_suffix(".old.h5")
    with h5py.File(path, "r") as src, h5py.File(new, "w", libver="earliest") as old:
        for name in src:
            src.copy(src[name], old, name)
        old.attrs.update(src.attrs)
    os.replace(new, path)
    assert not swmr_format(path)


def test_a_file_of_the_format_before_swmr_is_continued_without_it(written, tmp_path):
    """--restart of a file of the older format: it goes on without SWMR (its
    format has none), ends equal to the uninterrupted run, stays readable."""
    folder, done, case = written
    part = tmp_path / "part.h5"
    short = write_case(tmp_path, faults.long_case(end=0.2, every=10), "part")
    assert cli("run", short, "-o", part, "--quiet").returncode == 0
    older_format(part)
    p = cli("run", case, "--restart", part, "--quiet")
    assert p.returncode == 0, p.stderr
    assert not swmr_format(part) and Result(part).status == "completed"
    assert faults.same_end(str(part), str(done))
    ok, detail = faults.consistent(part)
    assert ok, detail


def test_a_run_writes_in_swmr_mode_and_a_plain_open_is_refused(written, tmp_path):
    """While a run writes, its file is in SWMR mode: a Result reads it in
    SWMR read mode, HDF5 refuses a plain open; once closed, it opens plainly."""
    _, done, _ = written
    out = tmp_path / "running.h5"
    proc = faults.start(write_case(tmp_path, faults.long_case(end=1e3), "long"), out)
    try:
        assert faults.wait_for(str(out), proc)
        assert swmr_format(out) and Result(out)._swmr
        with pytest.raises(OSError, match="already open for write"):
            h5py.File(out, "r", locking=False)
    finally:
        proc.kill()
        proc.communicate()
    with pytest.raises(OSError, match="already open for write"):     # killed: still marked
        h5py.File(out, "r", locking=False)
    assert Result(out).status == "killed"
    with h5py.File(done, "r", locking=False) as f:                   # closed: a plain open
        assert f.attrs["status"] == "completed"
