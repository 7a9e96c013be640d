"""The numpy kernels, checked without PETSc."""

import math

import numpy as np
import pytest
from scipy import integrate

from conftest import bar, make_case
from vstpetsc.spacetime import slab
from vstpetsc.line import bands
from vstpetsc.spacetime.history import History
from vstpetsc.kernels.gap import (closed_on_slab, closed_throughout, gap_coefficients,
    pair_integrals, roots01)
from vstpetsc.line.model import band_mult, build_model, dense


def two_bodies():
    """The operators of two bodies (mesh-free kernels take them)."""
    case = make_case(0.1, 1.0, [bar("a", (0.0, 1.0), 4, E=2.0, rho=3.0, area=0.5),
                                bar("b", (1.5, 2.0), 3, E=7.0, rho=1.0, area=2.0)])
    return build_model(case).ops


def test_mass_and_stiffness_bands():
    lay = two_bodies()
    M, K = dense(lay)
    # mass of each body is rho A L, rigid motions carry no strain energy
    ones = np.ones(M.shape[0])
    assert np.isclose(ones[:5] @ M[:5, :5] @ ones[:5], 3.0 * 0.5 * 1.0)
    assert np.isclose(ones[5:] @ M[5:, 5:] @ ones[5:], 1.0 * 2.0 * 0.5)
    assert np.allclose(K @ ones, 0.0)
    assert M[4, 5] == 0.0 and K[4, 5] == 0.0   # no element joins two bodies
    u = np.random.default_rng(0).normal(size=M.shape[0])
    assert np.allclose(band_mult(lay.m_diag, lay.m_off, u), M @ u)


def test_slab_matrix_is_kronecker_form_and_csr_matches():
    lay = two_bodies()
    M, K = dense(lay)
    dt = 0.3
    n = M.shape[0]
    # interleaved per node: dof 2i + a
    A = np.kron(M, slab.HM) + dt ** 2 * np.kron(K, slab.HK)
    blocks = bands.slab_matrix(lay, dt)
    indptr, indices, data = bands.block_rows_csr(blocks, 0, n)
    B = np.zeros((2 * n, 2 * n))
    for r in range(2 * n):
        B[r, indices[indptr[r]:indptr[r + 1]]] = data[indptr[r]:indptr[r + 1]]
    assert np.allclose(A, B)
    # a slice of rows gives the same rows
    i2, j2, d2 = bands.block_rows_csr(blocks, 3, 6)
    assert np.array_equal(j2, indices[indptr[6]:indptr[12]])
    assert np.allclose(d2, data[indptr[6]:indptr[12]])


def test_time_matrices_from_shape_functions():
    # HM = int T_a dT_b/dtheta + jump at theta = 0; HK = int T_a I_b / dt^2
    T = [lambda s: 1 - s, lambda s: s]
    Ih = [lambda s: s - s * s / 2, lambda s: s * s / 2]
    dT = [-1.0, 1.0]
    for a in range(2):
        for b in range(2):
            hm = integrate.quad(lambda s: T[a](s) * dT[b], 0, 1)[0] + (a == 0) * T[b](0)
            hk = integrate.quad(lambda s: T[a](s) * Ih[b](s), 0, 1)[0]
            assert np.isclose(slab.HM[a, b], hm)
            assert np.isclose(slab.HK[a, b], hk)


@pytest.mark.parametrize("coef,expected", [
    ((1.0, -4.0, 3.0), [1 / 3]),          # roots 1/3 and 1 (1 is the slab end)
    ((0.02, -0.3, 1.0), [0.1, 0.2]),
    ((1.0, 0.0, 1.0), []),                # no real root
    ((0.5, -1.0, 0.0), [0.5]),            # linear
    ((-1.0, 0.0, 0.0), []),               # constant
    ((1e-12, -1.0, 1e-14), [1e-12]),      # cancellation-prone
])
def test_roots01(coef, expected):
    got = roots01(*coef)
    assert len(got) == len(expected)
    assert np.allclose(got, expected, rtol=1e-10, atol=0)


def _quad_reference(gn, d1, d2, dt, power):
    a0, a1, a2 = gap_coefficients(gn, d1, d2, dt)
    g = lambda s: a0 + a1 * s + a2 * s * s
    I = [lambda s: dt * (s - s * s / 2), lambda s: dt * s * s / 2]
    T = [lambda s: 1 - s, lambda s: s]
    phi = T if power else I
    opts = dict(points=list(roots01(a0, a1, a2)) or None, limit=200, epsabs=0, epsrel=1e-13)
    G = [dt * integrate.quad(lambda s: min(0.0, g(s)) * phi[a](s), 0, 1, **opts)[0]
         for a in range(2)]
    W = [[dt * integrate.quad(lambda s: (g(s) < 0) * phi[a](s) * I[b](s), 0, 1,
                              **opts)[0] for b in range(2)] for a in range(2)]
    return np.array(G), np.array(W)


def _integrals(gn, d1, d2, dt, power):
    """(G, W) as arrays, zeros when the pair stays open."""
    out = pair_integrals(gn, d1, d2, dt, power)
    if out is None:
        return np.zeros(2), np.zeros((2, 2))
    return np.array(out[:2]), np.array(out[2:]).reshape(2, 2)


@pytest.mark.parametrize("power", [False, True])
def test_pair_integrals_exact_and_tangent_matches_finite_differences(power, rng):
    dt = 0.1
    for _ in range(40):
        gn = rng.uniform(-0.05, 0.05)
        d1, d2 = rng.uniform(-1, 1, size=2)
        G, W = _integrals(gn, d1, d2, dt, power)
        Gr, Wr = _quad_reference(gn, d1, d2, dt, power)
        assert np.allclose(G, Gr, rtol=1e-9, atol=1e-15)
        assert np.allclose(W, Wr, rtol=1e-8, atol=1e-15)
        closed = pair_integrals(gn, d1, d2, dt, power) is not None
        assert closed == closed_on_slab(gn, d1, d2, dt) == bool(np.any(Gr != 0))
        # W = -dG/dd: central differences
        h = 1e-7
        for b in range(2):
            dp, dm = np.array([d1, d2]), np.array([d1, d2])
            dp[b] += h
            dm[b] -= h
            fd = (_integrals(gn, *dp, dt, power)[0] - _integrals(gn, *dm, dt, power)[0]) / (2 * h)
            assert np.allclose(-fd, W[:, b], rtol=1e-5, atol=1e-12)


@pytest.mark.parametrize("power", [False, True])
def test_closed_form_of_a_gap_closed_over_the_slab(power, rng):
    """Steady contact takes closed forms: they match the quadrature."""
    dt, hits = 0.1, 0
    for _ in range(40):
        gn = rng.uniform(-0.05, -0.01)
        d1, d2 = rng.uniform(-0.2, 0.2, size=2)
        if not closed_throughout(*gap_coefficients(gn, d1, d2, dt)):
            continue
        hits += 1
        G, W = _integrals(gn, d1, d2, dt, power)
        Gr, Wr = _quad_reference(gn, d1, d2, dt, power)
        assert np.allclose(G, Gr, rtol=1e-12, atol=0) and np.allclose(W, Wr, rtol=1e-12, atol=0)
    assert hits > 30


def test_barely_closed_pair_is_integrated_accurately():
    # g dips below zero by 1e-9 around its vertex t*: there
    # g = a2 (t - t*)^2 - m on |t - t*| < w = sqrt(m / a2), and
    # int min(0, g) dt = -4/3 m w dt, times phi(t*) up to O(w^2)
    dt, d1, d2, m = 0.1, 1.0, -1.0, 1e-9
    a1, a2 = -dt * d1, 0.5 * dt * (d1 - d2)
    gn = a1 * a1 / (4 * a2) - m
    t = -a1 / (2 * a2)
    G, _ = _integrals(gn, d1, d2, dt, True)
    expected = -4.0 / 3.0 * m * math.sqrt(m / a2) * dt * np.array([1 - t, t])
    assert np.allclose(G, expected, rtol=1e-6, atol=0)


def test_power_impulse_is_time_integral_of_force():
    # sum_a T_a = 1: the power variant's impulse is exactly int k max(0, -g) dt
    dt, gn, d1, d2 = 0.2, 0.01, 0.3, -0.1
    G, _ = _integrals(gn, d1, d2, dt, True)
    a0, a1, a2 = gap_coefficients(gn, d1, d2, dt)
    ref = dt * integrate.quad(lambda s: min(0.0, a0 + a1 * s + a2 * s * s), 0, 1,
                              points=list(roots01(a0, a1, a2)))[0]
    assert np.isclose(G.sum(), ref, rtol=1e-12)


def test_history_hat_integrals_exact():
    h = History([[0.0, 0.0], [0.013, 2.0], [0.031, -1.0], [0.05, 0.5]])
    for t0, t1 in [(0.0, 0.01), (0.005, 0.04), (0.03, 0.07), (0.06, 0.08)]:
        ref = [integrate.quad(lambda t: h(t) * (t1 - t) / (t1 - t0), t0, t1,
                              points=h.t, epsrel=1e-13)[0],
               integrate.quad(lambda t: h(t) * (t - t0) / (t1 - t0), t0, t1,
                              points=h.t, epsrel=1e-13)[0]]
        assert np.allclose(h.hat_integrals(t0, t1), ref, rtol=1e-11, atol=1e-15)
    assert np.allclose(History(value=3.0).hat_integrals(1.0, 1.5), [0.75, 0.75])


def block_dense(blocks):
    """Dense 2N x 2N matrix of node blocks (N, 3, 2, 2)."""
    n = blocks.shape[0]
    out = np.zeros((2 * n, 2 * n))
    for i in range(n):
        for j, c in enumerate((i - 1, i, i + 1)):
            if 0 <= c < n:
                out[2 * i:2 * i + 2, 2 * c:2 * c + 2] += blocks[i, j]
    return out


@pytest.mark.parametrize("dt", [0.05, 0.7])
def test_running_sum_right_hand_side_equals_the_state_form(dt):
    """slab.recurrence: W r^{n+1} = W r^n + G z^n - W (T - I) F^n, with
    x = V z per node, equals r^{n+1} = R (mask Y^n + Q x^n); z_2 is the
    displacement increment; the solver's matrix is (W x I) A (V x I)."""
    lay = two_bodies()
    n = lay.m_diag.size
    rng = np.random.default_rng(5)
    W, V, gm, gk = slab.recurrence(dt)
    I = np.eye(n)
    A = block_dense(bands.slab_matrix(lay, dt))
    R = block_dense(bands.rhs_operator(lay, dt))
    Q = np.kron(I, slab.advance_block(dt))
    mask = np.tile([1.0, 0.0], n)
    WI, VI = np.kron(I, W), np.kron(I, V)
    assert np.allclose(block_dense(bands.slab_matrix(lay, dt, W, V)), WI @ A @ VI)
    assert np.allclose(block_dense(bands.rhs_operator(lay, dt, W)), WI @ R)
    band = bands.increment_bands(lay, dt, 0, n)          # difference form: G's matrix
    G = np.zeros((2 * n, 2 * n))
    for i in range(n):
        for a in range(2):
            row, (left, total, right) = 2 * i + a, band[i, a]
            G[row, 2 * i + a] = total - left - right
            if i > 0:
                G[row, 2 * i - 2 + a] = left
            if i < n - 1:
                G[row, 2 * i + 2 + a] = right
    Y = rng.normal(size=2 * n)
    running = WI @ R @ Y
    for _ in range(3):
        F = rng.normal(size=2 * n)
        x = np.linalg.solve(A, R @ Y + F)
        z = np.linalg.solve(VI, x)
        Y_next = mask * Y + Q @ x
        assert np.allclose(z[1::2], Y_next[0::2] - Y[0::2], rtol=1e-13, atol=1e-13)
        running = running + G @ z - WI @ np.kron(I, slab.CARRY - np.eye(2)) @ F
        direct = WI @ R @ Y_next
        assert np.allclose(running, direct, rtol=0, atol=1e-10 * np.abs(direct).max())
        Y = Y_next
