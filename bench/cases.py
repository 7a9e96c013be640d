"""The steel bar the benchmarks share, as case-file text.

No PETSc here: bench/parallel_solvers.py and sweep_speed.py start
`mpirun` children, which fail (exit 1, no message) when the parent
process has started Open MPI itself, as importing petsc4py does.
"""

import math

C = math.sqrt(2.0e11 / 7850.0)          # wave speed of steel [m/s]


def steel_bar(elements, slabs, cfl=0.5, every=100000):
    """The [time], [output] and [[body]] tables of a steel bar of 1 m,
    c dt / h = ``cfl`` (the body's v0 and the rest to follow)."""
    dt = cfl / elements / C
    return (f"[time]\ndt = {dt!r}\nend = {slabs * dt!r}\n[output]\nevery = {every}\n"
            f"[[body]]\nname = \"bar\"\nx = [0.0, 1.0]\nelements = {elements}\n"
            "E = 2.0e11\nrho = 7850.0\n")
