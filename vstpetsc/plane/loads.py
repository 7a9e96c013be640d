"""What a plane-strain model prescribes per slab, on one rank: the nodal
force integrals int T_a f dt of its loads (a nodal pattern times a
history each: tractions, incident waves, gravity) and the velocities of
its held dofs.  Histories are evaluated for blocks of slabs at a time,
exactly (their own slab integrals, vstpetsc.spacetime.blocks).
Pure numpy and scipy."""

import numpy as np
import scipy.sparse as sp

from vstpetsc.spacetime.blocks import Blocks


class PlaneLoads:
    """``slab(k)`` = (forces (2 n, 2): int T_a f dt of every owned dof,
    velocities (m, 2): (v^1, v^2) of the held dofs ``held``) of slab k;
    ``terms``: [(pattern over the owned dofs, History)]."""

    def __init__(self, terms, held, held_histories, dt, ndofs):
        self.dt = dt
        self.histories = [h for _, h in terms]
        self.patterns = sp.csr_matrix(np.column_stack([p for p, _ in terms])) if terms \
            else sp.csr_matrix((ndofs, 0))
        self.held = np.asarray(held, dtype=int)
        self.moving = [(i, h) for i, h in enumerate(held_histories) if h is not None]
        self.all_fixed = not self.moving
        self.blocks = Blocks(self._evaluate)

    def _evaluate(self, k0, k1):
        count, dt = k1 - k0, self.dt
        integrals = np.zeros((count, len(self.histories), 2))
        for j, h in enumerate(self.histories):
            integrals[:, j] = h.slab_integrals(dt, k0, k1)
        velocities = np.zeros((count, self.held.size, 2))
        ends = dt * np.arange(k0, k1 + 1)
        for i, h in self.moving:
            values = h(ends)
            velocities[:, i, 0], velocities[:, i, 1] = values[:-1], values[1:]
        return integrals, velocities

    def slab(self, k):
        (integrals, velocities), i = self.blocks.at(k)
        forces = self.patterns @ integrals[i] if self.histories else None
        return forces, velocities[i], None


def unit_gravity(M):
    """The nodal pattern of a unit body force along +y: the rows of the
    mass matrix M (CSR, interleaved dofs) times the unit field along y
    (int rho N_a dA on y dofs)."""
    return np.asarray(M[:, 1::2].sum(axis=1)).ravel()


def gravity_pattern(model):
    """The nodal pattern per unit g of this rank's owned dofs: the weight
    (unit_gravity of its rows of the solid's M, without Westergaard's added
    masses: model.unit_weight) and the water's pressure
    (vstpetsc.plane.water), which follows g as the weight does."""
    from vstpetsc.plane.water import owned_pattern

    pattern = model.unit_weight()
    if model.case.plane.waters:
        pattern = pattern + owned_pattern(model.local.mesh, model.owned_local,
                                          model.case.plane.waters)
    return pattern


def whole_gravity(model, M):
    """The pattern per unit g of gravity_pattern on rank 0's whole mesh
    (its numbering as read), M the whole mesh's mass matrix: the static
    solve's."""
    from vstpetsc.plane.water import whole_pattern

    pattern = unit_gravity(M)
    if model.case.plane.waters:
        pattern = pattern + whole_pattern(model.mesh, model.case.plane.waters)
    return pattern


def uplift_pattern(model):
    """The uplift's forces on this rank's owned dofs (2 n,)
    (vstpetsc.plane.uplift; zeros without): constant in time."""
    from vstpetsc.plane.uplift import owned_pattern

    nown = model.owned_original.size
    if model.uplift is None:
        return np.zeros(2 * nown)
    return owned_pattern(model.pairs.global_nodes, model.uplift, model.first, nown)


def plane_loads(model, dt, extra=()):
    """The PlaneLoads of a model: its boundaries' patterns and held dofs,
    gravity (a body force rho g along +y, g the [gravity] history, with the
    water's pressure, gravity_pattern), the uplift (constant,
    uplift_pattern) and the ``extra`` terms (a static start's
    reactions)."""
    from vstpetsc.spacetime.history import History

    terms = list(model.boundaries.patterns) + list(extra)
    if model.uplift is not None:
        terms.append((uplift_pattern(model), History(value=1.0)))
    gravity = model.case.gravity
    if gravity is not None and not gravity.g.is_zero:
        terms.append((gravity_pattern(model), gravity.g))
    held, histories = model.boundaries.held_dofs()
    return PlaneLoads(terms, held, histories, dt, 2 * (model.local.stop - model.local.start))
