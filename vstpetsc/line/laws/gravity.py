"""Gravity: the body force rho A g(t) along +x on every body, and m g(t) on
every support mass.  Its consistent nodal load is the row sums of M (the
bars' masses and the support masses) times g (docs/loads.md section 1), on
the axial field only (gravity is along x; the shear motion is across)."""

from vstpetsc.line.laws.base import FieldLoad, Law


class Gravity(Law):
    def __init__(self, spec, axial_nodes):
        self.g = spec.g
        self.axial_nodes = axial_nodes
        self.ops = None

    def add_operators(self, ops):
        self.ops = ops      # read in loads(), after every law added its masses

    def loads(self):
        ops = self.ops
        lumped = ops.m_diag.copy()
        lumped[:-1] += ops.m_off
        lumped[1:] += ops.m_off
        lumped[self.axial_nodes:] = 0.0
        return [FieldLoad(lumped, self.g)]

    def static_loads(self):
        """The weight at g(0), whatever g does later: a static start is the
        state under the initial gravity, and g(t) - g(0) acts dynamically."""
        return self.loads()

    def describe(self):
        g = self.g
        what = f"g = {g.f[0]:g}" if g.is_constant else f"g(t) ({g.t.size} points)"
        return f"gravity: {what} along +x"


def build(spec, mesh):
    return Gravity(spec, mesh.axial_nodes)
