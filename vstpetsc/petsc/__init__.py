"""What of petsc4py both geometries share: options, the collectives over
ranks (:mod:`vstpetsc.petsc.ranks`) and the translation of PETSc's errors.
The slab matrices, the factored linear solver and Newton on the laws' dofs
are each room's (:mod:`vstpetsc.line.solver`, :mod:`vstpetsc.plane.solver`).

``initialize(args)`` starts PETSc with command-line options when it has not
started yet (options such as -log_view act only at start-up).
"""

import atexit
import os
import sys
import weakref


# Open MPI's start-up of a process that mpirun did not launch (a
# "singleton") spawns a helper daemon and probes every transport: 0.4 s of
# waiting (measured: `from petsc4py import PETSc` 0.58 s, 0.23 s with
# these).  A singleton talks only to itself; a user's own setting wins.
SINGLETON_MPI = {"OMPI_MCA_ess_singleton_isolated": "1", "OMPI_MCA_pml": "ob1",
                 "OMPI_MCA_btl": "self"}
LAUNCHED = ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK")
# Launched by Open MPI's mpirun with every rank on this node: shared memory
# carries all messages, and the default pml's start-up (UCX probing the
# network hardware) costs 0.2 s a rank (MPI_Init 0.33 s, 0.13 s with
# these; a sweep of short runs on two ranks feels it).  Ranks on several
# nodes keep Open MPI's defaults; a user's own setting wins.
ONE_NODE_MPI = {"OMPI_MCA_pml": "ob1", "OMPI_MCA_btl": "self,vader"}


# the options that PETSc was started with by initialize(): a run's own,
# which its scoped() block removes again (except those read when PETSc
# ends, such as -log_view), so that later runs of the process do not
# inherit them
STARTED_WITH = set()
AT_FINALIZE = ("log_", "malloc", "memory_", "options_left", "info")


def initialize(args=()):
    """Start PETSc (with ``args`` as its command line if it has not started
    yet) and return the PETSc module."""
    if "petsc4py.PETSc" not in sys.modules:
        STARTED_WITH.update(a.lstrip("-") for a in args
                            if a.startswith("-") and not a.lstrip("-").startswith(AT_FINALIZE))
        if "mpi4py.MPI" not in sys.modules:
            for key, value in _mpi_defaults(os.environ).items():
                os.environ.setdefault(key, value)
        import petsc4py
        petsc4py.init([sys.argv[0] if sys.argv and sys.argv[0] else "vstpetsc", *args])
    from petsc4py import PETSc
    return PETSc


# petsc4py 3.18 hands the objects Python lets go to PETSc's garbage (see
# release); what is left of it when PETSc ends is destroyed then, after
# the interpreter has gone, and an object whose type calls into Python (a
# Python matrix or preconditioner: its context) crashes the process there
# (SEGV, exit 59).  Each such object that still lives is made a plain one
# at exit (``how``), and the garbage destroyed, while Python runs.
_PLAIN_AT_EXIT = {}     # id: (weak reference, how)
_HOOKED = []


def plain_before_petsc_ends(obj, how):
    """Call ``how(obj)`` at exit if ``obj`` (a petsc4py object) still lives
    then: make it a type that needs no Python (a Python matrix a shell, a
    Python preconditioner none)."""
    if not _HOOKED:
        # registered after petsc4py's own hook (petsc4py is imported: obj
        # is its object), so run before it
        atexit.register(_before_petsc_ends)
        _HOOKED.append(True)
    key = id(obj)
    _PLAIN_AT_EXIT[key] = (weakref.ref(obj, lambda _: _PLAIN_AT_EXIT.pop(key, None)), how)


def python_preconditioner(ksp, context):
    """Make ``ksp``'s preconditioner the Python ``context``, plain again
    before PETSc ends (plain_before_petsc_ends)."""
    pc = ksp.getPC()
    pc.setType("python")
    pc.setPythonContext(context)
    plain_before_petsc_ends(ksp, lambda ksp: ksp.getPC().setType("none"))


def python_context(ksp, kind):
    """The Python context of ``ksp``'s preconditioner if it is a direct
    solve (KSP preonly) by an object of type ``kind``, else None."""
    pc = ksp.getPC()
    if ksp.getType() != "preonly" or pc.getType() != "python":
        return None
    context = pc.getPythonContext()
    return context if isinstance(context, kind) else None


def _before_petsc_ends():
    for alive, how in list(_PLAIN_AT_EXIT.values()):
        obj = alive()
        if obj is not None:
            how(obj)
    from petsc4py import PETSc

    release(PETSc.COMM_WORLD)


def _mpi_defaults(env):
    """The Open MPI settings for a process that starts MPI: a singleton's,
    or those of ranks that mpirun placed on one node."""
    if not any(var in env for var in LAUNCHED):
        return SINGLETON_MPI
    size = env.get("OMPI_COMM_WORLD_SIZE")
    if size is not None and size == env.get("OMPI_COMM_WORLD_LOCAL_SIZE"):
        return ONE_NODE_MPI if not any(k in env for k in ONE_NODE_MPI) else {}
    return {}


def communicator(comm=None):
    """A PETSc communicator from a PETSc or mpi4py one (default: every rank)."""
    PETSc = initialize()
    return PETSc.COMM_WORLD if comm is None else PETSc.Comm(comm)


def release(comm, collect=True):
    """Destroy the PETSc objects Python has let go (collective on the PETSc
    communicator ``comm``).  petsc4py 3.18 hands an object whose last
    Python reference goes to PETSc's garbage, destroyed only by
    PETSc.garbage_cleanup or when PETSc ends: a process that runs case
    after case (a sweep, the API, the tests) would keep every run's
    matrices (measured: a 1.2 GB matrix let go kept its memory until
    cleaned up; tests/test_plane_memory.py).  ``collect``: Python's cyclic
    garbage collected first (5-50 ms with the objects of a process)."""
    import gc

    PETSc = initialize()
    if collect:                 # (a solver and its restart refer to each other)
        gc.collect()
    PETSc.garbage_cleanup(comm)
    if comm.getSize() > 1:
        PETSc.garbage_cleanup(PETSc.COMM_SELF)


def rank():
    """This process's MPI rank, without starting MPI when it has not started
    (the command line validates input before, and only rank 0 speaks)."""
    if "petsc4py.PETSc" in sys.modules:
        return sys.modules["petsc4py.PETSc"].COMM_WORLD.getRank()
    for var in ("OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"):
        if os.environ.get(var, "").isdigit():
            return int(os.environ[var])
    return 0
