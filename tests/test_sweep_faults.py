"""Sweep faults (issue 25): a history file edited between two sweeps, a
misspelled --set key, a folder that cannot be one, two sweeps into one
folder (and the lock file gone when a sweep ends), an error on one rank of
an mpirun sweep, empty summaries to plot."""

import fcntl
import os
import shutil
import sys

import pytest

import faults
import vstpetsc
from conftest import bar, cli, make_case, write_case
from test_parallel import mpirun as parallel_mpirun
from test_sweep import wall_case
from vstpetsc.runner import sweep_folder
from vstpetsc.errors import InputError
from vstpetsc.runner.sweep import quantities, read_summary
from vstpetsc.runner.sweep_folder import LOCK

needs_mpirun = pytest.mark.skipif(shutil.which("mpirun") is None, reason="no mpirun")


def mpirun(*args, timeout=90, **kw):
    """mpirun -n 2 (test_parallel's) with a shorter limit: a hang fails the
    test (TimeoutExpired) instead of blocking the suite."""
    return parallel_mpirun(*args, timeout=timeout, **kw)


def ours(p):
    """vstpetsc's lines on stderr (mpirun adds its own), no traceback."""
    assert "Traceback" not in p.stderr, p.stderr
    return [line for line in p.stderr.splitlines() if line.startswith("vstpetsc:")]


def one_line(p, code, words):
    return (p.returncode == code and faults.one_clean_line(p.stderr.replace("\r", ""))
            and words in p.stderr)


def pushed_case(folder):
    """A bar at rest pushed onto a wall by a traction read from push.csv."""
    (folder / "push.csv").write_text("t,f\n0.0,0.0\n0.5,0.2\n1.5,0.0\n")
    return make_case(0.01, 1.5, [bar("bar", (0.0, 1.0), 20, E=1.0, rho=1.0)],
                     contacts=[dict(pair=["bar", "wall"], wall=1.0, formulation="power")],
                     bcs=[dict(body="bar", end="left", type="traction",
                               value={"file": "push.csv", "column": "f"})],
                     folder=folder)


def test_an_edited_history_file_is_run_again(tmp_path):
    """The case text is unchanged but the CSV it reads is multiplied by 10:
    the runs are made again and the rows are the new case's."""
    case = pushed_case(tmp_path)
    settings = {"body.bar.E": [1.0, 2.0]}
    before = vstpetsc.sweep(case, settings, str(tmp_path / "s"))
    stamps = [os.stat(tmp_path / "s" / r["file"]).st_mtime_ns for r in before]
    same = vstpetsc.sweep(case, settings, str(tmp_path / "s"))
    assert stamps == [os.stat(tmp_path / "s" / r["file"]).st_mtime_ns for r in same]
    (tmp_path / "push.csv").write_text("t,f\n0.0,0.0\n0.5,2.0\n1.5,0.0\n")
    edited = vstpetsc.Case.from_text(case.to_toml(), folder=str(tmp_path))
    assert edited == case                           # the same text
    after = vstpetsc.sweep(edited, settings, str(tmp_path / "s"))
    for old, new in zip(before, after):
        direct = vstpetsc.run(edited.with_value("body.bar.E", new["body.bar.E"]),
                              output=str(tmp_path / "direct.h5"), quiet=True)
        assert {k: new[k] for k in quantities(direct)} == quantities(direct)
        assert new["force_peak_0"] > 0 and new["force_peak_0"] != old["force_peak_0"]
    _, data = read_summary(str(tmp_path / "s" / "summary.csv"))
    assert data["force_peak_0"] == [r["force_peak_0"] for r in after]
    assert edited.input_digests != case.input_digests


def test_misspelled_set_key_is_refused_up_front(tmp_path):
    case_file = write_case(tmp_path, wall_case())
    p = cli("sweep", case_file, "--set", "body.bar.vv0=1,2", "-o", tmp_path / "s")
    assert one_line(p, 2, "body.bar.vv0: unknown key (did you mean 'v0'?"), p.stderr
    assert not (tmp_path / "s").exists()
    case = wall_case()
    for path, words in (("body.bar.vv0", "body.bar.vv0: unknown key (did you mean 'v0'?"),
                        ("body.bar.damping.alpah", "unknown key (did you mean 'alpha'?"),
                        ("body.bar.dampin.alpha", "unknown key 'dampin' (did you mean 'damping'?"),
                        ("tme.dt", "tme.dt: unknown key 'tme' (did you mean 'time'?"),
                        ("contact.0.penalti", "unknown key (did you mean 'penalty'?")):
        for call in (lambda: case.check_path(path), lambda: case.with_value(path, 1.0),
                     lambda: vstpetsc.sweep(case, {path: [1.0]}, str(tmp_path / "api"))):
            with pytest.raises(vstpetsc.CaseError) as err:
                call()
            assert len(err.value.problems) == 1 and words in err.value.problems[0], path
    assert not (tmp_path / "api").exists()
    # keys a table allows but the case does not give are paths
    for path in ("body.bar.area", "contact.0.penalty", "body.bar.damping.alpha",
                 "contact.0.formulation", "output.every"):
        case.check_path(path)


def test_plane_tables_are_reached_by_name(tmp_path):
    """A 2-D case's [[interface]] and [[water]] by name or index, as
    [[region]] and [[boundary]]: a friction or a water level sweeps (they
    were "not a table"); a name the case has not, a misspelled key, or a
    [[water]] in a case without one: one line, exit 2, nothing run."""
    from vstpetsc import bundled

    dam = vstpetsc.Case.from_toml(bundled.path("gravity-dam-reservoir"))
    assert dam.with_value("interface.contact.friction", 0.45).plane.interfaces[0].friction == 0.45
    assert dam.with_value("interface.0.friction", 0.5).plane.interfaces[0].friction == 0.5
    assert dam.with_value("water.reservoir.level", 30.0).plane.waters[0].level == 30.0
    for path in ("interface.contact.penalty", "water.0.uplift", "region.dam.E"):
        dam.check_path(path)
    dry = tmp_path / "dry.toml"
    assert cli("example", "gravity-dam", "-o", dry).returncode == 0
    for path, words in (("interface.base.friction", "no interface with name or index 'base'"),
                        ("interface.contact.frction", "unknown key (did you mean 'friction'?"),
                        ("water.0.level", "water.0.level: water is not a table")):
        p = cli("sweep", dry, "--set", f"{path}=0.5,0.6", "-o", tmp_path / "s")
        assert one_line(p, 2, words), (path, p.stderr)
        assert not (tmp_path / "s").exists()


def test_output_that_cannot_be_a_folder(tmp_path):
    case = write_case(tmp_path, wall_case())
    taken = tmp_path / "taken"
    taken.write_text("mine\n")
    for out, words in ((taken, "exists and is not a folder"),
                       (taken / "below", "cannot write there"),
                       ("/proc/vstpetsc-sweep", "cannot write there")):
        p = cli("sweep", case, "--set", "body.bar.v0=1,2", "-o", out)
        assert one_line(p, 2, f"-o {out}: {words}"), p.stderr
    assert taken.read_text() == "mine\n"


def test_summary_that_cannot_be_written_fails_with_one_line(tmp_path):
    case = write_case(tmp_path, wall_case())
    (tmp_path / "s" / "summary.csv").mkdir(parents=True)
    p = cli("sweep", case, "--set", "body.bar.v0=1,2", "-o", tmp_path / "s")
    assert one_line(p, 3, "summary.csv (Is a directory); the runs' files are kept"), p.stderr
    assert [vstpetsc.Result(tmp_path / "s" / f"run-{i}.h5").status for i in (0, 1)] == \
        ["completed"] * 2
    assert LOCK not in os.listdir(tmp_path / "s")


def test_the_lock_file_goes_when_a_sweep_ends(tmp_path, monkeypatch):
    """Completed, or stopped by an error in a run: no .sweep.lock left."""
    out = tmp_path / "s"
    rows = vstpetsc.sweep(wall_case(), {"body.bar.v0": [1.0, 2.0]}, str(out))
    assert [r["status"] for r in rows] == ["completed"] * 2
    assert sorted(os.listdir(out)) == ["run-0.h5", "run-1.h5", "summary.csv"]

    def broken(*args):
        raise RuntimeError("disk gone")
    monkeypatch.setattr(sys.modules["vstpetsc.runner.sweep"], "run_one", broken)
    with pytest.raises(RuntimeError, match="disk gone"):
        vstpetsc.sweep(wall_case(), {"body.bar.v0": [4.0]}, str(tmp_path / "t"))
    assert os.listdir(tmp_path / "t") == []


def test_a_sweep_that_opened_a_removed_lock_file_takes_the_new_one(tmp_path, monkeypatch):
    """Sweep B opens the lock file, sweep A ends (removes it, drops its
    lock), sweep C makes a new one and holds it: B's lock on the removed
    file would let B and C write into the folder together, so B checks
    the file it locked is the folder's, opens the new one and is refused;
    once C has ended too, B takes the folder with the file it holds."""
    folder = str(tmp_path / "s")
    path = os.path.join(folder, LOCK)
    first = sweep_folder.take(folder)
    opened = os.open(path, os.O_RDWR)                  # B, before A ends
    sweep_folder.release(folder, first)
    assert not os.path.exists(path)
    third = sweep_folder.take(folder)
    real_open = sweep_folder._open
    given = []

    def open_once_stale(folder_, path_):
        fd = os.dup(opened) if not given else real_open(folder_, path_)
        given.append(fd)
        return fd
    monkeypatch.setattr(sweep_folder, "_open", open_once_stale)
    with pytest.raises(InputError, match="being used by another sweep"):
        sweep_folder.take(folder)
    assert len(given) == 2                              # the removed file, then the new one
    sweep_folder.release(folder, third)
    given.clear()
    fd = sweep_folder.take(folder)
    assert len(given) == 2 and os.fstat(fd).st_ino == os.stat(path).st_ino
    sweep_folder.release(folder, fd)
    os.close(opened)
    assert os.listdir(folder) == []


def test_two_sweeps_into_one_folder(tmp_path):
    """A sweep holding the folder: a second one is refused before it
    touches anything; the first's runs are all completed and so labelled."""
    case = write_case(tmp_path, faults.long_case(end=8.0), "long")
    held, detail = faults.simultaneous_sweeps(str(tmp_path), case, delay=0.0)
    assert held and "refused" in detail, detail
    held, detail = faults.simultaneous_sweeps(str(tmp_path), case, delay=0.3)
    assert held, detail


def test_held_folder_refused_with_one_line(tmp_path):
    case = write_case(tmp_path, wall_case())
    out = tmp_path / "s"
    out.mkdir()
    with open(out / LOCK, "w") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        p = cli("sweep", case, "--set", "body.bar.v0=1,2", "-o", out)
    assert one_line(p, 2, f"-o {out}: the folder is being used by another sweep"), p.stderr
    assert sorted(os.listdir(out)) == [LOCK]


@needs_mpirun
def test_mpirun_sweep_errors_end_every_rank(tmp_path):
    """An existing file as -o, a folder held by another sweep (seen by
    rank 0 only): both ranks stop, one line, exit 2 (no rank left waiting)."""
    case = write_case(tmp_path, wall_case())
    taken = tmp_path / "taken"
    taken.write_text("mine\n")
    p = mpirun("sweep", case, "--set", "body.bar.v0=1,2", "-o", taken)
    assert p.returncode == 2 and ours(p) == [f"vstpetsc: error: -o {taken}: exists and is "
                                             "not a folder"], p.stderr
    out = tmp_path / "s"
    out.mkdir()
    with open(out / LOCK, "w") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        p = mpirun("sweep", case, "--set", "body.bar.v0=1,2", "-o", out)
    assert p.returncode == 2 and ours(p) == [f"vstpetsc: error: -o {out}: the folder is being "
                                             "used by another sweep; nothing was changed"], p.stderr


@needs_mpirun
def test_mpirun_sweep_error_in_one_ranks_run_ends_every_rank(tmp_path):
    """An unexpected error in rank 1's run: rank 0 stops too, naming it."""
    script = tmp_path / "script.py"
    script.write_text(
        "import sys, vstpetsc\n"
        "from vstpetsc import petsc\n"
        "sw = sys.modules['vstpetsc.runner.sweep']    # vstpetsc.sweep is the function\n"
        "real = sw.run_one\n"
        "def broken(*args):\n"
        "    if petsc.rank() == 1:\n"
        "        raise RuntimeError('disk gone')\n"
        "    return real(*args)\n"
        "sw.run_one = broken\n"
        "case = vstpetsc.Case.from_toml(sys.argv[1])\n"
        "try:\n"
        "    vstpetsc.sweep(case, {'body.bar.v0': [1, 2]}, sys.argv[2])\n"
        "except Exception as exc:\n"
        "    with open(f'{sys.argv[2]}.{petsc.rank()}', 'w') as f:   # lines would interleave\n"
        "        f.write(f'{type(exc).__name__}: {exc}')\n")
    p = mpirun(script, write_case(tmp_path, wall_case()), tmp_path / "s",
               program=sys.executable)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "s.0").read_text() == \
        "SolveFailed: sweep stopped: rank 1: RuntimeError: disk gone"
    assert (tmp_path / "s.1").read_text() == "RuntimeError: disk gone"


@pytest.mark.parametrize("text, words", [("", "not a sweep summary"),
                                         ("x,file,status,wall_time,message\n", "holds no runs")])
def test_plot_of_an_empty_summary(tmp_path, text, words):
    summary = tmp_path / "summary.csv"
    summary.write_text(text)
    p = cli("plot", summary)
    assert one_line(p, 2, f"{summary}: {words}"), p.stderr


def test_plot_of_a_column_of_words(tmp_path):
    case = write_case(tmp_path, wall_case())
    out = tmp_path / "s"
    p = cli("sweep", case, "--set", "contact.0.formulation=seed,power", "-o", out, "--quiet")
    assert p.returncode == 0, p.stderr
    p = cli("plot", out / "summary.csv")
    assert one_line(p, 2, "--x contact.0.formulation: a column of numbers is needed, got 'seed'")
