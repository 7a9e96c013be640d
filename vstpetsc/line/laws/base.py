"""The protocol every boundary and interface law follows.

A law is built from one table of the case ([[bc]], [[contact]], ...) and
speaks to the solver only through the methods below; the solver knows no
law by name.

Linear part (enters the slab matrix, factored once per run, or the
right-hand side):

- ``add_operators(ops)``: add to the bands of M, C and K (supports, dashpots);
- ``constraints()``: prescribed velocities, a list of :class:`Constraint`;
- ``loads()``: nodal forces, a list of :class:`Load` (a weight times a
  history on one node) and :class:`FieldLoad` (a vector times a history),
  integrated exactly against the time shape functions every slab;
- ``held_nodes()``: nodes held fixed while the static initial state is
  computed (their reactions then act as constant forces);
- ``static_loads()``: the loads the static initial state carries, at their
  t = 0 values (default: those whose history is constant; the others act
  from t = 0 as after a start from rest).

Nonlinear part, on the law's few ``nodes`` with ``signs`` c_k: the law
sees two reduced coordinates y^a = sum_k c_k v_k^a (a = 1, 2: the slab's
velocities v^{n+} and v^{(n+1)-}; for a pair, the rates at which its gap
closes), and its terms in the slab equations of node k are c_k f^a(y):

- ``start_slab(u, dt)``: displacements of its nodes at t^n, before Newton;
- ``start_time(t0)``: the slab's start time (a law with a history of time);
- ``acts(y1, y2)``: whether the law does anything in the slab at y (a
  cheap test before Newton);
- ``force(y1, y2)``: (f1, f2, df1/dy1, df1/dy2, df2/dy1, df2/dy2) in plain
  floats (same sign as A v - r), or None when the law does nothing anywhere
  in the slab;
- ``finish_slab(t0, dt)``: after convergence (the last ``force`` call was at
  the converged coordinates): update its state and what it reports;
- ``work_terms(w)`` (optional): how the slab's work w = f . y it took
  splits over the energy terms ``energy_keys``, ((key, value), ...);
  default all of it to ``energy_key``;
- ``static(u)``: (residual, tangent) on its nodes for the static initial
  state; ``static_limit(u)``: a line naming the law's key when it cannot
  carry its share of the static load (None: it can).

A contact pair (laws/pair.py) also records, in ``finish_slab``, the times
inside the slab where it starts and stops acting (``track``): its events,
which the recorder takes with every kept row (``take_events``).

Result file: ``group`` (e.g. "contact/0", None for nothing), ``series``
(its scalar datasets per kept row), ``attrs()`` and ``values(u)``; a restart
hands the last row back through ``restore(values)``.
"""

from dataclasses import dataclass

import numpy as np

from vstpetsc.spacetime.history import History


@dataclass
class Constraint:
    """Prescribed velocity of ``node``: v^1 = h(t^n), v^2 = h(t^{n+1});
    ``history`` None is a fixed node (zero)."""

    node: int
    history: History | None


@dataclass
class Load:
    """A nodal force ``weight * history(t)`` on ``node``."""

    node: int
    weight: float
    history: History


@dataclass
class FieldLoad:
    """Nodal forces ``vector * history(t)`` on every node (a body force)."""

    vector: np.ndarray
    history: History


class Law:
    """Base of every law: contributes nothing unless a method is overridden."""

    nodes = np.zeros(0, dtype=int)
    group = None
    series = ()
    formulation = None

    def add_operators(self, ops):
        """Add the law's linear terms to the bands of M, C and K."""

    def constraints(self):
        return []

    def loads(self):
        return []

    def held_nodes(self):
        return []

    def start_time(self, t0):
        """The start time t0 of the slab that follows."""

    def static_loads(self):
        """The loads that a static start carries: those constant in time
        (a load that changes is dynamic from t = 0, as after a start from
        rest, so that a static start is the static state plus the response
        to everything that moves)."""
        return [load for load in self.loads() if load.history.is_constant]

    def static_limit(self, u):
        return None

    def describe(self):
        """One line for the run header."""
        return ""

    def attrs(self):
        return {}

    def values(self, u):
        return {}

    def restore(self, values):
        """Continue from the ``series`` values of a result file's last row."""
