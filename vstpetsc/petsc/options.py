"""Options: vstpetsc's solvers read PETSc's options database under the
prefix ``vst_`` (``-vst_ksp_type``, ``-vst_snes_monitor``, ...), so that the
``-ksp_*`` options of a user's own PETSc code cannot reach them.

A run's ``options`` (the API's list, the command line's PETSc options) name
them without the prefix, as PETSc users write them: :func:`scoped` adds the
prefix to solver options (``-ksp_*``, ``-pc_*``, ``-snes_*``, ``-sub_*``,
``-redundant_*``, ``-newton_*``), keeps ``-vst_*`` and every other option
(``-log_view``) as given, sets them for the run and restores the database
afterwards.  vstpetsc's own options are read once, by :class:`SolverOptions`.

The string functions here do not start PETSc (the command line uses them
before it does).
"""

import contextlib
from dataclasses import dataclass

from vstpetsc.errors import InputError

PREFIX = "vst_"
SOLVER_FAMILIES = ("ksp_", "pc_", "snes_", "sub_", "redundant_", "newton_")
NEWTONS = ("condensed", "full")
MAT_TYPES = ("baij", "aij")


def parse(args):
    """[(name without dash, value or None)] of an option list such as
    ["-ksp_type", "gmres", "-snes_monitor"]; values may be negative numbers."""
    out, i = [], 0
    args = [str(a) for a in args]
    while i < len(args):
        tok = args[i]
        if not tok.startswith("-") or tok in ("-", "--"):
            raise InputError(f"{tok}: an option must start with '-'")
        value = None
        if i + 1 < len(args) and is_value(args[i + 1]):
            value = args[i + 1]
            i += 1
        out.append((tok.lstrip("-"), value))
        i += 1
    return out


def is_value(tok):
    """Whether a command-line token is an option's value (not an option)."""
    if not tok.startswith("-"):
        return True
    try:
        float(tok)
        return True
    except ValueError:
        return False


def prefixed(name):
    """The database name of option ``name`` as a vstpetsc run reads it."""
    return PREFIX + name if name.startswith(SOLVER_FAMILIES) else name


def translate(args):
    """The option list with vstpetsc's prefix where it belongs."""
    out = []
    for name, value in parse(args):
        out += [f"-{prefixed(name)}"] + ([] if value is None else [value])
    return out


@contextlib.contextmanager
def scoped(args):
    """Set the (prefixed) options ``args`` for the duration of the block."""
    from petsc4py import PETSc

    from vstpetsc import petsc

    opts = PETSc.Options()
    saved = []
    for name, value in parse(args):
        name = prefixed(name)
        # put there by this run's own start of PETSc: not the user's
        ours = name in petsc.STARTED_WITH
        petsc.STARTED_WITH.discard(name)
        saved.append((name, opts.getString(name) if opts.hasName(name) and not ours else False))
        opts.setValue(name, "" if value is None else value)
    try:
        yield
    finally:
        for name, old in reversed(saved):
            if old is False:
                opts.delValue(name)
            else:
                opts.setValue(name, "" if old is None else old)


def default(name, value):
    """Set option ``name`` (already prefixed) unless the user gave it."""
    from petsc4py import PETSc

    opts = PETSc.Options()
    if not opts.hasName(name):
        opts.setValue(name, value)


@dataclass
class SolverOptions:
    """vstpetsc's own options, read once per run.

    - ``-vst_mat_type baij|aij``: storage of the slab matrix (aij for
      solvers that need it, e.g. SuperLU_dist);
    - ``-vst_newton condensed|full``: Newton on the laws' dofs (default) or
      on all unknowns;
    - ``-vst_fd_jacobian``: the laws' tangent by central differences;
    - ``-vst_ownership n0,n1,...``: nodes per rank (the DMDA layout);
    - ``-vst_flush_interval SECONDS``: the longest wall time between two
      blocks of rows written to the result file (0: every kept row);
    - ``-vst_native 0``: the Python path instead of the compiled kernels
      (:mod:`vstpetsc.native`: the Newton for penalty pairs, the end of a
      slab and the copies of kept rows on one rank; the same answer to
      rounding).
    """

    mat_type: str = "baij"
    newton: str = "condensed"
    fd_jacobian: bool = False
    ownership: tuple | None = None
    flush_interval: float = 0.5
    native: bool = True

    @classmethod
    def read(cls, nnodes, size):
        from petsc4py import PETSc

        opts = PETSc.Options()
        mat_type = opts.getString(PREFIX + "mat_type", "baij")
        if mat_type not in MAT_TYPES:
            raise InputError(f"-vst_mat_type: 'baij' or 'aij', got {mat_type!r}")
        newton = opts.getString(PREFIX + "newton", "condensed")
        if newton not in NEWTONS:
            raise InputError(f"-vst_newton: 'condensed' or 'full', got {newton!r}")
        text = opts.getString(PREFIX + "flush_interval", "0.5")
        try:
            interval = float(text)
            assert interval >= 0
        except (ValueError, AssertionError):
            raise InputError(f"-vst_flush_interval: seconds >= 0, got {text!r}") from None
        return cls(mat_type, newton, opts.getBool(PREFIX + "fd_jacobian", False),
                   _ownership(opts, nnodes, size), interval,
                   opts.getBool(PREFIX + "native", True))


def _ownership(opts, nnodes, size):
    """Node counts per rank from -vst_ownership n0,n1,... (None if absent)."""
    if not opts.hasName(PREFIX + "ownership"):
        return None
    text = opts.getString(PREFIX + "ownership")
    try:
        counts = [int(c) for c in text.split(",")]
    except ValueError:
        raise InputError(f"-vst_ownership: node counts separated by commas, got {text!r}") from None
    if len(counts) != size or sum(counts) != nnodes or min(counts) < 1:
        raise InputError(f"-vst_ownership: needs {size} positive counts summing to the "
                          f"{nnodes} nodes, got {text!r}")
    return tuple(counts)
