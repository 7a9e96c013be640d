"""A prescribed velocity history at an end: v^1 = vh(t^n), v^2 = vh(t^{n+1})."""

from vstpetsc.line.laws.base import Constraint
from vstpetsc.line.laws.end import EndLaw

KEYS = ("value",)


def read(chk, tbl, where):
    value = chk.history(tbl, "value", where, "t", required=True, records=True)
    return None if value is None else {"value": value}


class Velocity(EndLaw):
    def constraints(self):
        return [Constraint(self.node, self.spec.params["value"])]


def build(spec, index, case, mesh):
    return Velocity(spec, index, case, mesh)
