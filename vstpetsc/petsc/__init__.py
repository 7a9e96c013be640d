"""Everything of vstpetsc that imports petsc4py: the slab matrices, the
factored linear solver, Newton on the laws' dofs, options.

``initialize(args)`` starts PETSc with command-line options when it has not
started yet (options such as -log_view act only at start-up).
"""

import sys


def initialize(args=()):
    """Start PETSc (with ``args`` as its command line if it has not started
    yet) and return the PETSc module."""
    if "petsc4py.PETSc" not in sys.modules:
        import petsc4py
        petsc4py.init([sys.argv[0] if sys.argv and sys.argv[0] else "vstpetsc", *args])
    from petsc4py import PETSc
    return PETSc
