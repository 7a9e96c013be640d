"""An independent explicit reference for a yielding column with a sliding
interface (interface.md, "A yielding column with interfaces"): MKZ soil
with the extended Masing rules and Coulomb friction in one run. numpy
only; it imports nothing of vstpetsc. It reuses, by import, the
Masing point and the layered column of mkz.py (with its Lysmer base rule)
and the Coulomb stick/slide rule of coulomb_column.py (base_kick).

Two models, horizontal (shear) motion w(x, t) only, x up, area A:

(a) column_on_coulomb_base: an MKZ column, x from 0 (base) to H (free
    top), on rigid ground moving with the velocity v_g(t) (piecewise
    linear between the samples, held outside them); the base node is
    held by Coulomb friction with a constant normal force N (in the
    vstpetsc tests the column's weight rho A H g, from the static start):
    |T| <= mu N, stuck the base moves with the ground, sliding
    T = -mu N sign(w_base_t - v_g). slip = w_base - w_ground (the
    vstpetsc pair ["wall", "column"]). mu = inf welds the base: then it
    is mkz.py's column on RigidBase(ground).
(b) block_on_yielding_column: the same MKZ column on mkz.py's Lysmer base
    (a half-space of impedance Z per unit area below, carrying the
    incident velocity v_in: force A Z (2 v_in - v_0) on the base node,
    outcrop motion = 2 v_in), and on its top, across a Coulomb pair with
    N = the block's weight, a block: a linear elastic chain (Block with
    elements >= 1) or a point mass (elements = 0). slip = w_block_bottom -
    w_column_top (the pair ["column", "block"]).

The discretisation. Each body is mkz.py's lumped chain: node masses half
of each adjacent element's rho_e h_e A, element strain gamma_e = (w_{e+1}
- w_e) / h_e, its stress tau_e from its own MasingPoint (a linear block:
gamma_ref = inf), force A tau_e on its lower node and -A tau_e on its
upper one. Central differences (leapfrog): v^{n+1/2} = v^{n-1/2} + dt a^n,
w^{n+1} = w^n + dt v^{n+1/2}, the first kick dt/2 from rest (every node
of (a) at v_g(0); (b) at 0), w = 0 at t = 0. dt = courant * min(h / Vs)
over both bodies (courant <= 0.9, default 0.5), shortened so whole steps
end exactly at t_end (t_n = t_end n / steps).
  - Ground pair (a): coulomb_column.base_kick, the trial force that
    makes the base's half-step velocity the ground's at t_n + dt/2,
    projected on [-mu N, mu N] (backward-Euler Coulomb, no chattering).
  - Block pair (b): the same rule on the relative motion: reduced mass
    m* = m_c m_b / (m_c + m_b) of the column's top node and the block's
    bottom node, relative velocity v_b - v_c, relative force m* (f_b / m_b
    - f_c / m_c), target 0; stuck, both nodes take the momentum-conserving
    common velocity (exactly equal, so a stuck pair never slips),
    sliding, the force +T on the block and -T on the column's top.
  - Lysmer base (b): mkz.py's rule (the base node's update solved for the
    mean velocity, implicit in one scalar).
  Slip advances by dt (relative half-step velocity): exactly 0 while
  stuck. Friction energy = sum -T^n (s^{n+1} - s^n) = mu N times the slip
  path. Velocities at t_n: mean of the half steps around t_n (the initial
  ones at t_0); accelerations (v^{n+1/2} - v^{n-1/2}) / dt (the kick's).
  Energies [J] at t_n: kinetic 1/2 sum m v^2; stored sum A h tau^2 / (2 G)
  (both bodies); internal work sum A h int tau dgamma (trapezoidal per
  step); hysteretic = internal work - stored (0 up to rounding for the
  linear block); friction; dashpot int A Z v_0^2 dt and input (a: int T
  v_g dt, the ground's work on the column; b: int 2 A Z v_in v_0 dt) by
  the trapezoidal rule. energy_residual() = kinetic + internal work +
  friction + dashpot - input - initial: leapfrog's half-step identity
  makes it an O(dt^2) boundary term plus O(dt^2) per stick/slip event.

Convergence (measured in tests/test_reference_yielding_interface.py):
the elastic waves converge at order 2 in h and dt (mkz.py,
coulomb_column.py). Halving h and dt together (dt = 0.5 h / Vs, 10 to 80
elements) changes the slip history (max over time) by 5.0e-4, 1.8e-4,
5.8e-5 m in (a) (order 1.5, 1.6) and 2.3e-4, 4.9e-5, 1.8e-5 m in (b)
(order 2.2, 1.4): stick/slip events meet the Masing reversals and the
chain's grid-scale ringing, so expect about 1.5, not 2. The energy
residual falls by 4.0 per halving of dt at a fixed mesh (a: 5e-6 of the
input at 20 elements and dt = 0.5 h / Vs). An elastic block tends to the
point mass as its Vs grows (slip within 5e-4 at Vs = 2000 m/s). The
limits: (a) welded (mu = inf) is mkz.py's column on RigidBase bit for bit
(input work to 5e-8: the first step's power convention); (a) linear
(gamma_ref = inf) is coulomb_column.py's column to 1e-11; (b) welded with
an elastic block is mkz.py's layered column (block = a linear top layer)
to 1e-12; (b) with mu = 0 leaves mkz.py's column bit for bit. Cost: about
4 us per element and step (the Masing points, plain Python) plus about
50 us per step.

API (keyword arguments after t_end):
    column_on_coulomb_base(H, elements, rho, Vs, A, gamma_ref, beta, s, mu,
                           normal, ground_t, ground_v, t_end, dt=None,
                           courant=0.5) -> InterfaceRun
    block_on_yielding_column(H, elements, rho, Vs, A, gamma_ref, beta, s,
                             block, mu, rock_Z, incident_t, incident_v, t_end,
                             dt=None, normal=None, g=9.81, courant=0.5)
                             -> InterfaceRun
        block = Block(length, elements, rho, Vs): elements = 0 a point mass
        rho A length; normal None: the block's weight rho A length g;
        rock_Z per unit area (rho_rock Vs_rock); incident = outcrop / 2.
    run_on_coulomb_base(column, A, mu, normal, ground_t, ground_v, t_end, ...)
    run_block_on_column(column, block, A, mu, normal, rock_Z, incident_t,
                        incident_v, t_end, ...)
        the same for a layered mkz.Column (mkz.Column.layered).
    Runs start at t = 0 (histories held before their first sample).
    mu = math.inf welds the pair. InterfaceRun arrays over t: slip,
    slip_rate, shear_force (the friction force on the pair's second side,
    along +w: the column in (a), the block in (b)), w_top, v_top, a_top, v_base
    (the column's top and base nodes, absolute), v_block, v_block_top
    ((b) only, else None), kinetic, stored, internal_work, friction,
    input, dashpot; property hysteretic; energy_residual(); peak_strain
    per column element, dt, x (the column's nodes).
"""

import math
from dataclasses import dataclass

import numpy as np

from references.coulomb_column import base_kick
from references.mkz import (Column, LysmerBase, MasingPoint, _Base, _check, _history,
                            _time_integral)


@dataclass(frozen=True)
class Block:
    """The body on top in (b): length, elements (0: a point mass), rho, Vs."""
    length: float
    elements: int
    rho: float
    Vs: float = math.inf

    def column(self):
        """The block as a linear mkz.Column (None for a point mass)."""
        if self.elements == 0:
            return None
        return Column.uniform(self.length, self.elements, self.rho, self.Vs)


class _Body:
    """One lumped chain (mkz.py's, times the area A) in the leapfrog: w at
    t_n, v at t_n - dt/2, each element's MasingPoint, strain and stress."""

    def __init__(self, column, A, point_mass=None):
        self.column, self.A = column, A
        if column is None:                      # a point mass
            self.mass, self.h, self.G = np.array([point_mass]), np.zeros(0), np.ones(0)
            self.points = []
        else:
            self.mass, self.h, self.G = A * column.mass, column.h, column.G
            self.points = [MasingPoint(law) for law in column.laws()]
        self.w, self.v = np.zeros(len(self.mass)), np.zeros(len(self.mass))
        self.gamma, self.tau = np.zeros(len(self.h)), np.zeros(len(self.h))
        self.work, self.peak = 0.0, np.zeros(len(self.h))

    def forces(self):
        f = np.zeros_like(self.w)
        f[:-1] += self.A * self.tau
        f[1:] -= self.A * self.tau
        return f

    def now(self, n, v_next):
        """The velocities at t_n (the initial ones at t_0)."""
        return self.v if n == 0 else 0.5 * (self.v + v_next)

    def kinetic(self, v_now):
        return 0.5 * float(np.dot(self.mass, v_now ** 2))

    def stored(self):
        return self.A * float(np.dot(self.h, self.tau ** 2 / (2.0 * self.G)))

    def drift(self, dt, v_next):
        """w to t_{n+1}; the new strains, stresses and internal work."""
        self.w += dt * v_next
        self.v = v_next
        if not self.points:
            return
        gamma = np.diff(self.w) / self.h
        tau = np.array([p.strain_to(g) for p, g in zip(self.points, gamma)])
        self.work += self.A * float(np.dot(self.h, 0.5 * (self.tau + tau)
                                           * (gamma - self.gamma)))
        self.gamma, self.tau = gamma, tau
        self.peak = np.maximum(self.peak, np.abs(gamma))


def pair_kick(lower, upper, length, limit):
    """The Coulomb pair between two free nodes, each (v, f, m): v at the
    half step before, f the other forces, m the mass. Returns their
    velocities after a kick of `length` and the force T on the upper node
    (-T on the lower): coulomb_column.base_kick on the relative motion."""
    (v_lo, f_lo, m_lo), (v_hi, f_hi, m_hi) = lower, upper
    reduced = m_lo * m_hi / (m_lo + m_hi)
    relative, force = base_kick(v_hi - v_lo, reduced * (f_hi / m_hi - f_lo / m_lo),
                                reduced, length, 0.0, limit)
    if relative == 0.0:                         # stuck: one common velocity
        common = (m_lo * v_lo + m_hi * v_hi + length * (f_lo + f_hi)) / (m_lo + m_hi)
        return common, common, force
    return v_lo + length * (f_lo - force) / m_lo, v_hi + length * (f_hi + force) / m_hi, force


@dataclass
class InterfaceRun:
    """The history at every whole step t_n (module docstring)."""
    t: np.ndarray
    slip: np.ndarray
    slip_rate: np.ndarray
    shear_force: np.ndarray
    w_top: np.ndarray
    v_top: np.ndarray
    a_top: np.ndarray
    v_base: np.ndarray
    kinetic: np.ndarray
    stored: np.ndarray
    internal_work: np.ndarray
    friction: np.ndarray
    input: np.ndarray
    dashpot: np.ndarray
    peak_strain: np.ndarray
    dt: float
    x: np.ndarray
    v_block: np.ndarray = None
    v_block_top: np.ndarray = None

    @property
    def hysteretic(self):
        return self.internal_work - self.stored

    @property
    def energies(self):
        """The energy histories by name (hysteretic included)."""
        names = ("kinetic", "stored", "internal_work", "hysteretic", "friction",
                 "input", "dashpot")
        return {name: getattr(self, name) for name in names}

    def energy_residual(self):
        total = self.kinetic + self.internal_work + self.friction + self.dashpot - self.input
        return total - (self.kinetic[0] + self.stored[0])


def _time_grid(bodies, t_end, dt, courant):
    """t_n = t_end n / steps, dt = courant min(h / Vs) unless given."""
    _check("courant", courant, 0.0 < courant <= 0.9, "must be in (0, 0.9]")
    _check("t_end", t_end, t_end > 0.0, "must be > 0")
    limit = min(c.dt_limit() for c in bodies if c is not None)
    dt = courant * limit if dt is None else dt
    _check("dt", dt, 0.0 < dt <= 0.9 * limit, f"must be in (0, 0.9 min(h / Vs) = "
           f"{0.9 * limit:g}]")
    steps = math.ceil(t_end / dt - 1e-9)
    return t_end * np.arange(steps + 1) / steps


def _limit(mu, normal):
    _check("mu", mu, mu >= 0.0, "must be >= 0 (inf: welded)")
    _check("normal", normal, math.isfinite(normal) and normal > 0.0, "must be positive")
    return math.inf if math.isinf(mu) else mu * normal


_ROWS = ("slip", "slip_rate", "shear_force", "w_top", "v_top", "a_top", "v_base", "v_block",
         "v_block_top", "kinetic", "stored", "internal_work", "friction",
         "input_power", "dashpot_power")


def _finish(rows, t, column_body):
    """The InterfaceRun of the rows (one per step, in _ROWS' order)."""
    columns = dict(zip(_ROWS, np.array(rows).T))
    dt = t[1] - t[0]
    for name in ("v_block", "v_block_top"):
        if np.all(np.isnan(columns[name])):
            columns[name] = None
    return InterfaceRun(t=t, dt=dt, input=_time_integral(columns.pop("input_power"), dt),
                        dashpot=_time_integral(columns.pop("dashpot_power"), dt),
                        peak_strain=column_body.peak, x=column_body.column.x, **columns)


class _Slip:
    """The pair's slip and friction energy: ds = dt (relative half-step
    velocity), friction -= T ds."""

    def __init__(self):
        self.slip, self.friction = 0.0, 0.0

    def advance(self, relative, force, dt):
        ds = relative * dt
        self.slip += ds
        self.friction -= force * ds if ds != 0.0 else 0.0


def run_on_coulomb_base(column, A, mu, normal, ground_t, ground_v, t_end, dt=None,
                        courant=0.5):
    """Model (a) for an mkz.Column (module docstring). Returns an InterfaceRun."""
    _check("A", A, math.isfinite(A) and A > 0.0, "must be positive")
    limit, ground = _limit(mu, normal), _history("ground", ground_t, ground_v)
    t = _time_grid([column], t_end, dt, courant)
    dt = t[1] - t[0]
    body, pair, rows = _Body(column, A), _Slip(), []
    body.v[:] = ground(0.0)
    for n, time in enumerate(t):
        length = dt / 2.0 if n == 0 else dt
        f = body.forces()
        v_next = body.v + length * f / body.mass
        vg_half = ground(time + dt / 2.0)
        v_next[0], force = base_kick(body.v[0], f[0], body.mass[0], length, vg_half, limit)
        vg_now = ground(time) if n == 0 else 0.5 * (ground(time - dt / 2.0) + vg_half)
        v_now = body.now(n, v_next)
        rows.append((pair.slip, v_now[0] - vg_now, force, body.w[-1], v_now[-1],
                     (v_next[-1] - body.v[-1]) / length, v_now[0], math.nan, math.nan,
                     body.kinetic(v_now), body.stored(), body.work, pair.friction,
                     force * vg_now, 0.0))
        if n + 1 < len(t):
            pair.advance(v_next[0] - vg_half, force, dt)
            body.drift(dt, v_next)
    return _finish(rows, t, body)


def _block_step(soil, block, base, limit, time, length, dt):
    """One kick of model (b): the new half-step velocities of both bodies,
    the pair force and the base's input and dashpot powers."""
    f_soil, f_block = soil.forces(), block.forces()
    v_soil = soil.v + length * f_soil / soil.mass
    v_block = block.v + length * f_block / block.mass
    v_soil[0], p_in, p_dash = base.kick(soil.v[0], f_soil[0], time, length, dt)
    v_soil[-1], v_block[0], force = pair_kick(
        (soil.v[-1], f_soil[-1], soil.mass[-1]), (block.v[0], f_block[0], block.mass[0]),
        length, limit)
    return v_soil, v_block, force, p_in, p_dash


def run_block_on_column(column, block, A, mu, normal, rock_Z, incident_t, incident_v,
                        t_end, dt=None, courant=0.5):
    """Model (b) for an mkz.Column and a Block (module docstring); normal
    is the pair's normal force. Returns an InterfaceRun."""
    _check("A", A, math.isfinite(A) and A > 0.0, "must be positive")
    _check("block.elements", block.elements, int(block.elements) == block.elements
           and block.elements >= 0, "a whole number >= 0")
    limit, block_column = _limit(mu, normal), block.column()
    t = _time_grid([column, block_column], t_end, dt, courant)
    dt = t[1] - t[0]
    soil = _Body(column, A)
    top = _Body(block_column, A, point_mass=block.rho * A * block.length)
    base = _Base(LysmerBase(A * rock_Z, incident_t, incident_v), soil.mass[0])
    pair, rows = _Slip(), []
    for n, time in enumerate(t):
        length = dt / 2.0 if n == 0 else dt
        v_soil, v_block, force, p_in, p_dash = _block_step(soil, top, base, limit, time,
                                                           length, dt)
        now_soil, now_block = soil.now(n, v_soil), top.now(n, v_block)
        rows.append((pair.slip, now_block[0] - now_soil[-1], force, soil.w[-1], now_soil[-1],
                     (v_soil[-1] - soil.v[-1]) / length, now_soil[0], now_block[0],
                     now_block[-1], soil.kinetic(now_soil) + top.kinetic(now_block),
                     soil.stored() + top.stored(), soil.work + top.work, pair.friction,
                     p_in, p_dash))
        if n + 1 < len(t):
            pair.advance(v_block[0] - v_soil[-1], force, dt)
            soil.drift(dt, v_soil)
            top.drift(dt, v_block)
    return _finish(rows, t, soil)


def column_on_coulomb_base(H, elements, rho, Vs, A, gamma_ref, beta, s, mu, normal,
                           ground_t, ground_v, t_end, *, dt=None, courant=0.5):
    """Model (a) for a uniform column of `elements` elements (module
    docstring); gamma_ref = inf: linear. Returns an InterfaceRun."""
    column = Column.uniform(H, elements, rho, Vs, gamma_ref, beta, s)
    return run_on_coulomb_base(column, A, mu, normal, ground_t, ground_v, t_end, dt=dt,
                               courant=courant)


def block_on_yielding_column(H, elements, rho, Vs, A, gamma_ref, beta, s, block, mu,
                             rock_Z, incident_t, incident_v, t_end, *, dt=None,
                             normal=None, g=9.81, courant=0.5):
    """Model (b) for a uniform column (module docstring); normal None: the
    block's weight rho_b A length g. Returns an InterfaceRun."""
    column = Column.uniform(H, elements, rho, Vs, gamma_ref, beta, s)
    normal = block.rho * A * block.length * g if normal is None else normal
    return run_block_on_column(column, block, A, mu, normal, rock_Z, incident_t,
                               incident_v, t_end, dt=dt, courant=courant)
