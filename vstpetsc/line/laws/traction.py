"""A traction history at an end: force per unit area along +x (t = sigma n),
times the area of the end element, integrated exactly against the time
shape functions."""

from vstpetsc.line.laws.base import Load
from vstpetsc.line.laws.end import EndLaw

KEYS = ("value",)


def read(chk, tbl, where):
    value = chk.history(tbl, "value", where, "t", required=True, records=True)
    return None if value is None else {"value": value}


class Traction(EndLaw):
    def __init__(self, spec, index, case, mesh):
        super().__init__(spec, index, case, mesh)
        self.area = float(mesh.A[self.element])

    def loads(self):
        return [Load(self.node, self.area, self.spec.params["value"])]


def build(spec, index, case, mesh):
    return Traction(spec, index, case, mesh)
