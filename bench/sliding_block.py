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

Used by tests/test_sliding_block_reference.py (the closed forms it is
checked against are derived there).
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
