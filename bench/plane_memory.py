"""Memory and time of a plane-strain run by size (issue 48): the square
of bench/plane_slab.py (quadrilaterals, absorbing base, an incident
wave, c dt / h = 1) at 1e4, 1e5 and 1e6 cells, solved by GMRES + ILU(0)
(rtol 1e-12: the option that fits 1e6 cells on one rank), with the
slab matrix in 4 x 4 node blocks (the default, BAIJ), as one value
an index (AIJ, -vst_plane_blocks 0), and matrix-free (-vst_plane_matrix_free:
the blocks only set up the ILU, then go). Each size and form in a process of
its own: its peak resident memory (getrusage), set-up (mesh, matrices,
factors) and the slab's ms (min / median of REPEATS batches of BATCH
slabs). The goal: 1e6 cells within 4 GB and no slower than 1.4 s a slab.

    .venv/bin/python bench/plane_memory.py [CELLS ...]
"""

import json
import os
import resource
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SIZES = (10_000, 100_000, 1_000_000)
# each form's options (prefix vst_plane_)
FORMS = {"BAIJ(4)": {"blocks": "1"}, "AIJ": {"blocks": "0"},
         "matrix-free": {"blocks": "1", "matrix_free": "1"}}
REPEATS = 3


def child(cells, form):
    """In the child process: one size and form, its figures as JSON."""
    from petsc4py import PETSc

    opts = PETSc.Options()
    for key, value in [("ksp_type", "gmres"), ("pc_type", "ilu"), ("ksp_rtol", "1e-12")] + \
            list(FORMS[form].items()):
        opts[f"vst_plane_{key}"] = value
    import plane_slab

    plane_slab.BATCH = 5
    solver, loads, setup = plane_slab.build(plane_slab.square_case(cells))
    times = [plane_slab.slabs(solver, loads, plane_slab.BATCH * k) for k in range(REPEATS)]
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024       # kB on Linux
    print(json.dumps({"cells": cells, "nodes": int(solver.model.nnodes), "peak": peak,
                      "iterations": solver.ksp.getIterationNumber(),
                      "setup": setup, "min_ms": 1e3 * min(times),
                      "median_ms": 1e3 * statistics.median(times)}))


def measure(sizes):
    rows = []
    for cells in sizes:
        for form in FORMS:
            out = subprocess.run([sys.executable, __file__, "--child", str(cells), form],
                                 capture_output=True, text=True, check=True, cwd=HERE)
            row = json.loads(out.stdout.strip().splitlines()[-1])
            row["form"] = form
            rows.append(row)
            print(f"{cells:8d} {form:8s} peak {row['peak'] / 1e9:6.2f} GB "
                  f"({row['peak'] / row['nodes'] / 1e3:.2f} kB a node), set-up "
                  f"{row['setup']:.1f} s, slab {row['min_ms']:.1f} / {row['median_ms']:.1f} ms",
                  flush=True)
    return rows


def section(rows):
    """The README's section of the measured ``rows``."""
    lines = ["## Memory by size (issue 48)", "",
             "bench/plane_memory.py: the square of bench/plane_slab.py (quadrilaterals, "
             "absorbing base, an incident wave, c dt / h = 1), GMRES + ILU(0) (rtol 1e-12), one "
             "rank, each size and form in a process of its own: its peak resident memory, "
             "set-up, ms a slab (min / median of 3 batches of 5). BAIJ(4): the slab matrix in "
             "4 x 4 node blocks (the default); AIJ: `-vst_plane_blocks 0` (both with the spatial "
             "matrices assembled in chunks of cells); matrix-free: `-vst_plane_matrix_free 1` "
             "(the slab's products from M, C, K; the blocks set up the ILU(0) and go). "
             "GMRES iterations a slab in the last column. The goal: 1e6 cells within 4 GB, no "
             "slower than 1.4 s a slab (2026-11-29, before both: 8.86 GB, 1.4 s, set-up 50 s: "
             "bench/README.md above).", "",
             "| cells | form | peak GB | kB a node | set-up s | slab ms (min / median) | "
             "iterations |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['cells']:.0e} | {r['form']} | {r['peak'] / 1e9:.2f} | "
                     f"{r['peak'] / r['nodes'] / 1e3:.2f} | {r['setup']:.1f} | "
                     f"{r['min_ms']:.1f} / {r['median_ms']:.1f} | {r.get('iterations', '')} |")
    return "\n".join(lines) + "\n"


def main(argv):
    if argv[:1] == ["--child"]:
        sys.path.insert(0, HERE)
        return child(int(argv[1]), argv[2])
    sizes = [int(float(a)) for a in argv] or list(SIZES)
    rows = measure(sizes)
    if not argv:
        sys.path.insert(0, HERE)
        from plane_interfaces import keep
        keep("plane_memory", rows, section)


if __name__ == "__main__":
    main(sys.argv[1:])
