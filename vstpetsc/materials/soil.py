"""A hysteretic shear field: the elements of the bodies with a
``shear_law``, their Masing state, the slab integrals of the stress beyond
the linear one, and what they report (stress, strain envelope, energy).
Pure numpy; :mod:`vstpetsc.line.solver.material_newton` solves the slab with it.
"""

import numpy as np

from vstpetsc.materials import masing, mkz

HEAD = 3          # work, support work, the stored energy at t = 0
PARTS = 6         # per element: gamma, tau, direction, depth, tau_min, tau_max


class HystereticSoil:
    """The shear law of the elements ``elements`` of ``mesh``.

    ``ke_h``: E A / h of those elements (as the slab matrix has them) times
    h, so that ``ke_h * gamma`` is the linear force the matrix applies."""

    def __init__(self, mesh, elements, gamma_ref, beta, s, ke):
        self.elements = elements
        self.left = mesh.elem_node[elements]
        self.h, self.A, self.G = mesh.h[elements], mesh.A[elements], mesh.E[elements]
        self.ke_h = ke[elements] * self.h
        self.backbone = masing.Backbone(self.G, gamma_ref, beta, s)
        self.state = None
        self.version = 0           # counts the states taken (the compiled kernel rebinds)
        self.path = None
        self.native = None         # the compiled kernel (vstpetsc.native.masing), if used
        self.work = 0.0            # the correction forces' work so far
        self.support_work = 0.0    # what prescribed nodes' supports did against them

    @classmethod
    def of(cls, parts, mesh):
        """From {twin body: parts}."""
        mid = 0.5 * (mesh.x[mesh.elem_node] + mesh.x[mesh.elem_node + 1])
        chosen = np.zeros(mid.size, dtype=bool)
        params = [np.ones(mid.size) for _ in mkz.PARAMETERS]
        for body, body_parts in parts.items():
            el = mesh.elements(body)
            mask, *values = mkz.parameters(body_parts, mid[el])
            chosen[el] = mask
            for arr, val in zip(params, values):
                arr[el] = val
        elements = np.flatnonzero(chosen)
        ke = mesh.element_stiffness()
        return cls(mesh, elements, *(p[elements] for p in params), ke)

    @property
    def nodes(self):
        """The nodes of the governed elements (sorted, unique)."""
        return np.unique(np.concatenate([self.left, self.left + 1]))

    def start(self, u):
        """The state at t = 0 from the displacements (global nodes)."""
        gamma = (u[self.left + 1] - u[self.left]) / self.h
        self.state = masing.MasingState(self.backbone, gamma)
        self.version += 1
        tau = self.state.tau
        self.tau_min, self.tau_max = tau.copy(), tau.copy()
        self.work = self.support_work = 0.0
        self.stored0 = self.stored_beyond_linear()

    def slab(self, D1, D2, dt, tangent=True):
        """(Q, dQ/dD) of the slab for strain increments D1, D2 (the numpy
        reference; the compiled kernel is called by the solver's coupling)."""
        Q, dQ, self.path = masing.slab_integrals(self.state, D1, D2, self.A, self.ke_h,
                                                 dt, tangent)
        return Q, dQ

    def finish(self, D1, D2, Q, dt):
        """Take (D1, D2) as the slab's solution (Q: its integrals, the last
        evaluation, whose path this state still holds): its work, the
        state at the slab end, the envelopes."""
        self.work += float(np.sum(self.h / dt * (D1 * Q[:, 0] + D2 * Q[:, 1])))
        st = self.state
        if self.native is not None:
            _, gamma, tau, direction, st.stack.g, st.stack.t, st.stack.k = \
                self.native.finish(D1, D2, dt)
        else:
            gamma, tau, st.stack, direction = self.path.end()
            # as the compiled kernel: nothing stale beyond the depth
            beyond = np.arange(masing.DEPTH)[None, :] >= st.stack.k[:, None]
            st.stack.g[beyond], st.stack.t[beyond] = 0.0, 0.0
        st.gamma, st.tau, st.direction = gamma, tau, direction
        self.version += 1
        np.minimum(self.tau_min, tau, out=self.tau_min)
        np.maximum(self.tau_max, tau, out=self.tau_max)
        self.path = None

    @property
    def stress(self):
        return self.state.tau

    def stored_beyond_linear(self):
        """sum A h tau^2 / (2 G) - (E A / h) h^2 gamma^2 / 2: the energy the
        elements hold (unloading at G would return it) minus what the
        linear strain energy 1/2 u^T K u counts for them."""
        st = self.state
        return float(np.sum(self.A * self.h * st.tau ** 2 / (2.0 * self.G)
                            - 0.5 * self.ke_h * self.h * st.gamma ** 2))

    def energies(self):
        """(strain beyond the linear expression, hysteretic dissipation):
        since t = 0 the elements' internal work is the change of
        1/2 u^T K u plus ``work``; what they hold changed by that of 1/2
        u^T K u plus stored_beyond_linear's; the rest was dissipated."""
        stored = self.stored_beyond_linear()
        return stored, self.work - (stored - self.stored0)

    def snapshot(self):
        """Everything a restart needs, as one flat array."""
        st = self.state
        per = np.concatenate([st.gamma, st.tau, st.direction, st.stack.k.astype(float),
                              self.tau_min, self.tau_max])
        return np.concatenate([[self.work, self.support_work, self.stored0], per,
                               st.stack.g.ravel(), st.stack.t.ravel()])

    def restore(self, flat):
        n = self.elements.size
        self.work, self.support_work, self.stored0 = (float(v) for v in flat[:HEAD])
        parts = np.split(flat[HEAD:HEAD + PARTS * n], PARTS)
        st = self.state
        st.gamma, st.tau, st.direction = parts[0].copy(), parts[1].copy(), parts[2].copy()
        self.version += 1
        st.stack.k = parts[3].astype(np.int64)
        self.tau_min, self.tau_max = parts[4].copy(), parts[5].copy()
        rest = flat[HEAD + PARTS * n:]
        st.stack.g = rest[:n * masing.DEPTH].reshape(n, masing.DEPTH).copy()
        st.stack.t = rest[n * masing.DEPTH:].reshape(n, masing.DEPTH).copy()
