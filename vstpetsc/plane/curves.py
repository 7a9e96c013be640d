"""The [[boundary]] tables of a plane-strain model on one rank: per named
curve, the held dofs (fixed, velocity), the nodal patterns of the loads
(traction per unit length, an incident wave's 2 Z v_in), and the
Lysmer dashpots (vstpetsc.plane.boundaries), each rank over the curve's
edges it holds (the overlap gives it every edge around its owned
vertices) and keeping its owned vertices' rows.  Pure numpy and scipy."""

import numpy as np
import scipy.sparse as sp

from vstpetsc.plane import boundaries
from vstpetsc.plane.schema import COMPONENTS

AXES = {c: i for i, c in enumerate(COMPONENTS)}     # a component's column


def edge_cells(mesh, edges):
    """The cell holding each edge (m, 2) (a curve's edge on the domain's
    boundary has one; an inner curve's: the first found)."""
    owner, a, b = mesh.edges()
    keys = mesh.edge_keys(a, b)
    order = np.argsort(keys, kind="stable")
    want = mesh.edge_keys(edges[:, 0], edges[:, 1])
    return owner[order[np.searchsorted(keys[order], want)]]


class Boundaries:
    """What the [[boundary]] tables give one rank of a PlaneModel."""

    def __init__(self, model, specs):
        self.model, self.specs = model, specs
        local = model.local
        self.mesh = local.mesh
        self.nown = local.stop - local.start
        # each local vertex's position among the owned dofs' nodes (-1: not owned)
        self.position = -np.ones(self.mesh.nnodes, dtype=int)
        self.position[model.owned_local] = np.arange(model.owned_local.size)
        self.held = {}                    # owned dof position -> History or None
        self.patterns = []                # (pattern over owned dofs, History)
        self.constant = []                # the patterns of loads constant in time, at t = 0
        self.blocks = []                  # (owned node positions, (n, 2, 2) dashpots)
        for spec in specs:
            getattr(self, f"_{spec.type}")(spec, self.mesh.curves.get(spec.name,
                                                                       np.zeros((0, 2), int)))

    def _owned(self, nodes):
        pos = self.position[nodes]
        return pos[pos >= 0]

    def hold_still(self, nodes, component):
        """Hold at zero the owned ones of the local ``nodes`` along
        ``component`` (0: x, 1: y): an acoustic water's (its surface's w,
        every node's y slot)."""
        for dof in 2 * self._owned(nodes) + component:
            self.held.setdefault(int(dof), None)

    def _fixed(self, spec, edges):
        self._velocity(spec, edges)

    def _velocity(self, spec, edges):
        nodes = self._owned(np.unique(edges))
        for comp, history in spec.values.items():
            for dof in 2 * nodes + AXES[comp]:
                self.held.setdefault(int(dof), None if history.is_zero else history)

    def _traction(self, spec, edges):
        length, _, _ = boundaries.edge_frames(self.mesh, edges) if len(edges) else (
            np.zeros(0), None, None)
        share = np.zeros(self.mesh.nnodes)
        np.add.at(share, edges[:, 0], 0.5 * length)
        np.add.at(share, edges[:, 1], 0.5 * length)
        for comp, history in spec.values.items():
            pattern = np.zeros(2 * self.nown)
            pattern[2 * self.position[self._mine()] + AXES[comp]] = share[self._mine()]
            self.patterns.append((pattern, history))
            if history.is_constant and not history.is_zero:
                self.constant.append(pattern * float(history(np.zeros(1))[0]))

    def _mine(self):
        return np.flatnonzero(self.position >= 0)

    def _absorbing(self, spec, edges):
        if not len(edges):
            nodes, blocks = np.zeros(0, int), np.zeros((0, 2, 2))
        else:
            if spec.rock is not None:
                rho, vp, vs = spec.rock
            else:
                cells = edge_cells(self.mesh, edges)
                mat = self.model.materials
                rho = mat["rho"][cells]
                vp = np.sqrt((mat["lam"][cells] + 2 * mat["mu"][cells]) / rho)
                vs = np.sqrt(mat["mu"][cells] / rho)
            nodes, blocks = boundaries.dashpot_blocks(self.mesh, edges, rho, vp, vs)
            keep = self.position[nodes] >= 0
            nodes, blocks = self.position[nodes[keep]], blocks[keep]
        self.blocks.append((nodes, blocks))
        for comp, history in spec.incident.items():
            pattern = np.zeros(2 * self.nown)
            j = AXES[comp]
            pattern[2 * nodes] = 2.0 * blocks[:, 0, j]
            pattern[2 * nodes + 1] = 2.0 * blocks[:, 1, j]
            self.patterns.append((pattern, history))

    def dashpots(self):
        """The dashpots' rows (CSR, owned dofs x global dofs), None if none."""
        if not self.blocks:
            return None
        first, size = self.model.first, self.model.nnodes
        nodes = np.concatenate([n for n, _ in self.blocks])
        blocks = np.concatenate([b for _, b in self.blocks])
        dof = 2 * nodes[:, None] + np.arange(2)
        rows = np.repeat(dof, 2, axis=1).ravel()
        cols = np.tile(dof, (1, 2)).ravel() + 2 * first
        return sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(2 * self.nown, 2 * size))

    def constant_loads(self):
        """The owned dofs' forces of the tractions constant in time (what a
        static start carries beside the weight, as in 1-D)."""
        return np.sum(self.constant, axis=0) if self.constant else np.zeros(2 * self.nown)

    def held_dofs(self):
        """(owned dof positions (sorted), their Histories or None for 0)."""
        dofs = np.array(sorted(self.held), dtype=int)
        return dofs, [self.held[d] for d in dofs]

    def absorbing_dofs(self):
        """The owned dof positions on absorbing curves (sorted)."""
        nodes = [n for n, _ in self.blocks]
        nodes = np.unique(np.concatenate(nodes)) if nodes else np.zeros(0, dtype=int)
        return (2 * nodes[:, None] + np.arange(2)).ravel()
