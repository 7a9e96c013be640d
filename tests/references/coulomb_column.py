"""An independent explicit reference for issue 27: a flexible shear column
on a Coulomb base. numpy only; it imports nothing of vstpetsc.

The model. A vertical column, x from 0 (base) to H (free top), area A,
density rho, shear modulus G = rho Vs^2, moves horizontally:
rho A w_tt = (G A w_x)_x, free at the top (G A w_x = 0). Its base rests on
rigid ground moving with velocity v_g(t), piecewise linear between the
samples (ground_t, ground_v) and held at its last value after them (so the
ground acceleration is piecewise constant). The interface carries Coulomb
friction with a constant normal force N: the force T on the column's base
(along +w) obeys |T| <= mu N; stuck, the base moves with the ground;
sliding, T = -mu N sign(w_base_t - v_g). mu = inf welds the base. No
damping. The column starts at rest relative to the ground (every node at
velocity v_g(t0)), in the shape w0 (default 0).

The discretisation. A lumped-mass chain: nodes x_i = i h, h = H / elements,
masses rho A h (half at both ends), springs G A / h between neighbours.
Central differences in the leapfrog form: velocities at half steps,
v^{n+1/2} = v^{n-1/2} + dt a^n, w^{n+1} = w^n + dt v^{n+1/2}, the first kick
dt/2 from the initial velocity. dt defaults to 0.2 h / Vs (the chain's
limit is h / Vs); it is shortened so that whole steps end at t_end.

The base, each step. Its trial force to stick is the force that makes its
velocity at n+1/2 the ground's: T_stick = m_0 (v_g^{n+1/2} - v_0^{n-1/2}) / dt
- f_0^n (f_0 the spring's force on it). |T_stick| <= mu N: stick, T =
T_stick, the base takes the ground's velocity. Otherwise slide with
T = mu N sign(T_stick). This single rule is the usual explicit one in closed
form: a sliding base whose relative velocity keeps its sign under
T = -mu N sign(v_rel) has T_stick beyond that force, so it keeps sliding;
one whose relative velocity would reverse within the step has T_stick on
the other side of it, so it sticks at the ground's velocity for the step
if |T_stick| <= mu N (no chattering), or slides the other way; from rest
it slides opposite to the trial force's push, i.e. T has the sign of
T_stick. T is the projection of T_stick on [-mu N, mu N], which is the
backward-Euler Coulomb law T in -mu N Sign(v_rel^{n+1/2}).

Outputs at the whole steps t_n: the slip s = w_base - w_ground (advanced by
dt (v_0 - v_g) at the half steps: exactly 0 while stuck), the slip rate and
velocities as the mean of the two neighbouring half-step values, the force
T^n of the kick around t_n, the kinetic energy of those velocities, the
strain energy of w^n, the friction energy mu N times the slip path
(= -sum T^n (s^{n+1} - s^n), exactly, by the rule above; nondecreasing) and
the ground's work, the trapezoidal sum of T^n v_g^n. Leapfrog's exact
identity (its energy at the half steps changes by F^n . v^n dt) makes
kinetic + strain + friction - work - initial energy an O(dt^2) residual.

What converges and how (measured in tests/test_coulomb_column_reference.py):
a welded column oscillates in its discrete modes at leapfrog's frequency
2/dt asin(omega dt / 2), exactly (the sampled sin(pi x / 2H) is the lumped
chain's first mode, omega = 2 Vs/h sin(pi h / 4H)), its energy fluctuating
by (omega dt / 2)^2; the energy-balance residual falls as dt^2 (ratio 4.0
per halving), stick/slip events included; at a fixed mesh the final slip
converges in dt at order about 2 (each stop inside a step errs by O(dt^2)
in slip); in elements (with dt = 0.2 h / Vs) the final slip's successive
differences shrink by 2.8 to 6.4 per halving (8 to 128 elements), irregularly (events meet the
elastic ringing); as Vs grows the slip tends to the rigid block's
(sliding_block.py here, a_y = mu N / (rho A H)), for a rectangular pulse
with an error proportional to 4H/Vs over the pulse length.
"""

import math
from dataclasses import dataclass

import numpy as np


@dataclass
class ColumnRun:
    """The history at every whole step t_n (arrays of one length)."""
    t: np.ndarray                 # times [s]
    slip: np.ndarray              # w_base - w_ground [m]
    slip_rate: np.ndarray         # d slip / dt [m/s]
    base_shear: np.ndarray        # friction force on the column, along +w [N]
    top_velocity: np.ndarray      # absolute velocity of the top node [m/s]
    top_displacement: np.ndarray  # absolute displacement of the top node [m]
    friction_energy: np.ndarray   # mu N times the slip path so far [J]
    kinetic_energy: np.ndarray    # [J]
    strain_energy: np.ndarray     # [J]
    ground_work: np.ndarray       # work of the base force on the ground's motion [J]
    dt: float                     # the step used [s]

    def energy_residual(self):
        """kinetic + strain + friction - ground work - the initial energy
        (0 for an exact balance) at every step [J]."""
        total = self.kinetic_energy + self.strain_energy + self.friction_energy
        return total - self.ground_work - total[0]


class _Chain:
    """The lumped-mass chain: node masses, spring stiffness, forces."""

    def __init__(self, H, elements, rho, Vs, A):
        self.h = H / elements
        self.x = np.linspace(0.0, H, elements + 1)
        self.mass = np.full(elements + 1, rho * A * self.h)
        self.mass[[0, -1]] /= 2.0
        self.k = rho * Vs ** 2 * A / self.h

    def force(self, w):
        """The springs' forces on the nodes."""
        tension = self.k * np.diff(w)
        f = np.zeros_like(w)
        f[:-1] += tension
        f[1:] -= tension
        return f

    def strain_energy(self, w):
        return 0.5 * self.k * float(np.dot(np.diff(w), np.diff(w)))


def base_kick(v0, f0, m0, dt, vg_next, limit):
    """The base node's velocity after a kick of length dt and the friction
    force T of the kick: stick (velocity vg_next, T the force that needs)
    when |T| <= limit = mu N, else slide with T = limit sign(T_stick)."""
    stick_force = m0 * (vg_next - v0) / dt - f0
    if abs(stick_force) <= limit:
        return vg_next, stick_force
    force = math.copysign(limit, stick_force)
    return v0 + dt * (f0 + force) / m0, force


_COLUMNS = ("slip", "slip_rate", "base_shear", "top_velocity", "top_displacement",
            "friction_energy", "kinetic_energy", "strain_energy", "ground_power")


class _Run:
    """The leapfrog state (w at t_n, v at the half step before it; at t0
    the initial velocity) and the per-step records."""

    def __init__(self, chain, limit, ground, t, w0):
        self.chain, self.limit, self.ground, self.t = chain, limit, ground, t
        self.dt = t[1] - t[0]
        self.w = np.array(w0, float)
        self.v = np.full_like(self.w, ground(t[0]))
        self.slip, self.friction = 0.0, 0.0
        self.rows = np.zeros((len(t), len(_COLUMNS)))

    def kick(self, n):
        """The kick around t_n (dt/2 from t0 for n = 0): the velocities at
        t_n + dt/2 and the base force."""
        chain = self.chain
        length = self.dt / 2.0 if n == 0 else self.dt
        f = chain.force(self.w)
        v_next = self.v + length * f / chain.mass
        v_next[0], force = base_kick(self.v[0], f[0], chain.mass[0], length,
                                     self.ground(self.t[n] + self.dt / 2.0), self.limit)
        return v_next, force

    def record(self, n, v_next, force):
        """The values at t_n; velocities are the mean of the half steps
        around t_n (the initial ones at t0)."""
        t, half = self.t[n], self.dt / 2.0
        if n == 0:
            v_now, vg_now = self.v, self.ground(t)
        else:
            v_now = 0.5 * (self.v + v_next)
            vg_now = 0.5 * (self.ground(t - half) + self.ground(t + half))
        kinetic = 0.5 * float(np.dot(self.chain.mass, v_now ** 2))
        self.rows[n] = (self.slip, v_now[0] - vg_now, force, v_now[-1], self.w[-1],
                        self.friction, kinetic, self.chain.strain_energy(self.w),
                        force * vg_now)

    def drift(self, n, v_next, force):
        """w to t_{n+1}; the slip by the relative half-step velocity, and
        the friction energy by -T ds (= mu N |ds| while sliding, 0 stuck)."""
        ds = (v_next[0] - self.ground(self.t[n] + self.dt / 2.0)) * self.dt
        self.slip += ds
        self.friction -= force * ds if ds != 0.0 else 0.0
        self.w += self.dt * v_next
        self.v = v_next

    def go(self):
        for n in range(len(self.t)):
            v_next, force = self.kick(n)
            self.record(n, v_next, force)
            if n + 1 < len(self.t):
                self.drift(n, v_next, force)
        columns = dict(zip(_COLUMNS, self.rows.T))
        power = columns.pop("ground_power")
        steps = 0.5 * self.dt * (power[1:] + power[:-1])     # trapezoidal rule
        work = np.concatenate(([0.0], np.cumsum(steps)))
        return ColumnRun(t=self.t, ground_work=work, dt=self.dt, **columns)


def _check(name, value, ok, what):
    if not ok:
        raise ValueError(f"{name}: {what} (got {value!r})")


def _initial_shape(w0, x):
    if w0 is None:
        return np.zeros_like(x)
    shape = np.asarray(w0(x) if callable(w0) else w0, float)
    _check("w0", w0, shape.shape == x.shape and np.all(np.isfinite(shape)),
           f"{len(x)} finite node values or a function of x")
    return shape


def _ground(ground_t, ground_v):
    """v_g(t): piecewise linear between the samples, held outside them."""
    gt, gv = np.asarray(ground_t, float), np.asarray(ground_v, float)
    _check("ground_t", ground_t, gt.ndim == 1 and gt.shape == gv.shape and len(gt) >= 1
           and np.all(np.diff(gt) > 0) and np.all(np.isfinite(gv)),
           "increasing 1-D samples, as many as ground_v (finite)")
    return lambda time: float(np.interp(time, gt, gv))


def column_on_coulomb_base(H, elements, rho, Vs, A, mu, normal, ground_t, ground_v,
                           t_end, dt=None, w0=None):
    """The column of the module docstring from ground_t[0] to t_end under
    the ground velocity record (ground_t, ground_v); mu = inf welds the
    base; w0: the initial shape (node values, or a function of x).
    Returns a ColumnRun."""
    for name, value in (("H", H), ("rho", rho), ("Vs", Vs), ("A", A), ("normal", normal)):
        _check(name, value, math.isfinite(value) and value > 0.0, "must be positive")
    _check("elements", elements, int(elements) == elements and elements >= 1,
           "a whole number >= 1")
    _check("mu", mu, mu >= 0.0, "must be >= 0 (inf: welded)")
    chain = _Chain(H, int(elements), rho, Vs, A)
    ground = _ground(ground_t, ground_v)
    span, limit_dt = t_end - float(ground_t[0]), chain.h / Vs
    dt = 0.2 * limit_dt if dt is None else dt
    _check("t_end", t_end, span > 0.0, "must be after ground_t[0]")
    _check("dt", dt, 0.0 < dt < limit_dt, f"must be in (0, h / Vs = {limit_dt:g})")
    steps = math.ceil(span / dt - 1e-9)
    t = float(ground_t[0]) + span * np.arange(steps + 1) / steps
    limit = math.inf if math.isinf(mu) else mu * normal
    return _Run(chain, limit, ground, t, _initial_shape(w0, chain.x)).go()
