"""Hydrodynamic pressure on a rigid vertical dam face shaken horizontally
and harmonically: Chopra's (1967) infinite reservoir, the same reservoir
truncated at a plane-wave absorber, and Fenves & Chopra's (1984) partly
absorbing bottom. numpy and scipy.special only; it imports nothing of
vstpetsc.

Sources.
- A. K. Chopra (1967), "Hydrodynamic pressures on dams during earthquakes",
  J. Eng. Mech. Div. ASCE 93(EM6), 205-223: the infinite reservoir of
  constant depth on a rigid bottom, the series (a) below.
- H. M. Westergaard (1933), "Water pressures on dams during earthquakes",
  Trans. ASCE 98, 418-433: the same problem, and his parabola
  p = (7/8) rho a sqrt(H (H - y)).
- G. Fenves and A. K. Chopra (1983), "Effects of reservoir bottom
  absorption on earthquake response of concrete gravity dams", Earthquake
  Eng. Struct. Dyn. 11, 809-829; (1984) "EAGD-84: a computer program for
  earthquake analysis of concrete gravity dams", report UCB/EERC-84/11:
  the bottom condition with the wave reflection coefficient alpha and the
  complex vertical eigenvalues, (c) below.
The formulas here are derived afresh from the wave equation (below); the
papers are cited for the model, not copied.

Geometry and signs. The face is x = 0 and the water occupies x >= 0:
x is the horizontal DISTANCE FROM THE FACE INTO THE RESERVOIR, y the
height above the (horizontal) bottom, 0 <= y <= H, the free surface at
y = H. The ground, and the rigid dam with it, accelerates
a(t) = Re[a0 exp(i omega t)] = a0 cos(omega t) (a0 real or complex) in
the +x direction, i.e. TOWARD THE WATER. A vstpetsc dam has its reservoir
on the left (upstream face at x_face, water at x < x_face): there
x_here = x_face - x_model and a0 = -(the model's x acceleration).
Every function returns complex amplitudes P, the pressure being
p(x, y, t) = Re[P exp(i omega t)]; p > 0 is compression, so a face pushed
into the water (a0 > 0, omega -> 0) carries p > 0.

The problem. The linearised Euler equation rho u_tt = -grad p and
continuity give the wave equation p_tt = c^2 (p_xx + p_yy), i.e. for the
amplitude P_xx + P_yy + k^2 P = 0, k = omega / c, with
- the face (fluid acceleration = the face's):  P_x(0, y) = -rho a0;
- the free surface (no gravity waves):          P(x, H) = 0;
- the bottom, rigid:                            P_y(x, 0) = 0,
  or absorbing (c below): dp/dn = -q dp/dt with n the outward normal -y,
  i.e. P_y(x, 0) = i omega q P(x, 0), q = (1 - alpha) / ((1 + alpha) c);
- far away, (a): P bounded and outgoing; (b): at x = L the plane-wave
  dashpot dp/dn = -(1/c) dp/dt, n = +x, i.e. P_x(L, y) = -i k P(L, y).

(a) Rigid bottom, infinite reservoir. The vertical modes cos(lambda_n y),
lambda_n = (2n - 1) pi / (2H), n = 1, 2, ..., satisfy the bottom and the
surface; the constant face load expands as
1 = sum_n c_n cos(lambda_n y), c_n = 4 (-1)^(n+1) / ((2n - 1) pi), and
    P(x, y) = rho a0 sum_n c_n cos(lambda_n y) exp(-kappa_n x) / kappa_n,
    kappa_n = sqrt(lambda_n^2 - k^2)  (real > 0 below the n-th cut-off
              omega_n = c lambda_n),
    kappa_n = i sqrt(k^2 - lambda_n^2) above it (exp(i(omega t - |kappa| x)):
              a wave travelling away from the dam, +x).
This is Chopra's series: p = (4 rho a0 / pi) sum (-1)^(n+1) / (2n-1)
cos(lambda_n y) exp(-kappa_n x) / kappa_n. At omega = omega_n the n-th
term is infinite (the reservoir's resonance): refused here. The resultant
on the face (per unit width, pushing the dam in -x, away from the water) is
    F = int_0^H P(0, y) dy = rho a0 sum_n c_n (-1)^(n+1) / (lambda_n kappa_n).

Incompressible limit (k = 0, kappa_n = lambda_n): with w = exp(-pi (x + i y) / (2H)),
cos(lambda_n y) exp(-lambda_n x) = Re w^(2n-1), so
    P0(x, y) = (8 rho a0 H / pi^2) Re Ti2(w),   Ti2(w) = sum_m (-1)^m w^(2m+1) / (2m+1)^2
             = (Li2(i w) - Li2(-i w)) / (2 i)  (the inverse tangent integral),
    P0_x = -(4 rho a0 / pi) Re atan(w),   P0_y = (4 rho a0 / pi) Im atan(w).
At the heel (x = y = 0, w = 1) Ti2(1) is Catalan's constant G, so
P0 = (8 G / pi^2) rho a0 H = 0.742454 rho a0 H (Westergaard's and Chopra's
0.743); F0 = (16 / pi^3)(7/8) zeta(3) rho a0 H^2 = 0.542784 rho a0 H^2
(Westergaard's parabola: 7/12 = 0.5833). On the face, 0 < y < H, Re atan(w)
= pi/4 exactly: the closed form meets the face condition exactly.

Evaluation. The series' terms fall as 1/n^2 at the face (its x-derivative's
only as 1/n: the cosine series of a constant). The functions here sum
P = P0 (closed form) + sum_n [term_n - term_n at k = 0, rigid, infinite],
whose differences fall as 1/n^4 (a, b) or 1/n^3 (c, the absorbing bottom's
modes tending to the rigid ones): n_modes = 400 leaves errors growing
like (omega H / c)^2 / N^3, below 1e-9 rho a0 H for (a) and (b) up to
omega = 5.5 pi c / 2H, and of 1e-7 to 1.5e-6 rho a0 H for (c)
(largest at the heel, falling as 1/N^2). The x-derivative converges as
fast away from the bottom; at the heel corner itself, for alpha < 1, its
series converges only as 1/N (the constant face load does not meet the
bottom's Robin condition). `pressure_series` is the plain truncated
series, for checking all this.

(b) Truncated at x = L with the dashpot. Per vertical mode the
x-dependence X'' = kappa^2 X, X'(0) = -rho a0 c_n, X'(L) + i k X(L) = 0 gives
    X(x) = rho a0 c_n [(kappa + i k) e^(-kappa x) + (kappa - i k) e^(-kappa (2L - x))]
           / (kappa [(kappa + i k) - (kappa - i k) e^(-2 kappa L)])
         = rho a0 c_n [cosh(kappa (L - x)) + i k sinh(kappa (L - x)) / kappa]
           / (kappa sinh(kappa L) + i k cosh(kappa L))
(the second form where |kappa| L is small: it is finite at the cut-off,
kappa = 0, where the truncated reservoir has no resonance). The dashpot is
exact only for a plane wave (lambda = 0); each mode reflects from it with
R = (kappa - i k) / (kappa + i k): |R| = 1 for an evanescent mode (whose
reflection decays as exp(-2 kappa L)), |R| = (|kappa| - k)/(|kappa| + k) < 1
for a propagating one. Below the first cut-off (omega < pi c / (2H)) (b)
tends to (a) as exp(-2 kappa_1 L); above it a propagating mode's
reflection does not decay with L and (b) stays different from (a). A
finite-element model of exactly this truncated reservoir (same face,
surface, bottom and dashpot) converges to (b). At omega = 0 the dashpot
is a rigid wall (P_x(L) = 0).

(c) Absorbing bottom (alpha < 1; alpha = 1 is rigid, alpha = 0 absorbs a
vertically incident wave, -1 < alpha <= 1). The vertical modes
Y_n(y) = sin(lambda_n (H - y)) vanish at the surface; the bottom condition
-lambda cos(lambda H) = i omega q sin(lambda H), i.e. with theta = lambda H,
sigma = omega q H:
    theta cos(theta) + i sigma sin(theta) = 0
    <=> exp(2 i theta) = (sigma - theta) / (sigma + theta)
(Fenves & Chopra's characteristic equation). Its roots are complex, with
Im theta > 0 where Re theta > 0 (|exp(2 i theta)| < 1), in +- pairs; theta = 0
is trivial (Y = 0). There is no double root for real sigma >= 0 (a double
root would need theta^2 = sigma^2 - i sigma, Im theta < 0). The n-th root
stays in the strip (n - 1/2) pi < Re theta < n pi for every sigma > 0
(moving from (n - 1/2) pi at sigma = 0 toward n pi as sigma -> inf, e.g. the
first from pi/2 to pi; for (n - 1/2) pi >> sigma it is about
(n - 1/2) pi + i sigma / ((n - 1/2) pi)): it is found by Newton's method on
the equation's logarithm in that strip (characteristic_roots), which
neither loses nor merges roots.
The modes are not orthogonal in the Hermitian sense but in the bilinear
one, int_0^H Y_m Y_n dy = 0 for m != n (Green's identity; the Robin
coefficient i omega q is the same for all modes), so
    1 = sum_n c_n Y_n(y),  c_n = int Y_n / int Y_n^2
      = [(1 - cos theta_n) / lambda_n] / [H/2 - sin(2 theta_n) / (4 lambda_n)],
and (a), (b) hold with these Y_n, c_n and kappa_n = sqrt(lambda_n^2 - k^2)
on the principal branch (Re kappa > 0, and Im kappa > 0: decaying and
outgoing). The rigid case is c_n Y_n = 4 (-1)^(n+1)/((2n-1) pi) cos(lambda_n y)
as above. Horizontal ground motion only (Fenves & Chopra also treat the
vertical).

Functions (x, y broadcast; complex amplitudes per unit a0 unless a0 given):
pressure_infinite(x, y, H, rho, c, omega, a0, alpha=1, n_modes=400, derivative=None)
    (a), and (c) with alpha < 1; derivative "x" or "y" for the gradient;
pressure_truncated(x, y, H, L, rho, c, omega, a0, alpha=1, ...)  (b), (b)+(c);
force_infinite(H, rho, c, omega, a0, alpha=1), force_truncated(H, L, ...):
    int_0^H P(0, y) dy;
pressure_incompressible(x, y, H, rho, a0, derivative=None): the closed form;
pressure_series(x, y, H, rho, c, omega, a0, n_terms): the plain series (a);
westergaard_parabola(y, H, rho, a0); cutoff_frequencies(H, c, n);
bottom_q(alpha, c); characteristic_roots(sigma, n); vertical_modes(...);
horizontal_wavenumbers(lam, omega, c); HEEL_COEFFICIENT = 8 G / pi^2,
FORCE_COEFFICIENT = 14 zeta(3) / pi^3.
"""

import math

import numpy as np
from scipy.special import spence

CATALAN = 0.915965594177219015054603514932384110774
# the incompressible pressure at the heel, P0(0, 0) / (rho a0 H) = 8 G / pi^2
HEEL_COEFFICIENT = 8.0 * CATALAN / math.pi ** 2
ZETA3 = 1.202056903159594285399738161511449990765
# the incompressible resultant on the face, F0 / (rho a0 H^2) = 14 zeta(3) / pi^3
FORCE_COEFFICIENT = 14.0 * ZETA3 / math.pi ** 3


def _li2(z):
    """The dilogarithm Li2(z) = sum z^k / k^2 (scipy's spence(1 - z))."""
    return spence(1.0 - z)


def _w(x, y, H):
    return np.exp(-math.pi * (np.asarray(x, float) + 1j * np.asarray(y, float)) / (2.0 * H))


def pressure_incompressible(x, y, H, rho, a0=1.0, derivative=None):
    """Closed form of (a) at omega = 0 (Westergaard's incompressible
    reservoir): P0 = (8 rho a0 H / pi^2) Re Ti2(w), w = exp(-pi (x + i y) / 2H).
    derivative None -> P0; "x" -> dP0/dx; "y" -> dP0/dy. x, y broadcast;
    real values (times a0)."""
    w = _w(x, y, H)
    if derivative is None:
        ti2 = (_li2(1j * w) - _li2(-1j * w)) / 2j
        return 8.0 * rho * H / math.pi ** 2 * ti2.real * a0
    if derivative == "x":
        return -4.0 * rho / math.pi * np.arctan(w).real * a0
    if derivative == "y":
        return 4.0 * rho / math.pi * np.arctan(w).imag * a0
    raise ValueError(f"derivative must be None, 'x' or 'y', not {derivative!r}")


def westergaard_parabola(y, H, rho, a0=1.0):
    """Westergaard's (1933) approximation (7/8) rho a0 sqrt(H (H - y)),
    y the height above the bottom (H - y the depth below the surface)."""
    depth = np.clip(H - np.asarray(y, float), 0.0, None)
    return 0.875 * rho * a0 * np.sqrt(H * depth)


def cutoff_frequencies(H, c, n_modes=3):
    """The rigid-bottom reservoir's cut-off (resonance) circular frequencies
    omega_n = (2n - 1) pi c / (2H), n = 1..n_modes [rad/s]."""
    n = np.arange(1, n_modes + 1)
    return (2 * n - 1) * math.pi * c / (2.0 * H)


def bottom_q(alpha, c):
    """Fenves & Chopra's admittance q = (1 - alpha) / ((1 + alpha) c) [s/m]."""
    if not -1.0 < alpha <= 1.0:
        raise ValueError(f"alpha must be in (-1, 1], not {alpha}")
    return (1.0 - alpha) / ((1.0 + alpha) * c)


def characteristic_roots(sigma, n_modes, iterations=100):
    """The first n_modes roots theta_n (Re > 0, ascending) of
    theta cos(theta) + i sigma sin(theta) = 0, sigma = omega q H >= 0.

    With theta = (n - 1/2) pi + delta the equation is
    exp(2 i delta) = (theta - sigma) / (theta + sigma), whose right side has
    Im > 0 when Im theta > 0 (sigma > 0): with the principal logarithm,
        F_n(theta) = theta - (n - 1/2) pi - Log((theta - sigma) / (theta + sigma)) / (2 i) = 0
    labels the n-th root, 0 < Re delta < pi/2, Im delta > 0. No root crosses
    the strip's sides as sigma grows from 0 (that needs a real theta), so
    the strip (n - 1/2) pi < Re theta < n pi holds exactly one root, the
    n-th: Newton on F_n (kept in its strip), vectorised over n. Raises if
    it does not converge."""
    n = np.arange(1, n_modes + 1)
    base = (n - 0.5) * math.pi
    if sigma < 0.0:
        raise ValueError("sigma must be >= 0")
    if sigma == 0.0:
        return base.astype(complex)

    def F(theta):
        return theta - base - np.log((theta - sigma) / (theta + sigma)) / 2j

    theta = base + 0.5j
    theta = base + np.log((theta - sigma) / (theta + sigma)) / 2j
    for _ in range(iterations):
        step = F(theta) / (1.0 + 1j * sigma / (theta * theta - sigma * sigma))
        theta = theta - step
        theta = (np.clip(theta.real, base, base + 0.5 * math.pi)
                 + 1j * np.maximum(theta.imag, 1e-300))
        if np.all(np.abs(step) <= 1e-14 * np.abs(theta)):
            break
    scale = (np.abs(theta) + sigma) * np.cosh(theta.imag)
    residual = np.abs(theta * np.cos(theta) + 1j * sigma * np.sin(theta))
    if not (np.all(np.abs(F(theta)) <= 1e-10 * np.abs(theta))
            and np.all(residual <= 1e-10 * scale)):
        raise ArithmeticError("characteristic_roots: Newton did not converge")
    return theta


def vertical_modes(H, n_modes, omega=0.0, c=1.0, alpha=1.0):
    """The vertical eigenvalues lambda_n ([1/m]; real for the rigid bottom,
    alpha = 1 or omega = 0, complex otherwise) and a function
    shape(y) -> (n_modes, ...) giving c_n Y_n(y) (the face's unit load's
    expansion: sum_n c_n Y_n(y) = 1 on 0 <= y < H) and, with derivative=True,
    c_n Y_n'(y)."""
    q = bottom_q(alpha, c)
    theta = characteristic_roots(omega * q * H, n_modes)
    if np.all(theta.imag == 0.0):
        theta = theta.real                        # the rigid bottom: real arithmetic
    lam = theta / H
    coef = ((1.0 - np.cos(theta)) / lam) / (H / 2.0 - np.sin(2.0 * theta) / (4.0 * lam))

    def shape(y, derivative=False):
        y = np.asarray(y, float)[None, ...]
        lam_, coef_ = (v.reshape((-1,) + (1,) * (y.ndim - 1)) for v in (lam, coef))
        if derivative:
            return -coef_ * lam_ * np.cos(lam_ * (H - y))
        return coef_ * np.sin(lam_ * (H - y))
    return lam, shape


def horizontal_wavenumbers(lam, omega, c):
    """kappa_n = sqrt(lambda_n^2 - (omega/c)^2), Re >= 0, and +i times the
    root above a rigid bottom's cut-off (the outgoing wave for exp(i omega t))."""
    k = omega / c
    arg = np.asarray(lam, complex) ** 2 - k * k
    arg = np.where(arg.imag == 0.0, arg.real + 0j, arg)   # -a + 0j -> +i sqrt(a)
    return np.sqrt(arg)


def _x_factor(x, kappa, k, L, derivative):
    """X(x) / (rho a0 c_n): the mode's x-dependence with X'(0) = -1, for
    L = inf (decaying/outgoing) or the dashpot at L."""
    x = np.asarray(x, float)[None, ...]
    kap = kappa.reshape((-1,) + (1,) * (x.ndim - 1))
    if L is None or math.isinf(L):
        if np.any(np.abs(kappa) <= 1e-9 * max(k, 1e-300)):
            raise ZeroDivisionError("omega is a cut-off frequency (to 1e-9): the "
                                    "infinite reservoir's response is unbounded there")
        e = np.exp(-kap * x)
        return -e if derivative == "x" else e / kap
    if np.any(x > L * (1 + 1e-12)):
        raise ValueError("x beyond the truncation L")
    small = (kap.real * L < 20.0) & (np.abs(kap) * L < 20.0)
    # exponential form (no overflow, Re kappa L large)
    with np.errstate(all="ignore"):
        e1, e2, e3 = np.exp(-kap * x), np.exp(-kap * (2 * L - x)), np.exp(-2 * kap * L)
        den = kap * ((kap + 1j * k) - (kap - 1j * k) * e3)
        if derivative == "x":
            big_val = kap * (-(kap + 1j * k) * e1 + (kap - 1j * k) * e2) / den
        else:
            big_val = ((kap + 1j * k) * e1 + (kap - 1j * k) * e2) / den
        # hyperbolic form (finite at kappa = 0)
        s = L - x
        ch, sh = np.cosh(kap * s), np.sinh(kap * s)
        nz = kap != 0
        safe = np.where(nz, kap, 1.0)
        sh_over = np.where(nz, sh / safe, s)                  # sinh(kappa s)/kappa
        den2 = kap * np.sinh(kap * L) + 1j * k * np.cosh(kap * L)
        if derivative == "x":
            small_val = -(kap * sh + 1j * k * ch) / den2
        else:
            small_val = (ch + 1j * k * sh_over) / den2
    return np.where(small, small_val, big_val)


def _field(x, y, H, rho, c, omega, a0, alpha, L, n_modes, derivative):
    if derivative not in (None, "x", "y"):
        raise ValueError(f"derivative must be None, 'x' or 'y', not {derivative!r}")
    if omega < 0.0:
        raise ValueError("omega must be >= 0")
    k = omega / c
    lam, shape = vertical_modes(H, n_modes, omega, c, alpha)
    kappa = horizontal_wavenumbers(lam, omega, c)
    x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
    if derivative == "y":
        Y = shape(y, derivative=True)
        X = _x_factor(x, kappa, k, L, None)
    else:
        Y = shape(y)
        X = _x_factor(x, kappa, k, L, derivative)
    # minus the same modes of the rigid, incompressible, infinite reservoir,
    # plus that reservoir's closed form (the subtracted terms' sum)
    lam0, shape0 = vertical_modes(H, n_modes)
    X0 = _x_factor(x, lam0.astype(complex), 0.0, None, "x" if derivative == "x" else None)
    if alpha == 1.0:                              # the same vertical modes
        total = np.sum(Y * (X - X0), axis=0)
    else:
        Y0 = shape0(y, derivative=(derivative == "y"))
        total = np.sum(Y * X - Y0 * X0, axis=0)
    return a0 * (rho * total + pressure_incompressible(x, y, H, rho, 1.0, derivative))


def pressure_infinite(x, y, H, rho, c, omega, a0=1.0, alpha=1.0, n_modes=400,
                      derivative=None):
    """(a) Chopra's infinite reservoir (rigid bottom, alpha = 1) or (c) with
    Fenves & Chopra's absorbing bottom (alpha < 1): the complex amplitude of
    p at (x, y) (broadcast), x >= 0 the distance from the face into the
    water, y the height above the bottom; derivative "x" / "y" for dP/dx,
    dP/dy. omega [rad/s], c [m/s], a0 the ground acceleration toward the
    water [m/s^2]."""
    return _field(x, y, H, rho, c, omega, a0, alpha, None, n_modes, derivative)


def pressure_truncated(x, y, H, L, rho, c, omega, a0=1.0, alpha=1.0, n_modes=400,
                       derivative=None):
    """(b) the reservoir truncated at x = L by the plane-wave dashpot
    dp/dx = -(1/c) dp/dt (and (c)'s bottom with alpha < 1); as
    pressure_infinite, 0 <= x <= L."""
    return _field(x, y, H, rho, c, omega, a0, alpha, float(L), n_modes, derivative)


def force_infinite(H, rho, c, omega, a0=1.0, alpha=1.0, n_modes=4000):
    """The resultant int_0^H P(0, y) dy per unit width on the face (pushing
    the dam away from the water, -x), complex amplitude [N/m]."""
    return _force(H, rho, c, omega, a0, alpha, None, n_modes)


def force_truncated(H, L, rho, c, omega, a0=1.0, alpha=1.0, n_modes=4000):
    """As force_infinite for the truncated reservoir (b)."""
    return _force(H, rho, c, omega, a0, alpha, float(L), n_modes)


def _force(H, rho, c, omega, a0, alpha, L, n_modes):
    k = omega / c
    lam, _ = vertical_modes(H, n_modes, omega, c, alpha)
    kappa = horizontal_wavenumbers(lam, omega, c)
    theta = lam * H
    c_n = ((1.0 - np.cos(theta)) / lam) / (H / 2.0 - np.sin(2.0 * theta) / (4.0 * lam))
    integral_Y = (1.0 - np.cos(theta)) / lam                          # int_0^H Y_n dy
    X = _x_factor(np.zeros(1), kappa, k, L, None)[:, 0]
    lam0 = (np.arange(1, n_modes + 1) - 0.5) * math.pi / H
    rigid0 = (4.0 / ((2 * np.arange(1, n_modes + 1) - 1) * math.pi)) / lam0 ** 2
    series = np.sum(c_n * integral_Y * X - rigid0)
    return a0 * rho * (series + FORCE_COEFFICIENT * H * H)


def pressure_series(x, y, H, rho, c, omega, a0=1.0, n_terms=1000, derivative=None):
    """Chopra's series (a), rigid bottom, infinite reservoir, summed plainly
    to n_terms (no acceleration): for checking. derivative "x" sums
    -rho a0 c_n cos(lambda_n y) exp(-kappa_n x) (the face's cosine series)."""
    n = np.arange(1, n_terms + 1)
    lam = (2 * n - 1) * math.pi / (2.0 * H)
    kappa = horizontal_wavenumbers(lam, omega, c)
    c_n = 4.0 * (-1.0) ** (n + 1) / ((2 * n - 1) * math.pi)
    x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
    sh = (-1,) + (1,) * x.ndim
    cy = np.cos(lam.reshape(sh) * y[None])
    ex = np.exp(-kappa.reshape(sh) * x[None])
    if derivative == "x":
        terms = -c_n.reshape(sh) * cy * ex
    else:
        terms = c_n.reshape(sh) * cy * ex / kappa.reshape(sh)
    return rho * a0 * np.sum(terms, axis=0)
