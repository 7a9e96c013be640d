"""The reliability catalogue (docs/troubleshooting.md): faults and hostile
input, each with what must happen.  Scenarios live in tests/faults.py;
`make soak` runs them many more times (bench/soak.py, bench/soak.md)."""

import contextlib
import io
import os
import signal
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import faults
from conftest import bar, cli, make_case, write_case
from test_case import GOOD
from vstpetsc import Result
from vstpetsc.input import toml_text
from vstpetsc import cli as vcli


@pytest.fixture(scope="module")
def long(tmp_path_factory):
    """(folder, case file, uninterrupted result) of faults.long_case."""
    folder = tmp_path_factory.mktemp("long")
    case = write_case(folder, faults.long_case(), "long")
    p = cli("run", case, "-o", folder / "full.h5", "--quiet", timeout=300)
    assert p.returncode == 0, p.stderr
    return folder, case, folder / "full.h5"


@pytest.mark.parametrize("delay", [0.0, 0.004, 0.35, 1.2])
def test_sigkill_then_restart(long, delay):
    """SIGKILL at any time: the file (if it has its name) is readable by
    info, plot and Result, and --restart ends bit for bit equal."""
    held, detail = faults.kill_and_restart(*long, delay=delay)
    assert held, detail


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT, signal.SIGUSR1])
def test_stop_signal_then_restart(long, sig):
    folder, case, full = long
    out = folder / f"stopped-{sig}.h5"
    proc = faults.start(case, out)
    assert faults.wait_for(out, proc)
    proc.send_signal(sig)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 128 + sig and faults.one_clean_line(stderr.replace("\r", "")), stderr
    part = Result(out)
    assert part.status == "interrupted" and part.attrs["slabs_done"] == part.solver["slab"][-1]
    ref = Result(full)
    n = part.time.size - 1                     # rows kept before the signal
    assert np.array_equal(part.body("a").u[:n], ref.body("a").u[:n])
    p = cli("run", case, "--restart", out, "--quiet", timeout=300)
    assert p.returncode == 0, p.stderr
    assert Result(out).attrs["restarts"] == 1 and faults.same_end(out, full)


def test_concurrent_runs_on_one_file(long):
    held, detail = faults.concurrent_runs(*long)
    assert held, detail


def test_two_runs_started_together(long):
    held, detail = faults.simultaneous_runs(*long)
    assert held, detail


@pytest.mark.skipif(os.geteuid() != 0, reason="mounting a small tmpfs needs root")
def test_disk_full(long):
    held, detail = faults.disk_full(*long, size_kb=2500)
    assert held, detail


def test_output_is_the_case_file(tmp_path):
    case = write_case(tmp_path, faults.long_case(end=0.1))
    before = case.read_text()
    p = cli("run", case, "-o", case)
    assert p.returncode == 2 and faults.one_clean_line(p.stderr) and "input file" in p.stderr
    doc = faults.long_case(end=0.1).to_dict()
    doc["output"]["path"] = "case.toml"
    (tmp_path / "other.toml").write_text(toml_text.dumps(doc))
    p = cli("run", tmp_path / "other.toml")            # another case file: not a result
    assert p.returncode == 2 and faults.one_clean_line(p.stderr) and "not a vstpetsc" in p.stderr
    (tmp_path / "self.toml").write_text(toml_text.dumps(
        {**doc, "output": {"path": "self.toml"}}))
    p = cli("run", tmp_path / "self.toml")
    assert p.returncode == 2 and "input file" in p.stderr
    assert case.read_text() == before


@pytest.mark.parametrize("output,message", [
    ("/proc/x.h5", "cannot create"), ("/nonexistent/r.h5", "does not exist"),
    ("{tmp}", "is a folder"), ("{tmp}/a\\u0001b.h5", "control character")])
def test_unusable_output_paths(tmp_path, output, message):
    doc = faults.long_case(end=0.1).to_dict()
    doc["output"]["path"] = output.replace("{tmp}", str(tmp_path))
    (tmp_path / "c.toml").write_text(toml_text.dumps(doc).replace(
        "\\\\u0001", "\\u0001"))
    p = cli("run", tmp_path / "c.toml")
    assert p.returncode == 2 and faults.one_clean_line(p.stderr) and message in p.stderr, p.stderr
    assert sorted(os.listdir(tmp_path)) == ["c.toml"]


@pytest.mark.parametrize("name", [".", "..", "x/y", "a\u0000b", "a b", ""])
def test_names_that_cannot_be_group_names(tmp_path, name):
    case = make_case(0.1, 1.0, [bar("ok", (0.0, 1.0), 2)]).to_dict()
    case["body"].append({**case["body"][0], "name": name, "x": [2.0, 3.0]})
    path = tmp_path / "c.toml"
    path.write_text(toml_text.dumps(case))
    p = cli("run", path)
    assert p.returncode == 2 and faults.one_clean_line(p.stderr) and "body[1]" in p.stderr


def test_restart_refuses_another_case_or_sampling(tmp_path):
    case = tmp_path / "case.toml"
    text = make_case(0.01, 0.5, [bar("a", (0.0, 1.0), 20, E=1.0, rho=1.0, v0=1.0)]).to_toml()
    case.write_text(text)
    out = tmp_path / "r.h5"
    assert cli("run", case, "-o", out, "--quiet").returncode == 0
    p = cli("run", case, "--restart", out)
    assert p.returncode == 2 and "already reaches slab 50" in p.stderr
    case.write_text(text.replace("end = 0.5", "end = 0.8"))       # only end: allowed
    p = cli("run", case, "--restart", out, "--every", "2")
    assert p.returncode == 2 and "every 1" in p.stderr and faults.one_clean_line(p.stderr)
    assert cli("run", case, "--restart", out, "--quiet").returncode == 0
    assert Result(out).time[-1] == pytest.approx(0.8)
    case.write_text(text.replace("end = 0.5", "end = 0.9").replace("E = 1.0", "E = 2.0"))
    p = cli("run", case, "--restart", out)
    assert p.returncode == 2 and "differs" in p.stderr and faults.one_clean_line(p.stderr)
    p = cli("run", case, "--restart", tmp_path / "none.h5")
    assert p.returncode == 2 and "no such file" in p.stderr


@pytest.mark.parametrize("edit,message", [
    (lambda d: d["time"].update(dt=5e-324, end=1e-322), "time.dt: must lie in"),
    (lambda d: d["body"][0].update(u0=[[0.0, 0.0], [1.0, 0.1]]), "overlap by 0.05"),
    (lambda d: d["body"][0].update(elemnts=3), "did you mean 'elements'"),
])
def test_hostile_values(tmp_path, edit, message):
    doc = faults.long_case(end=0.1).to_dict()
    edit(doc)
    path = tmp_path / "c.toml"
    path.write_text(toml_text.dumps(doc))
    p = cli("run", path)
    assert p.returncode == 2 and faults.one_clean_line(p.stderr) and message in p.stderr, p.stderr


HOSTILE = {"binary": "\x00\x01binary", "many tables": "[time]\n" + "[a]\n" * 5000,
           "deep nesting": "a = " + "[" * 500 + "]" * 500,
           "20000 bodies": "[[body]]\nname = \"b\"\n" * 20000, "BOM": "\ufeff[time]\ndt = 1\n"}


@pytest.mark.parametrize("text", HOSTILE.values(), ids=HOSTILE.keys())
def test_hostile_files(tmp_path, text):
    path = tmp_path / "c.toml"
    path.write_text(text)
    p = cli("run", path)
    assert p.returncode == 2 and "Traceback" not in p.stderr and p.stderr.startswith("vstpetsc:")


def test_linear_solver_failures_name_where(tmp_path):
    case = write_case(tmp_path, faults.long_case(end=0.1))
    p = cli("run", case, "-o", tmp_path / "r.h5", "-ksp_type", "gmres", "-pc_type", "jacobi",
            "-ksp_max_it", "1")
    assert p.returncode == 2 and faults.one_clean_line(p.stderr) and "set-up" in p.stderr
    assert not (tmp_path / "r.h5").exists()
    free = faults.long_case(end=0.1).to_dict()
    del free["contact"]
    (tmp_path / "free.toml").write_text(toml_text.dumps(free))
    p = cli("run", tmp_path / "free.toml", "-o", tmp_path / "f.h5", "-ksp_type", "gmres",
            "-pc_type", "jacobi", "-ksp_max_it", "1")
    assert p.returncode == 3 and faults.one_clean_line(p.stderr) and "slab 1:" in p.stderr
    assert Result(tmp_path / "f.h5").status == "failed"


def test_help_and_version():
    for args in (["run", "--help"], ["info", "-h"], ["--help"], ["--version"]):
        p = cli(*args)
        assert p.returncode == 0 and p.stdout and not p.stderr, args


@pytest.mark.skipif(subprocess.run(["which", "mpirun"], capture_output=True).returncode,
                    reason="no mpirun")
@pytest.mark.parametrize("sig,code", [(signal.SIGUSR1, 138), (signal.SIGTERM, None)])
def test_signals_under_mpirun(long, sig, code):
    """SIGUSR1 reaches every rank through mpirun: exit 138, file interrupted.
    SIGTERM is Open MPI's: mpirun exits 1 and kills the ranks a second later;
    the file still holds every block written before and restarts."""
    folder, case, full = long
    out = folder / f"mpi-{sig}.h5"
    proc = faults.start(case, out, mpi=2)
    assert faults.wait_for(out, proc)
    proc.send_signal(sig)
    proc.communicate(timeout=60)
    if code is not None:
        assert proc.returncode == code and Result(out).status == "interrupted"
    assert Result(out).status in ("interrupted", "killed")
    assert faults.readable(out)[0]
    p = cli("run", case, "--restart", out, "--quiet", timeout=300)
    assert p.returncode == 0, p.stderr
    assert faults.same_end(out, full)


MUTATIONS = st.one_of(
    st.integers(-10**15, 10**15), st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=8), st.booleans(), st.lists(st.floats(-10, 10), max_size=3),
    st.lists(st.lists(st.floats(-1, 1), max_size=3), max_size=3),
    st.sampled_from(["wall", "a", "b", "left", "right", "fixed", "seed", "power", "[[0, 1]]"]))


def _toml_value(v):
    import json
    if isinstance(v, float) and not np.isfinite(v):
        return "nan" if np.isnan(v) else ("inf" if v > 0 else "-inf")
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return json.dumps(v)


LINES = [i for i, line in enumerate(GOOD.splitlines()) if " = " in line]


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.sampled_from(LINES), MUTATIONS), min_size=1, max_size=3),
       st.booleans())
def test_fuzzed_cases_give_exit_0_or_2_with_messages(tmp_path_factory, edits, drop):
    lines = GOOD.splitlines()
    for i, value in edits:
        key = lines[i].split(" = ")[0]
        lines[i] = "" if drop else f"{key} = {_toml_value(value)}"
    path = tmp_path_factory.mktemp("fuzz") / "case.toml"
    path.write_text("\n".join(lines) + "\n")
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        rc = vcli.main(["run", str(path), "--dry-run"])      # any exception fails the test
    assert rc in (0, 2)
    if rc == 2:
        msgs = err.getvalue().strip().splitlines()
        assert msgs and all(m.startswith("vstpetsc: error: ") and ": " in m[17:] for m in msgs)


def test_restart_of_a_file_from_another_version_is_refused(tmp_path):
    """A file without a dataset this version writes (here energy/transferred,
    new in 0.2) cannot be continued: one line, exit 2, the file untouched."""
    import h5py
    case = write_case(tmp_path, faults.long_case(end=0.1), "short")
    out = tmp_path / "old.h5"
    assert cli("run", case, "-o", out, "--quiet").returncode == 0
    with h5py.File(out, "a") as f:
        del f["energy/transferred"]
    before = out.read_bytes()
    p = cli("run", case, "--restart", out, "--quiet")
    assert p.returncode == 2 and p.stderr.count("\n") == 1, p.stderr
    assert "has no energy/transferred" in p.stderr and out.read_bytes() == before


INJECTED_FAILURE = """
import sys
from vstpetsc import cli
from vstpetsc.results import writer

calls = []
append = writer._append


def failing(*args):
    calls.append(1)
    if len(calls) > {after}:
        raise OSError("injected write error")
    return append(*args)


writer._append = failing
sys.exit(cli.main(sys.argv[1:]))
"""


def test_a_block_failing_on_the_writer_thread(tmp_path):
    """An HDF5 error while a block is written on the thread
    (results/blocks.py): one line naming the last slab the file keeps,
    exit 3, and the file holds every slab up to it."""
    case = write_case(tmp_path, make_case(0.01, 0.6, [bar("a", (0.0, 1.0), 10, v0=1.0)]))
    out = tmp_path / "r.h5"
    script = tmp_path / "failing.py"
    script.write_text(INJECTED_FAILURE.format(after=200))
    p = subprocess.run([sys.executable, str(script), "run", str(case), "-o", str(out),
                        "--quiet", "-vst_flush_interval", "0"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 3 and faults.one_clean_line(p.stderr), p.stderr
    assert "injected write error" in p.stderr
    kept = int(p.stderr.split("up to slab ")[1].split()[0])
    r = Result(out)
    assert 0 < kept < 60 and int(r.solver["slab"][-1]) == kept and r.time.size == kept + 1
    assert r.status == "killed"     # HDF5 failed: left unclosed, read as after a kill


def test_a_file_that_cannot_be_created_leaves_no_writer_thread(tmp_path, monkeypatch):
    """The first block is written on the writer's thread; when the file
    then cannot be published, the run stops with InputError, nothing is
    left under the name, and the thread ends with the file."""
    import threading

    from vstpetsc import InputError, run
    from vstpetsc.results import files

    def refuse(self, fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(files.OutputLock, "publish", refuse)
    out = tmp_path / "r.h5"
    with pytest.raises(InputError, match="cannot create"):
        run(make_case(0.01, 0.1, [bar("a", (0.0, 1.0), 10, v0=1.0)]), out, quiet=True)
    assert not out.exists()
    assert not [t for t in threading.enumerate() if t.name == "vstpetsc-block"]
