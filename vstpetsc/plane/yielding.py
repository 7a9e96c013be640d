"""A plane-strain model's yielding zone (issue 46; docs/nonlinear-soil.md
section 7): the cells of the regions with a ``shear_law``, their strain
points (vstpetsc.plane.material_points), the MKZ law with extended Masing
rules on the points' deviators (vstpetsc.materials.deviatoric) and its
slab integrals (vstpetsc.materials.deviatoric_slab).

The zone is a nonlinear term of the slab's Newton beside the interface
pairs (vstpetsc.plane.solver.newton_terms.ZoneTerm): at its unknowns z
(the slab's (T1, T2) values of every spatial dof its cells touch) it
gives the forces of the points' stress beyond the linear one already in
the slab matrix,

    F_a = S^T (w Q_a),  Q_a = dt int T_a (sigma - C_el eps) dtheta,

and their Jacobian S^T (w dQ_ab) S dt (D_b = dt S v^b).  Like the pairs'
kernels it runs on rank 0 on the whole mesh.  The work of F over a slab,
sum_a v^a . F_a, is the work of the stress beyond the linear one: its
part that the points store (sigma's recoverable energy s:s / 4G + p^2 / 2K
beyond the linear 1/2 eps C_el eps) is strain energy, the rest the loops'
dissipation, /energy/hysteretic.

The points' strains are measured from the run's initial state (at rest, a
region's u0, or a static start's equilibrium, which carries its stress
linearly): the zone starts on the backbone at zero strain, so a static
start stays at rest."""

import numpy as np
import scipy.sparse as sp

from vstpetsc.errors import InputError

from vstpetsc.materials.deviatoric import PlaneMasing, equivalent_strain
from vstpetsc.materials.deviatoric_slab import slab_integrals
from vstpetsc.plane.material_points import material_points


def zone_cells(regions, region):
    """(cells, {gamma_ref, beta, s} per cell) of the regions with a
    shear_law (``regions`` per region index, ``region`` per cell)."""
    laws = [r.shear_law for r in regions]
    yielding = np.array([law is not None for law in laws], dtype=bool)
    cells = np.flatnonzero(yielding[region]) if len(region) else np.zeros(0, dtype=int)
    params = {key: np.array([(law or {}).get(key, 1.0) for law in laws])[region[cells]]
              for key in ("gamma_ref", "beta", "s")}
    return cells, params


class ZoneUnknowns:
    """What a rank other than 0 knows of the zone: its unknowns' global
    slab indices (the Newton's scatter needs their number everywhere)."""

    def __init__(self, slab_index):
        self.slab_index = slab_index



class YieldingZone:
    """The zone of ``cells`` of ``mesh`` (the whole mesh, rank 0) with
    Lame's ``lam``, ``mu`` per cell and the MKZ ``params`` per cell;
    ``global_of`` each node's global number (the slab vector's order)."""

    def __init__(self, mesh, cells, lam, mu, params, dt, global_of):
        self.dt, self.ncells, self.cells = dt, mesh.ncells, cells
        points = material_points(mesh, cells)
        used = np.unique(points.strain.indices)           # spatial dofs (mesh's numbering)
        self.S = sp.csr_matrix(points.strain[:, used])
        self.St = sp.csr_matrix(self.S.T)
        self.weight, self.cell = points.weight, points.cell
        node, comp = used // 2, used % 2
        self.spatial = used
        self.slab_index = 2 * (2 * global_of[node] + comp)[:, None] + np.arange(2)
        where = np.searchsorted(cells, self.cell)
        G, K = mu[self.cell], lam[self.cell] + 2.0 * mu[self.cell] / 3.0
        self.law = PlaneMasing(G, params["gamma_ref"][where], params["beta"][where],
                               params["s"][where], K)
        self.motion = None
        self.work = 0.0                          # the slab sums of v . F so far
        self.strain_max = np.zeros(self.ncells)
        self.strain_time = np.zeros(self.ncells)     # when each cell's strain_max was reached
        self.slabs = 0                               # slabs committed since t = 0
        self._last = None
        self.frozen = None              # the points' decisions kept (None: the rules decide)
        self.integrals = slab_integrals     # or the compiled twin (use_native)

    def use_native(self, lib):
        """Take the slab integrals from the compiled kernel of ``lib``
        (vstpetsc.native.library(); None: keep the Python reference)."""
        if lib is not None:
            from vstpetsc.native.deviatoric import NativeSlabIntegrals

            self.integrals = NativeSlabIntegrals(lib)

    @property
    def G(self):
        """The points' small-strain shear moduli (the law's)."""
        return self.law.backbone.G[:, 0]

    def evaluate(self, z):
        """The forces F (m, 2) at the zone's unknowns z (m, 2) (with the
        ``frozen`` decisions, when set)."""
        D1 = self.dt * (self.S @ z[:, 0]).reshape(-1, 3)
        D2 = self.dt * (self.S @ z[:, 1]).reshape(-1, 3)
        Q, dQ, path = self.integrals(self.law, D1, D2, self.dt, self.motion,
                                     frozen=self.frozen)
        w = self.weight[:, None]
        F = np.column_stack([self.St @ (w * Q[:, a]).ravel() for a in range(2)])
        self._last = (path, F, z, dQ)
        return F

    def apply(self, dz):
        """The Jacobian's product with dz (m, 2): sum_b S^T (w dQ_ab) S dt dz_b."""
        path, F, z, dQ = self._last
        n = self.weight.size
        # strains of both time nodes side by side (n, 6) against dQ as
        # (n, 6, 6) blocks: one batched product
        strains = self.dt * (self.S @ dz).reshape(n, 3, 2).transpose(0, 2, 1).reshape(n, 6)
        stress = (dQ.reshape(n, 6, 6) @ strains[:, :, None])[:, :, 0].reshape(n, 2, 3)
        stress *= self.weight[:, None, None]
        return self.St @ stress.transpose(0, 2, 1).reshape(-1, 2)

    def decisions(self):
        """The last evaluation's Decisions (deviatoric_slab)."""
        return self._last[0].decisions()

    def finish_slab(self):
        """Take the last evaluated slab as converged: the law's state moves
        to its end, the work of F is summed."""
        path, F, z, _ = self._last
        self.work += float((F * z).sum())
        self.motion = path.commit()
        self.slabs += 1
        self._envelope(self.law.eps, self.slabs * self.dt)

    def snapshot(self):
        """The zone's state as one flat array (its shape fixed for the run:
        a restart's dataset is made before the file's SWMR mode): the loops'
        work, whether a motion is known, the slabs done, the points' strain,
        stress, deviator, reversal stack and last motion, the cells'
        strain_max and its time."""
        law, n = self.law, self.weight.size
        motion = np.zeros((n, 3)) if self.motion is None else self.motion
        return np.concatenate([[self.work, float(self.motion is not None), float(self.slabs)],
                               law.eps.ravel(), law.sigma.ravel(), law.dev.ravel(),
                               law.stack.c.ravel(), law.stack.s.ravel(),
                               law.stack.k.astype(float), motion.ravel(), self.strain_max,
                               self.strain_time])

    def restore(self, flat):
        """Continue from a snapshot (bit for bit)."""
        law, n = self.law, self.weight.size
        depth = law.stack.c.shape[1]
        sizes = [3 * n, 4 * n, 3 * n, 3 * depth * n, 3 * depth * n, n, 3 * n, self.ncells,
                 self.ncells]
        if flat.size != 3 + sum(sizes):
            raise InputError(f"--restart: the file's yielding zone state has {flat.size} "
                             f"values, this case's zone {3 + sum(sizes)}: not the same case")
        parts = np.split(np.asarray(flat, dtype=float)[3:], np.cumsum(sizes)[:-1])
        self.work, self.slabs = float(flat[0]), int(flat[2])
        law.eps, law.sigma, law.dev = (parts[0].reshape(n, 3), parts[1].reshape(n, 4),
                                       parts[2].reshape(n, 3))
        law.stack.c, law.stack.s = parts[3].reshape(n, depth, 3), parts[4].reshape(n, depth, 3)
        law.stack.k = parts[5].astype(np.int64)
        self.motion = parts[6].reshape(n, 3) if flat[1] else None
        self.strain_max, self.strain_time = parts[7].copy(), parts[8].copy()

    def _envelope(self, eps, t):
        """strain_max and strain_time with the points' strains ``eps`` at
        time ``t``."""
        now = np.zeros(self.ncells)
        np.maximum.at(now, self.cell, equivalent_strain(eps))
        grew = now > self.strain_max
        self.strain_max[grew], self.strain_time[grew] = now[grew], t

    def stored_beyond_linear(self):
        """sum w (s:s / 4G + p^2 / 2K - 1/2 eps C_el eps): the energy the
        points would give back unloading elastically beyond what the linear
        strain energy 1/2 u^T K u counts for them."""
        law, w = self.law, self.weight
        G, K = self.G, law.K
        s, e = law.dev, law.eps
        tr = e[:, 0] + e[:, 1]
        p = (law.sigma[:, 0] + law.sigma[:, 1] + law.sigma[:, 3]) / 3.0
        lam = K - 2.0 * G / 3.0
        linear = 0.5 * (lam * tr * tr + 2.0 * G * (e[:, 0] ** 2 + e[:, 1] ** 2)
                        + G * e[:, 2] ** 2)
        return float(w @ ((s * s).sum(axis=1) / (4.0 * G) + p * p / (2.0 * K) - linear))

    def energies(self):
        """(strain energy beyond the linear expression, hysteretic
        dissipation) since t = 0 (the points start unstrained: nothing
        stored then)."""
        stored = self.stored_beyond_linear()
        return stored, self.work - stored

    def cell_stress(self):
        """(ne, 3) each cell's mean in-plane stress over its points (cells
        outside the zone: NaN, the caller's linear stress stands)."""
        out = np.zeros((self.ncells, 3))
        count = np.bincount(self.cell, weights=self.weight, minlength=self.ncells)
        for i in range(3):
            out[:, i] = np.bincount(self.cell, weights=self.weight * self.law.sigma[:, i],
                                    minlength=self.ncells)
        with np.errstate(invalid="ignore", divide="ignore"):
            return out / count[:, None]
