"""An independent reference for issue 28's nonlinear soil law: the MKZ
backbone with the extended Masing rules, one material point at a time and
in an explicit shear column. numpy and scipy only; it imports nothing of
vstpetsc (written from the physics, to check the solver against).

The law (one material point). Backbone
    tau = F(gamma) = G gamma / (1 + beta (|gamma| / gamma_ref)^s),
G the small-strain shear modulus, gamma the engineering shear strain
(gamma_ref = inf or beta = 0: linear, tau = G gamma). The point is virgin
at gamma = 0 (on the backbone) and is driven by a strain history: strains
at successive instants, linear between them (so the strain only reverses
at a sample). State: the direction of the last nonzero increment and a
stack of open reversal points (gamma_k, tau_k), oldest first.
  - Reversal: an increment whose sign is opposite to the last nonzero
    one pushes the current point (the previous sample) on the stack.
    Zero increments change nothing.
  - Branch: empty stack, tau = F(gamma) (the backbone); otherwise, from the
    newest point (g_k, t_k), tau = t_k + 2 F((gamma - g_k) / 2).
  - Rejoin an earlier branch: with two or more points, the branch from g_k
    passes through g_{k-1} (where the previous branch began: F is odd);
    when the strain reaches or passes g_{k-1} in the branch's direction
    the two newest points are dropped and the point continues on the
    branch from g_{k-2} (or the backbone if none is left), same direction.
  - Rejoin the backbone: with one point (g_1, t_1), which is on the
    backbone, the branch passes through the mirrored point (-g_1, -t_1);
    when the strain reaches or passes -g_1 the point is dropped and the
    backbone followed.
  Drops repeat within one increment while they apply; the stress is the
  then-current branch at the new strain (path-independent within a
  monotonic increment). MasingPoint implements this in plain scalar
  Python; masing_stress(strains, ...) runs it over a history.

Masing damping of a symmetric loop of amplitude gamma_a (tau_a = F(gamma_a)):
the loading branch -tau_a + 2 F((g + gamma_a)/2) lies above the unloading
one tau_a + 2 F((g - gamma_a)/2); the loop area A is their difference
integrated over [-gamma_a, gamma_a] (loop_damping_quadrature: adaptive
quadrature, D = A / (2 pi tau_a gamma_a)). Substituting, A = 8 W - 4 tau_a
gamma_a with W = int_0^gamma_a F, so D = (2/pi) (2 W / (tau_a gamma_a) - 1)
(loop_damping_closed_form), W = G gamma_a^2 / 2 * 2F1(1, 2/s; 1 + 2/s;
-beta (gamma_a / gamma_ref)^s) in closed form (backbone_work).

The column (run_column). A vertical shear column, x from the base (0) up
to the free surface (H), area 1, elements (layers) of length h_e with
rho_e, G_e = rho_e Vs_e^2 and MKZ parameters each (Column, Column.layered
with layers listed from the base up). Horizontal motion w(x, t):
rho w_tt = tau_x, tau = the law at gamma = w_x. Discretisation: a lumped
chain, nodes x_0 = 0 < ... < x_N = H, node masses half of each adjacent
element's rho_e h_e; element strain gamma_e = (w_{e+1} - w_e) / h_e, its
stress tau_e from its own MasingPoint; the element pulls its lower node
by +tau_e and its upper node by -tau_e. Central differences (leapfrog):
velocities at half steps, v^{n+1/2} = v^{n-1/2} + dt a^n, w^{n+1} = w^n +
dt v^{n+1/2}, the first kick dt/2 from the initial state (at rest, or in
the shape w0, at velocity 0; a rigid base's column starts moving rigidly
with v_b(0)). dt = courant * min_e(h_e / Vs_e) (courant <= 0.9; the
lumped chain is stable up to 1 by Gershgorin), shortened so whole steps
end at t_end. Input histories are piecewise linear between samples and
held outside them.
  - RigidBase(t, v): the base node moves with v_b(t) (within motion):
    v_0^{n+1/2} = v_b(t_n + dt/2). Its reaction R^n = m_0 a_0^n - f_0^n
    (f_0 the element force on it) does the input work.
  - LysmerBase(Z, t, v_in): a half-space of impedance Z below carrying the
    incident velocity v_in(t); the base node receives Z (2 v_in - v_0),
    with v_0 the mean of the half-step velocities around t_n (the base
    node's update is solved for it: implicit in one scalar, so the dashpot
    never limits dt). Outcrop motion = 2 v_in.
  The surface (node N) is free.

Outputs at every whole step t_n (ColumnRun): velocities as the mean of the
two half-step velocities around t_n (the initial ones at t_0),
accelerations (v^{n+1/2} - v^{n-1/2}) / dt (the kick's; f/m at t_0), of
the surface and base nodes; the peak |gamma_e| per element over every step
(t_0 included); energies per unit area: kinetic 1/2 sum m v^2, stored
sum h tau^2 / (2 G), internal work sum_e h_e int tau dgamma (trapezoidal
in time: (tau^n + tau^{n+1}) / 2 (gamma^{n+1} - gamma^n) per step, the
strain being linear over a step), hysteretic = internal work - stored
(exactly 0 for a linear law), dashpot int Z v_0^2 dt and input (int 2 Z
v_in v_0 dt, or int R v_b dt) by the trapezoidal rule on the step values.
energy_residual() = kinetic + internal work + dashpot - input - initial
energy: leapfrog's exact half-step identity makes it an O(dt^2) boundary
term (it does not accumulate), measured in tests/test_mkz_reference.py.
Optionally the strain and stress histories of chosen elements
(record=...): their stress is exactly masing_stress(their strain).
response_spectrum(t, a, periods, damping) gives pseudo-spectral
accelerations of a sampled record (each oscillator integrated exactly for
an acceleration linear between samples).

What is measured (tests/test_mkz_reference.py): a symmetric strain cycle
through MasingPoint gives the closed-form D within 1e-3 at 0.2, 2 and 20
gamma_ref, and the closed form and the loop quadrature agree to 1e-9; an
inner unload-reload rejoins the outer branch exactly (to 1e-12) and the
backbone beyond it; a linear column moves in the lumped chain's exact
first mode (to 1e-12), matches d'Alembert's solution on a rigid and on a
matched Lysmer base at order h^2 (dt = 0.5 h / Vs) and the Lysmer base
lets the wave out; the energy residual of a layered MKZ column (peak
strain > 1.5 gamma_ref, a third to all of the input dissipated by
hysteresis) falls by 4.0 per halving of dt; the surface's peak velocity
and 5 % spectrum (0.1 to 1 s) converge under mesh refinement (1.5 % and
less between h = 1.25 and 0.625 m). The raw peak surface acceleration
converges at order 2 for a linear column only: after the Masing reversals
a nonlinear run carries grid-scale ringing (near the chain's highest
frequency 2 Vs / h) that this lossless scheme never damps, a few per cent
of the peak acceleration, not shrinking with h (it moves to higher
frequency); compare spectra, not peak accelerations, against a scheme
with numerical dissipation. Cost: about 4 us per element and step (a
100-element column over 20000 steps in about 8 s).
"""

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.integrate
import scipy.linalg
import scipy.special


@dataclass(frozen=True)
class Mkz:
    """The MKZ backbone: tau = G gamma / (1 + beta (|gamma| / gamma_ref)^s)."""
    G: float
    gamma_ref: float = math.inf
    beta: float = 1.0
    s: float = 1.0

    def backbone(self, gamma):
        """F(gamma) for a float or an array."""
        ratio = abs(gamma) / self.gamma_ref      # abs: fast on floats, also arrays
        return self.G * gamma / (1.0 + self.beta * ratio ** self.s)


class MasingPoint:
    """One material point under the extended Masing rules (module docstring).
    strain_to(gamma) moves it to a new strain and returns the stress."""

    def __init__(self, law):
        self.law = law
        self.gamma, self.tau = 0.0, 0.0
        self.direction = 0          # sign of the last nonzero strain increment
        self.reversals = []         # open reversal points (gamma, tau), oldest first

    def strain_to(self, gamma):
        gamma = float(gamma)
        step = gamma - self.gamma
        if step == 0.0:
            return self.tau
        direction = 1 if step > 0.0 else -1
        if direction == -self.direction:
            self.reversals.append((self.gamma, self.tau))
        self.direction = direction
        self._drop_passed(gamma)
        self.gamma, self.tau = gamma, self._branch(gamma)
        return self.tau

    def _target(self):
        """The strain where the current branch meets the branch it then
        continues on: the previous branch's start, or the mirrored point."""
        if len(self.reversals) >= 2:
            return self.reversals[-2][0]
        return -self.reversals[0][0]

    def _drop_passed(self, gamma):
        while self.reversals and self.direction * (gamma - self._target()) >= 0.0:
            del self.reversals[-2:]     # one point when only the first is left

    def _branch(self, gamma):
        if not self.reversals:
            return float(self.law.backbone(gamma))
        g_k, t_k = self.reversals[-1]
        return t_k + 2.0 * float(self.law.backbone((gamma - g_k) / 2.0))


def masing_stress(strains, G, gamma_ref=math.inf, beta=1.0, s=1.0):
    """The stress at every instant of a strain history (a 1-D array; the
    virgin point starts at 0 and goes linearly to strains[0] first)."""
    point = MasingPoint(Mkz(G, gamma_ref, beta, s))
    return np.array([point.strain_to(g) for g in np.asarray(strains, float)])


def backbone_work(law, gamma_a):
    """W = int_0^gamma_a F (gamma_a > 0), in closed form with 2F1."""
    if law.beta == 0.0 or math.isinf(law.gamma_ref):
        return 0.5 * law.G * gamma_a ** 2
    z = -law.beta * (gamma_a / law.gamma_ref) ** law.s
    b = 2.0 / law.s
    return 0.5 * law.G * gamma_a ** 2 * float(scipy.special.hyp2f1(1.0, b, 1.0 + b, z))


def loop_damping_closed_form(law, gamma_a):
    """Masing D = (2/pi) (2 W / (tau_a gamma_a) - 1)."""
    tau_a = float(law.backbone(gamma_a))
    return 2.0 / math.pi * (2.0 * backbone_work(law, gamma_a) / (tau_a * gamma_a) - 1.0)


def loop_damping_quadrature(law, gamma_a):
    """Masing D = loop area / (2 pi tau_a gamma_a), the area between the two
    Masing branches of the symmetric loop by adaptive quadrature."""
    tau_a = float(law.backbone(gamma_a))

    def gap(g):                       # loading branch minus unloading branch
        loading = -tau_a + 2.0 * law.backbone((g + gamma_a) / 2.0)
        unloading = tau_a + 2.0 * law.backbone((g - gamma_a) / 2.0)
        return float(loading - unloading)

    area, _ = scipy.integrate.quad(gap, -gamma_a, gamma_a, epsabs=0.0, epsrel=1e-12,
                                   limit=200)
    return area / (2.0 * math.pi * tau_a * gamma_a)


# ---------------------------------------------------------------- the column

def _per_element(name, value, n):
    array = np.broadcast_to(np.asarray(value, float), (n,)).copy()
    _check(name, value, np.all(~np.isnan(array)), "must be numbers")
    return array


def _check(name, value, ok, what):
    if not ok:
        raise ValueError(f"{name}: {what} (got {value!r})")


@dataclass
class Column:
    """Elements from the base up: lengths h, density rho, shear wave speed
    Vs and MKZ parameters (each an array of one value per element)."""
    h: np.ndarray
    rho: np.ndarray
    Vs: np.ndarray
    gamma_ref: np.ndarray
    beta: np.ndarray
    s: np.ndarray

    def __post_init__(self):
        n = np.size(self.h)
        for name in ("h", "rho", "Vs", "gamma_ref", "beta", "s"):
            setattr(self, name, _per_element(name, getattr(self, name), n))
        for name in ("h", "rho", "Vs", "gamma_ref", "s"):
            _check(name, getattr(self, name), np.all(getattr(self, name) > 0.0),
                   "must be > 0")
        _check("beta", self.beta, np.all(self.beta >= 0.0), "must be >= 0")

    @classmethod
    def uniform(cls, H, elements, rho, Vs, gamma_ref=math.inf, beta=1.0, s=1.0):
        return cls(np.full(int(elements), H / elements), rho, Vs, gamma_ref, beta, s)

    @classmethod
    def layered(cls, layers, h_max):
        """layers: (thickness, rho, Vs, gamma_ref, beta, s) from the base up,
        each cut into ceil(thickness / h_max) equal elements."""
        rows = []
        for thickness, *params in layers:
            n = math.ceil(thickness / h_max - 1e-9)
            rows += [(thickness / n, *params)] * n
        return cls(*(np.array(c, float) for c in zip(*rows)))

    @property
    def G(self):
        return self.rho * self.Vs ** 2

    @property
    def x(self):
        return np.concatenate(([0.0], np.cumsum(self.h)))

    @property
    def mass(self):
        """Lumped node masses (area 1)."""
        half = 0.5 * self.rho * self.h
        return np.concatenate((half, [0.0])) + np.concatenate(([0.0], half))

    def laws(self):
        return [Mkz(*p) for p in zip(self.G, self.gamma_ref, self.beta, self.s)]

    def dt_limit(self):
        return float(np.min(self.h / self.Vs))


def _history(name, t, v):
    """v(t): piecewise linear between the samples, held outside them."""
    t, v = np.asarray(t, float), np.asarray(v, float)
    _check(name, t, t.ndim == 1 and t.shape == v.shape and len(t) >= 1
           and np.all(np.diff(t) > 0) and np.all(np.isfinite(v)),
           "increasing 1-D sample times, as many as the (finite) values")
    return lambda time: float(np.interp(time, t, v))


@dataclass
class RigidBase:
    """The base node moves with the velocity v(t) (within motion)."""
    t: np.ndarray
    v: np.ndarray


@dataclass
class LysmerBase:
    """A half-space of impedance Z (per unit area) with incident velocity
    v_in(t): force Z (2 v_in - v_0) on the base node."""
    Z: float
    t: np.ndarray
    v_in: np.ndarray


@dataclass
class ColumnRun:
    """The history at every whole step t_n (energies per unit area)."""
    t: np.ndarray
    surface_velocity: np.ndarray
    surface_acceleration: np.ndarray
    base_velocity: np.ndarray
    base_acceleration: np.ndarray
    peak_strain: np.ndarray        # (elements,) max |gamma| over every step
    kinetic: np.ndarray
    stored: np.ndarray             # sum h tau^2 / (2 G)
    internal_work: np.ndarray      # sum h int tau dgamma
    dashpot: np.ndarray
    input: np.ndarray
    dt: float
    x: np.ndarray
    strain: dict = field(default_factory=dict)   # element -> gamma at every step
    stress: dict = field(default_factory=dict)   # element -> tau at every step

    @property
    def hysteretic(self):
        return self.internal_work - self.stored

    def energy_residual(self):
        total = self.kinetic + self.internal_work + self.dashpot - self.input
        return total - (self.kinetic[0] + self.stored[0])


class _Base:
    """The base node's kick: its new half-step velocity and the input and
    dashpot powers at t_n (from the mean velocity over the kick)."""

    def __init__(self, base, m0):
        self.m0 = m0
        if isinstance(base, RigidBase):
            self.Z, self.v = None, _history("base.v", base.t, base.v)
        else:
            _check("base.Z", base.Z, base.Z >= 0.0, "must be >= 0")
            self.Z, self.v = float(base.Z), _history("base.v_in", base.t, base.v_in)

    def start_velocity(self):
        return self.v(0.0) if self.Z is None else 0.0

    def kick(self, v0, f0, t, length, dt):
        """(v0 at t + dt/2, input power, dashpot power) for a kick of
        `length` around t, f0 the element force on the base node."""
        m0 = self.m0
        if self.Z is None:
            v_next = self.v(t + dt / 2.0)
            reaction = m0 * (v_next - v0) / length - f0
            return v_next, reaction * 0.5 * (v0 + v_next), 0.0
        Z, v_in = self.Z, self.v(t)
        # m0 (v+ - v-) / L = f0 + Z (2 v_in - (v+ + v-) / 2), solved for v+
        v_next = (m0 * v0 / length + f0 + 2.0 * Z * v_in - 0.5 * Z * v0) / (m0 / length + 0.5 * Z)
        mean = 0.5 * (v0 + v_next)
        return v_next, 2.0 * Z * v_in * mean, Z * mean ** 2


_ROWS = ("surface_velocity", "surface_acceleration", "base_velocity", "base_acceleration",
         "kinetic", "stored", "internal_work", "input_power", "dashpot_power")


class _ColumnStepper:
    """The leapfrog state: w at t_n, v at t_n - dt/2 (the initial velocity
    at t_0), each element's MasingPoint and its strain and stress at t_n."""

    def __init__(self, column, base, w0, record):
        self.column, self.record = column, list(record)
        self.mass, self.G = column.mass, column.G
        self.base = _Base(base, self.mass[0])
        self.w = np.array(w0, float)
        self.v = np.full_like(self.w, self.base.start_velocity())
        self.points = [MasingPoint(law) for law in column.laws()]
        self.gamma = np.diff(self.w) / column.h
        self.tau = self._stress(self.gamma)
        self.work = float(np.dot(column.h, [backbone_work(p.law, abs(g)) for p, g
                                            in zip(self.points, self.gamma)]))
        self.peak = np.abs(self.gamma)

    def _stress(self, gamma):
        return np.array([p.strain_to(g) for p, g in zip(self.points, gamma)])

    def kick(self, t, length, dt):
        """The velocities at t + dt/2 and the base's powers at t."""
        f = np.zeros_like(self.w)
        f[:-1] += self.tau
        f[1:] -= self.tau
        v_next = self.v + length * f / self.mass
        v_next[0], p_in, p_dash = self.base.kick(self.v[0], f[0], t, length, dt)
        return v_next, p_in, p_dash

    def row(self, n, v_next, length, p_in, p_dash):
        v_now = self.v if n == 0 else 0.5 * (self.v + v_next)
        a_now = (v_next - self.v) / length
        kinetic = 0.5 * float(np.dot(self.mass, v_now ** 2))
        stored = float(np.dot(self.column.h, self.tau ** 2 / (2.0 * self.G)))
        return (v_now[-1], a_now[-1], v_now[0], a_now[0], kinetic, stored, self.work,
                p_in, p_dash)

    def drift(self, dt, v_next):
        """w to t_{n+1}; the new strains and stresses and the internal work."""
        self.w += dt * v_next
        self.v = v_next
        gamma = np.diff(self.w) / self.column.h
        tau = self._stress(gamma)
        self.work += float(np.dot(self.column.h, 0.5 * (self.tau + tau) * (gamma - self.gamma)))
        self.gamma, self.tau = gamma, tau
        self.peak = np.maximum(self.peak, np.abs(gamma))


def _time_grid(column, t_end, dt, courant):
    _check("courant", courant, 0.0 < courant <= 0.9, "must be in (0, 0.9]")
    limit = 0.9 * column.dt_limit()
    dt = courant * column.dt_limit() if dt is None else dt
    _check("dt", dt, 0.0 < dt <= limit, f"must be in (0, 0.9 min(h / Vs) = {limit:g}]")
    _check("t_end", t_end, t_end > 0.0, "must be > 0")
    steps = math.ceil(t_end / dt - 1e-9)
    return t_end * np.arange(steps + 1) / steps


def run_column(column, base, t_end, dt=None, courant=0.5, w0=None, record=()):
    """The column of the module docstring from t = 0 to t_end on `base`
    (RigidBase or LysmerBase); w0: initial node displacements (default 0);
    record: element indices whose strain and stress histories to keep.
    Returns a ColumnRun."""
    t = _time_grid(column, t_end, dt, courant)
    dt = t[1] - t[0]
    w0 = np.zeros(len(column.h) + 1) if w0 is None else np.asarray(w0, float)
    _check("w0", w0, w0.shape == (len(column.h) + 1,), "one value per node")
    state = _ColumnStepper(column, base, w0, record)
    rows = np.zeros((len(t), len(_ROWS)))
    strain = {e: np.zeros(len(t)) for e in state.record}
    stress = {e: np.zeros(len(t)) for e in state.record}
    for n, time in enumerate(t):
        for e in state.record:
            strain[e][n], stress[e][n] = state.gamma[e], state.tau[e]
        length = dt / 2.0 if n == 0 else dt
        v_next, p_in, p_dash = state.kick(time, length, dt)
        rows[n] = state.row(n, v_next, length, p_in, p_dash)
        if n + 1 < len(t):
            state.drift(dt, v_next)
    columns = dict(zip(_ROWS, rows.T))
    return ColumnRun(t=t, peak_strain=state.peak, dt=dt, x=column.x, strain=strain,
                     stress=stress, input=_time_integral(columns.pop("input_power"), dt),
                     dashpot=_time_integral(columns.pop("dashpot_power"), dt), **columns)


def _time_integral(power, dt):
    """The running trapezoidal integral of the step values."""
    return np.concatenate(([0.0], np.cumsum(0.5 * dt * (power[1:] + power[:-1]))))


# ---------------------------------------------------------------- spectra

def _sdof_steps(period, damping, dt):
    """The exact one-step map of u'' + 2 zeta w u' + w^2 u = -a(t) with a
    linear over the step: (u, v, a0, a') at the step's start -> (u, v)."""
    w = 2.0 * math.pi / period
    system = np.array([[0.0, 1.0, 0.0, 0.0],
                       [-w * w, -2.0 * damping * w, -1.0, 0.0],
                       [0.0, 0.0, 0.0, 1.0],
                       [0.0, 0.0, 0.0, 0.0]])
    return scipy.linalg.expm(system * dt)[:2]


def response_spectrum(t, a, periods, damping=0.05):
    """Pseudo-spectral accelerations w^2 max|u| of linear oscillators at
    rest at t[0] under the base acceleration a (samples at the uniform
    times t, linear between them), integrated exactly step by step."""
    t, a = np.asarray(t, float), np.asarray(a, float)
    dt = t[1] - t[0]
    _check("t", t, np.allclose(np.diff(t), dt, rtol=1e-9, atol=0.0), "uniform steps")
    maps = np.array([_sdof_steps(T, damping, dt) for T in periods])   # (nT, 2, 4)
    state, peak = np.zeros((len(periods), 2)), np.zeros(len(periods))
    slope = np.diff(a) / dt
    for n in range(len(a) - 1):
        state = (np.einsum("pij,pj->pi", maps[:, :, :2], state)
                 + maps[:, :, 2] * a[n] + maps[:, :, 3] * slope[n])
        peak = np.maximum(peak, np.abs(state[:, 0]))
    w = 2.0 * math.pi / np.asarray(periods, float)
    return w * w * peak
