"""Fault scenarios for the reliability catalogue: tests/test_reliability.py
runs each once (the suite), bench/soak.py many times (`make soak`).

Every scenario returns (held, detail): held is True when vstpetsc behaved
as docs/troubleshooting.md says, detail says what happened.
"""

import os
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

import vstpetsc
import vstpetsc.input.toml_text
from vstpetsc.results.files import held

VSTPETSC = os.path.join(os.path.dirname(sys.executable), "vstpetsc")
MPI_ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1",
               OMPI_MCA_btl_vader_single_copy_mechanism="none")
COMPARED = ("body/a/u", "body/a/v", "body/b/u", "body/b/v", "contact/0/impulse_total",
            "contact/0/episodes", "energy/kinetic", "energy/numerical")
ENVELOPES = ("body/a/stress_min", "body/a/stress_max", "body/b/stress_max")
# every slab (whatever `every` is): equal over the whole run after a restart
GAUGES = ("gauge/a-mid/u", "gauge/a-mid/stress", "gauge/b-left/v", "gauge/b-left/strain")
# written with the blocks: equal over the whole run after a restart
EVENTS = ("contact/0/events",)


def long_case(every=40, end=24.0, elements=1000):
    """Two bars in contact, the far end fixed: 24 000 slabs of 2000
    elements, about two seconds of running (long enough to be stopped at
    any moment, also as the solver gets faster)."""
    bar = lambda name, x, **kw: {"name": name, "x": x, "elements": elements, "E": 1.0, "rho": 1.0,
                                 **kw}
    return vstpetsc.Case.from_dict({
        "time": {"dt": 0.001, "end": end}, "output": {"every": every},
        "body": [bar("a", [0.0, 1.0], v0=1.0), bar("b", [1.05, 2.05], E=2.0)],
        "contact": [{"pair": ["a", "b"], "formulation": "power"}],
        "bc": [{"body": "b", "end": "right", "type": "fixed"}],
        "gauge": [{"name": "a-mid", "body": "a", "x": 0.5003},
                  {"name": "b-left", "body": "b", "x": 1.05}]})


def cli(*args, timeout=300, env=None):
    return subprocess.run([VSTPETSC, *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, env=env)


def start(case, out, *args, mpi=0):
    command = ([VSTPETSC] if not mpi else ["mpirun", "-n", str(mpi), VSTPETSC])
    return subprocess.Popen(command + ["run", str(case), "-o", str(out), "--quiet", *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=MPI_ENV if mpi else None)


def wait_for(path, proc, timeout=60):
    """Wait until ``path`` exists (False if the run ended first)."""
    t0 = time.time()
    while not os.path.exists(path):
        if proc.poll() is not None or time.time() - t0 > timeout:
            return False
        time.sleep(0.002)
    return True


def one_clean_line(stderr):
    lines = stderr.strip().splitlines()
    return len(lines) == 1 and "Traceback" not in stderr and lines[0].startswith("vstpetsc:")


def readable(out):
    """(ok, detail): info, plot and the Result reader take the file."""
    p = cli("info", out)
    if p.returncode != 0:
        return False, f"info: {p.stderr.strip()}"
    p = cli("plot", out, "-o", str(out) + ".png")
    if p.returncode != 0:
        return False, f"plot: {p.stderr.strip()}"
    r = vstpetsc.Result(out)
    if r.time.size < 1 or r.body("a").u.shape[0] != r.time.size:
        return False, f"{r.time.size} times, u has {r.body('a').u.shape[0]} rows"
    last = int(r.solver["slab"][-1])
    if r.gauges and r.gauge("a-mid").u.size < last + 1:
        return False, f"the gauges stop before the last kept slab {last}"
    return True, f"{r.time.size} rows, status {r.status}"


def same_end(out, reference):
    """Whether the last rows (and the envelopes) of two result files are
    equal bit for bit."""
    with h5py.File(out, "r", locking=False) as a, h5py.File(reference, "r", locking=False) as b:
        if a["time"][-1] != b["time"][-1]:
            return False
        return (all(np.array_equal(a[key][-1], b[key][-1]) for key in COMPARED)
                and all(np.array_equal(a[key], b[key]) for key in ENVELOPES + GAUGES + EVENTS))


def kill_and_restart(folder, case, reference, delay, sig=signal.SIGKILL, extra=()):
    """Stop a run ``delay`` seconds after its file appeared, then check the
    file and continue it; held if the restart ends equal to ``reference``."""
    out = os.path.join(folder, f"killed-{sig}-{delay:.3f}.h5")
    proc = start(case, out, "-vst_flush_interval", "0.1", *extra)
    appeared = wait_for(out, proc)
    time.sleep(delay)
    proc.send_signal(sig)
    _, stderr = proc.communicate(timeout=60)
    if not appeared and not os.path.exists(out):
        return True, "killed before the file had its name (nothing to check)"
    ok, detail = readable(out)
    if not ok:
        return False, detail
    if sig != signal.SIGKILL and proc.returncode not in (0, 128 + sig):
        return False, f"exit {proc.returncode}: {stderr.strip()}"
    p = cli("run", case, "--restart", out, "--quiet")
    if vstpetsc.Result(out).status == "completed" and p.returncode == 2:
        pass                                  # it had finished before the signal
    elif p.returncode != 0:
        return False, f"restart exit {p.returncode}: {p.stderr.strip()}"
    if not same_end(out, reference):
        return False, "restarted run differs from the uninterrupted one"
    return True, f"{detail}; restart equal bit for bit"


def concurrent_runs(folder, case, reference, tries=3):
    """A second run (new, then --restart) on a file being written.  The
    first run writes a block per kept row (``-vst_flush_interval 0``: the
    same file, written more slowly) so that it is still writing when the
    others have started; a trial in which it ended before them tests
    nothing and is repeated (3 processes on 2 cores: the others' start-up
    took over a second in ``make soak``)."""
    for trial in range(tries):
        outcome = _concurrent_trial(os.path.join(folder, f"busy-{trial}.h5"), case, reference)
        if outcome is not None:
            held_, detail = outcome
            return held_, detail + (f" (trial {trial + 1})" if trial else "")
    return False, f"the first run ended before the others in all {tries} trials"


def _concurrent_trial(out, case, reference):
    """(held, detail) of one trial of :func:`concurrent_runs`; None when
    the first run had ended before the others did."""
    first = start(case, out, "-vst_flush_interval", "0")
    t0 = time.time()
    while not held(out):             # the first run has taken the file
        if first.poll() is not None or time.time() - t0 > 60:
            return False, "the first run did not start"
        time.sleep(0.002)
    # both at once, while the first run is still writing
    others = [start(case, out), subprocess.Popen(
        [VSTPETSC, "run", str(case), "--restart", str(out), "--quiet"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)]
    second, third = [subprocess.CompletedProcess(p.args, 0, *p.communicate(timeout=300))
                     for p in others]
    second.returncode, third.returncode = (p.returncode for p in others)
    overlapped = first.poll() is None
    _, stderr = first.communicate(timeout=300)
    if first.returncode != 0:
        return False, f"first run: exit {first.returncode}: {stderr.strip()}"
    if not overlapped:
        return None
    for name, p in (("second run", second), ("restart", third)):
        if p.returncode != 2 or not one_clean_line(p.stderr) or "another run" not in p.stderr:
            return False, f"{name}: exit {p.returncode}: {p.stderr.strip()}"
    if vstpetsc.Result(out).status != "completed" or not same_end(out, reference):
        return False, "the first run's file is not the uninterrupted result"
    return True, "second run and restart refused (exit 2); first file intact"


def simultaneous_runs(folder, case, reference):
    """Two runs on one new file started at the same moment: one writes it,
    the other stops with one line; the file is the uninterrupted result."""
    out = os.path.join(folder, f"same-{time.monotonic_ns()}.h5")
    runs = [start(case, out), start(case, out)]
    results = [(p.returncode, err) for p in runs for _, err in [p.communicate(timeout=300)]]
    codes = sorted(code for code, _ in results)
    if codes != [0, 2]:
        return False, f"exit statuses {codes}: {[err.strip()[-200:] for _, err in results]}"
    loser = [err for code, err in results if code == 2][0]
    if not one_clean_line(loser) or "another run" not in loser:
        return False, f"the refused run said: {loser.strip()}"
    if not same_end(out, reference):
        return False, "the file is not the uninterrupted result"
    return True, "one ran, the other stopped with exit 2; the file is intact"


def disk_full(folder, case, reference, size_kb):
    """The run on a tmpfs of ``size_kb``: exit 3 with one line, the file
    readable and failed; moved to a big disk it continues bit for bit."""
    mount = os.path.join(folder, f"disk{size_kb}")
    os.makedirs(mount, exist_ok=True)
    if subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size_kb}k", "tmpfs", mount],
                      capture_output=True).returncode != 0:
        return None, "cannot mount a tmpfs (not root?)"
    try:
        out = os.path.join(mount, "r.h5")
        p = cli("run", case, "-o", out, "--quiet", "-vst_flush_interval", "0.05")
        if p.returncode == 2 and "cannot create" in p.stderr and not os.path.exists(out):
            return one_clean_line(p.stderr), "too small for the first row: exit 2, no file"
        if p.returncode != 3 or not one_clean_line(p.stderr) or "disk full" not in p.stderr:
            return False, f"exit {p.returncode}: {p.stderr.strip()}"
        ok, detail = readable(out)
        status = vstpetsc.Result(out).status
        if not ok or status != "failed":
            return False, f"{detail}, status {status}"
        moved = os.path.join(folder, f"moved{size_kb}.h5")
        shutil.copy(out, moved)
    finally:
        subprocess.run(["umount", mount], capture_output=True)
    p = cli("run", case, "--restart", moved, "--quiet")
    if p.returncode != 0 or not same_end(moved, reference):
        return False, f"{detail}; moved and restarted: exit {p.returncode} {p.stderr.strip()}"
    return True, f"{detail}; moved to a big disk, restart equal bit for bit"


def simultaneous_sweeps(folder, case, delay=0.0):
    """Two sweeps into one new folder, the second started ``delay`` seconds
    after the first: one sweeps, the other stops with one line before it
    touches a run (or, if the first had finished, finds every run done);
    no completed run is called failed."""
    out = os.path.join(folder, f"sweep-{time.monotonic_ns()}")
    command = [VSTPETSC, "sweep", str(case), "--set", "time.end=1.0,1.5", "-o", out, "--quiet"]
    runs = [subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)]
    time.sleep(delay)
    runs.append(subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                 text=True))
    results = [(p.returncode, err) for p in runs for _, err in [p.communicate(timeout=300)]]
    codes = sorted(code for code, _ in results)
    if codes not in ([0, 2], [0, 0]):
        return False, f"exit statuses {codes}: {[err.strip()[-200:] for _, err in results]}"
    refused = [err for code, err in results if code == 2]
    if refused and (not one_clean_line(refused[0]) or "another sweep" not in refused[0]):
        return False, f"the refused sweep said: {refused[0].strip()}"
    from vstpetsc.runner.sweep import read_summary
    _, data = read_summary(os.path.join(out, "summary.csv"))
    statuses = data["status"] + [vstpetsc.Result(os.path.join(out, f)).status
                                 for f in data["file"]]
    if statuses != ["completed"] * 4:
        return False, f"statuses in summary.csv and the files: {statuses}"
    if ".sweep.lock" in os.listdir(out):
        return False, "the lock file stayed after both sweeps ended"
    how = "one refused (exit 2)" if refused else "the second found every run done"
    return True, f"{how}; every run completed and so labelled"


def consistent(out):
    """(ok, detail): a Result of ``out`` (also while a run writes it) shows
    every kept-row series with as many rows as /time, rows that are whole
    (time = slab dt, row by row), every gauge series with one length, at
    least up to the last kept slab, and a summary."""
    try:
        r = vstpetsc.Result(out)
        n, dt = r.time.size, float(r.attrs["dt"])
        lengths = {"u/v/stress of " + b: {r.body(b)[k].shape[0] for k in ("u", "v", "stress")}
                   for b in r.bodies}
        lengths.update((g, {s.size for s in r.series(g).values()})
                       for g in ("energy", "solver", *(f"contact/{k}" for k in range(r.ncontacts))))
        wrong = {name: sizes for name, sizes in lengths.items() if sizes != {n}}
        gauges = {s.size for g in r.gauges for s in r.series(f"gauge/{g}").values()}
        slabs = r.solver["slab"]
        r.summary()
    except Exception as exc:                     # any traceback is the fault
        return False, f"{type(exc).__name__}: {str(exc)[:200]}"
    if wrong:
        return False, f"{n} times, but {wrong}"
    if not np.array_equal(r.time, slabs * dt):
        return False, f"rows not whole: time and slab differ in {n} rows"
    if len(gauges) > 1 or (gauges and gauges.pop() < slabs[-1] + 1):
        return False, (f"gauge series of lengths {sorted(gauges)}, last kept slab {slabs[-1]} "
                       f"(gauges {r.gauges}, gauge rows {r._gauge_rows})")
    return True, f"{n} rows"


def _csv_lengths(folder):
    """{CSV file: number of lines} of the kept-row exports in ``folder``."""
    return {name: sum(1 for _ in open(os.path.join(folder, name)))
            for name in os.listdir(folder) if not name.startswith(("gauge", "envelope"))
            and not name.endswith("-events.csv")}          # a row per event, not per kept slab


def command_reads(out, k):
    """(ok, detail) of the k-th command in turn: info, export --csv (every
    kept-row CSV file as long as the others), plot; exit 0 each."""
    command = ("info", "export", "plot")[k % 3]
    folder = f"{out}.csv{k}"
    args = {"info": ("info", out), "export": ("export", out, "--csv", folder),
            "plot": ("plot", out, "-o", f"{out}.png")}[command]
    p = cli(*args)
    if p.returncode != 0:
        return False, f"{command}: exit {p.returncode}: {p.stderr.strip()[-300:]}"
    if command == "export" and len(set(_csv_lengths(folder).values())) != 1:
        return False, f"export: CSV files of different lengths {_csv_lengths(folder)}"
    return True, command


def read_while_running(folder, reads=1000, commands=3, every=1000, elements=1000, seconds=120.0):
    """A soak: ``reads`` Result reads and ``commands`` commands (info, export
    --csv, plot in turn) of the file a run writes, a block per kept row,
    with the other core kept busy; the run outlasts them (ten million
    slabs) and is then stopped (SIGTERM).  Every read must show a
    consistent prefix (:func:`consistent`) whose last row is the final
    file's row, bit for bit.  (ok, detail); not ok also when the reads
    took longer than ``seconds``."""
    out = os.path.join(folder, f"read-{time.monotonic_ns()}.h5")
    case = out[:-3] + ".toml"
    with open(case, "w") as f:
        f.write(long_case(end=1e4, every=every, elements=elements).to_toml())
    busy = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    proc = start(case, out, "-vst_flush_interval", "0")
    try:
        if not wait_for(out, proc):
            return False, f"the run did not start: {proc.communicate()[1].strip()}"
        seen, detail = _soak(out, proc, reads, commands, time.monotonic() + seconds)
        if seen is None:
            return False, detail
    finally:
        busy.kill()
        if proc.poll() is None:
            proc.send_signal(signal.SIGTERM)
        proc.communicate()
        busy.wait()
    return _prefixes_of(out, seen, detail)


def _soak(out, proc, reads, commands, deadline):
    """({rows: hash of the last row of body a's u} over the reads, detail),
    or (None, what failed).  A read: a new Result, its times, the last row
    of u and of every gauge series; every 250th the whole :func:`consistent`."""
    seen, done = {}, [0, 0]
    while done[0] < reads or done[1] < commands:
        if proc.poll() is not None:
            return None, f"the run ended after {done[0]} reads: {proc.communicate()[1][-300:]}"
        if time.monotonic() > deadline:
            return None, f"only {done[0]} reads and {done[1]} commands in time"
        if done[0] >= reads or (done[1] < commands and done[0] % 50 == 49):
            ok, detail = command_reads(out, done[1])
            done[1] += 1
        else:
            ok, detail = consistent(out) if done[0] % 250 == 0 else _prefix(out, seen)
            done[0] += 1
        if not ok:
            return None, f"after {done[0]} reads and {done[1]} commands: {detail}"
    return seen, f"{done[0]} reads and {done[1]} commands"


def _prefix(out, seen):
    """(ok, detail) of one light read (the last rows only); notes the hash
    of its last u row."""
    try:
        r = vstpetsc.Result(out)
        with r.session():
            n, slabs = r.time.size, r.solver["slab"]
            seen[n] = hash(r.read("body/a/u", np.s_[n - 1, :]).tobytes())
            last = [r.read(f"gauge/{g}/{k}", np.s_[-1]) for g in r.gauges
                    for k in r.keys(f"gauge/{g}")]
    except Exception as exc:                     # any traceback is the fault
        return False, f"{type(exc).__name__}: {str(exc)[:200]}"
    if not r._swmr:
        return False, "read without HDF5's SWMR mode"
    if slabs.size != n or r._gauge_rows < slabs[-1] + 1 or not np.isfinite(last).all():
        return False, f"{n} times, {slabs.size} slabs, {r._gauge_rows} gauge rows, last {last}"
    return True, f"{n} rows"


def _prefixes_of(out, seen, detail):
    """(ok, detail): the stopped run's file is whole and holds every row
    the reads saw, as they saw it."""
    ok, whole = consistent(out)
    if not ok:
        return False, f"the stopped run's file: {whole}"
    u = vstpetsc.Result(out).body("a").u
    differ = [n for n, h in seen.items() if n > len(u) or hash(u[n - 1].tobytes()) != h]
    if differ:
        return False, f"rows read differ from the final file's at {differ[:5]}"
    return True, f"{detail}, {len(seen)} distinct prefixes, all consistent"

