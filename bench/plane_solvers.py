"""The linear solve of a plane-strain slab (issue 37: choose the default by
measurement): the slab matrix [A] = HM (x) M + dt HC (x) C + dt^2 HK (x) K
of a rectangle of quadrilaterals (averaged mass, c dt / h = 1 for the P
wave: the Courant numbers people run), factored by PETSc's LU (nested
dissection) and by the external direct solvers Debian's PETSc has, and
solved by GMRES preconditioned by block Jacobi with ILU(0) (the slab
matrix is mass-dominated at these Courant numbers).  One rank; set-up
(factorisation) and one solve, min / median of REPEATS solves, in one
process, interleaved.

    .venv/bin/python bench/plane_solvers.py [CELLS ...]
"""

import statistics
import sys
import time

import numpy as np
from petsc4py import PETSc

from vstpetsc import slab
from vstpetsc.plane import assembly, elements, mesh as plane_mesh

REPEATS = 7
SOLVERS = {
    "LU petsc (nd)": {"pc_type": "lu", "pc_factor_mat_ordering_type": "nd"},
    "LU mumps": {"pc_type": "lu", "pc_factor_mat_solver_type": "mumps"},
    "LU umfpack": {"pc_type": "lu", "pc_factor_mat_solver_type": "umfpack"},
    "LU superlu": {"pc_type": "lu", "pc_factor_mat_solver_type": "superlu"},
    "GMRES + ILU(0)": {"ksp_type": "gmres", "pc_type": "ilu", "ksp_rtol": 1e-12},
}


def slab_matrix(cells):
    n = int(round(np.sqrt(cells)))
    m = plane_mesh.rectangle((0.0, float(n)), (0.0, float(n)), n, n)
    lam, mu = elements.lame(2.0e8, 0.3)
    M, K = assembly.matrices(m, lam, mu, 2000.0, "averaged")
    vp = np.sqrt((lam + 2 * mu) / 2000.0)
    A = slab.sparse_slab_matrix(M, None, K, 1.0 / vp)
    return assembly.petsc_matrix(A), m.ncells


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


def main(sizes=(10000, 100000)):
    print("| cells | unknowns | solver | set-up s | solve ms, min | median | relative residual "
          "| iterations |")
    print("|---|---|---|---|---|---|---|---|")
    for cells in sizes:
        A, ncells = slab_matrix(cells)
        for name, options in SOLVERS.items():
            setup, lo, med, res, its = measure(A, options)
            print(f"| {ncells} | {A.getSize()[0]} | {name} | {setup:.3f} | {1e3 * lo:.2f} | "
                  f"{1e3 * med:.2f} | {res:.1e} | {its} |", flush=True)


if __name__ == "__main__":
    main(*([int(a) for a in sys.argv[1:]],) if len(sys.argv) > 1 else ())
