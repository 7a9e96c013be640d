"""Sweeps: one case run for every combination of changed values, the runs
shared out over the ranks (one rank a run), one summary row a run
(docs/sweeps.md).

    rows = vstpetsc.sweep(case, {"body.bar.v0": [1, 2, 4]}, "out")

Each run writes ``out/run-<i>.h5``; rank 0 writes ``out/summary.csv``.  A
run whose file is complete and holds the same case is not run again, so a
killed sweep continues where it stopped.  A run that fails (bad value,
failed solve) is a row with status "failed" and its message; the others
go on.
"""

import csv
import io
import itertools
import math
import os
import time

import numpy as np

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
    out["numerical_energy"] = s["energy"].get("numerical", math.nan)
    for k, soil in enumerate(s.get("soils", [])):
        out.update({f"set_{k}": soil["set"], f"blow_count_{k}": soil["blow_count"]})
    if s.get("soils"):
        out["transferred_energy"] = s["energy"].get("transferred", math.nan)
    for body in s["bodies"]:
        out[f"stress_min_{body['name']}"] = body.get("compression", (math.nan,))[0]
        out[f"stress_max_{body['name']}"] = body.get("tension", (math.nan,))[0]
    return out


def _done(path, case):
    """The Result of ``path`` if it is a completed run of ``case``."""
    from vstpetsc.results.reader import Result

    try:
        result = Result(path)
        if result.status == "completed" and result.case() == case:
            return result
    except (InputError, CaseError, KeyError, OSError):
        pass
    return None


def run_one(case, values, path, options, comm):
    """One run of the sweep: its summary row (without the swept values)."""
    from vstpetsc.driver import run

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
    """
    from vstpetsc import petsc

    combos = combinations(settings)
    for key in settings:
        case.check_path(key)
    petsc.initialize([])
    comm = petsc.communicator(comm).tompi4py()
    group, groups = _groups(comm, ranks_per_run)
    if comm.Get_rank() == 0:
        os.makedirs(folder, exist_ok=True)
    comm.Barrier()
    width = len(str(len(combos) - 1))
    mine = {}
    for i in range(comm.Get_rank() // ranks_per_run, len(combos), groups):
        path = os.path.join(folder, f"run-{i:0{width}d}.h5")
        row = {**combos[i], **run_one(case, combos[i], path, options, group)}
        if group.Get_rank() == 0:
            mine[i] = row
    parts = comm.allgather(mine)
    rows = [next(p[i] for p in parts if i in p) for i in range(len(combos))]
    if comm.Get_rank() == 0:
        write_summary(os.path.join(folder, "summary.csv"), rows, list(settings))
    comm.Barrier()
    group.Free()
    return rows


def _groups(comm, ranks_per_run):
    """(this rank's group communicator, number of groups) of ``comm`` cut
    into groups of ``ranks_per_run`` consecutive ranks."""
    size = comm.Get_size()
    if not isinstance(ranks_per_run, int) or ranks_per_run < 1 or size % ranks_per_run:
        raise InputError(f"--ranks-per-run: a whole divisor of the {size} ranks, got "
                         f"{ranks_per_run!r}")
    return comm.Split(comm.Get_rank() // ranks_per_run, comm.Get_rank()), size // ranks_per_run


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
    """(header, {column: list of values}) of a summary.csv; numbers as floats."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        data = {c: [] for c in header}
        for row in reader:
            for c, cell in zip(header, row):
                data[c].append(_number(cell))
    return header, data


def _number(cell):
    try:
        return float(cell)
    except ValueError:
        return cell
