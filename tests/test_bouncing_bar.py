"""The bundled bouncing bar (Doyen, Ern & Piperno 2011) against its exact
solution over five bounces: contact force, closing and lift-off times,
the bounce period, the heights reached and the energy (docs/examples.md,
bouncing-bar, has the derivation)."""

import numpy as np
import pytest

import vstpetsc
from vstpetsc import bundled
from conftest import compliance_delay, solve

BOUNCES = 5


class Exact:
    """The exact solution (d'Alembert) of a uniform bar of length L, wave
    speed c, impedance Z = rho c A and mass m, let go at rest with its foot
    h0 above a rigid floor under gravity g (a magnitude, pulling towards the
    floor). It lands at v0 = sqrt(2 g h0) after v0 / g. Contact A (from an
    undeformed bar): F = Z (v0 + g s) for s < tau = 2L/c; the bar leaves at
    v0, uniform, with the strain -2 g (L - y) / c^2 (y from the foot), whose
    free vibration (period tau) moves the foot by -g sigma (tau - sigma),
    sigma = s mod tau, relative to the rigid flight. With a flight 2 v0 / g
    of N >= 2 vibration periods the foot lands at v0 after exactly 2 v0 / g,
    still compressed; contact B (that state plus a fixed-free vibration
    that undoes the strain) has F = Z v0 + 2 m g - Z g s and the bar leaves
    undeformed at v0. A, flight, B, flight: a bounce every tau + 2 v0 / g."""

    def __init__(self, case):
        body = case.bodies[0]
        x = body.x[0]
        E, rho, area = float(body.E(x)), float(body.rho(x)), float(body.area(x))
        self.L = body.x[1] - body.x[0]
        self.c = np.sqrt(E / rho)
        self.Z, self.m = rho * self.c * area, rho * area * self.L
        self.g = -float(case.gravity.g(0.0))
        self.h0 = x - case.contacts[0].wall
        self.v0 = np.sqrt(2 * self.g * self.h0)
        self.tau = 2 * self.L / self.c
        self.flight = 2 * self.v0 / self.g
        self.period = self.tau + self.flight          # from one landing to the next
        self.energy = self.m * self.g * self.h0

    def closes(self, count):
        return self.v0 / self.g + self.period * np.arange(count)

    def _phase(self, t):
        """(bounce number k, time s since the k-th landing)."""
        t = np.asarray(t, dtype=float)
        k = np.floor((t - self.v0 / self.g) / self.period)
        return k, t - self.v0 / self.g - k * self.period

    def force(self, t):
        """Contact force, compressive positive (0 in flight)."""
        k, s = self._phase(t)
        a = self.Z * (self.v0 + self.g * s)
        b = self.Z * self.v0 + 2 * self.m * self.g - self.Z * self.g * s
        return np.where((k >= 0) & (s < self.tau), np.where(k % 2 == 0, a, b), 0.0)

    def gap(self, t):
        """Height of the foot above the floor."""
        k, s = self._phase(t)
        f = s - self.tau                               # time since lift-off
        sigma = np.mod(f, self.tau)
        vibration = np.where(k % 2 == 0, -self.g * sigma * (self.tau - sigma), 0.0)
        flying = self.v0 * f - self.g * f ** 2 / 2 + vibration
        falling = self.h0 - self.g * np.asarray(t, dtype=float) ** 2 / 2
        return np.where(k < 0, falling, np.where(s < self.tau, 0.0, flying))


def example(elements=None, courant=None):
    """The bundled case, kept every slab; optionally another mesh and
    c dt / h (the penalty kept at 0.5 E A / h)."""
    case = vstpetsc.Case.from_toml(bundled.path("bouncing-bar")).with_value("output.every", 1)
    if elements is not None:
        body = case.bodies[0]
        h = (body.x[1] - body.x[0]) / elements
        E, rho = float(body.E(body.x[0])), float(body.rho(body.x[0]))
        case = (case.with_value("body.0.elements", elements)
                .with_value("time.dt", courant * h / np.sqrt(E / rho))
                .with_value("contact.0.penalty", 0.5 * E * float(body.area(body.x[0])) / h))
    return case


def contacts(result):
    """(closes, opens) from the pair's events; the events alternate."""
    events = result.contact(0).events[:]
    assert events.shape[0] % 2 == 0 and events.shape[0] > 0
    assert np.all(events[0::2, 1] == 1) and np.all(events[1::2, 1] == -1)
    return events[0::2, 0], events[1::2, 0]


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    case = example()
    return case, solve(tmp_path_factory.mktemp("bouncing"), case, name="bouncing-bar")


def test_the_exact_solution_is_consistent():
    """The example's data give a periodic solution (the flight is a whole
    number N >= 2 of vibration periods), each contact's impulse reverses
    the momentum against gravity (J - m g tau = 2 m v0), and the foot
    stays above the floor in flight."""
    ex = Exact(example())
    assert ex.v0 > 2 * ex.g * ex.L / ex.c           # the force jumps negative at 2L/c: lift-off
    n = ex.flight / ex.tau
    assert abs(n - round(n)) <= 1e-9 and round(n) >= 2
    s = np.linspace(0.0, ex.tau, 200_001)[:-1] + ex.tau / 400_000
    for k in range(2):
        impulse = ex.force(ex.closes(2)[k] + s).mean() * ex.tau
        assert abs(impulse - ex.m * ex.g * ex.tau - 2 * ex.m * ex.v0) <= 1e-9 * ex.m * ex.v0
    flight = ex.closes(1)[0] + ex.tau + np.linspace(0.0, 2 * ex.period, 100_001)
    airborne = ex.force(flight) == 0
    assert np.all(ex.gap(flight)[airborne][1:-1] >= 0)
    landing = ex.closes(3)[1:] - 1e-9 * ex.period      # the foot is back on the floor
    assert np.all(np.abs(ex.gap(landing)) <= 1e-6 * ex.h0)


def test_each_close_is_followed_by_an_open(run):
    case, r = run
    closes, opens = contacts(r)
    ex = Exact(case)
    assert closes.size == np.count_nonzero(ex.closes(20) < r.time[-1]) >= BOUNCES
    assert np.all(opens > closes) and np.all(closes[1:] > opens[:-1])


def test_closing_lift_off_and_period(run):
    """Each contact lasts 2L/c plus the penalty's release delay 2 Z / k
    (docs/accuracy.md) plus at most 4 h / c (the release front spread over
    a few elements: 1.3 to 2.9 h / c measured, the longer after the A
    contacts); every close and lift-off is late by at most that much per
    bounce so far; the bounce period is 2L/c + 2 v0 / g + 2 Z / k within
    0.2 %."""
    case, r = run
    ex = Exact(case)
    delay = compliance_delay(r, ex.Z)
    closes, opens = contacts(r)
    spread = 4 * ex.L / case.bodies[0].elements / ex.c
    per_bounce = delay + spread
    late = closes - ex.closes(closes.size)
    print(f"bouncing bar: closes late by {late / case.dt} dt, contacts "
          f"{(opens - closes - ex.tau - delay) / (spread / 4)} h/c longer than 2L/c + 2Z/k")
    assert abs(late[0]) <= 0.05 * case.dt
    assert np.all(late >= -0.05 * case.dt) and np.all(late <= per_bounce * np.arange(closes.size) + 0.05 * case.dt)
    longer = opens - closes - ex.tau - delay
    assert np.all(longer >= 0) and np.all(longer <= spread)
    lift_off = opens - (ex.closes(opens.size) + ex.tau)
    assert np.all(lift_off >= 0) and np.all(lift_off <= per_bounce * np.arange(1, opens.size + 1))
    period = np.diff(closes).mean()
    assert abs(period - (ex.period + delay)) <= 2e-3 * ex.period


def own_frame(r, ex, closes):
    """Per contact j: (rows inside it, the exact force there), the exact
    force taken from the j-th exact contact at the same time since the
    computed close (the slab-mean force at the slab's midpoint)."""
    t, dt = r.time[:], r.attrs["dt"]
    for j, close in enumerate(closes):
        rows = np.nonzero((t - dt >= close) & (t <= close + ex.tau))[0]
        yield rows, ex.force(ex.closes(j + 1)[j] + t[rows] - dt / 2 - close)


def peaks(r, ex, closes, opens):
    """Largest slab-mean force of each contact over the exact largest force
    Z v0 + 2 m g."""
    t, force = r.time[:], r.contact(0).force[:]
    dt = r.attrs["dt"]
    return np.array([force[(t > a) & (t <= b + dt)].max() for a, b in zip(closes, opens)]) \
        / (ex.Z * ex.v0 + 2 * ex.m * ex.g)


def test_contact_force_follows_the_exact_ramps(run):
    """Inside each contact (its middle 80 %) the force is the exact ramp
    within 2 % of Z v0 (1 % measured: the release's precursors at 90 %); the peaks: within 1.05 of the exact largest force at
    the first two contacts; the release overshoot grows as the fronts
    widen over the bounces (1.05 and 1.07 at the third and fifth contact
    here, as in periodic-impacts, docs/accuracy.md), within 1.10."""
    case, r = run
    ex = Exact(case)
    closes, opens = contacts(r)
    force = r.contact(0).force[:]
    t = r.time[:]
    for rows, exact in own_frame(r, ex, closes):
        s = t[rows] - t[rows[0] - 1]
        middle = (s > 0.1 * ex.tau) & (s < 0.9 * ex.tau)
        error = np.abs(force[rows][middle] - exact[middle]).max() / (ex.Z * ex.v0)
        print(f"bouncing bar: force within {error:.4f} Z v0 of the exact ramp")
        assert error <= 0.02
    peak = peaks(r, ex, closes, opens)
    print(f"bouncing bar: peak force / (Z v0 + 2 m g) per contact {np.round(peak, 4)}")
    assert np.all(peak[:2] <= 1.05) and np.all(peak <= 1.10)
    assert np.all(peak >= 0.95)


def test_contact_b_overshoots_before_its_release(run):
    """B ends at Z v0, released exactly as the free vibration's front
    reaches the foot; the computed force overshoots there (1.19 and 1.32 Z v0
    at the second and fourth contact with the defaults; 1.35 and 1.45 with
    the contact node's mass moved inward): within 1.5 Z v0; at least 1.05, so that a change which removes
    the overshoot shows here and the docs can be corrected."""
    case, r = run
    ex = Exact(case)
    closes, opens = contacts(r)
    t, force, dt = r.time[:], r.contact(0).force[:], case.dt
    for a, b in list(zip(closes, opens))[1::2]:
        last = force[(t > b - 0.2 * ex.tau) & (t <= b + dt)].max() / (ex.Z * ex.v0)
        print(f"bouncing bar: contact B's force before release {last:.3f} Z v0")
        assert 1.05 <= last <= 1.5


def test_a_finer_mesh_keeps_every_peak_within_five_percent(tmp_path):
    """200 elements at c dt/h = 1: every peak within 1.05."""
    case = example(200, 1.0)
    r = solve(tmp_path, case)
    ex = Exact(case)
    closes, opens = contacts(r)
    assert closes.size >= BOUNCES
    peak = peaks(r, ex, closes, opens)
    print(f"bouncing bar, 200 elements, c dt/h = 1: peaks {np.round(peak, 4)}")
    assert np.all(peak <= 1.05) and np.all(peak >= 0.95)


def test_heights_reached_in_flight(run):
    """The foot's highest point in each flight: h0 after a B contact (the
    bar undeformed), the exact maximum with the free vibration after an A
    contact; within 2 % of h0."""
    case, r = run
    ex = Exact(case)
    closes, opens = contacts(r)
    t, gap = r.time[:], r.contact(0).gap[:]
    for j in range(closes.size - 1):
        s = np.linspace(0.0, ex.flight, 20_001)
        exact = ex.gap(ex.closes(j + 1)[j] + ex.tau + s).max()
        got = gap[(t > opens[j]) & (t < closes[j + 1])].max()
        assert abs(got - exact) <= 0.02 * ex.h0, (j, got, exact)


def test_energy_is_kept_within_one_percent(run):
    """Kinetic + strain + the pair's stored energy + gravity's potential
    (minus its work) stays within 1 % of m g h0 over the bounces: the
    numerical energy the scheme dissipated, never decreasing."""
    case, r = run
    ex = Exact(case)
    e = r.energy
    total = e["kinetic"][:] + e["strain"][:] + e["contact"][:] - e["external"][:]
    numerical = e["numerical"][:]
    print(f"bouncing bar: energy lost {-total[-1] / ex.energy:.4%} of m g h0 "
          f"over {contacts(r)[0].size} bounces")
    assert np.abs(total).max() <= 0.01 * ex.energy
    assert np.allclose(total, -numerical, rtol=0, atol=1e-9 * ex.energy)
    assert np.all(np.diff(numerical) >= -1e-9 * ex.energy)
