"""Wall and CPU time of a sweep of 8 runs on one rank and on two
(`mpirun -n P vstpetsc sweep`, start-up included), issue 29.

Cases (the sweep varies v0 over 8 values):
- goal: the bundled bar-wall example run to 20 ms, a row kept every slab
  (10 000 slabs, about 0.7 s a run on a quiet core); goal 2 ranks >= 1.8 x;
- bar-wall refined to 2000 elements (c dt/h = 1, a row every 100 slabs),
  15 000 slabs (about 0.7 s a run) or 40 000 (bench/parallel_solvers.py);
- fixed costs: bar-wall for 2 slabs, i.e. a process's start-up and each
  run's set-up and file, which the runs' time must outweigh: with start-up
  S and runs of r seconds, 8 runs on two ranks are (S + 8 r) / (S + 4 r)
  times faster than on one, at least 1.8 only for r >= S;
- plane strain (issue 48): the bundled gravity-dam (639 cells, its base
  an interface) to 1 s, 4 runs, its horizontal record scaled by 0.5, 1,
  1.5, 2 (about 0.9 s a run): (S + 4 r) / (S + 2 r) at best.

CPU: user + system seconds of mpirun and its ranks (getrusage of the
children), over the sweep's wall time = the cores kept busy.  One rank
keeps about one core busy; two ranks about two, and their CPU exceeds one
rank's by one more start-up: a rank done with its runs sleeps (a rank
spinning in an MPI wait would add its waiting time).

    .venv/bin/python bench/sweep_speed.py [repetitions] [--plane]

Writes bench/sweeps.json and the section "Sweeps on two ranks" of
bench/README.md (`make bench`, after bench/run.py); with --plane only the
plane-strain row is measured again, the others kept from sweeps.json.
"""

import csv
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

from cases import steel_bar   # no PETSc in this process (see cases.py)
from readme import write_readme

HERE = os.path.dirname(os.path.abspath(__file__))
VSTPETSC = os.path.join(os.path.dirname(sys.executable), "vstpetsc")
VALUES = "0.5,0.75,1,1.25,1.5,1.75,2,2.25"
BAR_SET = f"body.bar.v0={VALUES}"
SCALES = "0.5,1,1.5,2"
PLANE_SET = f"boundary.base.incident.x.scale={SCALES}"
PLANE_CASE = "gravity-dam to 1 s, 4 record scales (2-D)"
SECTION = "## Sweeps on two ranks"


def case_text(elements=2000, slabs=15_000):
    return (steel_bar(elements, slabs, cfl=1.0, every=100) + "v0 = 1.0\n"
            "[[contact]]\npair = [\"bar\", \"wall\"]\nwall = 1.001\n")


def bar_wall(end):
    """The bundled bar-wall example run to ``end`` seconds (a row every
    slab, as it is)."""
    from vstpetsc import Case, bundled   # imports no PETSc

    return Case.from_toml(bundled.path("bar-wall")).with_value("time.end", end).to_toml()


def plane_dam(end=1.0):
    """The bundled gravity-dam run to ``end`` seconds: (its case text, the
    files it reads)."""
    from vstpetsc import Case, bundled   # imports no PETSc

    text = Case.from_toml(bundled.path("gravity-dam")).with_value("time.end", end).to_toml()
    return text, bundled.companions("gravity-dam")


def children_cpu():
    """User + system seconds of this process's finished children."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def sweep_seconds(folder, ranks, tag, text, setting=BAR_SET):
    """(wall, CPU) seconds of a whole `mpirun -n ranks vstpetsc sweep` of
    ``text`` over ``setting`` into a new folder, and the sum of its runs'
    own wall times (from summary.csv)."""
    case = os.path.join(folder, "case.toml")
    with open(case, "w") as f:
        f.write(text)
    out = os.path.join(folder, tag)
    cmd = ["mpirun", "-n", str(ranks), VSTPETSC, "sweep", case, "--set", setting, "-o", out,
           "--quiet"]
    cpu, t0 = children_cpu(), time.perf_counter()
    subprocess.run(cmd, capture_output=True, check=True)
    seconds, cpu = time.perf_counter() - t0, children_cpu() - cpu
    with open(os.path.join(out, "summary.csv")) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == setting.count(",") + 1 and all(r["status"] == "completed" for r in rows)
    return seconds, cpu, sum(float(r["wall_time"]) for r in rows)


def speedup(case, text, reps=3, setting=BAR_SET, companions=()):
    """One row: wall of the sweep of ``text`` over ``setting`` on 1 and 2
    ranks (min, median), the speed-up, the CPU seconds (median) and the
    runs' own time on each (their sum, the least over the repetitions), 1
    and 2 ranks interleaved; ``companions``: files the case reads, copied
    beside it."""
    got, load = {1: [], 2: []}, os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as folder:
        for path in companions:
            shutil.copy(path, folder)
        for rep in range(reps):
            for ranks in (1, 2):
                got[ranks].append(sweep_seconds(folder, ranks, f"s{ranks}-{rep}", text, setting))
    wall = {p: [g[0] for g in got[p]] for p in got}
    cpu = {p: statistics.median(g[1] for g in got[p]) for p in got}
    one, two = wall[1], wall[2]
    return {"case": case, "runs": setting.count(",") + 1, "one_min_s": min(one),
            "one_median_s": statistics.median(one),
            "two_min_s": min(two), "two_median_s": statistics.median(two),
            "speedup": min(one) / min(two),
            "speedup_median": statistics.median(one) / statistics.median(two),
            "cpu_one_s": cpu[1], "cpu_two_s": cpu[2],
            "cores_one": cpu[1] / statistics.median(one), "cores_two": cpu[2] / statistics.median(two),
            "run_sum_one_s": min(g[2] for g in got[1]), "run_sum_two_s": min(g[2] for g in got[2]),
            "date": time.strftime("%Y-%m-%d"), "load": load}


def plane_speedup(reps=3):
    """The plane-strain row: gravity-dam's sweep of 4 record scales."""
    text, companions = plane_dam()
    return speedup(PLANE_CASE, text, reps, PLANE_SET, companions)


def sweep_speedup(slabs, reps=3):
    """The refined bar-wall's row, runs of ``slabs`` slabs."""
    return {"slabs": slabs, **speedup(f"2000 elements, {slabs} slabs", case_text(slabs=slabs), reps)}


def head():
    """The table's head (markdown lines)."""
    return ["| case | 1 rank [s] min / median | 2 ranks [s] min / median | "
            "speed-up min / median | CPU [s] 1 / 2 ranks | busy cores 1 / 2 ranks | "
            "runs' sum [s] 1 / 2 ranks |", "|---|---|---|---|---|---|---|"]


def table(row):
    """Markdown lines for the row."""
    return [f"| {row['case']} | {row['one_min_s']:.2f} / {row['one_median_s']:.2f} | "
            f"{row['two_min_s']:.2f} / {row['two_median_s']:.2f} | "
            f"{row['speedup']:.2f} / {row['speedup_median']:.2f} | "
            f"{row['cpu_one_s']:.2f} / {row['cpu_two_s']:.2f} | "
            f"{row['cores_one']:.2f} / {row['cores_two']:.2f} | "
            f"{row['run_sum_one_s']:.2f} / {row['run_sum_two_s']:.2f} |"]


def section(rows, reps, load):
    """The README section (``load``: the 1-minute load average before; the
    first row's date and load when it has them)."""
    date, load = rows[0].get("date", time.strftime("%Y-%m-%d")), rows[0].get("load", load)
    lines = [SECTION, "",
             f"Generated by `bench/sweep_speed.py` (`make bench`) on {os.uname().nodename} "
             f"{os.cpu_count()} cores, {date}, load average {load:.1f} "
             "before. `mpirun -n P vstpetsc sweep` "
             f"of 8 runs (v0 = {VALUES}), start-up included, {reps} repetitions, 1 and 2 ranks "
             "interleaved; goal 2 ranks >= 1.8 x one for bar-wall to 20 ms with a row every "
             "slab. CPU: user + system seconds of mpirun and its ranks (median); busy cores: "
             "CPU over the median wall. Runs' sum: the runs' own wall times (least over the "
             "repetitions). The row of bar-wall for 2 slabs is start-up and the runs' fixed "
             "costs alone. On a "
             "machine shared with other work the two ranks get less than two cores: then the "
             "busy cores, not the speed-up, show what the sweep asks for.", ""]
    plane = [r for r in rows if r["case"] == PLANE_CASE]
    if plane:
        lines += [plane_note(plane[0]), ""]
    return "\n".join(lines + head() + [line for r in rows for line in table(r)]) + "\n"


def plane_note(row):
    """The plane-strain row's words: its case, when it was measured, and
    whether the two ranks had two cores."""
    shared = (f" The two ranks kept {row['cores_two']:.2f} cores busy: other work shared the "
              "machine, a noisy row." if row["cores_two"] < 1.8 else "")
    return (f"The 2-D row (issue 48): the bundled gravity-dam (639 cells, its base an "
            f"interface) to 1 s, 4 runs ({PLANE_SET}), one rank a run; measured "
            f"{row.get('date', '?')}, load average {row.get('load', float('nan')):.1f} before. "
            "4 runs on 2 ranks are at best (S + 4 r) / (S + 2 r) times faster than on one "
            "(start-up S, runs of r seconds)." + shared)


def main(reps=3, plane_only=False):
    load = os.getloadavg()[0]
    path = os.path.join(HERE, "sweeps.json")
    if plane_only:              # the other rows as they were measured
        with open(path) as f:
            rows = [r for r in json.load(f) if r["case"] != PLANE_CASE]
        rows.append(plane_speedup(reps))
    else:
        rows = [speedup("bar-wall to 20 ms, a row every slab (goal)", bar_wall(0.02), reps),
                sweep_speedup(15_000, reps),
                speedup("bar-wall, 2 slabs (fixed costs)", bar_wall(4.0e-6), reps),
                plane_speedup(reps)]
    with open(path, "w") as f:
        json.dump(rows, f, indent=1)
    write_readme(os.path.join(HERE, "README.md"), section(rows, reps, load))
    for r in rows:
        print(table(r)[0])


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--plane"]
    main(int(args[0]) if args else 3, "--plane" in sys.argv[1:])
