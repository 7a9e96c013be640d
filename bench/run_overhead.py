"""The fixed cost of a run (issue 29): what a run costs beyond its slabs.

(a) In one process, PETSc started: the bundled bar-wall cut to 2 slabs run
    through the API (``vstpetsc.run``, result file written and opened as
    the returned Result) ~20 times; its cost beyond its slabs is its wall
    time minus 2 slabs, a slab's cost being the marginal cost of the slabs
    of a long run of the same case (the difference of a long and the tiny
    run over their difference in slabs).  With the time of each phase.
(b) The start of a process: ``python -c "import vstpetsc"`` (and ``import
    numpy``, its floor), ``vstpetsc --help`` and ``vstpetsc run`` of the
    2-slab case, each in a subprocess
    (min and median of several), and inside one such process the time of
    the import (and reading the case), of PETSc's and MPI's start and of
    the first run (which loads what a run needs: h5py, the solver's
    modules, the compiled kernels, the BLAS lookup).

    .venv/bin/python bench/run_overhead.py [--runs 20] [--starts 7] [--readme]

``--readme`` writes the table into bench/README.md (its own section, after
bench/run.py has written the rest).  Timings only; tests/test_run_overhead.py
checks what the cuts must not change.
"""

import argparse
import functools
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
VSTPETSC = os.path.join(os.path.dirname(sys.executable), "vstpetsc")
LONG = 2000                     # slabs of the long run
TITLE = "## Fixed cost of a run"

# (label, module, attribute path): the phases of a run, as named in the code
PHASES = [("set-up (model, solver)", "vstpetsc.runner.driver", "TimeLoop.__init__"),
          ("file created, first row", "vstpetsc.runner.recorder", "Recorder.open"),
          ("slabs", "vstpetsc.runner.driver", "TimeLoop._loop"),
          ("last block, file closed", "vstpetsc.runner.recorder", "Recorder.close"),
          ("Result opened", "vstpetsc.results.reader", "Result.__init__")]

START = r"""
import json, sys, time
t0 = time.perf_counter()
import vstpetsc
case = vstpetsc.Case.from_toml(sys.argv[1])
t1 = time.perf_counter()
from vstpetsc import petsc
petsc.initialize()
t2 = time.perf_counter()
vstpetsc.run(case, sys.argv[2] + "/a.h5", quiet=True)
t3 = time.perf_counter()
vstpetsc.run(case, sys.argv[2] + "/b.h5", quiet=True)
t4 = time.perf_counter()
print(json.dumps([t1 - t0, t2 - t1, t3 - t2, t4 - t3]))
"""


def tiny_cases(folder):
    """(path of bar-wall cut to 2 slabs, the Case, the long Case)."""
    import vstpetsc
    from vstpetsc import bundled

    case = vstpetsc.Case.from_toml(bundled.path("bar-wall"))
    tiny = case.with_value("time.end", 2 * case.dt)
    path = os.path.join(folder, "tiny.toml")
    with open(path, "w") as f:
        f.write(tiny.text)
    return path, tiny, case.with_value("time.end", LONG * case.dt)


class PhaseClock:
    """Wall time spent in each of PHASES during one run (wrappers set
    around the functions, in this process only)."""

    def __init__(self):
        import importlib

        self.spent = {}
        for label, module, path in PHASES:
            owner_name, attr = path.split(".")
            owner = getattr(importlib.import_module(module), owner_name)
            setattr(owner, attr, self._timed(label, getattr(owner, attr)))

    def _timed(self, label, func):
        @functools.wraps(func)
        def timed(*args, **kwargs):
            start = time.perf_counter()
            try:
                return func(*args, **kwargs)
            finally:
                self.spent[label] = self.spent.get(label, 0.0) + time.perf_counter() - start
        return timed


def api_costs(folder, runs):
    """({'total': [s], phase: [s]}, seconds a slab) of ``runs`` tiny runs."""
    import vstpetsc

    _, tiny, long = tiny_cases(folder)
    clock = PhaseClock()
    vstpetsc.run(tiny, os.path.join(folder, "warm.h5"), quiet=True)   # PETSc started
    times = {"total": []}
    for i in range(runs):
        clock.spent.clear()
        start = time.perf_counter()
        vstpetsc.run(tiny, os.path.join(folder, f"tiny{i}.h5"), quiet=True)
        times["total"].append(time.perf_counter() - start)
        for label, spent in clock.spent.items():
            times.setdefault(label, []).append(spent)
    longs = []
    for i in range(3):
        start = time.perf_counter()
        vstpetsc.run(long, os.path.join(folder, f"long{i}.h5"), quiet=True)
        longs.append(time.perf_counter() - start)
    per_slab = (min(longs) - min(times["total"])) / (LONG - 2)
    return times, per_slab


def process_costs(folder, starts):
    """{what: [s]} of whole processes, and {phase: [s]} inside one."""
    tiny, _, _ = tiny_cases(folder)
    commands = {"python -c \"import numpy\"": [sys.executable, "-c", "import numpy"],
                "python -c \"import vstpetsc\"": [sys.executable, "-c", "import vstpetsc"],
                "vstpetsc --help": [VSTPETSC, "--help"],
                "vstpetsc run (2 slabs)": [VSTPETSC, "run", tiny, "-o",
                                           os.path.join(folder, "cli.h5")]}
    whole = {what: [] for what in commands}
    inside = {what: [] for what in ("import vstpetsc, case read", "PETSc and MPI started",
                                    "first run (2 slabs)", "second run (2 slabs)")}
    for _ in range(starts):
        for what, argv in commands.items():
            start = time.perf_counter()
            subprocess.run(argv, check=True, capture_output=True)
            whole[what].append(time.perf_counter() - start)
        out = subprocess.run([sys.executable, "-c", START, tiny, folder], check=True,
                             capture_output=True, text=True).stdout
        for what, t in zip(inside, json.loads(out)):
            inside[what].append(t)
    return whole, inside


def ms(values):
    return f"{min(values) * 1e3:.1f} | {statistics.median(values) * 1e3:.1f}"


def table(times, per_slab, whole, inside):
    """The section's markdown lines."""
    beyond = [t - 2 * per_slab for t in times["total"]]
    lines = ["| what | ms, min | median |", "|---|---|---|",
             f"| API run of 2 slabs, beyond its slabs ({len(beyond)} runs) | {ms(beyond)} |",
             f"| (a slab, from a {LONG}-slab run) | {per_slab * 1e3:.3f} | |"]
    lines += [f"| - {label} | {ms(times[label])} |" for label, _, _ in PHASES if label in times]
    lines += [f"| process: `{what}` | {ms(t)} |" for what, t in whole.items()]
    lines += [f"| - inside: {what} | {ms(t)} |" for what, t in inside.items()]
    return lines


def write_readme(lines):
    """Put the section into bench/README.md, replacing an earlier one."""
    path = os.path.join(HERE, "README.md")
    with open(path) as f:
        text = f.read()
    head, _, rest = text.partition(TITLE)
    tail = rest[rest.find("\n## "):] if "\n## " in rest else ""
    section = [TITLE, "", "Generated by `bench/run_overhead.py` (`make bench`): the bundled "
               "bar-wall cut to 2 slabs, through the API in one process (PETSc started) and "
               "as whole processes; see docs/architecture.md, \"What a run costs\". Before "
               "issue 29's cuts (commit 4381cc2; three rounds interleaved with them on a "
               "busier machine, minima): 33-38 ms beyond the slabs, `import vstpetsc` "
               "320-390 ms, `vstpetsc --help` 320-400 ms.", ""]
    with open(path, "w") as f:
        f.write(head.rstrip("\n") + "\n\n" + "\n".join(section + lines) + "\n" + tail)


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--starts", type=int, default=7)
    ap.add_argument("--readme", action="store_true")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder:
        whole, inside = process_costs(folder, args.starts)
        times, per_slab = api_costs(folder, args.runs)
    lines = table(times, per_slab, whole, inside)
    print("\n".join(lines))
    if args.readme:
        write_readme(lines)


if __name__ == "__main__":
    main()
