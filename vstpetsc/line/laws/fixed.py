"""A fixed end: both velocities of its node are zero."""

from vstpetsc.line.laws.base import Constraint
from vstpetsc.line.laws.end import EndLaw

KEYS = ("value",)


def read(chk, tbl, where):
    """``value`` may be given only as 0."""
    value = chk.history(tbl, "value", where, "t")
    if value is None:
        return None
    if not value.is_zero:
        chk.add(f"{where}.value", "a fixed end takes no value other than 0 "
                "(use type = \"velocity\" for a prescribed motion)")
        return None
    return {}


class Fixed(EndLaw):
    def constraints(self):
        return [Constraint(self.node, None)]


def build(spec, index, case, mesh):
    return Fixed(spec, index, case, mesh)
