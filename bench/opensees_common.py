"""The skeleton that bench/opensees.py (1-D) and bench/plane_opensees.py
(plane strain) share: OpenSees in a child process, the choice of the
cheapest run reaching a target, the interleaved timing of the chosen runs,
the results' head, the README section's closing lines, and `main`.

Each bench keeps what is its own: its problems, its runs, its search and
its README table.
"""

import json
import os
import subprocess
import sys
import time

import numpy as np

from readme import results_and_section


# ---------------------------------------------------------------- OpenSees (child)

class WorkerChild:
    """A child process running ``script --worker``: one JSON job a line in,
    one JSON answer a line out.  OpenSees runs there because openseespy and
    petsc4py crash in one process; start it before PETSc starts Open MPI."""

    def __init__(self, script, quiet=False, close_timeout=30):
        self.proc = subprocess.Popen([sys.executable, os.path.abspath(script), "--worker"],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                                     stderr=subprocess.DEVNULL if quiet else None)
        self.close_timeout = close_timeout

    def ask(self, job):
        """The child's answer (a dict) to ``job``."""
        self.proc.stdin.write(json.dumps(job) + "\n")
        self.proc.stdin.flush()
        answer = self.proc.stdout.readline()
        if not answer:
            raise RuntimeError(f"the OpenSees child died on {job}")
        return json.loads(answer)

    def close(self):
        self.proc.stdin.close()
        self.proc.wait(timeout=self.close_timeout)


class SystemChild(WorkerChild):
    """A WorkerChild whose answers carry OpenSees' version, that probes its
    linear ``systems`` on a job and keeps the fastest for the next jobs."""

    def __init__(self, script, systems):
        super().__init__(script, quiet=True, close_timeout=60)
        self.system, self.version = systems[0], None

    def ask(self, job):
        got = super().ask(job)
        self.version = got.pop("version")
        return got

    def probe(self, job):
        times = self.ask({"probe": job})["systems"]
        self.system = min((t, s) for s, t in times.items())[1]
        return times


def serve(answer):
    """The child's loop: one JSON job a line on stdin, ``answer(job)`` (a
    dict) one JSON line on stdout, flushed at once (the parent waits on it)."""
    for line in sys.stdin:
        sys.stdout.write(json.dumps(answer(json.loads(line))) + "\n")
        sys.stdout.flush()
    return 0


# ---------------------------------------------------------------- choice and timing

def cheapest(rows, target, work):
    """The row of least ``work(row)`` whose error is <= target, or None."""
    ok = [r for r in rows if r["error"] is not None and r["error"] <= target]
    return min(ok, key=work) if ok else None


def most_accurate(runs):
    """The run of least error among those that finished, or None."""
    done = [r for r in runs if r["error"] is not None]
    return min(done, key=lambda r: r["error"]) if done else None


def time_chosen(chosen, runners, reps, slow_total):
    """Run every chosen job ``reps`` times, interleaved (so that a change
    of the machine's load touches every method alike): (min, median) each;
    a job that has taken ``slow_total`` seconds stops after three runs."""
    times = {key: [] for key in chosen}
    for _ in range(reps):
        for key, (kind, job) in chosen.items():
            if len(times[key]) >= 3 and sum(times[key]) > slow_total:
                continue
            times[key].append(runners[kind](job)[0])
    return {key: (min(v), float(np.median(v))) for key, v in times.items()}


def results_head(quick):
    """The fields every results file starts with: mode, date, machine."""
    return {"quick": quick, "date": time.strftime("%Y-%m-%d"),
            "machine": f"{os.uname().nodename} {os.cpu_count()} cores"}


# ---------------------------------------------------------------- README

def fastest_line(label, table, target, time_text):
    """"- LABEL: the fastest method at ``target`` and its time
    (``time_text(seconds)``), the others as multiples of it, the methods
    that did not reach it"; None when none did."""
    rows = [r for r in table if r["target"] == target and r["run"]]
    if not rows:
        return None
    best = min(rows, key=lambda r: r["time_min"])
    others = ", ".join(f"{r['method']} {r['time_min'] / best['time_min']:.1f} x"
                       for r in rows if r is not best)
    missing = [r["method"] for r in table if r["target"] == target and not r["run"]]
    return (f"- {label}: {best['method']} {time_text(best['time_min'])}"
            + (f"; {others}" if others else "")
            + (f"; not reached: {', '.join(missing)}" if missing else "") + ".")


def section_text(lines, fastest):
    """The section: its head and table ``lines``, then the fastest lines."""
    return "\n".join(lines + ["", "Fastest per target (min times; the others as multiples "
                               "of it):", ""] + fastest) + "\n"


def bench_main(name, args, worker, measure, section, title):
    """What a bench does with its options: the child's loop under
    --worker; else measure (or read NAME.json back, --readme-only), keep
    the results and write the README section ``title``."""
    if args.worker:
        return worker()
    results_and_section(args.out, name, args.readme_only,
                        lambda: measure(args.quick, log=lambda s: print(s, flush=True)),
                        section, title)
    return 0


def generated_by(script, res):
    """The opening of an OpenSees comparison's README section: the script,
    the machine, the date, openseespy's version (``res``'s) and the mode."""
    return (f"Generated by `bench/{script}` (`make bench`) on {res['machine']}, {res['date']}; "
            f"openseespy {res['opensees_version']} from PyPI"
            + (" (quick mode)" if res["quick"] else "") + ". ")
