"""How close a slab comes to its physical limit: one solve with the factored
slab matrix.  Time per slab of whole `vstpetsc run`s (subprocesses, output
every 10^5 slabs) against one KSPSolve with PETSc's LU factors of the same
matrix, the growth with the number of elements, peak memory, and the cost
of a slab with an active contact pair.

Used by bench/run.py.
"""

import os
import statistics
import subprocess
import sys
import tempfile
import time

import h5py
from petsc4py import PETSc

from cases import steel_bar
from vstpetsc import Case
from vstpetsc.line.model import build_model
from vstpetsc.petsc.options import SolverOptions
from vstpetsc.line.solver.slab_solver import SlabSolver

VSTPETSC = os.path.join(os.path.dirname(sys.executable), "vstpetsc")


def bar_case(elements, slabs, contact=False, cfl=0.5):
    """A steel bar of 1 m: clamped and vibrating, or pressed onto a wall at
    zero gap (every slab of the run then has an active contact pair)."""
    text = steel_bar(elements, slabs, cfl)
    if contact:
        text += "v0 = 1.0\n[[contact]]\npair = [\"bar\", \"wall\"]\nwall = 1.0\n"
    else:
        text += ("v0 = [[0.0, 0.0], [1.0, 1.0]]\n"
                 "[[bc]]\nbody = \"bar\"\nend = \"left\"\ntype = \"fixed\"\n")
    return text


def factored_slab(text):
    """vstpetsc's own linear solve of the slab matrix of the case ``text``
    (the matrix factored with the run's defaults: PETSc's LU, natural
    ordering, BAIJ), and a random right-hand side and a solution vector."""
    case = Case.from_text(text)
    linear = SlabSolver(build_model(case), case.dt, PETSc.COMM_SELF, SolverOptions()).linear
    b, x = linear.ksp.getOperators()[0].createVecs()
    b.setRandom()
    return linear, b, x


def seconds_per_call(call, b, x, solves, reps):
    """(min, median) seconds of one ``call(b, x)`` over ``reps``
    repetitions of ``solves`` calls each (a batch: one call is too short
    for the clock)."""
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        for _ in range(solves):
            call(b, x)
        times.append((time.perf_counter() - t0) / solves)
    return min(times), statistics.median(times)


def solve_time(elements, solves=20, reps=3):
    """Seconds of one solve with the LU factors of the slab matrix of the
    benchmark bar (left end clamped, the case `vstpetsc run` solves below),
    (min, median) over ``reps`` repetitions of ``solves`` solves each: as
    one KSPSolve (the reference) and as one PCApply (KSPSolve without
    zeroing the solution first, what `vstpetsc run` calls)."""
    linear, b, x = factored_slab(bar_case(elements, 10))
    out = []
    for call in (linear.ksp.solve, linear.pc.apply):
        call(b, x)                  # the first call pays for set-up, not timed
        out += seconds_per_call(call, b, x, solves, reps)
    return tuple(out)


def _one_run(folder, elements, slabs, contact):
    """(seconds after setup, peak memory MB) of one `vstpetsc run`."""
    case = os.path.join(folder, "case.toml")
    with open(case, "w") as f:
        f.write(bar_case(elements, slabs, contact))
    out = os.path.join(folder, "r.h5")
    proc = subprocess.Popen([VSTPETSC, "run", case, "-o", out, "--quiet"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError(proc.stderr.read().decode())
    with h5py.File(out) as f:
        wall = f.attrs["wall_time"] - f.attrs["setup_time"]
        if contact and f["contact/0/force"][-1] <= 0.0:
            raise RuntimeError("the contact benchmark has no active contact")
    return wall, usage.ru_maxrss / 1024.0


def run_time(elements, slabs, contact=False, reps=3):
    """Seconds per slab of `vstpetsc run`, (min, median) over repetitions,
    and the peak resident memory in MB.  Each repetition runs ``slabs`` and
    ``2 slabs`` slabs and takes the difference, so fixed costs (setup, the
    first and last output rows) cancel."""
    short, long_, peak = [], [], 0.0
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(reps):
            w1, m1 = _one_run(folder, elements, slabs, contact)
            w2, m2 = _one_run(folder, elements, 2 * slabs, contact)
            short.append(w1)
            long_.append(w2)
            peak = max(peak, m1, m2)
    return (_per_slab(min(long_), min(short), slabs),
            _per_slab(statistics.median(long_), statistics.median(short), slabs), peak)


def _per_slab(long_, short, slabs):
    """(long - short) / slabs; on a busy machine the noise of the two runs
    can exceed the extra slabs' cost (a difference of 0 or less, seen
    under load), and then long / (2 slabs), fixed costs included: an
    upper bound, never a negative time."""
    difference = (long_ - short) / slabs
    return difference if difference > 0 else long_ / (2 * slabs)
