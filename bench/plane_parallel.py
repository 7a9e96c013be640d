"""Two ranks against one on plane-strain slabs (issue 37's goal: two ranks
at least 1.6 times faster than one on a 2e5-cell slab loop): a square of
quadrilaterals distributed by DMPlex (vstpetsc.plane.solver.distributed), the
slab matrix's solve by GMRES with block Jacobi / ILU(0) (the only
preconditioner here that distributes) and by MUMPS's LU; per slab: the
right-hand side's products, the solve, the update.  Run under mpirun by
the parent (``main``), which prints one table; min / median of the
slabs' times after the first few.

    .venv/bin/python bench/plane_parallel.py [CELLS] [--ranks 1,2,4] [--all | --solver NAME]

(--ranks beyond the cores oversubscribe them: a check that each solver
runs and what it iterates, not a speed.)
"""

import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SLABS = 12
SOLVERS = {"GMRES + bjacobi/ILU(0)": ["-vst_plane_ksp_type", "gmres", "-vst_plane_pc_type",
                                       "bjacobi", "-vst_plane_sub_pc_type", "ilu",
                                       "-vst_plane_ksp_rtol", "1e-12"],
           "GMRES + ASM(2)/ILU(0)": ["-vst_plane_ksp_type", "gmres", "-vst_plane_pc_type", "asm",
                                     "-vst_plane_pc_asm_overlap", "2",
                                     "-vst_plane_sub_pc_type", "ilu",
                                     "-vst_plane_ksp_rtol", "1e-12"],
           "LU mumps": ["-vst_plane_pc_type", "lu", "-vst_plane_pc_factor_mat_solver_type",
                        "mumps"],
           "GMRES + GAMG (AIJ)": ["-vst_plane_blocks", "0", "-vst_plane_ksp_type", "gmres",
                                  "-vst_plane_pc_type", "gamg", "-vst_plane_ksp_rtol", "1e-12"],
           "every rank's LU (redundant)": ["-vst_plane_pc_type", "redundant"],
           "every rank's LU, written out": ["-vst_plane_whole_lu", "1"],
           # (the default on several ranks; one rank: PETSc's LU)
           "interiors' LU + separator": []}
# the solvers of a plain run (`make bench`); --all: every one of SOLVERS
MAIN = ("GMRES + bjacobi/ILU(0)", "GMRES + ASM(2)/ILU(0)", "LU mumps")


def child(cells, options):
    import numpy as np
    from petsc4py import PETSc

    from vstpetsc.plane import elements, mesh as plane_mesh
    from vstpetsc.plane.solver.distributed import distribute, owned_rows
    from vstpetsc.plane import assembly
    from vstpetsc.plane.solver.stepper import PlaneSlabs

    comm = PETSc.COMM_WORLD
    n = int(round(np.sqrt(cells)))
    m = plane_mesh.rectangle((0.0, float(n)), (0.0, float(n)), n, n)
    start = time.perf_counter()
    local = distribute(m, comm)
    lam, mu = elements.lame(2.0e8, 0.3)
    parts = assembly.element_matrices(local.mesh, lam, mu, 2000.0)
    K = owned_rows(local, [(c, Ke) for c, Ke, _ in parts.values()])
    M = owned_rows(local, [(c, elements.MASSES["averaged"](Me)) for c, _, Me in parts.values()])
    dt = 1.0 / np.sqrt((lam + 2 * mu) / 2000.0)
    slabs = PlaneSlabs(M, None, K, dt, comm=comm, first=2 * local.start)
    setup = time.perf_counter() - start
    u = np.random.default_rng(comm.getRank()).normal(size=2 * (local.stop - local.start)) * 1e-3
    v = np.zeros_like(u)
    times = []
    for _ in range(SLABS):
        comm.barrier()
        t = time.perf_counter()
        u, v = slabs.step(u, v)
        comm.barrier()
        times.append(time.perf_counter() - t)
    twins = stream_twins(comm, slabs.A, 2 * local.size)
    if comm.getRank() == 0:
        print(json.dumps({"setup": setup, "slabs": times[2:],
                          "its": slabs.ksp.getIterationNumber(), **twins}))


def stream_twins(comm, A, total):
    """Memory-bound twins in the same run: a STREAM triad over this rank's
    share of 4 x ``total`` doubles, and a product with the slab matrix
    (min of 10, each between barriers): what two ranks can gain on this
    machine's memory at most."""
    import numpy as np

    n = 4 * total // comm.getSize()
    a, b, c = np.zeros(n), np.ones(n), np.full(n, 2.0)
    x, y = A.createVecs()
    x.set(1.0)
    out = {}
    for name, kernel in (("triad", lambda: np.add(b, 3.0 * c, out=a)),
                         ("matmult", lambda: A.mult(x, y))):
        times = []
        for _ in range(10):
            comm.barrier()
            t = time.perf_counter()
            kernel()
            comm.barrier()
            times.append(time.perf_counter() - t)
        out[name] = min(times)
    return out


def main(cells=200000, ranks=(1, 2), names=MAIN):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    print(f"| {cells} cells | ranks | set-up s | ms a slab, min | median | iterations | "
          "speed-up (min / median) | ceiling: triad, A x |")
    print("|---|---|---|---|---|---|---|---|")
    for name in names:
        rows = {}
        for n in ranks:
            p = subprocess.run(["mpirun", "-n", str(n), sys.executable, __file__, "child",
                                str(cells), *SOLVERS[name]], capture_output=True, text=True,
                               env=env)
            if p.returncode:
                print(f"| {name} | {n} | failed: {p.stderr.strip().splitlines()[-1:]} |")
                continue
            rows[n] = json.loads(p.stdout.strip().splitlines()[-1])
        for n, r in rows.items():
            lo, med = min(r["slabs"]), statistics.median(r["slabs"])
            base = rows.get(1)
            speed = ceiling = ""
            if n > 1 and base is not None:
                speed = f"{min(base['slabs']) / lo:.2f} / " \
                        f"{statistics.median(base['slabs']) / med:.2f}"
                ceiling = f"{base['triad'] / r['triad']:.2f}, {base['matmult'] / r['matmult']:.2f}"
            print(f"| {name} | {n} | {r['setup']:.2f} | {1e3 * lo:.1f} | {1e3 * med:.1f} | "
                  f"{r['its']} | {speed} | {ceiling} |", flush=True)


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "child":
        from petsc4py import init
        init(sys.argv[3:])
        child(int(sys.argv[2]), sys.argv[3:])
    else:
        args = sys.argv[1:]
        ranks = (1, 2)
        if "--ranks" in args:
            at = args.index("--ranks")
            ranks = tuple(int(r) for r in args[at + 1].split(","))
            del args[at:at + 2]
        names = tuple(SOLVERS) if "--all" in args else MAIN
        if "--solver" in args:
            at = args.index("--solver")
            names = (args[at + 1],)
            del args[at:at + 2]
        args = [a for a in args if a != "--all"]
        main(*(int(float(a)) for a in args[:1]), ranks=ranks, names=names)
