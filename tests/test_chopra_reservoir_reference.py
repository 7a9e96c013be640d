"""tests/references/chopra_reservoir.py, the harmonic hydrodynamic pressure
on a rigid vertical dam face (Chopra 1967; truncated at a plane-wave
dashpot; Fenves & Chopra's absorbing bottom), against facts derived here,
not against vstpetsc.

Facts used.
(1) The incompressible heel pressure (8 G / pi^2) rho a0 H = 0.742454 rho a0 H
    (G Catalan's constant), Westergaard's and Chopra's 0.743; the plain
    series' partial sums (alternating at the heel) differ from it by
    1 / (pi^2 N^2) (N terms).
(2) The boundary conditions, checked on the evaluated field by finite
    differences: the face P_x(0, y) = -rho a0, the surface P(x, H) = 0, the
    bottom P_y(x, 0) = i omega q P, the dashpot P_x(L, y) = -i (omega/c) P.
(3) Energy: the power the face puts in, -(a0 / 2 omega) Im F (F the
    resultant), leaves through any section x = X of the infinite reservoir
    (rigid bottom, above the first cut-off) and through the dashpot,
    (1 / 2 rho c) int |P(L, y)|^2 dy; below the cut-off it is 0.
(4) A second-order finite-difference solution of the Helmholtz problem in
    the truncated reservoir (ghost nodes at the face, the bottom and the
    dashpot), converging to (b) and (c) at rate h^2.
(5) Westergaard's parabola (7/8) rho a sqrt(H (H - y)) against the exact
    incompressible pressure: the figures below.
"""

import math

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spl

from references import chopra_reservoir as cr

H, RHO, C = 100.0, 1000.0, 1440.0
W1 = cr.cutoff_frequencies(H, C, 1)[0]          # pi c / 2H = 22.6 rad/s
SCALE = RHO * H                                 # pressure per unit a0


def gauss(n=200):
    """Gauss-Legendre points and weights on 0 <= y <= H."""
    t, w = np.polynomial.legendre.leggauss(n)
    return H * (t + 1) / 2, H * w / 2


# ------------------------------------------------------- incompressible limit

def test_heel_pressure_is_westergaards_0743():
    exact = 8 * 0.915965594177219015 / math.pi ** 2
    assert cr.HEEL_COEFFICIENT == pytest.approx(exact, rel=1e-15)
    assert abs(cr.HEEL_COEFFICIENT - 0.743) / 0.743 < 1e-3        # 7.4e-4
    # the plain Chopra series at omega = 0, many terms: its tail is 1/(pi^2 N^2)
    for n, tol in ((1000, 2.1e-7), (100_000, 2.1e-9)):
        heel = cr.pressure_series(0.0, 0.0, H, RHO, C, 0.0, n_terms=n).real / SCALE
        assert abs(heel - exact) < tol                               # 1.0e-7, 1.0e-11
    # the closed form, the accelerated sum and the plain series on the face
    ys = np.linspace(0.0, H, 11)
    closed = cr.pressure_incompressible(0.0, ys, H, RHO)
    series = cr.pressure_series(0.0, ys, H, RHO, C, 0.0, n_terms=100_000).real
    fast = cr.pressure_infinite(0.0, ys, H, RHO, C, 0.0)
    assert np.max(np.abs(series - closed)) / SCALE < 1e-8             # 1.6e-11 measured
    assert np.max(np.abs(fast - closed)) / SCALE < 1e-12
    assert closed[0] / SCALE == pytest.approx(cr.HEEL_COEFFICIENT, rel=1e-13)
    # the face's resultant: quadrature of the closed form, 14 zeta(3) / pi^3
    y, w = gauss()
    quad = np.sum(w * cr.pressure_incompressible(0.0, y, H, RHO)) / (RHO * H * H)
    assert quad == pytest.approx(cr.FORCE_COEFFICIENT, rel=1e-8)      # 1.8e-10 measured
    assert cr.FORCE_COEFFICIENT == pytest.approx(0.5427545, rel=1e-6)
    assert cr.force_infinite(H, RHO, C, 0.0).real / (RHO * H * H) == \
        pytest.approx(cr.FORCE_COEFFICIENT, rel=1e-12)


def test_westergaards_parabola_against_the_exact_incompressible_pressure():
    """The parabola is above the exact curve everywhere on the face; within
    3 % only on 0.4 H <= y <= 0.7 H (1.4 % at mid-depth); 17.9 % high at the
    heel (0.875 vs 0.7425); its resultant 7/12 is 7.48 % above the exact
    0.5428 rho a H^2."""
    ys = np.linspace(0.0, H, 201)[:-1]
    exact = cr.pressure_incompressible(0.0, ys, H, RHO)
    para = cr.westergaard_parabola(ys, H, RHO)
    assert np.all(para >= exact)
    mid = (ys >= 0.4 * H) & (ys <= 0.7 * H)
    assert np.max(para[mid] / exact[mid] - 1) < 0.03                  # 2.9 %
    assert para[0] / exact[0] == pytest.approx(0.875 / cr.HEEL_COEFFICIENT, rel=1e-12)
    assert 0.875 / cr.HEEL_COEFFICIENT - 1 == pytest.approx(0.1785, abs=1e-4)
    assert (7 / 12) / cr.FORCE_COEFFICIENT - 1 == pytest.approx(0.0748, abs=1e-4)


# ---------------------------------------------------- boundary conditions (a)

@pytest.mark.parametrize("omega", [0.0, 0.5 * W1, 1.5 * W1, 2.5 * W1])
def test_face_and_surface_conditions_infinite(omega):
    ys = np.array([0.1, 0.3, 0.5, 0.7, 0.9]) * H
    # the plain series' x-derivative at the face: the cosine series of a
    # constant, slowly convergent (error ~ 1/N away from the surface)
    d = cr.pressure_series(0.0, ys, H, RHO, C, omega, n_terms=20_000, derivative="x")
    assert np.max(np.abs(d + RHO)) / RHO < 2e-4      # 1.6e-5 at 0.1 H .. 1.0e-4 at 0.9 H
    # the evaluated field, one-sided second-order differences at the face
    h = 1e-3
    p = [cr.pressure_infinite(k * h, ys, H, RHO, C, omega) for k in range(3)]
    fd = (-3 * p[0] + 4 * p[1] - p[2]) / (2 * h)
    assert np.max(np.abs(fd + RHO)) / RHO < 1e-8                      # <= 7e-10
    # the free surface
    xs = np.array([0.0, 0.3 * H, 2.0 * H])
    assert np.max(np.abs(cr.pressure_infinite(xs, H, H, RHO, C, omega))) / SCALE < 1e-9
    assert np.max(np.abs(cr.pressure_series(xs, H, H, RHO, C, omega, n_terms=2000))) / SCALE < 1e-9


def test_compressible_series_and_the_fast_sum_agree():
    xs, ys = np.array([0.0, 10.0, 50.0, 0.0]), np.array([0.0, 30.0, 70.0, 95.0])
    for omega in (0.5 * W1, 1.5 * W1, 2.5 * W1):
        fast = cr.pressure_infinite(xs, ys, H, RHO, C, omega)
        plain = cr.pressure_series(xs, ys, H, RHO, C, omega, n_terms=200_000)
        assert np.max(np.abs(fast - plain)) / SCALE < 1e-8            # 2e-12 measured (the plain sum's tail)
    # below the first cut-off the response is real (in phase) and amplified
    p = cr.pressure_infinite(0.0, 0.0, H, RHO, C, 0.5 * W1)
    assert p.imag == 0.0 and p.real / SCALE > cr.HEEL_COEFFICIENT
    with pytest.raises(ZeroDivisionError):
        cr.pressure_infinite(0.0, 0.0, H, RHO, C, W1 * (1 + 0.0))


def test_energy_leaves_the_infinite_reservoir_outgoing():
    y, w = gauss()
    for omega in (1.5 * W1, 2.5 * W1):
        F = cr.force_infinite(H, RHO, C, omega)
        put_in = -F.imag / (2 * omega)                  # a0 = 1: 1/2 Re(F conj(v)), v = a0/(i omega)
        assert put_in > 0
        for X in (0.5 * H, 2.0 * H):
            P = cr.pressure_infinite(X, y, H, RHO, C, omega)
            Px = cr.pressure_infinite(X, y, H, RHO, C, omega, derivative="x")
            u = -Px / (1j * omega * RHO)
            flux = 0.5 * np.sum(w * (P * np.conj(u)).real)
            assert flux == pytest.approx(put_in, rel=1e-9)             # ~1e-15
    # below the cut-off nothing radiates: the force is real
    assert cr.force_infinite(H, RHO, C, 0.5 * W1).imag == 0.0


# ------------------------------------------------------------ (b) truncated

def test_truncated_tends_to_infinite_below_cutoff():
    xs, ys = np.array([0.0, 0.0, 20.0, 50.0]), np.array([0.0, 50.0, 30.0, 90.0])
    for omega in (0.0, 0.5 * W1, 0.9 * W1):
        a = cr.pressure_infinite(xs, ys, H, RHO, C, omega)
        kappa1 = math.sqrt(W1 ** 2 - omega ** 2) / C
        errs = []
        for L in (2 * H, 4 * H, 8 * H):
            b = cr.pressure_truncated(xs, ys, H, L, RHO, C, omega)
            errs.append(np.max(np.abs(b - a)) / SCALE)
            # the first mode's reflection: c_1 (X_b(0) - 1/kappa_1) with |R| = 1,
            # at most (4/pi) 2 E / (kappa_1 H (1 - E)), E = exp(-2 kappa_1 L)
            E = math.exp(-2 * kappa1 * L)
            assert errs[-1] < 1.2 * (4 / math.pi) * 2 * E / (kappa1 * H * (1 - E))
        # and it decays at that rate
        rate = math.log(errs[2] / errs[1]) / (-2 * kappa1 * 4 * H)
        assert 0.95 < rate < 1.05
    # above the cut-off a propagating mode reflects (|R| < 1 but not -> 0 with L)
    a = cr.pressure_infinite(0.0, 0.0, H, RHO, C, 1.5 * W1)
    for L in (4 * H, 16 * H):
        assert abs(cr.pressure_truncated(0.0, 0.0, H, L, RHO, C, 1.5 * W1) - a) / SCALE > 0.05


@pytest.mark.parametrize("omega,alpha", [(0.5 * W1, 1.0), (1.5 * W1, 1.0), (W1, 1.0),
                                         (1.5 * W1, 0.0), (2.5 * W1, 0.5)])
def test_dashpot_condition_at_L(omega, alpha):
    L, h = 2.0 * H, 1e-3
    ys = np.linspace(0.0, H, 9)
    p = [cr.pressure_truncated(L - k * h, ys, H, L, RHO, C, omega, alpha=alpha) for k in range(3)]
    fd = (3 * p[0] - 4 * p[1] + p[2]) / (2 * h)
    assert np.max(np.abs(fd + 1j * omega / C * p[0])) / np.max(np.abs(fd)) < 1e-8   # <= 4e-10


def test_energy_leaves_through_the_dashpot():
    y, w = gauss()
    L = 2.0 * H
    for omega in (0.5 * W1, W1, 1.5 * W1, 2.5 * W1):        # W1: finite here, no resonance
        F = cr.force_truncated(H, L, RHO, C, omega)
        put_in = -F.imag / (2 * omega)
        P = cr.pressure_truncated(L, y, H, L, RHO, C, omega)
        out = np.sum(w * np.abs(P) ** 2) / (2 * RHO * C)
        assert out == pytest.approx(put_in, rel=1e-9)                  # ~1e-15


# ------------------------------------------------------ (c) absorbing bottom

def test_characteristic_roots():
    for sigma in (0.0, 0.1, 1.0, math.pi / 2, 3.0, 10.0, 100.0, 1e4):
        th = cr.characteristic_roots(sigma, 3000)
        n = np.arange(1, th.size + 1)
        assert np.all(th.real >= (n - 0.5) * math.pi) and np.all(th.real <= n * math.pi)
        assert np.all(th.imag >= 0.0)
        scale = (np.abs(th) + sigma) * np.cosh(th.imag)
        assert np.max(np.abs(th * np.cos(th) + 1j * sigma * np.sin(th)) / scale) < 1e-11
    # the first root from pi/2 (rigid) toward pi (sigma -> inf)
    assert cr.characteristic_roots(1e4, 1)[0].real == pytest.approx(math.pi, rel=1e-7)
    # independent: eigenvalues of -Y'' with Y(H) = 0, Y'(0) = i sigma/H Y(0),
    # by second-order finite differences (ghost node at the bottom), two
    # grids and Richardson's extrapolation
    sigma = 1.0

    def fd_roots(m):
        hh = 1.0 / m                              # H = 1, nodes y = 0 .. (m-1) h
        A = (np.diag(np.full(m, 2.0 / hh ** 2, complex))
             + np.diag(np.full(m - 1, -1 / hh ** 2), 1) + np.diag(np.full(m - 1, -1 / hh ** 2), -1))
        A[0, 0] += 2j * sigma / hh                # ghost: Y_-1 = Y_1 - 2 h (i sigma) Y_0
        A[0, 1] = -2 / hh ** 2
        ev = np.sqrt(np.linalg.eigvals(A))
        return ev[np.argsort(ev.real)][:4]
    coarse, fine = fd_roots(60), fd_roots(120)
    th = cr.characteristic_roots(sigma, 4)
    assert np.max(np.abs(fine - th) / np.abs(th)) < 5e-4               # h^2: 3.5e-4
    assert np.max(np.abs((4 * fine - coarse) / 3 - th) / np.abs(th)) < 1e-6   # 1.5e-7


def test_absorbing_bottom_modes_and_conditions():
    omega = 1.5 * W1
    # bilinear orthogonality and the face's expansion
    lam, shape = cr.vertical_modes(H, 6, omega, C, alpha=0.3)
    y, w = gauss(400)
    Y = shape(y)
    gram = (Y * w) @ Y.T
    off = gram - np.diag(np.diag(gram))
    assert np.max(np.abs(off)) < 1e-10 * np.max(np.abs(gram))
    assert np.all(lam.imag > 0)
    # alpha = 1 is the rigid bottom; alpha -> 1 continuous
    pts = (np.array([0.0, 0.0, 30.0]), np.array([0.0, 50.0, 20.0]))
    rigid = cr.pressure_infinite(*pts, H, RHO, C, omega)
    assert np.max(np.abs(cr.pressure_infinite(*pts, H, RHO, C, omega, alpha=1.0) - rigid)) == 0.0
    near = cr.pressure_infinite(*pts, H, RHO, C, omega, alpha=1 - 1e-7)
    assert np.max(np.abs(near - rigid)) / SCALE < 1e-6
    for alpha in (0.5, 0.0, -0.5):
        q = cr.bottom_q(alpha, C)
        xs = np.array([0.0, 10.0, 50.0])
        h = 1e-3
        p = [cr.pressure_infinite(xs, k * h, H, RHO, C, omega, alpha=alpha) for k in range(3)]
        dy = (-3 * p[0] + 4 * p[1] - p[2]) / (2 * h)
        assert np.max(np.abs(dy - 1j * omega * q * p[0])) / np.max(np.abs(p[0])) < 1e-6   # <= 1.5e-7
        assert np.max(np.abs(cr.pressure_infinite(xs, H, H, RHO, C, omega, alpha=alpha))) / SCALE < 1e-9
        ys = np.array([0.1, 0.5, 0.9]) * H
        p = [cr.pressure_infinite(k * h, ys, H, RHO, C, omega, alpha=alpha, n_modes=2000)
             for k in range(3)]
        dx = (-3 * p[0] + 4 * p[1] - p[2]) / (2 * h)
        # (at the heel corner itself the x-derivative's series converges only
        # as 1/N for alpha < 1: 2.4e-4 at N = 2000; here <= 4e-9)
        assert np.max(np.abs(dx + RHO)) / RHO < 1e-7
        # the absorbing bottom takes energy: less leaves through a section
        F = cr.force_infinite(H, RHO, C, omega, alpha=alpha)
        assert -F.imag / (2 * omega) > 0


# -------------------------------------------- (b), (c) by finite differences

def finite_differences(L, omega, alpha, m):
    """P on the grid x = i h, y = j h (h = H / m) of the truncated reservoir:
    second-order differences, ghost nodes at the face, bottom and dashpot."""
    h, k = H / m, omega / C
    beta = 1j * omega * cr.bottom_q(alpha, C)
    nx, ny = int(round(L / h)), m
    I, J = np.meshgrid(np.arange(nx + 1), np.arange(ny), indexing="ij")
    idx = I * ny + J
    n = idx.size
    diag = np.full(I.shape, -4.0 / h ** 2 + k * k, complex)
    diag[-1, :] += -2j * k / h                           # dashpot ghost
    diag[:, 0] += -2.0 * beta / h                        # bottom ghost
    rows, cols, vals = [idx.ravel()], [idx.ravel()], [diag.ravel()]

    def link(src, dst, weight):
        rows.append(src.ravel()); cols.append(dst.ravel())
        vals.append(np.full(src.size, weight, complex))
    link(idx[1:-1], idx[:-2], 1 / h ** 2); link(idx[1:-1], idx[2:], 1 / h ** 2)
    link(idx[0], idx[1], 2 / h ** 2); link(idx[-1], idx[-2], 2 / h ** 2)
    link(idx[:, 1:], idx[:, :-1], 1 / h ** 2); link(idx[:, :-1], idx[:, 1:], 1 / h ** 2)
    link(idx[:, 0], idx[:, 1], 1 / h ** 2)               # bottom ghost: the second 1/h^2
    A = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(n, n))
    b = np.zeros(I.shape, complex)
    b[0, :] = -2.0 * RHO / h                             # face ghost, P_x = -rho (a0 = 1)
    return spl.spsolve(A.tocsc(), b.ravel()).reshape(I.shape)


@pytest.mark.parametrize("omega,alpha", [(0.5 * W1, 1.0), (1.5 * W1, 1.0), (2.5 * W1, 0.5)])
def test_truncated_reservoir_by_finite_differences(omega, alpha):
    L = 2.0 * H
    xs, ys = np.array([0.0, 50.0, 100.0, 200.0]), np.array([0.0, 50.0, 0.0, 25.0])
    ref = cr.pressure_truncated(xs, ys, H, L, RHO, C, omega, alpha=alpha)
    errs = []
    for m in (20, 40):
        P = finite_differences(L, omega, alpha, m)
        s = m / H
        got = P[np.rint(xs * s).astype(int), np.rint(ys * s).astype(int)]
        errs.append(np.max(np.abs(got - ref)) / np.max(np.abs(ref)))
    assert errs[1] < 1.5e-3                                             # 8e-5 .. 1.2e-3
    assert 3.9 < errs[0] / errs[1] < 4.1                                # second order: 4.00-4.01
