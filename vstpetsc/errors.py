"""The exceptions of vstpetsc, importable without PETSc.

The command line maps them to exit statuses: :class:`CaseError` and
:class:`InputError` to 2, :class:`SolveFailed` to 3, :class:`Interrupted` to
128 + the signal number.
"""


class CaseError(ValueError):
    """A case that cannot be run.

    Attributes
    ----------
    problems : list of str
        One line per defect, ``table.key: what is wrong``, all of them at once.
    """

    def __init__(self, problems):
        self.problems = [one_line(p) for p in problems]
        super().__init__("\n".join(self.problems))


class InputError(ValueError):
    """An option, argument, path or file that cannot be used (one line)."""

    def __init__(self, message):
        super().__init__(one_line(message))


class SolveFailed(RuntimeError):
    """A slab could not be solved; the message names the slab and the reason."""


class Interrupted(RuntimeError):
    """The run stopped on SIGTERM or SIGINT after finishing a slab."""

    def __init__(self, signum, message):
        super().__init__(message)
        self.signum = signum


def one_line(text):
    """``text`` with every non-printable character escaped, so that a message
    stays one line whatever a case file put into names."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(text))
