"""The node pairs of a plane-strain run's interfaces ([[interface]],
interface.md "Plane strain (2-D)") and their state: every interface's
pairs one after the other, each pair the 1-D contact pair along its
normal and, with friction, the 1-D Coulomb law along its tangent
(vstpetsc.plane.pair_kernels), per unit thickness with its tributary
length as its area.

Pair coordinates: the slab's unknowns of a pair's two nodes z (8: first
node (x, y), second node (x, y), each at the slab's two time nodes) give
y = (d1, d2, q1, q2), d = n . (v_first - v_second) the closing rate and
q = t . (v_first - v_second) = -s, s the second side's tangential
velocity relative to the first (the 1-D pair's signs: +1 first, -1
second).  The pair's terms f(y) enter the slab residual as E f (E: +n, +t
on the first node, -n, -t on the second).

A closed, sticking pair's terms are linear in y: W y + constant with
W = k dt^2 HK, the slab algebra of a spring k (the power penalty's and
the stick spring's, formulation.md), so the run factors A_c = A + dt^2
HK (x) S once (S: the springs of ``spring_n``, ``spring_t``, assembled
by PlaneModel.closed_springs) and Newton sees only e = f - W_c y
(``excess``, its tangent ``excess_tangent``).

Default stiffnesses per unit length (docs/interfaces.md): the 1-D
rules (vstpetsc.kernels.stiffness: DEFAULT_BETA, STICK_BETA) with the
adjacent cells' lambda + 2 mu (normal) or mu (tangential) for E and
their size across the curve for h, the stiffest edge's."""

from dataclasses import dataclass

import numpy as np

from vstpetsc.kernels.stiffness import DEFAULT_BETA, STICK_BETA
from vstpetsc.plane import pair_kernels as pk
from vstpetsc.results.plane_layout import PAIR_SERIES as SERIES
from vstpetsc.spacetime.slab import HK

CROSS_STEP = 1e-7
ROUNDING = 1e-12
# a given penalty's spring (its slab-mean stiffness per unit length) may be
# at most this many times the softest series stiffness of the cells beside
# the curve: A_c = A + dt^2 HK (x) S is factored in double precision, and a
# spring 1/eps times the cells' stiffness leaves their part of it
# unresolved (the balance went negative from 1e10 - 1e11 on, and to -100 %
# of the largest energy at 1e15: docs/interfaces.md, "The penalty's limit")
PENALTY_LIMIT = 1e8


@dataclass
class InterfaceInfo:
    """One interface of the run (every rank): its pairs' slice of the
    run's pairs, formulation, penalty and tangential stiffness per unit
    length (the latter 0 without friction) and friction coefficient."""

    name: str
    pairs: slice
    formulation: str
    penalty: float
    shear_stiffness: float
    friction: float | None
    given: bool

    @property
    def power(self):
        return self.formulation == "power"


def edge_stiffness(mesh, materials, edges):
    """Per edge of an inner curve, from the two cells that share it: the
    cells' (lambda + 2 mu) / h and mu / h, h their size across the edge
    (a quadrilateral's area / length, a triangle's 2 area / length),
    as (2, m) arrays for the normal and the tangential."""
    cells, a, b = mesh.edges()
    keys = mesh.edge_keys(a, b)
    order = np.argsort(keys, kind="stable")
    at = np.searchsorted(keys[order], mesh.edge_keys(edges[:, 0], edges[:, 1]))
    both = cells[order[np.stack([at, at + 1])]]             # (2, m) the two cells
    length = np.linalg.norm(np.diff(mesh.coordinates[edges], axis=1)[:, 0], axis=1)
    area = np.abs(mesh.areas())[both]
    h = area / length * np.where(mesh.cells[both, 3] < 0, 2.0, 1.0)
    lam, mu = materials["lam"][both], materials["mu"][both]
    return (lam + 2.0 * mu) / h, mu / h


def default_stiffnesses(mesh, materials, edges, formulation, dt):
    """(penalty, tangential stiffness) per unit length of an interface
    along ``edges`` by default (the module's docstring)."""
    normal, shear = edge_stiffness(mesh, materials, edges)
    if formulation == "power":
        penalty = DEFAULT_BETA["power"] / (1.0 / normal).sum(axis=0)
    else:
        penalty = 2.0 * DEFAULT_BETA["seed"] * normal.max(axis=0) / dt
    tangential = STICK_BETA / (1.0 / shear).sum(axis=0)
    return float(penalty.max()), float(tangential.max())


def penalty_limit(mesh, materials, edges, formulation, dt):
    """(the largest penalty per unit length an interface along ``edges``
    takes, the softest series stiffness (lambda + 2 mu) / h of the cells
    beside it): a spring (the power penalty, the seed's slab-mean
    stiffness penalty dt / 2) of PENALTY_LIMIT times the latter."""
    normal, _ = edge_stiffness(mesh, materials, edges)
    series = float((1.0 / (1.0 / normal).sum(axis=0)).min())
    spring = PENALTY_LIMIT * series
    return (spring if formulation == "power" else 2.0 * spring / dt), series


def stiffnesses(i, spec, mesh, materials, dt):
    """(penalty, tangential stiffness) per unit length of interface i
    (``spec``) on the mesh before its split: the given penalty or the
    default; ValueError naming the key for a penalty beyond
    :func:`penalty_limit`."""
    edges = mesh.curves[spec.name]
    if not len(edges):
        return 1.0, 1.0
    penalty, shear = default_stiffnesses(mesh, materials, edges, spec.formulation, dt)
    if spec.penalty is None:
        return penalty, shear
    limit, series = penalty_limit(mesh, materials, edges, spec.formulation, dt)
    if spec.penalty > limit:
        raise ValueError(
            f"interface[{i}] ({spec.name}).penalty: {spec.penalty:g} is stiffer than double "
            f"precision resolves beside these cells: at most {limit:.3g} ({PENALTY_LIMIT:g} "
            f"times the cells' stiffness (lambda + 2 mu) / h in series, {series:.3g}"
            f"{'' if spec.formulation == 'power' else ', as the slab-mean penalty dt / 2'}; "
            f"the default is {penalty:.3g})")
    return spec.penalty, shear


class PairSet:
    """Every pair of the run's interfaces (every rank holds the layout;
    rank 0 the state and the kernels): ``nodes`` (m, 2) in the mesh's
    numbering (split), ``normal``, ``tangent`` (m, 2), ``length`` (m,)."""

    def __init__(self, infos, nodes, normal, tangent, length, dt):
        self.infos, self.dt = infos, dt
        self.nodes, self.normal, self.tangent, self.length = nodes, normal, tangent, length
        self.m = length.size
        per = lambda f: np.concatenate([np.full(i.pairs.stop - i.pairs.start, f(i), float)
                                        for i in infos]) if infos else np.zeros(0)
        self.w = per(lambda i: i.penalty) * length
        self.kt = per(lambda i: i.shear_stiffness) * length
        self.mu = per(lambda i: i.friction or 0.0)
        # the closed, sticking springs A_c holds (the seed's: its slab-mean stiffness)
        self.spring_n = per(lambda i: i.penalty if i.power else 0.5 * i.penalty * dt) * length
        self.kernels = [pk.PairKernels(self.w[i.pairs], self.kt[i.pairs], self.mu[i.pairs], dt,
                                       i.power) for i in infos]
        self.hk = dt * dt * HK
        # a Jacobian block below this is a closed, sticking pair's rounding
        self.rounding = ROUNDING * float(max(np.abs(self.spring_n).max(initial=0.0),
                                             np.abs(self.kt).max(initial=0.0))) \
            * float(np.abs(self.hk).max())
        self.gap, self.stretch, self.slip = np.zeros(self.m), np.zeros(self.m), np.zeros(self.m)
        self.normal_force, self.shear_force = np.zeros(self.m), np.zeros(self.m)
        self.out = np.zeros((self.m, pk.OUT))
        self.y = np.zeros((self.m, 4))
        self._cross_at = np.zeros((self.m, 2, 2))

    @property
    def spring_t(self):
        """A_c's stick springs: the pairs' tangential stiffness."""
        return self.kt

    def springs(self, nodes, nnodes, closed=True, sticking=True):
        """The springs (2 nnodes square CSR) joining the pairs' ``nodes``
        (as read, or global): normal where ``closed``, tangential where
        also ``sticking`` (masks, or True for all)."""
        from vstpetsc.plane.interfaces import pair_matrix, spring_blocks

        kt = np.where(np.logical_and(sticking, closed), self.kt, 0.0)
        return pair_matrix(nodes, spring_blocks(self.normal, self.tangent,
                                                self.spring_n * closed, kt), nnodes)

    def relative(self, u):
        """(gap, tangential displacement) (m,) of each pair under the
        displacements u (nn, 2): n and t of u_second - u_first."""
        du = u[self.nodes[:, 1]] - u[self.nodes[:, 0]]
        return np.einsum("mc,mc->m", self.normal, du), np.einsum("mc,mc->m", self.tangent, du)

    def coordinates(self, z):
        """y (m, 4) from the pairs' slab unknowns z (m, 8)."""
        rel = z.reshape(-1, 2, 2, 2)
        rel = rel[:, 0] - rel[:, 1]                            # (m, component, time)
        return np.concatenate([np.einsum("mc,mca->ma", self.normal, rel),
                               np.einsum("mc,mca->ma", self.tangent, rel)], axis=1)

    def to_dofs(self, f):
        """The pairs' terms f (m, 4) as the entries of E f on their z (m, 8)."""
        node = (self.normal[:, :, None] * f[:, None, 0:2]
                + self.tangent[:, :, None] * f[:, None, 2:4])  # (m, component, time)
        return np.stack([node, -node], axis=1).reshape(-1, 8)

    def evaluate(self, z):
        """The kernels at the pairs' slab unknowns z (m, 8)."""
        self.evaluate_at(self.coordinates(z))

    def evaluate_at(self, y):
        """The kernels at the pairs' coordinates y (m, 4): fills ``out``
        and ``y`` (``cross`` is formed when first asked for: a Newton's
        trials that are not taken never need it)."""
        self.y = y
        for info, kernel in zip(self.infos, self.kernels):
            s = info.pairs
            self.out[s] = kernel.evaluate(self.gap[s], self.y[s], self.stretch[s])
        self._cross_at = None

    @property
    def cross(self):
        """d f_t / d d (m, 2, 2) at the last evaluation (``_cross``)."""
        if self._cross_at is None:
            self._cross_at = np.zeros((self.m, 2, 2))
            for info, kernel in zip(self.infos, self.kernels):
                if info.friction is not None:
                    self._cross_at[info.pairs] = self._cross(kernel, info.pairs)
        return self._cross_at

    def _cross(self, kernel, s):
        """d f_t / d d (m, 2, 2) by forward differences: friction's limit
        mu N follows the normal closing rates, which its kernel does not
        differentiate (zero where a pair sticks or is open).  Steps of
        CROSS_STEP of the rates' and the gap's size: the Jacobian then
        errs by about that, and Newton contracts by it per step."""
        y, gap, stretch = self.y[s], self.gap[s], self.stretch[s]
        base = self.out[s][:, pk.F_T].copy()
        # only a pair that slides somewhere in the slab feels its limit
        acting = (self.out[s][:, pk.ACTED] > 0) & (self.kt[s] > 0) & \
            (self.out[s][:, pk.DISSIPATED] != 0)
        cross = np.zeros((base.shape[0], 2, 2))
        if not acting.any():
            return cross
        size = np.abs(y[:, 0]) + np.abs(y[:, 1]) + np.abs(gap) / self.dt
        for b in range(2):
            step = CROSS_STEP * np.where(size > 0, size, 1.0)
            moved = y.copy()
            moved[:, b] += step
            f = kernel.evaluate(gap, moved, stretch)[:, pk.F_T]
            cross[:, :, b] = np.where(acting[:, None], (f - base) / step[:, None], 0.0)
        return cross

    def excess(self):
        """f - W_c y (m, 4) at the last evaluation: the pairs' terms beyond
        A_c's springs (a constant while a pair is closed and sticking)."""
        y = self.y
        f = self.forces()
        f[:, 0:2] -= self.spring_n[:, None] * (y[:, 0:2] @ self.hk.T)
        f[:, 2:4] -= self.spring_t[:, None] * (y[:, 2:4] @ self.hk.T)
        return f

    def forces(self):
        """f (m, 4) at the last evaluation: the pairs' normal and
        tangential terms."""
        return np.concatenate([self.out[:, pk.F_N], self.out[:, pk.F_T]], axis=1)

    def excess_tangent(self):
        """d(f - W_c y)/dy (m, 4, 4) at the last evaluation (friction's
        dependence on the normal rates from ``cross``)."""
        D = np.zeros((self.m, 4, 4))
        D[:, 0:2, 0:2] = self.out[:, pk.W_N].reshape(-1, 2, 2) - \
            self.spring_n[:, None, None] * self.hk
        D[:, 2:4, 2:4] = self.out[:, pk.W_T].reshape(-1, 2, 2) - \
            self.spring_t[:, None, None] * self.hk
        D[:, 2:4, 0:2] = self.cross
        return D

    def difference(self):
        """(f - W_c y as E's dof entries (m, 8), the Jacobian's difference
        blocks (m, 2, 2) normal, tangential and tangential by normal)."""
        D = self.excess_tangent()
        return self.to_dofs(self.excess()), D[:, 0:2, 0:2], D[:, 2:4, 2:4], D[:, 2:4, 0:2]

    def apply_difference(self, dz, dn, dtan, cross):
        """E (W - W_c) E^T on the pairs' entries dz (m, 8) (W with friction's
        dependence on the normal rates, ``cross``)."""
        y = self.coordinates(dz)
        f = np.concatenate([np.einsum("mab,mb->ma", dn, y[:, 0:2]),
                            np.einsum("mab,mb->ma", dtan, y[:, 2:4])
                            + np.einsum("mab,mb->ma", cross, y[:, 0:2])], axis=1)
        return self.to_dofs(f)

    def finish_slab(self):
        """Close the slab at the last evaluation (the converged one):
        (contact work, dissipated) of the slab, the state advanced."""
        out, y = self.out, self.y
        work_n = float(np.einsum("ma,ma->", out[:, pk.F_N], y[:, 0:2]))
        work_t = float(np.einsum("ma,ma->", out[:, pk.F_T], y[:, 2:4]))
        dissipated = float(out[:, pk.DISSIPATED].sum())
        self.gap -= 0.5 * self.dt * (y[:, 0] + y[:, 1])
        self.stretch = out[:, pk.STRETCH].copy()
        self.slip += out[:, pk.SLIP]
        self.normal_force = out[:, pk.IMPULSE] / self.dt
        self.shear_force = out[:, pk.SHEAR] / self.dt
        return work_n + work_t - dissipated, dissipated

    def stored_energy(self):
        """The springs' energy of the state: the power penalty's
        w g^2 / 2 of a closed pair and k_t e^2 / 2 (the seed's
        penalty stores none: it is not a potential)."""
        power = np.concatenate([np.full(i.pairs.stop - i.pairs.start, i.power)
                                for i in self.infos]) if self.infos else np.zeros(0, bool)
        closed = np.minimum(self.gap, 0.0)
        return float(0.5 * (self.w * power * closed ** 2).sum()
                     + 0.5 * (self.kt * self.stretch ** 2).sum())

    def start(self, u, static=False):
        """The state of t = 0 from the displacements u (nn, 2): the gaps,
        and for a static start the stick springs' stretch (at a sliding
        pair the limit mu N / k_t, none at an open one)."""
        self.gap, along = self.relative(u)
        self.stretch = np.zeros(self.m)
        if static:
            closed, sticking, sign = static_state(self, u)
            limit = self.mu * self.spring_n * np.maximum(-self.gap, 0.0) / \
                np.where(self.kt > 0, self.kt, 1.0)
            self.stretch = np.where(sticking, along, sign * limit) * closed * (self.kt > 0)
        self.slip = np.zeros(self.m)



def static_guess(pairs):
    """(closed, sticking, sign) of every pair: closed and sticking."""
    return np.ones(pairs.m, bool), np.ones(pairs.m, bool), np.zeros(pairs.m)


def static_state(pairs, u):
    """(closed, sticking, sign of the tangential displacement) of the
    pairs under the displacements u (nn, 2), with the static laws:
    closed where the gap is negative, sticking where the stick spring's
    force is within mu N (N = the normal spring's force)."""
    gap, along = pairs.relative(u)
    closed = gap < 0
    limit = pairs.mu * pairs.spring_n * np.maximum(-gap, 0.0)
    # no friction (k_t = 0): nothing along t, nothing to slide
    sticking = (closed & (pairs.kt * np.abs(along) <= limit)) | (pairs.kt == 0)
    return closed, sticking, np.sign(along) * ~sticking


def static_matrix(pairs, state, nnodes):
    """The pairs' static stiffness (2 nnodes square CSR, the numbering as
    read) for their states: normal springs where closed, stick springs
    where sticking, and where sliding the friction mu N along t against
    the tangential displacement, N = k_n (-g) (not symmetric)."""
    from vstpetsc.plane.interfaces import pair_matrix

    closed, sticking, sign = state
    # sliding: force -sign mu k_n (n . (u2 - u1)) t on the second node (its negative
    # on the first), -B (u2 - u1) with B = sign mu k_n t n^T: a spring's pattern of -B
    c = np.where(closed & ~sticking, sign * pairs.mu * pairs.spring_n, 0.0)
    block = c[:, None, None] * np.einsum("ma,mb->mab", pairs.tangent, pairs.normal)
    return pairs.springs(pairs.nodes, nnodes, closed, sticking) - \
        pair_matrix(pairs.nodes, block, nnodes)


def split_all(specs, mesh, materials, dt, wetted=()):
    """(the mesh split along every interface and every curve ``wetted`` (an
    acoustic water's faces) at once (interfaces.split_along: the same
    whatever the tables' order), [InterfaceInfo], the interfaces' pairs'
    (nodes, normal, tangent, length), {wetted curve: its NodePairs}) on
    rank 0; ValueError naming the interface for a curve the mesh has not,
    one on its boundary, an edge two interfaces share, or a penalty beyond
    its limit."""
    from vstpetsc.plane.interfaces import split_along

    for i, spec in enumerate(specs):
        if spec.name not in mesh.curves:
            raise ValueError(f"interface[{i}] ({spec.name}).name: the mesh has no curve "
                             f"{spec.name!r} (curves: {', '.join(mesh.curves) or 'none'})")
    names = [spec.name for spec in specs]
    try:
        split_mesh, parts = split_along(mesh, names + list(wetted))
    except ValueError as exc:
        named = next((i for i, n in enumerate(names) if repr(n) in str(exc)), None)
        if named is None:       # between wetted faces: the water's keys
            raise ValueError(f"water.faces: {exc}") from None
        raise ValueError(f"interface[{named}] ({names[named]}).name: {exc}") from None
    wet = dict(zip(wetted, parts[len(names):]))
    parts = parts[:len(names)]
    infos, start = [], 0
    for i, (spec, pairs) in enumerate(zip(specs, parts)):
        penalty, shear = stiffnesses(i, spec, mesh, materials, dt)
        m = pairs.length.size
        infos.append(InterfaceInfo(spec.name, slice(start, start + m), spec.formulation,
                                   penalty, shear if spec.friction is not None else 0.0,
                                   spec.friction, spec.penalty is not None))
        start += m
    join = lambda key, shape: np.concatenate([getattr(p, key) for p in parts]) if parts \
        else np.zeros(shape)
    return split_mesh, infos, (join("nodes", (0, 2)).astype(int), join("normal", (0, 2)),
                               join("tangent", (0, 2)), join("length", (0,))), wet


class InterfaceRecord:
    """One interface's part of the pairs' state, as the result file keeps
    it (group ``interface/<name>``): its rows' values, its attributes,
    its restart."""

    def __init__(self, pairs, info):
        self.pairs, self.info = pairs, info
        self.group = f"interface/{info.name}"

    def values(self):
        s, p = self.info.pairs, self.pairs
        return {key: getattr(p, key)[s] for key in SERIES}

    def restore(self, values):
        s, p = self.info.pairs, self.pairs
        for key in SERIES:
            getattr(p, key)[s] = np.asarray(values[key], dtype=float)

    def attrs(self):
        i = self.info
        return {"formulation": i.formulation, "penalty": i.penalty,
                "penalty_given": int(i.given), "friction": -1.0 if i.friction is None
                else i.friction, "shear_stiffness": i.shear_stiffness}

    def final_attrs(self):
        slip = self.pairs.slip[self.info.pairs]
        return {"permanent_slip": float(slip[np.argmax(np.abs(slip))]) if slip.size else 0.0}
