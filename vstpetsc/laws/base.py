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
  computed (their reactions then act as constant forces).

Nonlinear part, on the law's few ``nodes`` (unknowns per node: the
velocities v^1 = v^{n+} and v^2 = v^{(n+1)-}):

- ``start_slab(u, dt)``: displacements of its nodes at t^n, before Newton;
- ``residual(v)``: its terms in the slab equations of its nodes (rows of the
  untransformed equations, same sign as A v - r), shape (n, 2), and whether
  any of them is nonzero anywhere in the slab;
- ``tangent(v)``: d residual / d v, shape (2 n, 2 n), dof 2 k + a for node k;
- ``finish_slab(t0, dt)``: after convergence (the last ``residual`` call was
  at the converged velocities): update its state and what it reports.

Result file: ``group`` (e.g. "contact/0", None for nothing), ``series``
(its scalar datasets per kept row), ``attrs()`` and ``values(u)``; a restart
hands the last row back through ``restore(values)``.
"""

from dataclasses import dataclass

import numpy as np

from vstpetsc.history import History


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

    def describe(self):
        """One line for the run header."""
        return ""

    def attrs(self):
        return {}

    def values(self, u):
        return {}

    def restore(self, values):
        """Continue from the ``series`` values of a result file's last row."""
