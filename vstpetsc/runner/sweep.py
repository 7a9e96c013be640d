"""Sweeps: one case run for every combination of changed values, the runs
shared out over the ranks (one rank a run), one summary row a run
(docs/sweeps.md).

    rows = vstpetsc.sweep(case, {"body.bar.v0": [1, 2, 4]}, "out")

Each run writes ``out/run-<i>.h5``; rank 0 writes ``out/summary.csv``.  A
run whose file is complete and holds the same case (its text, and the
contents of the history files it reads) is not run again, so a killed
sweep continues where it stopped.  One sweep at a time writes into a
folder (:mod:`vstpetsc.runner.sweep_folder`).  A run that fails (bad value,
failed solve) is a row with status "failed" and its message; the others
go on.
"""

import contextlib
import csv
import io
import itertools
import json
import math
import os
import time

import numpy as np

from vstpetsc.runner import sweep_folder
from vstpetsc.runner.dealing import RunQueue, wait_for_all
from vstpetsc.errors import CaseError, InputError, SolveFailed

FIXED = ("file", "status", "wall_time")


def parse_setting(text):
    """(key, [values]) of a command-line setting ``KEY=V1,V2,...``; each
    value read as a TOML value (a number, true/false, a quoted string),
    else taken as a string."""
    import tomllib

    key, sep, values = text.partition("=")
    if not sep or not key or not values:
        raise InputError(f"--set {text}: give KEY=V1,V2,... (e.g. body.bar.v0=1,2,4)")
    out = []
    for item in values.split(","):
        try:
            out.append(tomllib.loads(f"v = {item.strip()}")["v"])
        except tomllib.TOMLDecodeError:
            out.append(item.strip())
    if any(v == "" for v in out):
        raise InputError(f"--set {text}: an empty value")
    return key, out


def combinations(settings):
    """Every combination of ``settings`` ({key: [values]}), the first key
    varying slowest: a list of {key: value}."""
    keys = list(settings)
    for key in keys:
        if not isinstance(settings[key], (list, tuple)) or not settings[key]:
            raise InputError(f"sweep: {key}: give a non-empty list of values")
    return [dict(zip(keys, values)) for values in itertools.product(*settings.values())]


def quantities(result):
    """{column: value} of the summary quantities of a result file."""
    s = result.summary()
    out = {}
    for k, pair in enumerate(s["pairs"]):
        out.update({f"force_peak_{k}": pair["peak_force"],
                    f"contact_time_{k}": pair["duration"], f"impulse_{k}": pair["impulse"]})
        if "slip" in pair:
            out.update({f"slip_{k}": pair["slip"], f"slip_max_{k}": pair["slip_max"]})
    out["numerical_energy"] = s["energy"].get("numerical", math.nan)
    for k, soil in enumerate(s.get("soils", [])):
        out.update({f"set_{k}": soil["set"], f"blow_count_{k}": soil["blow_count"]})
    if s.get("soils"):
        out["transferred_energy"] = s["energy"].get("transferred", math.nan)
    for body in s["bodies"]:
        out[f"stress_min_{body['name']}"] = body.get("compression", (math.nan,))[0]
        out[f"stress_max_{body['name']}"] = body.get("tension", (math.nan,))[0]
    out.update(shear_quantities(s))
    out.update(plane_quantities(s))
    return out


def plane_quantities(s):
    """The columns of a plane-strain run, from its summary ``s``: per
    interface NAME ``slip_NAME`` (the permanent slip: the largest |slip|
    at the end, signed), ``slip_max_NAME`` (the largest |slip| of the
    run) and ``opening_max_NAME`` (the largest gap: below zero, closed
    throughout), as `vstpetsc info` prints them and as a 1-D pair's
    ``slip_<k>`` and ``slip_max_<k>``; ``tension_max``, the largest
    principal stress over the run (/field/principal_max); {} for a 1-D
    run."""
    plane = s.get("plane") or {}
    out = {}
    for g in plane.get("interfaces", ()):
        if g.get("slip") is not None:
            out.update({f"slip_{g['name']}": g["permanent"][0],
                        f"slip_max_{g['name']}": abs(g["slip"][0]),
                        f"opening_max_{g['name']}": g["opening"][0]})
    if plane.get("tension") is not None:
        out["tension_max"] = plane["tension"][0]
    return out


def shear_quantities(s):
    """The columns of a run with a shear component (some body's file has
    /body/<name>/shear), from its summary ``s``: ``strain_max``, the largest
    |shear strain| over every body's ``shear/strain_max``, and
    ``hysteretic``, the last /energy/hysteretic (0 without a hysteretic
    soil); {} for a run without one (its cells empty in the sweep's
    summary), and no ``strain_max`` or ``hysteretic`` where the file lacks
    the dataset (an older file).  A plane-strain run with a yielding region
    gives the same two: its largest /field/strain_max and hysteretic
    energy."""
    plane = s.get("plane") or {}
    if plane.get("strain") is not None:      # a plane-strain run with a yielding region
        return {"strain_max": plane["strain"][0],
                "hysteretic": s["energy"].get("hysteretic", math.nan)}
    peaks = [b["shear"] for b in s["bodies"] if "shear" in b]
    if not peaks:
        return {}
    out = {}
    strains = [p["strain"][0] for p in peaks if "strain" in p]
    if strains:
        out["strain_max"] = max(strains)
    if "hysteretic" in s["energy"]:
        out["hysteretic"] = s["energy"]["hysteretic"]
    return out


def _done(path, case):
    """The Result of ``path`` if it is a completed run of ``case``: the
    same case text and the same contents of every file it reads (a history
    file edited since is a new case)."""
    from vstpetsc.results.reader import Result

    try:
        result = Result(path)
        if (result.status == "completed" and result.case() == case
                and json.loads(result.attrs.get("input_digests", "{}")) == case.input_digests):
            return result
    except (InputError, CaseError, KeyError, OSError, ValueError):
        pass
    return None


def run_one(case, values, path, options, comm):
    """One run of the sweep: its summary row (without the swept values)."""
    from vstpetsc.runner.driver import run

    name = os.path.basename(path)
    start = time.perf_counter()
    try:
        changed = case
        for key, value in values.items():
            changed = changed.with_value(key, value)
        result = _done(path, changed)
        if result is None:
            result = run(changed, output=path, options=options, quiet=True, comm=comm,
                         out=io.StringIO(), err=io.StringIO())
    except (CaseError, InputError, SolveFailed) as exc:
        message = "; ".join(exc.problems) if isinstance(exc, CaseError) else str(exc)
        return {"file": name, "status": "failed", "wall_time": time.perf_counter() - start,
                "message": message}
    wall = float(result.attrs.get("wall_time", time.perf_counter() - start))
    return {"file": name, "status": result.status, "wall_time": wall, **quantities(result)}


def sweep(case, settings, folder, options=(), comm=None, ranks_per_run=1):
    """Run ``case`` for every combination of ``settings`` into ``folder``.

    Parameters
    ----------
    case : vstpetsc.Case
    settings : dict
        {path: [values]}, paths as for :meth:`Case.with_value`
        (``"body.bar.v0"``, ``"time.dt"``, ...).
    folder : str
        Made if missing: ``run-<i>.h5`` per combination and ``summary.csv``.
    options : sequence of str
        PETSc options for every run.
    comm : PETSc or mpi4py communicator, optional
        The ranks to share the runs over (default every rank).
    ranks_per_run : int
        Ranks that run one case together (a big case); the ranks form
        groups of this many, and the groups share out the runs.

    Returns
    -------
    list of dict
        One row per combination, in order, on every rank: the swept values,
        ``file``, ``status``, ``wall_time``, then the summary quantities
        (``message`` for a failed run).

    Raises
    ------
    CaseError
        A key that names no value of the case (on every rank, before
        anything runs).
    InputError
        ``folder`` cannot be made or written, or another sweep writes into
        it (on every rank).
    SolveFailed
        ``summary.csv`` cannot be written, or a rank's runs raised (on
        every rank; that rank raises its own error).
    """
    combos = _checked(case, settings, folder)
    comm = _communicator(comm)
    group = _group(comm, ranks_per_run)
    try:
        with _held(comm, folder):
            rows = _run_all(case, combos, folder, options, comm, group)
            _on_root(comm, lambda: _write_summary_or_fail(folder, rows, list(settings)))
    finally:
        group.Free()
    return rows


def _checked(case, settings, folder):
    """The combinations of ``settings``, once its keys and ``folder`` are
    found fit (on every rank alike, before anything runs)."""
    combos = combinations(settings)
    for key in settings:
        case.check_path(key)
    sweep_folder.check(folder)
    return combos


def _communicator(comm):
    """The mpi4py communicator of ``comm`` (default every rank), PETSc
    started."""
    from vstpetsc import petsc

    petsc.initialize([])
    return petsc.communicator(comm).tompi4py()


@contextlib.contextmanager
def _held(comm, folder):
    """``folder`` made and held by this sweep (rank 0 holds it) for the
    with block; given up, its lock file removed, however the block ends."""
    lock = _on_root(comm, lambda: sweep_folder.take(folder))
    try:
        yield
    finally:
        if lock is not None:
            sweep_folder.release(folder, lock)


def _run_all(case, combos, folder, options, comm, group):
    """Every run's row, in order, on every rank: the groups take runs as
    they ask for them (RunQueue), then share their rows."""
    queue = RunQueue(comm, group, len(combos))
    try:
        mine = _share(comm, lambda: _my_runs(case, combos, folder, options, group, queue))
    finally:
        queue.free()
    parts = comm.allgather(mine)
    return [next(p[i] for p in parts if i in p) for i in range(len(combos))]


def _my_runs(case, combos, folder, options, group, indices):
    """{i: row} of the runs ``indices`` (this rank's group's share, a
    RunQueue; the rows are kept by the group's first rank)."""
    width = len(str(len(combos) - 1))
    mine = {}
    for i in indices:
        path = os.path.join(folder, f"run-{i:0{width}d}.h5")
        row = {**combos[i], **run_one(case, combos[i], path, options, group)}
        if group.Get_rank() == 0:
            mine[i] = row
    return mine


def _write_summary_or_fail(folder, rows, keys):
    """write_summary into ``folder``; SolveFailed (exit 3) if it cannot."""
    path = os.path.join(folder, "summary.csv")
    try:
        write_summary(path, rows, keys)
    except OSError as exc:
        raise SolveFailed(f"cannot write {path} ({exc.strerror}); the runs' files "
                          "are kept") from None


def _on_root(comm, action):
    """``action()`` on rank 0 (its value there, None elsewhere); an
    InputError or SolveFailed it raises is raised on every rank, so that no
    rank waits for it in a later collective call."""
    value, error = None, None
    if comm.Get_rank() == 0:
        try:
            value = action()
        except (InputError, SolveFailed) as exc:
            error = exc
    error = comm.bcast(error, root=0)
    if error is not None:
        raise error
    return value


def _share(comm, action):
    """``action()`` on every rank; if it raises on some rank, every rank
    raises (that rank its own error, the others SolveFailed naming it)."""
    error = None
    try:
        value = action()
    except Exception as exc:        # shared below, whatever it is, then raised
        error = exc
    wait_for_all(comm)              # the ranks still running keep their cores
    messages = comm.allgather(None if error is None else f"{type(error).__name__}: {error}")
    if error is not None:
        raise error
    for rank, message in enumerate(messages):
        if message is not None:
            raise SolveFailed(f"sweep stopped: rank {rank}: {message}")
    return value


def _group(comm, ranks_per_run):
    """This rank's group communicator of ``comm`` cut into groups of
    ``ranks_per_run`` consecutive ranks."""
    size = comm.Get_size()
    if not isinstance(ranks_per_run, int) or ranks_per_run < 1 or size % ranks_per_run:
        raise InputError(f"--ranks-per-run: a whole divisor of the {size} ranks, got "
                         f"{ranks_per_run!r}")
    return comm.Split(comm.Get_rank() // ranks_per_run, comm.Get_rank())


def columns(rows, keys):
    """The summary's columns: the swept keys, the fixed ones, then every
    quantity in order of first appearance (``message`` last)."""
    out = list(keys) + list(FIXED)
    for row in rows:
        out += [c for c in row if c not in out and c != "message"]
    return out + ["message"]


def write_summary(path, rows, keys):
    """``rows`` as CSV (header line; numbers with 17 significant digits;
    a quantity a run lacks is empty), written whole then renamed."""
    names = columns(rows, keys)
    temp = path + ".part"
    with open(temp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(names)
        for row in rows:
            w.writerow([_cell(row.get(c, "")) for c in names])
    os.replace(temp, path)


def _cell(value):
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    return value


def read_summary(path):
    """(header, {column: list of values}) of a summary.csv; numbers as
    floats.  InputError for a file that is no sweep summary or holds no
    run (empty, a header line only)."""
    try:
        with open(path, newline="") as f:
            lines = list(csv.reader(f))
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror})") from None
    except (UnicodeDecodeError, csv.Error) as exc:
        raise InputError(f"{path}: not a CSV text file ({exc})") from None
    header = lines[0] if lines else []
    if not {"status", "wall_time"} <= set(header):
        raise InputError(f"{path}: not a sweep summary (no status and wall_time columns)")
    if len(lines) < 2:
        raise InputError(f"{path}: holds no runs (a header line only)")
    data = {c: [] for c in header}
    for row in lines[1:]:
        for c, cell in zip(header, row):
            data[c].append(_number(cell))
    return header, data


def _number(cell):
    try:
        return float(cell)
    except ValueError:
        return cell
