"""The nonlinear terms of a plane-strain slab's Newton
(vstpetsc.plane.solver.contact_newton), each at its own unknowns z (m, w)
gathered on rank 0 (a PairDofs): ``evaluate(z)`` gives its residual's
entries beyond A_c and whether it is linear there (its step then one solve
with A_c), ``apply(dz)`` its Jacobian's entries beyond A_c times dz;
``values`` and ``z`` the last evaluation's (the held dofs' work)."""

import numpy as np


class PairTerm:
    """Interface pairs (vstpetsc.plane.pairs.PairSet): f - W_c y beyond
    A_c's closed, sticking springs."""

    def __init__(self, pairs, dofs):
        self.pairs, self.dofs = pairs, dofs
        self.values = self.z = self.blocks = None

    def evaluate(self, z):
        self.pairs.evaluate(z)
        self.values, *self.blocks = self.pairs.difference()
        self.z = z
        linear = max(float(np.abs(b).max(initial=0.0)) for b in self.blocks) <= \
            self.pairs.rounding
        return self.values, linear

    def apply(self, dz):
        return self.pairs.apply_difference(dz, *self.blocks)


class ZoneTerm:
    """A yielding zone (vstpetsc.plane.yielding.YieldingZone): its points'
    stress beyond the linear one, never linear."""

    def __init__(self, zone, dofs):
        self.zone, self.dofs = zone, dofs
        self.values = self.z = None

    def evaluate(self, z):
        self.values, self.z = self.zone.evaluate(z), z
        return self.values, False

    def apply(self, dz):
        return self.zone.apply(dz)
