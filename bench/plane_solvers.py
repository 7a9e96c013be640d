"""The linear solve of a plane-strain slab (issue 37: choose the default by
measurement): the slab matrix [A] = HM (x) M + dt HC (x) C + dt^2 HK (x) K
of a rectangle of quadrilaterals (averaged mass, c dt / h = 1 for the P
wave by default, `--courant 1,4,16` for others), factored by PETSc's LU (nested
dissection) and by the external direct solvers Debian's PETSc has, and
solved by GMRES preconditioned by block Jacobi with ILU(0) (the slab
matrix is mass-dominated at these Courant numbers).  One rank; set-up
(factorisation) and one solve, min / median of REPEATS solves, in one
process, interleaved.

    .venv/bin/python bench/plane_solvers.py [CELLS ...] [--courant 1,4,16]
"""

import statistics
import sys
import time

import numpy as np
from petsc4py import PETSc

from vstpetsc.spacetime import slab
from vstpetsc.plane import assembly, elements, mesh as plane_mesh
from vstpetsc.plane.solver import matrices

REPEATS = 7
SOLVERS = {
    "LU petsc (nd)": {"pc_type": "lu", "pc_factor_mat_ordering_type": "nd"},
    "LU mumps": {"pc_type": "lu", "pc_factor_mat_solver_type": "mumps"},
    "LU umfpack": {"pc_type": "lu", "pc_factor_mat_solver_type": "umfpack"},
    "LU superlu": {"pc_type": "lu", "pc_factor_mat_solver_type": "superlu"},
    "GMRES + ILU(0)": {"ksp_type": "gmres", "pc_type": "ilu", "ksp_rtol": 1e-12},
}


def slab_matrix(cells, courant=1.0):
    n = int(round(np.sqrt(cells)))
    m = plane_mesh.rectangle((0.0, float(n)), (0.0, float(n)), n, n)
    lam, mu = elements.lame(2.0e8, 0.3)
    M, K = assembly.matrices(m, lam, mu, 2000.0, "averaged")
    vp = np.sqrt((lam + 2 * mu) / 2000.0)
    A = slab.sparse_slab_matrix(M, None, K, courant / vp)      # h = 1
    return matrices.petsc_matrix(A), m.ncells


def measure(A, options):
    opts = PETSc.Options()
    prefix = "bench_"
    for k, v in options.items():
        opts[prefix + k] = v
    ksp = PETSc.KSP().create(comm=PETSc.COMM_SELF)
    ksp.setOptionsPrefix(prefix)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.setFromOptions()
    x, b = A.createVecs()
    b.setRandom()
    start = time.perf_counter()
    ksp.setUp()
    setup = time.perf_counter() - start
    times = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        ksp.solve(b, x)
        times.append(time.perf_counter() - start)
    r = b.duplicate()
    A.mult(x, r)
    r.axpy(-1.0, b)
    for k in options:
        opts.delValue(prefix + k)
    return setup, min(times), statistics.median(times), r.norm() / b.norm(), ksp.getIterationNumber()


def main(sizes=(10000, 100000), courants=(1.0,)):
    print("| cells | unknowns | c dt / h | solver | set-up s | solve ms, min | median | "
          "relative residual | iterations |")
    print("|---|---|---|---|---|---|---|---|---|")
    for cells in sizes:
        for courant in courants:
            A, ncells = slab_matrix(cells, courant)
            for name, options in SOLVERS.items():
                setup, lo, med, res, its = measure(A, options)
                print(f"| {ncells} | {A.getSize()[0]} | {courant:g} | {name} | {setup:.3f} | "
                      f"{1e3 * lo:.2f} | {1e3 * med:.2f} | {res:.1e} | {its} |", flush=True)


if __name__ == "__main__":
    # CELLS ... [--courant C,C,...]
    args = sys.argv[1:]
    courants = (1.0,)
    if "--courant" in args:
        i = args.index("--courant")
        courants = tuple(float(c) for c in args[i + 1].split(","))
        del args[i:i + 2]
    main(*([int(float(a)) for a in args],) if args else (), courants=courants)
