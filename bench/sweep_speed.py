"""Wall time of a sweep of 8 runs on one rank and on two (`mpirun -n P
vstpetsc sweep`, start-up included), and of the ideal: the runs' share of
one rank's time, i.e. what two ranks would take if a run cost on two busy
cores what it costs on one.

Case: the bundled bar-wall refined to 2000 elements (dt so that c dt/h = 1),
run for 15 000 slabs (about 1 s a run) or 40 000 (about 2.5 s); the sweep
varies v0 over 8 values.
Used by bench/parallel_solvers.py (`make bench-parallel`).
"""

import os
import statistics
import subprocess
import sys
import tempfile
import time

from cases import steel_bar

VSTPETSC = os.path.join(os.path.dirname(sys.executable), "vstpetsc")
VALUES = "0.5,0.75,1,1.25,1.5,1.75,2,2.25"


def case_text(elements=2000, slabs=15_000):
    return (steel_bar(elements, slabs, cfl=1.0, every=100) + "v0 = 1.0\n"
            "[[contact]]\npair = [\"bar\", \"wall\"]\nwall = 1.001\n")


def sweep_seconds(folder, ranks, tag, slabs):
    """Seconds of a whole `mpirun -n ranks vstpetsc sweep` into a new folder,
    and the sum of its runs' own wall times (from summary.csv)."""
    case = os.path.join(folder, "case.toml")
    with open(case, "w") as f:
        f.write(case_text(slabs=slabs))
    out = os.path.join(folder, tag)
    cmd = ["mpirun", "-n", str(ranks), VSTPETSC, "sweep", case, "--set",
           f"body.bar.v0={VALUES}", "-o", out, "--quiet"]
    t0 = time.perf_counter()
    subprocess.run(cmd, capture_output=True, check=True)
    seconds = time.perf_counter() - t0
    import csv
    with open(os.path.join(out, "summary.csv")) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 8 and all(r["status"] == "completed" for r in rows)
    return seconds, sum(float(r["wall_time"]) for r in rows)


def sweep_speedup(slabs, reps=3):
    """One row: wall of the sweep of runs of ``slabs`` slabs on 1 and 2
    ranks (min, median), the speed-up, and the runs' own time on each
    (their sum, the least over the repetitions)."""
    wall = {1: [], 2: []}
    runs = {1: [], 2: []}
    with tempfile.TemporaryDirectory() as folder:
        for rep in range(reps):
            for ranks in (1, 2):
                seconds, inside = sweep_seconds(folder, ranks, f"s{ranks}-{rep}", slabs)
                wall[ranks].append(seconds)
                runs[ranks].append(inside)
    one, two = wall[1], wall[2]
    return {"runs": 8, "slabs": slabs, "one_min_s": min(one), "one_median_s": statistics.median(one),
            "two_min_s": min(two), "two_median_s": statistics.median(two),
            "speedup": min(one) / min(two),
            "speedup_median": statistics.median(one) / statistics.median(two),
            "run_sum_one_s": min(runs[1]), "run_sum_two_s": min(runs[2])}


def table(row):
    """Markdown lines for the row."""
    return [f"| {row['slabs']} | {row['one_min_s']:.2f} / {row['one_median_s']:.2f} | "
            f"{row['two_min_s']:.2f} / {row['two_median_s']:.2f} | "
            f"{row['speedup']:.2f} / {row['speedup_median']:.2f} | "
            f"{row['run_sum_one_s']:.2f} / {row['run_sum_two_s']:.2f} |"]


if __name__ == "__main__":
    print(sweep_speedup(int(sys.argv[1]) if len(sys.argv) > 1 else 15_000))
