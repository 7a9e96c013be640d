"""The peer for sliding: the rigid-block analysis of Newmark (1965), two-way,
integrated exactly for a piecewise-linear ground acceleration record.
numpy only; it imports nothing of vstpetsc, so it is an independent
reference for the friction of issue 27.

The model. A rigid block of mass m rests on a horizontal plane whose
acceleration is a_g(t) (along +x). The plane resists relative sliding by
Coulomb friction mu m g, i.e. a yield acceleration a_y = mu g; the block
slides when the plane would have to push it harder than that. With
u = x_block - x_ground, v = du/dt (the relative motion):

    stuck:   v = 0, friction = m a_g, allowed while -a_y_neg <= a_g <= a_y
    sliding: dv/dt = -a_g - s Y(s),   s = sign(v),  Y(-1) = a_y, Y(+1) = a_y_neg

a_g > a_y starts sliding with v < 0 (the block lags a plane accelerating
along +x), a_g < -a_y_neg with v > 0. a_y_neg defaults to a_y (two-way,
symmetric); a_y_neg = inf gives one-way sliding (a slope whose downslope
direction is -x: give a_y the downslope yield acceleration; the usual
Newmark slope reduction of mu to a_y is the caller's). A slide ends where
v returns to 0: the block sticks if |a_g| is within the yield there,
otherwise it slides the other way at once.

Exactness. On a sample interval a_g = a_k + b tau is linear, so while
sliding dv/dt is linear in tau, v is quadratic and u cubic:

    v(tau) = v0 + c tau - b tau^2 / 2,      c = -a_k - s Y(s)
    u(tau) = u0 + v0 tau + c tau^2 / 2 - b tau^3 / 6

The stop is the smallest positive root of v (a quadratic, solved in the
cancellation-free form), the start of a slide the root of the linear
a_g = a_y or a_g = -a_y_neg. Everything is closed form; the only error is
rounding. The friction energy is Y(s) m |u(tau_1) - u(tau_0)| summed over
the sub-intervals of one sign of v (the path length times mu m g).

Also here: ``coupled_single_mode``, the single-mode coupled model of
Rathje & Bray (2000), by RK4 with located events (not exact; see there);
and ``rigid_block``, the block under the ground motion of a vstpetsc
case's moving wall (read from the Case, nothing of vstpetsc imported).

Checked in tests/test_sliding_block_reference.py (the closed forms it is
checked against are derived there); used by tests/test_friction.py,
tests/test_examples.py, tests/test_sliding_sweep.py and
studies/sliding_study.py.
"""

import math
from dataclasses import dataclass

import numpy as np


@dataclass
class Sliding:
    """The relative motion at every sample time and every stick/slip event
    (sorted; an event at a sample time appears twice), and after the record
    the run-out to the final stop with a_g = 0 when the block still slides
    at its end, so ``u[-1]`` is the permanent displacement."""
    t: np.ndarray             # times [s]
    u: np.ndarray             # relative displacement x_block - x_ground [m]
    v: np.ndarray             # relative velocity [m/s]
    friction_energy: np.ndarray  # integral of friction force * |v| dt so far [J]
    path: np.ndarray          # sliding path length so far, integral |v| dt [m]
    events: list              # (time, "slip+" | "slip-" | "stick") in order

    @property
    def permanent(self):
        """The displacement left when the block has stopped for good [m]."""
        return float(self.u[-1])


class _Block:
    """The state of the block as the record is walked: time, u, v, the sign
    s of a slide (0 while stuck) and the running totals."""

    def __init__(self, a_y, a_y_neg, mass, t0):
        self.yields = {-1: float(a_y), 1: float(a_y_neg)}
        self.mass = float(mass)
        self.t, self.u, self.v, self.s = float(t0), 0.0, 0.0, 0
        self.energy, self.path = 0.0, 0.0
        self.rows, self.events = [], []
        self.record()

    def record(self):
        self.rows.append((self.t, self.u, self.v, self.energy, self.path))

    def slide_sign_for(self, a):
        """The sign of the slide an acceleration a of the plane starts from
        rest, 0 if friction can hold the block."""
        if a > self.yields[-1]:
            return -1
        if a < -self.yields[1]:
            return 1
        return 0

    def settle(self, a):
        """At rest relative to the plane with plane acceleration a: stick or
        start a slide (named by the sign of v)."""
        self.v = 0.0
        s = self.slide_sign_for(a)
        if s != self.s:
            self.events.append((self.t, {0: "stick", -1: "slip-", 1: "slip+"}[s]))
        self.s = s


def _first_positive_root(alpha, beta, gamma):
    """Smallest tau > 0 with alpha tau^2 + beta tau + gamma = 0, where
    gamma >= 0 (the current value); a root at tau = 0 (gamma = 0) does not
    count. None if there is none."""
    if gamma == 0.0:
        # tau (alpha tau + beta): the other root only
        return -beta / alpha if alpha != 0.0 and -beta / alpha > 0.0 else None
    if alpha == 0.0:
        return -gamma / beta if beta < 0.0 else None
    disc = beta * beta - 4.0 * alpha * gamma
    if disc < 0.0:
        return None
    q = -0.5 * (beta + math.copysign(math.sqrt(disc), beta))
    roots = [r for r in (q / alpha, gamma / q if q != 0.0 else -1.0) if r > 0.0]
    return min(roots) if roots else None


def _slip_start(block, a0, b, h):
    """While stuck on a segment a_g = a0 + b tau, tau in [0, h]: the first tau
    where |a_g| leaves the yield band, None if it stays inside."""
    up, down = block.yields[-1], -block.yields[1]
    candidates = []
    if b > 0.0 and a0 <= up < a0 + b * h:
        candidates.append((up - a0) / b)
    if b < 0.0 and a0 >= down > a0 + b * h:
        candidates.append((down - a0) / b)
    return min(candidates) if candidates else None


def _slide(block, a0, b, h):
    """Slide along a_g = a0 + b tau from tau = 0 to the stop or to h;
    returns the tau reached and whether v reached 0 there."""
    s, v0 = block.s, block.v
    c = -a0 - s * block.yields[s]
    if v0 == 0.0 and s * c < 0.0:
        # a slide from rest starts where a_g crosses the yield: c = 0 but
        # for rounding, which must not stop it at once
        c = 0.0
    stop = _first_positive_root(-s * b / 2.0, s * c, max(s * v0, 0.0))
    stopped = stop is not None and stop <= h
    tau = stop if stopped else h
    du = v0 * tau + c * tau ** 2 / 2.0 - b * tau ** 3 / 6.0
    v1 = 0.0 if stopped else v0 + c * tau - b * tau ** 2 / 2.0
    block.u += du
    block.v = v1 if s * v1 > 0.0 else 0.0   # a stop at h itself, up to rounding
    block.path += abs(du)
    block.energy += block.mass * block.yields[s] * abs(du)
    return tau, block.v == 0.0


def _start_slide(block, s):
    """Stuck until now, the plane's acceleration leaves the yield band
    (upward: s = -1, downward: s = +1)."""
    block.s = s
    block.events.append((block.t, "slip-" if s < 0 else "slip+"))


def _walk_segment(block, t1, a0, a1):
    """Advance the block over one sample interval [block.t, t1] with a_g
    linear from a0 to a1, recording every event."""
    h = t1 - block.t
    if h <= 0.0:                          # a repeated time: a jump of a_g
        if block.s == 0:
            block.settle(a1)
        return
    b, start, done = (a1 - a0) / h, block.t, 0.0
    for _ in range(100):                  # a stop and a start per interval, a few at most
        if block.s == 0:
            tau = _slip_start(block, a0 + b * done, b, h - done)
            if tau is None:
                break
            done += tau
            block.t = start + done
            block.record()
            _start_slide(block, -1 if b > 0.0 else 1)
            continue
        tau, stopped = _slide(block, a0 + b * done, b, h - done)
        done += tau
        block.t = start + done
        if stopped:
            block.settle(a1 if done >= h else a0 + b * done)
        if not stopped or done >= h:
            break
        block.record()
    else:
        raise RuntimeError(f"more than 100 stick/slip events in [{start}, {t1}]")
    block.t = t1
    block.record()


def _run_out(block):
    """After the record a_g = 0: a sliding block decelerates at its yield
    to rest (v t / 2 further); appended as a last row."""
    if block.s == 0:
        return
    y = block.yields[block.s]
    t_stop = abs(block.v) / y
    du = block.v * t_stop / 2.0
    block.t += t_stop
    block.u += du
    block.path += abs(du)
    block.energy += block.mass * y * abs(du)
    block.settle(0.0)
    block.record()


def newmark(t, a_g, a_y, a_y_neg=None, mass=1.0):
    """Rigid-block sliding of a block on a plane with acceleration history
    a_g at times t (piecewise linear between samples; a repeated time is a
    jump), yield acceleration a_y = mu g for slides toward -x and a_y_neg
    (default a_y; inf: one-way) toward +x, starting at rest relative to the
    plane. Returns a Sliding."""
    t, a_g = np.asarray(t, float), np.asarray(a_g, float)
    if t.ndim != 1 or t.shape != a_g.shape or len(t) < 2 or np.any(np.diff(t) < 0):
        raise ValueError("t, a_g: equal-length 1-D samples with t non-decreasing")
    a_y_neg = a_y if a_y_neg is None else a_y_neg
    if not (a_y > 0.0 and a_y_neg > 0.0):
        raise ValueError("a_y, a_y_neg: must be positive")
    block = _Block(a_y, a_y_neg, mass, t[0])
    block.settle(a_g[0])
    for k in range(len(t) - 1):
        _walk_segment(block, t[k + 1], a_g[k], a_g[k + 1])
    _run_out(block)
    rows = np.array(block.rows)
    return Sliding(rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3], rows[:, 4],
                   block.events)


# The single-mode coupled model (Rathje & Bray 2000, after Chopra & Zhang
# 1991): a flexible column in its first mode, modal coordinate q (the
# column's displacement relative to its base is phi(y) q), on a base that
# slides by s on the plane. With m the total mass, L = int phi dm,
# M = int phi^2 dm, gamma = L / M (participation), kappa = L / m:
#
#   stuck:   q'' + 2 xi w q' + w^2 q = -gamma a_g,   s' = 0,
#            the base force asks for d = a_g + kappa q'' (per unit mass),
#            allowed while -a_y_neg <= d <= a_y
#   sliding: q'' + 2 xi w q' + w^2 q = -gamma (a_g + s''),
#            a_g + s'' = -kappa q'' - sgn(s') Y   (the base's equilibrium), so
#            q'' (1 - gamma kappa) = gamma sgn(s') Y - 2 xi w q' - w^2 q.
#
# gamma kappa = L^2 / (m M) < 1 (Cauchy-Schwarz). A uniform shear column
# (phi = sin(pi y / 2H)): gamma = 4 / pi, kappa = 2 / pi. Integrated by
# RK4 on sub-steps of each sample interval, the stick/slip events found by
# bisection inside a sub-step; a reference for comparisons, not exact.

UNIFORM_SHEAR_COLUMN = (4.0 / math.pi, 2.0 / math.pi)


class _Column:
    """The coupled model's right-hand sides and event functions."""

    def __init__(self, omega, xi, a_y, a_y_neg, gamma, kappa):
        self.w, self.xi, self.gamma, self.kappa = omega, xi, gamma, kappa
        self.yields = {-1: a_y, 1: a_y_neg}

    def q_acc(self, mode, ag, q, qd):
        spring = 2.0 * self.xi * self.w * qd + self.w ** 2 * q
        if mode == 0:
            return -self.gamma * ag - spring
        return (self.gamma * mode * self.yields[mode] - spring) / (1.0 - self.gamma * self.kappa)

    def rhs(self, mode, ag, y):
        q, qd, _, sd = y
        qdd = self.q_acc(mode, ag, q, qd)
        sdd = 0.0 if mode == 0 else -ag - self.kappa * qdd - mode * self.yields[mode]
        return (qd, qdd, sd, sdd)

    def new_mode(self, ag, y):
        """Stick, or the slide the base force starts, at rest on the plane."""
        d = ag + self.kappa * self.q_acc(0, ag, y[0], y[1])
        return -1 if d > self.yields[-1] else 1 if d < -self.yields[1] else 0

    def leaves(self, mode, ag, y):
        """Whether the state y (at acceleration ag) has left the mode."""
        return self.new_mode(ag, y) != 0 if mode == 0 else mode * y[3] <= 0.0


def _rk4(column, mode, y, t0, h, a_of):
    k1 = column.rhs(mode, a_of(t0), y)
    k2 = column.rhs(mode, a_of(t0 + h / 2), [a + h / 2 * b for a, b in zip(y, k1)])
    k3 = column.rhs(mode, a_of(t0 + h / 2), [a + h / 2 * b for a, b in zip(y, k2)])
    k4 = column.rhs(mode, a_of(t0 + h), [a + h * b for a, b in zip(y, k3)])
    return [a + h / 6 * (b + 2 * c + 2 * d + e) for a, b, c, d, e in zip(y, k1, k2, k3, k4)]


def _step_to_event(column, mode, y, t0, h, a_of):
    """One sub-step, cut at the first event (bisection): (h done, y, event?)."""
    y1 = _rk4(column, mode, y, t0, h, a_of)
    if not column.leaves(mode, a_of(t0 + h), y1):
        return h, y1, False
    lo, hi = 0.0, h
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        if column.leaves(mode, a_of(t0 + mid), _rk4(column, mode, y, t0, mid, a_of)):
            hi = mid
        else:
            lo = mid
    return hi, _rk4(column, mode, y, t0, hi, a_of), True


def coupled_single_mode(t, a_g, a_y, omega, xi=0.0, a_y_neg=None,
                        modal=UNIFORM_SHEAR_COLUMN, substeps=4, steps_per_radian=10):
    """The coupled sliding of a column's first mode (circular frequency
    omega, damping ratio xi, modal = (gamma, kappa)) on a Coulomb base
    under the piecewise-linear record (t, a_g), from rest. Returns times,
    sliding displacement s, its velocity, the modal coordinate q and the
    events; s is the permanent displacement once the record ends in a rest
    long enough for the base to stop. Sub-steps: at least ``substeps`` per
    sample interval and ``steps_per_radian`` per radian of the sliding
    mode's frequency omega / sqrt(1 - gamma kappa)."""
    t, a_g = np.asarray(t, float), np.asarray(a_g, float)
    column = _Column(omega, xi, a_y, a_y if a_y_neg is None else a_y_neg, *modal)
    max_step = math.sqrt(1.0 - modal[0] * modal[1]) / (omega * steps_per_radian)
    y, mode, rows, events = [0.0, 0.0, 0.0, 0.0], 0, [], []
    for k in range(len(t) - 1):
        h_all = t[k + 1] - t[k]
        if h_all <= 0.0:
            continue
        b = (a_g[k + 1] - a_g[k]) / h_all

        def a_of(time, k=k, b=b):
            return a_g[k] + b * (time - t[k])
        now, h = t[k], min(h_all / substeps, max_step)
        if k == 0:
            mode = column.new_mode(a_of(now), y)
        while now < t[k + 1] - 1e-12 * h_all:
            done, y, event = _step_to_event(column, mode, y, now, min(h, t[k + 1] - now), a_of)
            now += done
            if event:
                y[3] = 0.0 if mode != 0 else y[3]
                mode = column.new_mode(a_of(now), y)
                events.append((now, {0: "stick", -1: "slip-", 1: "slip+"}[mode]))
            rows.append((now, y[2], y[3], y[0]))
    rows = np.array([(t[0], 0.0, 0.0, 0.0)] + rows)
    return rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3], events


# ---------------------------------------------------------------- a case's record

def ground_acceleration(case, end=None):
    """(t, a_g) of a case's wall: an integrated record's own acceleration
    (linear between samples), else the slope of its piecewise-linear shear
    velocity on each sample interval (a repeated time is a jump); then at
    rest to ``end`` (the history is held after its last sample)."""
    wall = case.contacts[0].wall_shear_velocity
    if wall.slopes is not None:
        t, a = wall.t, wall.slopes
    else:
        acc = np.diff(wall.f) / np.diff(wall.t)
        t, a = np.repeat(wall.t, 2)[1:-1], np.repeat(acc, 2)
    if end is not None and end > wall.t[-1]:
        t, a = np.append(t, [wall.t[-1], end]), np.append(a, [0.0, 0.0])
    return t, a


def rigid_block(case, end=None):
    """Newmark's rigid block under the case's ground motion, a_y = mu g."""
    yield_acceleration = case.contacts[0].friction * -case.gravity.g(0.0)
    return newmark(*ground_acceleration(case, end), yield_acceleration)
