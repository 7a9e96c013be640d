"""The energy book of bodies on a line: the state's kinetic, strain and
spring energy from the bands of M and K (the balance itself is the shared
:class:`vstpetsc.runner.energy.EnergyBook`)."""

import numpy as np

from vstpetsc.line import model as model_mod
from vstpetsc.runner.energy import EnergyBook


class LineEnergyBook(EnergyBook):
    """The energy rows of a 1-D model."""

    def __init__(self, model):
        super().__init__(model)
        ops = model.ops
        self.m_diag, self.m_off = ops.m_diag, ops.m_off
        self.stiffness = -ops.k_off              # E A / h of the node pairs (0 between bodies)
        n = ops.m_diag.size
        self.squares, self.products = np.empty(n), np.empty(max(n - 1, 0))
        self.sprung = ops.sprung
        self._v = None

    def state(self, u, v, d=None, known=None):
        """Kinetic 1/2 v^T M v, strain 1/2 u^T K u = sum 1/2 (E A / h) d^2
        over the elements (d: the elongations u_{i+1} - u_i, from u when
        None) and spring energy; ``known`` (kinetic, strain) when the
        solver summed them already."""
        spring = model_mod.spring_energy(self.model.ops, u) if self.sprung else 0.0
        if known is not None:
            return {"kinetic": known[0], "strain": known[1], "spring": spring}
        sq, pr = self.squares, self.products
        np.multiply(v, v, out=sq)
        kinetic = 0.5 * float(self.m_diag.dot(sq))
        if v is not self._v:             # one rank: the solver's array every row
            self._v, self._left, self._right = v, v[:-1], v[1:]
        np.multiply(self._left, self._right, out=pr)
        kinetic += float(self.m_off.dot(pr))
        if d is None:
            d = np.subtract(u[1:], u[:-1], out=pr)
        np.multiply(d, d, out=pr)
        return {"kinetic": kinetic, "strain": 0.5 * float(self.stiffness.dot(pr)),
                "spring": spring}

    def start(self, u, v):
        """t = 0: the initial total, stored contact energy included."""
        stored = sum(law.stored_energy(u) for law in self.model.recorded
                     if hasattr(law, "stored_energy"))
        self.offset["contact"] = stored
        soil = self.model.soil
        if soil is not None:
            soil.start(u)
            self.beyond0 = soil.stored_beyond_linear()
        self.held0 = sum(self.state(u, v).values()) + self.beyond0
        self.initial = self.held0 + stored
        self.largest = abs(self.initial)
