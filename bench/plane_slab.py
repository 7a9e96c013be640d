"""A free slab of a plane-strain run against its floor (issue 37): the
whole slab of the run's solver (vstpetsc.plane.solver.slab_solver.PlaneSolver: the
right-hand side's two products, the solve with A's factors, the slab's
energy terms and the update of u and v) against one application of the
slab matrix's factors alone (KSP solve), at 1e4 and 1e5 cells (a square
of quadrilaterals, absorbing base, c dt / h = 1 for the P wave);
set-up (mesh, distribution, assembly, factorisation) against one slab.
One rank, min / median of REPEATS repetitions of BATCH slabs each,
interleaved, in one process.

    .venv/bin/python bench/plane_slab.py [CELLS ...]
"""

import io
import statistics
import sys
import time

import numpy as np
from petsc4py import PETSc

import vstpetsc
from vstpetsc.plane.loads import plane_loads
from vstpetsc.plane.model import PlaneModel
from vstpetsc.plane.solver.slab_solver import PlaneSolver

REPEATS, BATCH = 5, 10


def square_case(cells):
    n = int(round(np.sqrt(cells)))
    vp = 400.0
    return vstpetsc.Case.from_dict({
        "time": {"dt": 1.0 / vp, "end": 1000.0 / vp},
        "mesh": {"rectangle": {"x": [0.0, float(n)], "y": [0.0, float(n)], "nx": n, "ny": n}},
        "region": [{"name": "domain", "Vs": 200.0, "Vp": vp, "rho": 2000.0}],
        "boundary": [{"name": "bottom", "type": "absorbing",
                      "incident": {"x": [[0.0, 0.0], [0.05, 1.0], [0.1, 0.0]]}}]})


def build(case):
    comm = PETSc.COMM_SELF
    t0 = time.perf_counter()
    model = PlaneModel(case, comm)
    loads = plane_loads(model, case.dt)
    solver = PlaneSolver(model, case.dt, comm, loads)
    setup = time.perf_counter() - t0
    u = np.zeros((model.nnodes, 2))
    solver.set_state(u, u)
    return solver, loads, setup


def slabs(solver, loads, k0):
    t0 = time.perf_counter()
    for k in range(k0, k0 + BATCH):
        solver.rhs(*loads.slab(k))
        solver.solve(k)
        solver.advance()
    return (time.perf_counter() - t0) / BATCH


def floor(solver):
    t0 = time.perf_counter()
    for _ in range(BATCH):
        solver.ksp.solve(solver.b, solver.x)
    return (time.perf_counter() - t0) / BATCH


def main(sizes):
    print("| cells | set-up s | set-up / slab | slab ms (min / median) | factors' solve ms "
          "(min / median) | slab / solve (min / median) |")
    print("|---|---|---|---|---|---|")
    for cells in sizes:
        solver, loads, setup = build(square_case(cells))
        whole, alone, k = [], [], 1
        for _ in range(REPEATS):
            whole.append(slabs(solver, loads, k))
            k += BATCH
            alone.append(floor(solver))
        ratio = [w / a for w, a in zip(whole, alone)]
        print(f"| {cells:.0e} | {setup:.2f} | {setup / min(whole):.0f} | {1e3 * min(whole):.2f} / "
              f"{1e3 * statistics.median(whole):.2f} | {1e3 * min(alone):.2f} / "
              f"{1e3 * statistics.median(alone):.2f} | {min(ratio):.2f} / "
              f"{statistics.median(ratio):.2f} |", flush=True)


if __name__ == "__main__":
    main([int(float(a)) for a in sys.argv[1:]] or [10_000, 100_000])
