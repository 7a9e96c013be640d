"""Interrupted, killed and restarted runs; fuzzed case files."""

import contextlib
import io
import os
import signal
import subprocess
import time

import h5py
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import VSTPETSC, bar, cli, make_case
from test_case import GOOD
from vstpetsc import Result
from vstpetsc import cli as vcli


def long_case(every=3):
    """Two bars with contact, a few seconds of slabs (TOML text)."""
    return make_case(0.002, 6.0, [bar("a", (0.0, 1.0), 300, E=1.0, rho=1.0, v0=1.0),
                                  bar("b", (1.05, 2.05), 300, E=2.0, rho=1.0)],
                     contacts=[dict(pair=["a", "b"], formulation="power")],
                     bcs=[dict(body="b", end="right", type="fixed")], every=every).to_toml()


def start_and_wait(case, out, min_rows_bytes=200_000, timeout=60):
    """Start a run and return once its time loop has run for a while.  The
    first row allocates whole HDF5 chunks, so the file's size says only
    that the loop started; half a second more is some hundred slabs of the
    ~9 s run (HDF5 locks the file, so it cannot be read meanwhile)."""
    proc = subprocess.Popen([VSTPETSC, "run", case, "-o", out, "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    t0 = time.time()
    while time.time() - t0 < timeout:
        if os.path.exists(out) and os.path.getsize(out) > min_rows_bytes:
            time.sleep(0.5)
            if proc.poll() is not None:
                raise AssertionError(f"run ended early: {proc.stderr.read()}")
            return proc
        if proc.poll() is not None:
            raise AssertionError(f"run ended early: {proc.stderr.read()}")
        time.sleep(0.05)
    proc.kill()
    raise AssertionError("the run did not start writing in time")


@pytest.mark.parametrize("sig,code", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_interrupt_then_restart_equals_uninterrupted(tmp_path, sig, code):
    case = tmp_path / "case.toml"
    case.write_text(long_case())
    full = cli("run", case, "-o", tmp_path / "full.h5", "--quiet", timeout=300)
    assert full.returncode == 0, full.stderr
    out = tmp_path / "part.h5"
    proc = start_and_wait(case, out)
    proc.send_signal(sig)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == code, stderr
    assert "Traceback" not in stderr and len(stderr.strip().splitlines()) == 1
    part = Result(out)
    assert part.status == "interrupted"
    ref = Result(tmp_path / "full.h5")
    k = int(part.solver["slab"][-1])
    assert 0 < k < 3000
    # every row kept before the signal is the uninterrupted run's
    n = part.time.size - 1
    assert np.array_equal(part.body("a").u[:n], ref.body("a").u[:n])
    p = cli("run", case, "--restart", out, "--quiet", timeout=300)
    assert p.returncode == 0, p.stderr
    done = Result(out)
    assert done.status == "completed" and done.attrs["restarts"] == 1
    for key in ("body/a/u", "body/a/v", "body/b/u", "body/b/v", "contact/0/impulse_total",
                "contact/0/episodes", "energy/kinetic"):
        assert np.array_equal(done[key][-1], ref[key][-1]), key
    assert done.time[-1] == ref.time[-1]


def test_sigkill_leaves_a_readable_unfinished_file(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(long_case(every=1))
    out = tmp_path / "killed.h5"
    proc = start_and_wait(case, out)
    proc.kill()
    proc.wait(timeout=30)
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] != "completed"
        n = f["time"].shape[0]
        assert n > 1 and f["body/a/u"].shape[0] >= n - 1
    # and the run continues from the last complete row
    p = cli("run", case, "--restart", out, "--quiet", timeout=300)
    assert p.returncode == 0, p.stderr
    assert Result(out).status == "completed"


def test_restart_refuses_a_different_case(tmp_path):
    case = tmp_path / "case.toml"
    text = make_case(0.01, 0.5, [bar("a", (0.0, 1.0), 20, E=1.0, rho=1.0, v0=1.0)]).to_toml()
    case.write_text(text)
    out = tmp_path / "r.h5"
    assert cli("run", case, "-o", out, "--quiet").returncode == 0
    p = cli("run", case, "--restart", out)
    assert p.returncode == 2 and "already reaches slab 50" in p.stderr
    case.write_text(text.replace("end = 0.5", "end = 0.8"))       # only end: allowed
    assert cli("run", case, "--restart", out, "--quiet").returncode == 0
    assert Result(out).time[-1] == pytest.approx(0.8)
    case.write_text(text.replace("end = 0.5", "end = 0.9").replace("E = 1.0", "E = 2.0"))
    p = cli("run", case, "--restart", out)
    assert p.returncode == 2 and "differs" in p.stderr and "Traceback" not in p.stderr
    p = cli("run", case, "--restart", tmp_path / "none.h5")
    assert p.returncode == 2 and "no such file" in p.stderr


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


LINES = [i for i, l in enumerate(GOOD.splitlines()) if " = " in l]


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
