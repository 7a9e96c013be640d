"""What the principal stress envelopes cost per slab (issue 47,
vstpetsc/plane/principal.py): the welded gravity dam of
bench/plane_interfaces.py (cells of about H_CELL, shaken), one rank, its
slab (rhs, solve, advance: the envelopes' update included) against the
update alone (the sparse D B product, the principal stresses, the
maxima) and against gathering the envelopes for a block.  Min / median
of REPEATS batches of BATCH slabs.

    .venv/bin/python bench/plane_principal.py
"""

import statistics
import time

from plane_interfaces import BATCH, H_CELL, build, dam_case, run_slab

REPEATS = 7


def timed(action, n=BATCH):
    t0 = time.perf_counter()
    for _ in range(n):
        action()
    return (time.perf_counter() - t0) / n


def main():
    solver, loads, k, model, _ = build(dam_case(None, H_CELL))
    principal = solver.principal
    slabs, updates, gathers = [], [], []
    for _ in range(REPEATS):
        start = k
        slabs.append(timed(lambda: run_slab(solver, loads, start)))
        k += BATCH
        updates.append(timed(lambda: principal.after_slab(solver.u)))
        gathers.append(timed(principal.gathered))
    show = lambda xs: f"min {1e3 * min(xs):.3f} ms, median {1e3 * statistics.median(xs):.3f} ms"
    print(f"dam at h = {H_CELL:g}: {model.ncells} cells, {model.nnodes} nodes, "
          f"stress operator {principal.B.getInfo()['nz_used']:.0f} non-zeros")
    print(f"  slab (with the update): {show(slabs)}")
    print(f"  the update alone:       {show(updates)}  "
          f"({min(updates) / min(slabs):.2%} of the slab)")
    print(f"  gathering (a block):    {show(gathers)}")


if __name__ == "__main__":
    main()
