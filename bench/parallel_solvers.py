"""Time per slab of the linear slab solve with several solvers on 1 and 2
ranks (issue 5): a clamped bar without contact, c dt / h = 1.

Writes bench/parallel.json and the table bench/parallel.md.
Run: make bench-parallel   (ELEMENTS=1000000 SLABS=40 by default; REPS=3
repetitions of the speed-up rows)
     bench/parallel_solvers.py [ELEMENTS [SLABS [SOLVER ...]]]  only those solvers' rows
     bench/parallel_solvers.py --speedup [ELEMENTS]   only the speed-up rows again; the
                                    solver table and the sweeps kept from parallel.json
"""

import json
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

import sweep_speed
from cases import steel_bar   # no PETSc in this process (see cases.py)

HERE = os.path.dirname(os.path.abspath(__file__))
VSTPETSC = os.path.join(os.path.dirname(sys.executable), "vstpetsc")
SOLVERS = {
    "LU (PETSc)": ["-pc_type", "lu", "-pc_factor_mat_solver_type", "petsc"],
    "LU (MUMPS)": ["-pc_type", "lu", "-pc_factor_mat_solver_type", "mumps"],
    "LU (SuperLU_dist, AIJ)": ["-pc_type", "lu", "-pc_factor_mat_solver_type", "superlu_dist",
                               "-vst_mat_type", "aij"],
    "GMRES + block Jacobi LU (natural)": ["-ksp_type", "gmres", "-pc_type", "bjacobi",
                                          "-sub_pc_type", "lu",
                                          "-sub_pc_factor_mat_ordering_type", "natural"],
    "redundant LU (PETSc, natural)": [
        "-pc_type", "redundant", "-redundant_pc_factor_mat_ordering_type", "natural"],
    "PETSc's additive Schwarz (PCASM), overlap 32, LU per rank": [
        "-pc_type", "asm", "-pc_asm_overlap", "32", "-sub_pc_type", "lu",
        "-sub_pc_factor_mat_ordering_type", "natural"],
    "default (one rank: LU; several: restricted Schwarz written out, overlap 32)": [
        "-pc_asm_overlap", "32"],
}


def case_text(elements, slabs):
    return (steel_bar(elements, slabs, cfl=1.0, every=10) +
            "v0 = [[0.0, 0.0], [1.0, 1.0]]\n"
            "[[bc]]\nbody = \"bar\"\nend = \"left\"\ntype = \"fixed\"\n")


def measure(folder, ranks, options, elements, slabs):
    case = os.path.join(folder, "case.toml")
    with open(case, "w") as f:
        f.write(case_text(elements, slabs))
    out = os.path.join(folder, f"r{ranks}.h5")
    cmd = [VSTPETSC, "run", case, "-o", out, "--quiet", *options]
    if ranks > 1:
        cmd = ["mpirun", "-n", str(ranks)] + cmd
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        lines = [l for l in p.stderr.splitlines() if l.startswith("vstpetsc: error")] or ["?"]
        return {"error": lines[0].replace("vstpetsc: error: ", "").strip()[:160]}
    with h5py.File(out) as f:
        wall = f["solver/wall_time"][:]
        v = f["body/bar/v"][-1]
    per_slab = (wall[-1] - wall[1]) / (slabs - 10)   # kept every 10: skip the first block
    return {"setup_s": float(wall[1] - 10 * per_slab), "ms_per_slab": 1e3 * per_slab,
            "v_end": v.tolist()[-1]}


def run_seconds(folder, ranks, text, copies=1):
    """Seconds of a run after its set-up (no output but the first and last
    rows); with ``copies`` > 1 that many one-rank runs at once, the slowest."""
    case = os.path.join(folder, "s.toml")
    with open(case, "w") as f:
        f.write(text)
    outs = [os.path.join(folder, f"s{ranks}-{k}.h5") for k in range(copies)]
    cmd = [VSTPETSC, "run", case, "--quiet", "-o"]
    if ranks > 1:
        cmd = ["mpirun", "-n", str(ranks)] + cmd
    for p in [subprocess.Popen(cmd + [out], stdout=subprocess.DEVNULL) for out in outs]:
        if p.wait() != 0:
            raise RuntimeError(f"{' '.join(cmd)} failed")
    seconds = []
    for out in outs:
        with h5py.File(out) as f:
            seconds.append(float(f.attrs["wall_time"] - f.attrs["setup_time"]))
    return max(seconds)


def speedup(elements, slabs, reps=3):
    """Per-slab time of 1 rank (its LU), 2 ranks (the default, restricted
    Schwarz) and the ideal (two one-rank runs of half the bar at once: no
    communication, no overlap) from the difference of runs of ``slabs`` and
    3 ``slabs`` slabs without output (fixed costs cancel): min and median
    over reps, and the ratios to one rank."""
    times = {"one": [], "two": [], "halves": []}
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(reps):
            for key, ranks, size, copies in (("one", 1, elements, 1), ("two", 2, elements, 1),
                                             ("halves", 1, elements // 2, 2)):
                short, long = (run_seconds(folder, ranks, case_text(size, n).replace(
                    "every = 10", "every = 1000000000"), copies) for n in (slabs, 3 * slabs))
                times[key].append((long - short) / (2 * slabs))
    out = {"elements": elements, "slabs": slabs, "reps": reps}
    for key, t in times.items():
        out[f"{key}_min_ms"], out[f"{key}_median_ms"] = 1e3 * min(t), 1e3 * np.median(t)
    for key in ("two", "halves"):
        out[f"speedup_{key}"] = min(times["one"]) / min(times[key])
        out[f"speedup_{key}_median"] = float(np.median(times["one"]) / np.median(times[key]))
    return out


def solver_rows(elements, slabs, only):
    """The solver table's rows, each solver on 1 and 2 ranks."""
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for ranks in (1, 2):
            for name, opts in SOLVERS.items():
                if only and name not in only:
                    continue
                m = measure(folder, ranks, opts, elements, slabs)
                rows.append({"ranks": ranks, "solver": name, **m})
                print(ranks, name, m, flush=True)
    ref = next(r for r in rows if r["ranks"] == 1 and "v_end" in r)["v_end"]
    for r in rows:
        if "v_end" in r:
            r["rel_diff_vs_first"] = abs(r["v_end"] - ref) / abs(ref)
    return rows


def solver_table(rows, elements, slabs):
    lines = ["# Linear slab solve: solvers on 1 and 2 ranks", "",
             f"Generated by `bench/parallel_solvers.py`: clamped steel bar, {elements} "
             f"elements ({2 * (elements + 1)} unknowns), c dt / h = 1, no contact, "
             f"{slabs} slabs, output every 10. Time per slab of a whole `vstpetsc run` "
             "(right-hand side, solve, update), setup = matrices and factorisation.", "",
             "| ranks | solver | ms per slab | setup [s] | end velocity vs first row |",
             "|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['ranks']} | {r['solver']} | failed: {r['error']} | | |")
        else:
            lines.append(f"| {r['ranks']} | {r['solver']} | {r['ms_per_slab']:.1f} | "
                         f"{r['setup_s']:.2f} | {r['rel_diff_vs_first']:.1e} |")
    return lines


def speed_table(speed, sweeps):
    reps = speed[0].get("reps", 3)
    lines = ["", "Speed-up of the default: time per slab from the difference of runs of n and "
             "3n slabs without output (set-up and the first and last rows cancel), "
             f"{reps} repetitions; goal 2 ranks >= 1.6 x one rank at 1e6, faster at 1e5. Ideal: two "
             "one-rank runs of half the bar at once (what two cores give with no "
             "communication and no overlap).", "",
             "| elements | slabs | 1 rank (LU) [ms] min / median | 2 ranks [ms] min / median "
             "| speed-up min / median | ideal [ms] min / median | ideal speed-up min / median |",
             "|---|---|---|---|---|---|---|"]
    for r in speed:
        lines.append(f"| {r['elements']} | {r['slabs']} | {r['one_min_ms']:.2f} / "
                     f"{r['one_median_ms']:.2f} | {r['two_min_ms']:.2f} / "
                     f"{r['two_median_ms']:.2f} | {r['speedup_two']:.2f} / "
                     f"{r['speedup_two_median']:.2f} | {r['halves_min_ms']:.2f} / "
                     f"{r['halves_median_ms']:.2f} | {r['speedup_halves']:.2f} / "
                     f"{r['speedup_halves_median']:.2f} |")
    lines += ["", "Sweeps (bench/sweep_speed.py): `mpirun -n P vstpetsc sweep` of 8 runs of "
              "bar-wall at 2000 elements, c dt/h = 1, start-up included; 3 repetitions; goal "
              "2 ranks >= 1.8 x one. CPU: user + system seconds of mpirun and its ranks; busy "
              "cores: CPU over wall. Last column: the runs' own wall times summed (the least "
              "over repetitions), on one rank and on two (two runs at once).", ""]
    lines += sweep_speed.head()
    for r in sweeps:
        lines += sweep_speed.table(r)
    return lines


def main(*args):
    reps = int(os.environ.get("REPS", 3))
    if args[:1] == ("--speedup",):
        # the speed-up rows again (they vary with the hour): the rest of the
        # last full run kept
        with open(os.path.join(HERE, "parallel.json")) as f:
            last = json.load(f)
        elements, slabs, rows, sweeps = (last[k] for k in ("elements", "slabs", "rows", "sweeps"))
        big = int(args[1]) if len(args) > 1 else elements
        speed = [speedup(n, m, reps) for n, m in ((100_000, 300), (big, 100))]
    else:
        given = list(args) + [None, None]
        elements = int(given[0] or os.environ.get("ELEMENTS", 1_000_000))
        slabs = int(given[1] or os.environ.get("SLABS", 40))
        only = args[2:]
        rows = solver_rows(elements, slabs, only)
        speed = [speedup(n, m, reps) for n, m in ((100_000, 300), (elements, 100))]
        sweeps = [sweep_speed.sweep_speedup(n) for n in (15_000, 40_000)]
    with open(os.path.join(HERE, "parallel.json"), "w") as f:
        json.dump({"elements": elements, "slabs": slabs, "rows": rows, "speedup": speed,
                   "sweeps": sweeps}, f, indent=1)
    lines = solver_table(rows, elements, slabs) + speed_table(speed, sweeps)
    with open(os.path.join(HERE, "parallel.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
