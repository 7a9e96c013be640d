"""tests/references/sliding_block.py, the rigid-block (Newmark 1965) reference for the
friction of issue 27, against closed forms derived from the physics here.

Notation: a_g the plane's acceleration, a_y = mu g the yield acceleration,
u, v the block's displacement and velocity relative to the plane; while
sliding dv/dt = -a_g - s a_y with s = sign(v) (friction opposes v).

(a) Rectangular pulse a_g = A > a_y on [0, t1], then 0. Sliding from t = 0
    with dv/dt = -(A - a_y): v(t1) = -(A - a_y) t1, u(t1) = -(A - a_y) t1^2 / 2.
    Then dv/dt = +a_y until v = 0 after t_s = (A - a_y) t1 / a_y, a further
    v(t1) t_s / 2 = -(A - a_y)^2 t1^2 / (2 a_y). Sum:
        D = -(A - a_y) A t1^2 / (2 a_y)
    (issue 27's form: V = A t1, D = V^2/(2 a_y) (1 - a_y/A), the same).
    Energy: the work of the inertial force -m a_g on the relative motion is
    -m A u(t1) = m A (A - a_y) t1^2 / 2 = m a_y |D|, all dissipated.
(b1) Square wave +-A, period T, A > a_y, steady two-way sliding. The plane's
    velocity is a triangle wave of amplitude A T/4 and never lets the block
    stick (|a_g| = A > a_y). The block's velocity changes at +-a_y, so in the
    steady state it is a triangle wave of amplitude P = a_y T/4 (it falls by
    2P in half a period). It meets the plane's velocity at s = T/4 (1 - rho)
    after the plane's velocity peak (rho = a_y / A): A T/4 - A s = a_y T/4.
    Between two meetings (half a period) the block's velocity is linear
    from P to -P (no displacement), the plane's triangle wave gives
    A s (s - T/2), so the relative displacement swings by
        A s (T/2 - s) = A T^2 (1 - rho^2) / 16   (peak to peak), no drift.
    The steady state starts at a meeting: the record starts at phase
    T/2 + s of a wave that is +A on [0, T/2), i.e. -A for T/2 - s first.
(b2) Sine a_g = A sin(w t + th0), steady two-way sliding without stick.
    With the block velocity a triangle wave of slope a_y between meetings
    at th0 and th0 + pi: 2 (A/w) cos th0 = a_y pi / w, cos th0 = pi r / 2
    (r = a_y / A). The plane moves -(A/w^2)(sin(th0 + pi) - sin th0) between
    the meetings, the block's linear velocity nothing, so the swing is
        (2 A / w^2) sin th0 = (2 A / w^2) sqrt(1 - (pi r / 2)^2),
    no drift. No stick at a meeting needs A sin th0 > a_y, i.e.
    r < 1 / sqrt(1 + pi^2 / 4) = 0.537. Starting at phase th0 with v = 0 is
    on the steady orbit (v stays < 0 on (th0, th0 + pi): v w / A =
    r (th - th0) + cos th - cos th0, zero at both ends, one minimum between).
(b3) One sine cycle a_g = A sin(w t), t in [0, 2 pi / w], then 0, one-way
    (Newmark's slope case): sliding from th1 = asin r with
    v w / A = f(th) = r (th - th1) + cos th - cos th1 until f(th2) = 0,
    th2 in (pi - th1, 2 pi) (f falls until pi - th1 and f(2 pi) > 0):
        D = (A / w^2) [r (th2 - th1)^2 / 2 + sin th2 - sin th1 - cos th1 (th2 - th1)]
    th2 from bisection; the record, a sampled sine, converges to it.
"""

import math

import numpy as np
import pytest

from references import sliding_block as sb


def pulse(A, t1, t_end):
    """A rectangular acceleration pulse: A on [0, t1], 0 after (a jump)."""
    return np.array([0.0, t1, t1, t_end]), np.array([A, A, 0.0, 0.0])


def square_wave_on_orbit(A, a_y, T, cycles):
    """(b1)'s record over whole periods: a +-A square wave of period T
    starting at the steady state's meeting (-A for T/2 - s first), the jumps
    as repeated times."""
    s = T / 4.0 * (1.0 - a_y / A)
    end = cycles * T
    times, values, level = [0.0], [-A], -A
    for jump in T / 2.0 - s + T / 2.0 * np.arange(2 * cycles):
        times += [jump, jump]
        values += [level, -level]
        level = -level
    return np.array(times + [end]), np.array(values + [level])


def stops_in_record(result, t):
    """The events strictly inside the record (not the run-out after it)."""
    return [(te, e) for te, e in result.events if te < t[-1]]


def random_record(seed, n=400, dt=0.01, peak=4.0):
    """A rough record that starts and ends at a_g = 0."""
    rng = np.random.default_rng(seed)
    a = peak * rng.uniform(-1.0, 1.0, n)
    a[0] = a[-1] = 0.0
    return np.arange(n) * dt, a


@pytest.mark.parametrize("A, a_y, t1", [(3.0, 1.0, 0.5), (2.5, 2.0, 0.13), (10.0, 0.3, 1.0)])
def test_rectangular_pulse_gives_the_closed_form_displacement_and_energy(A, a_y, t1):
    mass = 7.0
    r = sb.newmark(*pulse(A, t1, 10.0 * t1), a_y, mass=mass)
    D = -(A - a_y) * A * t1 ** 2 / (2.0 * a_y)
    assert r.permanent == pytest.approx(D, rel=1e-13)
    g, ky, V = 9.81, a_y / 9.81, A * t1        # issue 27's form, ky in g
    assert abs(r.permanent) == pytest.approx(V ** 2 / (2 * g * ky) * (1 - ky * g / A), rel=1e-13)
    assert r.events == [(0.0, "slip-"), (pytest.approx(t1 * A / a_y, rel=1e-13), "stick")]
    assert r.friction_energy[-1] == pytest.approx(mass * A * (A - a_y) * t1 ** 2 / 2.0, rel=1e-13)
    assert r.path[-1] == pytest.approx(abs(D), rel=1e-13)


def test_a_pulse_below_the_yield_moves_nothing():
    r = sb.newmark(*pulse(1.0, 0.5, 2.0), 1.0)
    assert r.events == [] and np.all(r.u == 0.0) and r.friction_energy[-1] == 0.0


def test_a_train_of_separated_pulses_adds_their_displacements():
    A, a_y, t1, gap = 3.0, 1.0, 0.2, 1.0          # each slide ends after 0.6 s < gap
    t, a = [], []
    for k in range(4):                              # rest, jump up, hold, jump down
        t += [k * gap, k * gap, k * gap + t1, k * gap + t1]
        a += [0.0, A, A, 0.0]
    r = sb.newmark(t + [4 * gap], a + [0.0], a_y)
    assert r.permanent == pytest.approx(-4 * (A - a_y) * A * t1 ** 2 / (2 * a_y), rel=1e-13)
    assert [e for _, e in r.events] == ["slip-", "stick"] * 4


@pytest.mark.parametrize("A, a_y, T", [(3.0, 1.0, 0.4), (2.0, 1.9, 1.0)])
def test_steady_square_wave_swings_by_the_closed_form_without_drift(A, a_y, T):
    cycles = 5
    t, a = square_wave_on_orbit(A, a_y, T, cycles)
    r = sb.newmark(t, a, a_y)
    swing = A * T ** 2 * (1.0 - (a_y / A) ** 2) / 16.0
    events = stops_in_record(r, t)
    assert [e for _, e in events] == ["slip+", "slip-"] * cycles
    np.testing.assert_allclose([te for te, _ in events], T / 2.0 * np.arange(2 * cycles),
                               rtol=1e-13, atol=1e-13 * T)
    assert r.u.max() == pytest.approx(swing, rel=1e-12)
    assert r.u.min() == pytest.approx(0.0, abs=1e-13 * swing)
    assert abs(r.u[-1]) < 1e-13 * swing            # no drift


def sine_on_orbit(A, a_y, w, cycles, per_cycle):
    """(b2)'s record sampled per_cycle times a period, and its th0."""
    th0 = math.acos(math.pi * a_y / (2.0 * A))
    t = np.linspace(0.0, cycles * 2 * math.pi / w, cycles * per_cycle + 1)
    return t, A * np.sin(w * t + th0), th0


def test_steady_harmonic_sliding_swings_by_the_closed_form_and_converges_at_order_2():
    A, a_y, w, cycles = 2.0, 0.8, 2 * math.pi, 3   # r = 0.4 < 0.537
    errors, sizes = [], [16, 32, 64, 128, 256, 512]
    for n in sizes:
        t, a, th0 = sine_on_orbit(A, a_y, w, cycles, n)
        r = sb.newmark(t, a, a_y)
        swing = 2 * A / w ** 2 * math.sqrt(1 - (math.pi * a_y / (2 * A)) ** 2)
        assert "stick" not in [e for _, e in stops_in_record(r, t)]
        errors.append(max(abs(r.u.min() + swing), abs(r.u.max()), abs(r.u[-1])) / swing)
    order = -np.polyfit(np.log(sizes), np.log(errors), 1)[0]
    assert 1.9 < order < 2.1, (order, errors)
    assert errors[-1] < 1e-4                        # loose: 512 samples a period


def one_way_sine_cycle_displacement(A, a_y, w):
    """(b3): Newmark's one-way displacement for one sine cycle, th2 by bisection."""
    r = a_y / A
    th1 = math.asin(r)

    def f(th):
        return r * (th - th1) + math.cos(th) - math.cos(th1)
    lo, hi = math.pi - th1, 2 * math.pi
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < 0.0 else (lo, mid)
    th2 = 0.5 * (lo + hi)
    span = th2 - th1
    return A / w ** 2 * (r * span ** 2 / 2 + math.sin(th2) - math.sin(th1) - math.cos(th1) * span)


@pytest.mark.parametrize("r", [0.1, 0.5, 0.9])
def test_one_way_sine_cycle_converges_to_newmarks_displacement_at_order_2(r):
    A, w = 3.0, 4.0
    exact = one_way_sine_cycle_displacement(A, r * A, w)
    errors, sizes = [], [32, 64, 128, 256, 512]
    for n in sizes:
        t = np.linspace(0.0, 2 * math.pi / w, n + 1)
        res = sb.newmark(np.append(t, 10.0), np.append(A * np.sin(w * t), 0.0), r * A,
                         a_y_neg=np.inf)
        assert np.all(np.diff(res.u) <= 0.0)        # one-way: only toward -x
        errors.append(abs(res.permanent - exact) / abs(exact))
    order = -np.polyfit(np.log(sizes), np.log(errors), 1)[0]
    assert 1.9 < order < 2.1, (order, errors)
    assert errors[-1] < 1e-3                        # loose: short slides at r = 0.9


def test_friction_energy_is_the_yield_force_times_the_path_and_the_inertial_work():
    """(c): between two rows v keeps its sign, so the path is the sum of |du|
    and the energy mu m g times it per direction; and the work-energy
    theorem in the plane's frame: E_f = -m int a_g v dt - m v^2/2 (v0 = 0),
    here with the trapezoid rule on the rows of a finely sampled smooth
    record (they include every sample and every event)."""
    mass, a_y, a_y_neg = 3.0, 1.2, 2.0
    t = np.linspace(0.0, 4.0, 8001)
    a = 3.0 * np.sin(5.0 * t) + 2.5 * np.sin(13.0 * t + 1.0)
    r = sb.newmark(t, a, a_y, a_y_neg=a_y_neg, mass=mass)
    du = np.diff(r.u)
    assert r.path[-1] == pytest.approx(np.abs(du).sum(), rel=1e-12)
    by_direction = mass * (a_y * -du[du < 0].sum() + a_y_neg * du[du > 0].sum())
    assert r.friction_energy[-1] == pytest.approx(by_direction, rel=1e-12)
    end = np.searchsorted(r.t, t[-1], side="right")   # the record, not the run-out
    work = -mass * np.trapz(np.interp(r.t[:end], t, a) * r.v[:end], r.t[:end])
    kinetic = mass * r.v[end - 1] ** 2 / 2.0
    # the trapezoid rule's O(dt^2) error (it quarters as dt halves) is ~2e-6 here
    assert r.friction_energy[end - 1] == pytest.approx(work - kinetic, rel=1e-5)
    assert r.friction_energy[-1] > 0.0 and np.all(np.diff(r.friction_energy) >= 0.0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_reversed_polarity_reverses_a_two_way_result_exactly(seed):
    """(d): with a_y_neg = a_y the equations are odd in (a_g, u, v)."""
    t, a = random_record(seed)
    r, q = sb.newmark(t, a, 1.5), sb.newmark(t, -a, 1.5)
    assert np.array_equal(q.t, r.t) and np.array_equal(q.u, -r.u)
    assert np.array_equal(q.friction_energy, r.friction_energy)
    assert r.permanent != 0.0


def test_a_record_then_its_negative_after_a_rest_leaves_no_net_displacement():
    """(d): once stuck, the block restarts from the state it began in, so a
    record followed by its negative (after a rest) undoes it."""
    t, a = random_record(3)
    rest = t[-1] + 5.0
    r1 = sb.newmark(np.append(t, rest), np.append(a, 0.0), 1.5)
    assert r1.events[-1][1] == "stick" and r1.events[-1][0] < rest
    r = sb.newmark(np.concatenate([t, t + rest]), np.concatenate([a, -a]), 1.5)
    assert r1.permanent != 0.0
    assert abs(r.permanent) <= 1e-12 * abs(r1.permanent)


def test_bad_samples_and_yields_are_refused():
    with pytest.raises(ValueError, match="t, a_g"):
        sb.newmark([0.0, 1.0, 0.5], [0.0, 1.0, 0.0], 1.0)
    with pytest.raises(ValueError, match="a_y"):
        sb.newmark([0.0, 1.0], [0.0, 1.0], 0.0)


def explicit_stick_slip(t, a, a_y, a_y_neg, substeps):
    """An independent first-order peer: fixed sub-steps, a slide stops where
    v would change sign, a stuck block slides once |a_g| leaves the band."""
    yields = {-1: a_y, 1: a_y_neg}
    u = v = 0.0
    for k in range(len(t) - 1):
        dt = (t[k + 1] - t[k]) / substeps
        for j in range(substeps):
            ag = a[k] + (a[k + 1] - a[k]) * (j + 0.5) / substeps
            s = np.sign(v) or (-1 if ag > a_y else 1 if ag < -a_y_neg else 0)
            if s == 0:
                continue
            v_new = v + dt * (-ag - s * yields[s])
            v_new = v_new if np.sign(v_new) == s else 0.0
            u += dt * (v + v_new) / 2.0
            v = v_new
    return u


@pytest.mark.parametrize("seed, a_y, a_y_neg", [(4, 1.0, 1.0), (5, 1.5, 0.7), (6, 0.8, np.inf)])
def test_random_records_agree_with_a_fine_explicit_peer(seed, a_y, a_y_neg):
    """Stick, slip in either direction and reversal at a stop, in any order,
    within intervals: the peer converges to it at O(dt) (5e-4 at most here)."""
    t, a = random_record(seed, n=60, dt=0.05, peak=3.0)
    t, a = np.append(t, t[-1] + 10.0), np.append(a, 0.0)   # a rest: the run-out
    r = sb.newmark(t, a, a_y, a_y_neg=a_y_neg)
    assert len(r.events) > 6
    assert np.all(np.diff([te for te, _ in r.events]) > 0.0)   # no spurious stop at a start
    peer = explicit_stick_slip(t, a, a_y, a_y_neg, substeps=400)
    assert r.permanent == pytest.approx(peer, rel=2e-3)


GAMMA, KAPPA = sb.UNIFORM_SHEAR_COLUMN


def test_coupled_step_slides_only_past_the_first_modes_amplified_yield():
    """A step a_g = A from rest, xi = 0: q = -(gamma A / w^2)(1 - cos w t), so
    the base asks d = a_g + kappa q'' = A (1 - gamma kappa cos w t), largest
    A (1 + gamma kappa) at w t = pi: the base slides iff
    A > a_y / (1 + gamma kappa), first at cos w t* = (A - a_y) / (gamma kappa A)."""
    a_y, w = 1.0, 10.0
    threshold = a_y / (1.0 + GAMMA * KAPPA)
    assert sb.coupled_single_mode([0.0, 2.0], [0.999 * threshold] * 2, a_y, w)[4] == []
    for A in (1.01 * threshold, 0.9):
        events = sb.coupled_single_mode([0.0, 2.0], [A, A], a_y, w)[4]
        t_star = math.acos((A - a_y) / (GAMMA * KAPPA * A)) / w
        assert events[0] == (pytest.approx(t_star, abs=1e-7), "slip-")


def test_coupled_model_without_coupling_is_the_rigid_block():
    """kappa = 0: the column puts no force on the base, s'' = -a_g - sgn(s') a_y
    is cubic in t, which RK4 integrates exactly: only the events' bisection
    is left."""
    t, a = random_record(7, n=60, dt=0.05, peak=3.0)
    t, a = np.append(t, t[-1] + 2.0), np.append(a, 0.0)
    rigid = sb.newmark(t, a, 1.0, a_y_neg=0.7)
    coupled = sb.coupled_single_mode(t, a, 1.0, 5.0, a_y_neg=0.7, modal=(GAMMA, 0.0))
    assert [e for _, e in coupled[4]] == [e for _, e in rigid.events]
    assert coupled[1][-1] == pytest.approx(rigid.permanent, rel=1e-9)


def test_coupled_model_tends_to_the_rigid_block_as_the_column_stiffens():
    """One sine cycle, two-way: the error falls about as 1 / omega (measured)."""
    A, wg = 3.0, 4.0
    t = np.linspace(0.0, 2 * math.pi / wg, 129)
    t, a = np.append(t, t[-1] + 2.0), np.append(A * np.sin(wg * t), 0.0)
    rigid = sb.newmark(t, a, 1.0).permanent
    errors = [abs(sb.coupled_single_mode(t, a, 1.0, w)[1][-1] - rigid) / abs(rigid)
              for w in (100.0, 400.0)]
    assert errors[1] < errors[0] / 2.0 and errors[1] < 0.03, errors
