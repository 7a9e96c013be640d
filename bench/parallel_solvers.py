"""Time per slab of the linear slab solve with several solvers on 1 and 2
ranks (issue 5): a clamped bar without contact, c dt / h = 1.

Writes bench/parallel.json and the table bench/parallel.md.
Run: make bench-parallel   (ELEMENTS=1000000 SLABS=40 by default)
"""

import json
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

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
    "additive Schwarz, overlap 32, LU per rank (default on several ranks)": [
        "-pc_type", "asm", "-pc_asm_overlap", "32", "-sub_pc_type", "lu",
        "-sub_pc_factor_mat_ordering_type", "natural"],
}


def case_text(elements, slabs):
    c = np.sqrt(2.0e11 / 7850.0)
    dt = 1.0 / elements / c
    return (f"[time]\ndt = {dt!r}\nend = {slabs * dt!r}\n[output]\nevery = 10\n"
            f"[[body]]\nname = \"bar\"\nx = [0.0, 1.0]\nelements = {elements}\n"
            "E = 2.0e11\nrho = 7850.0\nv0 = [[0.0, 0.0], [1.0, 1.0]]\n"
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


def run_seconds(folder, ranks, text):
    """Seconds of a run after its set-up (no output but the first and last rows)."""
    case = os.path.join(folder, "s.toml")
    with open(case, "w") as f:
        f.write(text)
    out = os.path.join(folder, f"s{ranks}.h5")
    cmd = [VSTPETSC, "run", case, "-o", out, "--quiet"]
    if ranks > 1:
        cmd = ["mpirun", "-n", str(ranks)] + cmd
    subprocess.run(cmd, capture_output=True, check=True)
    with h5py.File(out) as f:
        return float(f.attrs["wall_time"] - f.attrs["setup_time"])


def speedup(elements, slabs, reps=3):
    """Per-slab time of 1 rank (its LU) and 2 ranks (the default, additive
    Schwarz) from the difference of runs of ``slabs`` and 3 ``slabs``
    slabs without output (fixed costs cancel): min and median over reps,
    and the ratios."""
    times = {1: [], 2: []}
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(reps):
            for ranks in (1, 2):
                short, long = (run_seconds(folder, ranks, case_text(elements, n).replace(
                    "every = 10", "every = 1000000000")) for n in (slabs, 3 * slabs))
                times[ranks].append((long - short) / (2 * slabs))
    one, two = (np.array(times[r]) for r in (1, 2))
    return {"elements": elements, "slabs": slabs, "one_min_ms": 1e3 * one.min(),
            "one_median_ms": 1e3 * np.median(one), "two_min_ms": 1e3 * two.min(),
            "two_median_ms": 1e3 * np.median(two), "speedup": one.min() / two.min(),
            "speedup_median": float(np.median(one) / np.median(two))}


def main(elements=None, slabs=None, *only):
    elements = int(elements or os.environ.get("ELEMENTS", 1_000_000))
    slabs = int(slabs or os.environ.get("SLABS", 40))
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
    speed = [speedup(n, m) for n, m in ((100_000, 300), (elements, 40))]
    with open(os.path.join(HERE, "parallel.json"), "w") as f:
        json.dump({"elements": elements, "slabs": slabs, "rows": rows, "speedup": speed}, f,
                  indent=1)
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
    lines += ["", "Speed-up of the default: time per slab from the difference of runs of n and "
              "3n slabs without output (set-up and the first and last rows cancel), 3 "
              "repetitions; goal 2 ranks >= 1.6 x one rank at 1e6, faster at 1e5.", "",
              "| elements | 1 rank (LU) [ms] min / median | 2 ranks (Schwarz) [ms] min / median "
              "| speed-up min / median |", "|---|---|---|---|"]
    for r in speed:
        lines.append(f"| {r['elements']} | {r['one_min_ms']:.2f} / {r['one_median_ms']:.2f} | "
                     f"{r['two_min_ms']:.2f} / {r['two_median_ms']:.2f} | "
                     f"{r['speedup']:.2f} / {r['speedup_median']:.2f} |")
    with open(os.path.join(HERE, "parallel.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
