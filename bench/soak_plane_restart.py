"""A soak of the two-rank restart of tests/test_plane_run.py (issue 44,
item 9): the dam of the test run whole under `mpirun -n 2`, and stopped
at slab k then continued with --restart to the end, for many k, with
the other cores kept busy; every dataset of the continued file compared
bit for bit with the whole run's (solver/wall_time aside), and every
whole run with the first one (a run that does not repeat itself is told
apart from a restart that does not continue it).  A tool, not a test:

    python bench/soak_plane_restart.py [--rounds 3] [--stops 2:79] [--load 1]
        [--jobs 0] [--json FILE] [-- PETSC OPTIONS]

--load: processes spinning on a core each; --jobs: loops of other
two-rank runs (what the other pytest worker ran beside the test in
`make test`).  Prints a line a pair and a summary (pairs, failures, the
stops that failed, the datasets and the first rows that differed, runs
that did not complete); --json writes it.
"""

import argparse
import json
import os
import random
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests"))

from agreement import datasets, unequal  # noqa: E402
from test_plane_run import DAM  # noqa: E402

DT, SLABS = 2.5e-3, 80
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_btl_vader_single_copy_mechanism="none")
VSTPETSC = [sys.executable, "-m", "vstpetsc"]


def case(folder, slabs, name):
    path = os.path.join(folder, f"{name}.toml")
    with open(path, "w") as f:
        f.write(DAM.format(end=f"{slabs * DT:.10g}"))
    return path


def mpirun(*args):
    p = subprocess.run(["mpirun", "-n", "2", *VSTPETSC, *map(str, args)], capture_output=True,
                       text=True, timeout=600, env=ENV)
    if p.returncode != 0:
        raise RuntimeError(f"{args}: exit {p.returncode}\n{p.stderr}")


def pair(folder, k, options):
    """(continued vs whole, whole vs the first whole) differences of one
    pair stopped at slab k."""
    whole, part = os.path.join(folder, "whole.h5"), os.path.join(folder, "part.h5")
    for path in (whole, part):
        if os.path.exists(path):
            os.remove(path)
    mpirun("run", case(folder, SLABS, "dam"), "-o", whole, "-q", *options)
    mpirun("run", case(folder, k, "half"), "-o", part, "-q", *options)
    mpirun("run", case(folder, SLABS, "half"), "--restart", part, "-q", *options)
    a, b = datasets(whole), datasets(part)
    return a, unequal(a, b)


def busy(n):
    """n processes spinning on a core each (the other core of the test's
    loaded machine)."""
    code = "while True: pass"
    return [subprocess.Popen([sys.executable, "-c", code]) for _ in range(n)]


def other_jobs(n, folder):
    """n loops of two-rank runs of the whole dam beside the soak's (what
    the other pytest worker may run in `make test`), each in its own
    session so that it ends with its mpirun."""
    out = []
    for i in range(n):
        path = case(folder, SLABS, f"load{i}")
        loop = (f"while true; do mpirun -n 2 {' '.join(VSTPETSC)} run {path} "
                f"-o {folder}/load{i}.h5 -q >/dev/null 2>&1; rm -f {folder}/load{i}.h5; done")
        out.append(subprocess.Popen(["bash", "-c", loop], env=ENV, start_new_session=True))
    return out


def stop(processes):
    for p in processes:
        if p.args[0] == "bash":        # the loop and its mpirun, which ends its ranks
            os.killpg(p.pid, signal.SIGTERM)
        else:
            p.kill()
        p.wait()


def verdict(diff, again):
    """A pair's line: {dataset: first differing row} of the continued file
    against its whole run, and of the whole run against the first one."""
    out = f"continued differs {json.dumps(diff)}" if diff else "bit for bit"
    return out + (f"; the whole run differs from the first {json.dumps(again)}" if again else "")


def parse_stops(text):
    lo, _, hi = text.partition(":")
    return list(range(int(lo), int(hi or lo) + 1)) if hi or lo else []


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=3, help="times each stop slab is run")
    ap.add_argument("--stops", default="2:79",
                    help="stop slabs, lo:hi (a run is two slabs at least)")
    ap.add_argument("--load", type=int, default=1, help="busy processes beside the runs")
    ap.add_argument("--jobs", type=int, default=0,
                    help="loops of other two-rank runs beside the soak's")
    ap.add_argument("--seed", type=int, default=int(time.time()))
    ap.add_argument("--json")
    ap.add_argument("options", nargs="*", help="PETSc options of every run (after --)")
    args = ap.parse_args(argv)
    stops = [k for k in parse_stops(args.stops) if 1 < k < SLABS]
    order = [k for _ in range(args.rounds) for k in stops]
    random.Random(args.seed).shuffle(order)
    failures, unrepeated, errors, first = [], [], [], None
    start = time.time()
    with tempfile.TemporaryDirectory() as folder, tempfile.TemporaryDirectory() as side:
        loaders = busy(args.load) + other_jobs(args.jobs, side)
        try:
            for i, k in enumerate(order):
                try:
                    whole, diff = pair(folder, k, args.options)
                except (RuntimeError, subprocess.TimeoutExpired) as exc:
                    errors.append({"stop": k, "error": str(exc)[-400:]})
                    print(f"{i + 1}/{len(order)} stop {k}: a run failed: {exc}", flush=True)
                    continue
                first = whole if first is None else first
                again = unequal(first, whole)
                failures += [{"stop": k, "datasets": diff}] if diff else []
                unrepeated += [{"stop": k, "datasets": again}] if again else []
                print(f"{i + 1}/{len(order)} stop {k}: {verdict(diff, again)}", flush=True)
        finally:
            stop(loaders)
    summary = {"pairs": len(order) - len(errors), "failures": len(failures),
               "runs_failed": len(errors),
               "whole_runs_unlike_the_first": len(unrepeated),
               "stops": f"{min(stops)}..{max(stops)}" if stops else "", "rounds": args.rounds,
               "load": f"{args.load} busy process(es), {args.jobs} loop(s) of two-rank runs, "
                       f"{os.cpu_count()} cores",
               "options": args.options, "seed": args.seed,
               "minutes": round((time.time() - start) / 60, 1),
               "failed": failures, "unrepeated": unrepeated, "errors": errors}
    print(json.dumps({k: v for k, v in summary.items()
                      if k not in ("failed", "unrepeated", "errors")}))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(summary, f, indent=1)
    return 1 if failures or unrepeated or errors else 0


if __name__ == "__main__":
    sys.exit(main())
