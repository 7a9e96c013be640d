"""Coulomb friction's slab kernel (kernels/coulomb.py): against the same law
followed by an explicit return mapping on 20000 sub-steps, its tangent
against finite differences, its exact limits, the work and kinematic
identities."""

import numpy as np
import pytest

from conftest import assert_tangent
from vstpetsc.kernels.coulomb import friction_integrals, penalty_normal
from vstpetsc.kernels.gap import gap_coefficients

DT, KT, MU, N0 = 1e-3, 1e7, 0.5, 1e4
EY = MU * N0 / KT           # the stretch at the yield under N0
SY = EY / DT                # the relative velocity that moves EY in a slab


def normal_at(th, normal, pieces):
    """N(theta) on an array: the polynomial on the pieces, 0 elsewhere."""
    n = np.zeros_like(th)
    for p, q in pieces:
        on = (th >= p) & (th <= q)
        n[on] = normal[0] + th[on] * (normal[1] + th[on] * normal[2])
    return np.maximum(n, 0.0)


def return_mapping(e_n, s1, s2, normal, pieces, steps=20000):
    """(F1, F2, e at the end, dissipation): e advanced by the exact relative
    displacement of each sub-step, then projected onto |k_t e| <= mu N at
    its end; trapezoid sums."""
    edges = [x for piece in pieces for x in piece]
    th = np.unique(np.concatenate([np.linspace(0.0, 1.0, steps + 1), edges]))
    steps = len(th) - 1         # sub-steps end where the gap opens or closes
    moved = DT * (s1 * (th - th ** 2 / 2) + s2 * th ** 2 / 2)
    step, n = np.diff(moved).tolist(), normal_at(th, normal, pieces)
    limit = (MU * n / KT).tolist()
    e, lim0 = [0.0] * (steps + 1), limit[0]
    e[0] = max(-lim0, min(lim0, e_n))
    for i in range(steps):
        trial, lim = e[i] + step[i], limit[i + 1]
        e[i + 1] = lim if trial > lim else -lim if trial < -lim else trial
    e = np.array(e)
    slip = e[:-1] + np.array(step) - e[1:]
    force = -KT * e
    dissipation = np.sum(MU * 0.5 * (n[:-1] + n[1:]) * np.abs(slip))
    return (DT * np.trapz(force * (1 - th), th), DT * np.trapz(force * th, th),
            e[-1], dissipation)


def constant(n=N0):
    return (n, 0.0, 0.0), [(0.0, 1.0)]


def quadratic(rng):
    """A normal force between about N0 / 2 and 2 N0 over the whole slab."""
    return (N0 * rng.uniform(0.8, 1.2), N0 * rng.uniform(-0.5, 0.5),
            N0 * rng.uniform(-0.3, 0.3)), [(0.0, 1.0)]


def opening(rng):
    """The power penalty of a gap that opens inside the slab."""
    kn, gn = 1e9, -N0 / 1e9 * rng.uniform(0.5, 1.5)
    d = -abs(gn) / DT * rng.uniform(1.5, 4.0, 2)
    return penalty_normal(*gap_coefficients(gn, d[0], d[1], DT), kn)


def bounce(rng):
    """A gap that closes and opens again inside the slab (d^1 = a gn / dt,
    d^2 = -b gn / dt: closed somewhere for a^2 > 2 (a + b), open at the end
    for b > a - 2)."""
    kn, gn = 1e9, 3.0 * N0 / 1e9 * rng.uniform(0.8, 1.2)
    a = rng.uniform(6.0, 8.0)
    b = a + rng.uniform(-1.0, 2.0)
    return penalty_normal(*gap_coefficients(gn, a * gn / DT, -b * gn / DT, DT), kn)


def cases(rng):
    """(name, e_n, s1, s2, normal, pieces), a few per kind of slab."""
    out = []
    for _ in range(6):
        sign = rng.choice([-1.0, 1.0])
        out.append(("elastic", EY * rng.uniform(-0.3, 0.3), *(SY * rng.uniform(-0.3, 0.3, 2)),
                    *constant()))
        out.append(("sliding", sign * EY, *(sign * SY * rng.uniform(1.0, 5.0, 2)), *constant()))
        out.append(("elastic->sliding", 0.0, *(sign * SY * rng.uniform(2.0, 6.0, 2)),
                    *quadratic(rng)))
        normal, pieces = quadratic(rng)
        out.append(("reversal", sign * MU * normal[0] / KT, sign * SY * rng.uniform(1.0, 4.0),
                    -sign * SY * rng.uniform(1.0, 4.0), normal, pieces))
        out.append(("opening", 0.0, *(SY * rng.uniform(-3.0, 3.0, 2)), *opening(rng)))
        out.append(("bounce", 0.0, *(SY * rng.uniform(-3.0, 3.0, 2)), *bounce(rng)))
        normal, pieces = quadratic(rng)
        out.append(("mixed", MU * normal[0] / KT * rng.uniform(-1.0, 1.0),
                    *(SY * rng.uniform(-3.0, 3.0, 2)), normal, pieces))
    return out


def kernel(e_n, s1, s2, normal, pieces, kt=KT, mu=MU):
    return friction_integrals(e_n, s1, s2, DT, kt, mu, normal, pieces)


def test_against_return_mapping_on_many_slabs(rng):
    kinds = set()
    for name, e_n, s1, s2, normal, pieces in cases(rng):
        got = kernel(e_n, s1, s2, normal, pieces)
        f1, f2, e_end, dissipation = return_mapping(e_n, s1, s2, normal, pieces)
        scale = DT * MU * N0
        assert abs(got.f1 - f1) <= 1e-6 * scale, name
        assert abs(got.f2 - f2) <= 1e-6 * scale, name
        assert abs(got.stretch - e_end) <= 1e-6 * EY, name
        assert abs(got.dissipation - dissipation) <= 1e-6 * MU * N0 * EY, name
        if name == "elastic":
            assert got.slip == 0.0 and got.dissipation == 0.0
        else:
            assert got.slip != 0.0, name
        kinds.add(name)
    assert len(kinds) == 7


def test_tangent_matches_central_differences(rng):
    for name, e_n, s1, s2, normal, pieces in cases(rng):
        got = kernel(e_n, s1, s2, normal, pieces)
        assert_tangent(lambda a, b: kernel(e_n, a, b, normal, pieces), (s1, s2), got,
                       1e-6 * SY, 1e-5, KT * DT * DT)


def test_without_friction_no_force(rng):
    for _, e_n, s1, s2, normal, pieces in cases(rng):
        got = kernel(0.0, s1, s2, normal, pieces, mu=0.0)
        assert got[:6] == (0.0,) * 6 and got.stretch == 0.0 and got.dissipation == 0.0


def test_stiff_spring_sliding_one_way_is_rigid_plastic(rng):
    for _ in range(10):
        (n0, n1, n2), pieces = quadratic(rng)
        sign = rng.choice([-1.0, 1.0])
        got = kernel(0.0, *(sign * SY * rng.uniform(0.5, 3.0, 2)), (n0, n1, n2), pieces, kt=1e14)
        rigid = (DT * (n0 / 2 + n1 / 6 + n2 / 12), DT * (n0 / 2 + n1 / 3 + n2 / 4))
        assert got.f1 == pytest.approx(-sign * MU * rigid[0], rel=1e-6)
        assert got.f2 == pytest.approx(-sign * MU * rigid[1], rel=1e-6)


def test_constant_normal_force_sliding_from_the_yield_is_exact(rng):
    for _ in range(10):
        sign, n = rng.choice([-1.0, 1.0]), N0 * rng.uniform(0.5, 2.0)
        got = kernel(sign * MU * n / KT, *(sign * SY * rng.uniform(0.1, 5.0, 2)), *constant(n))
        assert got.f1 == pytest.approx(-sign * MU * n * DT / 2, rel=1e-14)
        assert got.f2 == pytest.approx(-sign * MU * n * DT / 2, rel=1e-14)
        assert got[2:6] == (0.0,) * 4


def test_dissipation_is_the_work_less_the_spring_energy(rng):
    for name, e_n, s1, s2, normal, pieces in cases(rng):
        got = kernel(e_n, s1, s2, normal, pieces)
        work = -(s1 * got.f1 + s2 * got.f2)          # int (-T) s dt: the work into the spring
        energy = 0.5 * KT * (got.stretch ** 2 - e_n ** 2)
        assert got.dissipation >= 0.0
        assert got.dissipation == pytest.approx(work - energy, abs=1e-12 * DT * MU * N0 * SY), name


def test_stretch_is_contact_motion_less_slip(rng):
    for name, e_n, s1, s2, normal, pieces in cases(rng):
        got = kernel(e_n, s1, s2, normal, pieces)
        moved = sum(DT * (s1 * ((q - q * q / 2) - (p - p * p / 2)) + s2 * (q * q - p * p) / 2)
                    for p, q in pieces)
        assert got.stretch - e_n == pytest.approx(moved - got.slip, abs=1e-12 * EY), name


def test_open_gap_no_force_and_no_stretch():
    got = kernel(0.0, SY, -SY, *penalty_normal(1e-6, -1e-9, 0.0, 1e9))
    assert got == (0.0,) * 10       # released too: e_n = 0


@pytest.mark.parametrize("s1, s2", [(0.0, 0.0), (0.0, SY), (SY, SY), (-2.0 * SY, 0.0)])
def test_degenerate_motions_keep_the_identities(s1, s2):
    """No motion, a motion that starts or ends at rest, a constant one,
    while the gap opens: the stretch stays inside a limit that shrinks to
    zero, and nothing dissipates energy it was not given."""
    normal, pieces = penalty_normal(*gap_coefficients(-N0 / 1e9, -3e-5 / DT, -3e-5 / DT, DT), 1e9)
    for e_n in (0.0, MU * normal[0] / KT, -MU * normal[0] / KT):
        got = kernel(e_n, s1, s2, normal, pieces)
        f1, f2, e_end, _ = return_mapping(e_n, s1, s2, normal, pieces)
        work = -(s1 * got.f1 + s2 * got.f2) - 0.5 * KT * (got.stretch ** 2 - e_n ** 2)
        assert got.dissipation >= 0.0 and got.stretch == 0.0
        assert got.dissipation == pytest.approx(work, abs=1e-12 * MU * N0 * EY)
        assert abs(got.f1 - f1) + abs(got.f2 - f2) <= 1e-6 * DT * MU * N0


def test_limit_shrinking_onto_a_still_spring_dissipates_nothing_negative():
    """At rest with e = 0 while the gap opens: a rounding-negative N just
    inside the opening root once gave a dissipation of -1e-32."""
    got = kernel(0.0, 0.0, 0.0, (6153.3304639988855, -46793.024621636374, 19786.197931696963),
                 [(0.0, 0.1397604442188071)])
    assert got.dissipation >= 0.0 and got.f1 == got.f2 == 0.0
