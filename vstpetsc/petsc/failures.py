"""PETSc's errors in vstpetsc's terms: one line, the right exception."""

from petsc4py import PETSc

from vstpetsc.errors import InputError, SolveFailed


def message(exc):
    """The most specific line of a petsc4py error's traceback."""
    lines = [l.split("]", 1)[-1].strip() for l in str(exc).strip().splitlines()]
    text = [l for l in lines if l and "() at " not in l and not l.startswith("error code")]
    return "; ".join(reversed(text[-2:])) if text else lines[-1]   # most specific first


def setup_error(exc):
    """An InputError for a solver that cannot be set up with the given
    options (nothing is written yet); other exceptions are not PETSc's to
    explain (None)."""
    if isinstance(exc, PETSc.Error):
        return InputError("PETSc could not set up the solver with these options "
                          f"(error {exc.ierr}: {message(exc)})")
    if isinstance(exc, SolveFailed):
        return InputError(f"solver set-up: {exc}; the linear solver options cannot "
                          "solve the slab matrix (nothing was written)")
    return exc if isinstance(exc, InputError) else None


def slab_error(exc, slab):
    """A SolveFailed for a PETSc error inside slab ``slab`` (e.g. an option
    that breaks a solver); ``exc`` itself otherwise."""
    if isinstance(exc, PETSc.Error):
        return SolveFailed(f"slab {slab}: PETSc error {exc.ierr}: {message(exc)}")
    return exc
