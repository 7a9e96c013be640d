"""Lamb's problem in plane strain: the surface motion of an elastic
half-space under a vertical line load on its surface, by two independent
methods. numpy and scipy only; it imports nothing of vstpetsc (written from
the physics, to check a 2-D plane-strain space-time FEM run against).

The problem. A homogeneous isotropic linear elastic half-space y <= 0
(x along the surface, y up), density rho, P and S speeds vp, vs,
mu = rho vs^2, lambda = rho vp^2 - 2 mu; plane strain, per unit thickness,
at rest for t <= 0. On the free surface y = 0 a vertical line load of F(t)
per unit length acts along x = 0.

Sign convention (no parameter): F > 0 is a DOWNWARD force (along -y): it
pushes the surface into the half-space. In stresses, sigma_yy(x, 0, t) =
-F(t) delta(x) and sigma_xy(x, 0, t) = 0. The outputs are the surface
displacement (u_x, u_y) and velocity (v_x, v_y) at receivers x > 0, u_x > 0
along +x (away from the load), u_y > 0 UP: a slowly applied F > 0 moves
the surface down (u_y < 0) and towards the load (u_x < 0). F is smooth
with F(t) = 0 for t <= 0: a :class:`Pulse` (ricker_pulse, sin2_pulse,
sine_power_pulse, smooth_ramp), a bare callable or samples (as_pulse).
By symmetry u_x(-x) = -u_x(x) and u_y(-x) = u_y(x).

Method (a), closed form (surface_displacement, surface_velocity). Lamb
(1904) solved the problem; in the Cagniard-de Hoop form (de Hoop 1960;
Achenbach 1973 ch. 7; Miklowitz 1978) the surface displacement for an
impulsive load F = delta(t) is explicit. Laplace transform in t (real s),
Fourier in x with k = s kappa; for x > 0 the kappa path folds round the
branch cut on the positive imaginary axis, kappa = i p, and on the surface
the exponent is exp(-s p x), so p = t / x: the Laplace integral is read off
directly. With a = sqrt(1/vp^2 - p^2), b = sqrt(1/vs^2 - p^2) (each
+i sqrt(p^2 - 1/v^2) beyond its branch point: the side p - i0 of the cut),
q = 1/vs^2 - 2 p^2 and the Rayleigh denominator D = q^2 + 4 p^2 a b,
    G_x(x, t) = Im[-p (q - 2 a b) / D] / (pi mu x) + C_x delta(t - x/c_R),
    G_y(x, t) = Im[a / D] / (pi mu vs^2 x)             (both 0 for t < x/vp).
G_x's regular part lives between the P and S arrivals only. The Rayleigh
zero of D at p_R = 1/c_R lies on the cut: it gives G_x the delta (the two
sides' poles differ by 2 pi i delta) and G_y a principal-value pole
C_y / (t - x/c_R). With A = sqrt(p^2 - 1/vp^2), B = sqrt(p^2 - 1/vs^2),
D = q^2 - 4 p^2 A B (real) beyond 1/vs, and
    C_x = -p_R (q_R + 2 A_R B_R) / (mu D'(p_R)),
    C_y = A_R / (pi mu vs^2 D'(p_R)).
Near p_R, D is evaluated factored, (p - p_R)(p + p_R) Q(p^2) / (q^2 +
4 p^2 A B), Q the rationalised Rayleigh cubic with its root divided out,
so that G_y carries no cancellation next to its pole. The motion is
u = G * F and v = G * F' (F(0) = 0). Each convolution is a Gauss-Legendre
quadrature over the time since the load began, split at the load's end and
at the S and Rayleigh arrivals, with a cosine map on each piece (nodes
crowd both ends, so the square-root fronts at P and S integrate
spectrally); the Rayleigh pole is taken analytically, subtracting
C_y h(s_R) / (t - s - x/c_R) (h = F or F', s_R = t - x/c_R) and adding
back its principal value C_y h(s_R) ln((t - x/c_R) / (x/c_R - x/vp));
the delta adds C_x h(t - x/c_R). The motion is exactly zero before x/vp.

Method (b), wavenumber-frequency integration
(surface_displacement_wavenumber, surface_velocity_wavenumber), shares
none of (a)'s contour work. Laplace transform in t at complex s = eps + i w,
Fourier in x (u~(k) = int u e^{-ikx} dx); u = grad phi + curl(psi e_z),
phi = A e^{g_a y}, psi = B e^{g_b y}, g_a = sqrt(k^2 + s^2/vp^2),
g_b = sqrt(k^2 + s^2/vs^2) (Re > 0: decaying downwards); the two traction
conditions give
    u~_y = -F^(s) g_a s^2 / (vs^2 mu R),
    u~_x = -F^(s) i k (2 k^2 + s^2/vs^2 - 2 g_a g_b) / (mu R),
    R = (2 k^2 + s^2/vs^2)^2 - 4 k^2 g_a g_b,
R being the Rayleigh determinant (Achenbach 1973 ch. 5; Graff 1975 ch. 6).
eps > 0 keeps the Rayleigh pole off the real k and w axes.
  - The k integral is the discrete wavenumber sum (Bouchon & Aki 1977):
    Delta k = 2 pi / L is exact for a row of sources L apart, and
    L = 1.1 (max x + vp max t) keeps every image out of the time window.
    A smooth taper erfc((k - k_c) / delta) / 2 ends the sum: it is 1 (to
    1e-17) where the waves live, |k| < 2 |s| / c_R, and its own error,
    about exp(-(x delta)^2 / 4), is nil for delta >= 12 / min x.
  - The w integral is the trapezoid sum of period T = 6 max t, which
    aliases exp(-eps T) = 1e-12 of the later response into the window:
    eps = 12 ln 10 / T; exp(eps t) <= 1e2 undoes eps at the window's end.
  - F^(s) is a Gauss-Legendre quadrature of F e^{-st}, cut where |s F^|
    falls below 1e-11 of its peak, or at 40 cycles per load duration.
  It needs a load whose spectrum decays fast (a Ricker; a sin^n pulse
  with n >= 4 at some cost; sin^2's kinked F' converges slowly here).

Rayleigh speed (rayleigh_speed): the root c_R in (0, vs) of
(2 - c^2/vs^2)^2 = 4 sqrt(1 - c^2/vp^2) sqrt(1 - c^2/vs^2) (Rayleigh 1885).
The far field (rayleigh_wave_displacement, rayleigh_wave_velocity): the
pole terms alone, u_x = C_x F(t - x/c_R), u_y = pi C_y Hilbert[F](t - x/c_R)
(Hilbert[F](t) = PV int F(s) / (t - s) ds / pi), a non-dispersive pulse
that does not decay with distance (a line load's Rayleigh wave is not
spread geometrically), while the surface P and S motion falls like 1/x.
Static limit (Flamant 1892; Johnson 1985 "Contact mechanics" ch. 2): F
held at F0, u_x -> -(1 - 2 nu) F0 / (4 mu), exactly once the Rayleigh wave
and the ramp have passed (G_x is zero after its delta), and u_y(x1) -
u_y(x2) -> (1 - nu) F0 ln(x1 / x2) / (pi mu); u_y itself sinks like ln t
(the 2-D static displacement exists only up to a constant).

Accuracy (tests/test_reference_lamb.py): for a Ricker pulse at 2.7 to 10.7
Rayleigh wavelengths, (a) and (b) agree to 3e-12 of the peak velocity and
1.2e-12 of the peak displacement; also at 0.05 wavelength (5e-12). (a)
has converged by 64 nodes per piece (2e-14 against 128).

References.
  Lord Rayleigh (1885) On waves propagated along the plane surface of an
    elastic solid. Proc. London Math. Soc. 17, 4-11.
  A. Flamant (1892) Sur la repartition des pressions dans un solide
    rectangulaire charge transversalement. C. R. Acad. Sci. Paris 114, 1465.
  H. Lamb (1904) On the propagation of tremors over the surface of an
    elastic solid. Phil. Trans. R. Soc. A 203, 1-42.
  A. T. de Hoop (1960) A modification of Cagniard's method for solving
    seismic pulse problems. Appl. Sci. Res. B 8, 349-356.
  I. A. Viktorov (1967) Rayleigh and Lamb waves, Plenum.
  J. D. Achenbach (1973) Wave propagation in elastic solids, North-Holland.
  K. F. Graff (1975) Wave motion in elastic solids, Ohio State Univ. Press.
  M. Bouchon & K. Aki (1977) Discrete wave-number representation of
    seismic-source wave fields. Bull. Seism. Soc. Am. 67, 259-277.
  J. Miklowitz (1978) The theory of elastic waves and waveguides,
    North-Holland.
  K. L. Johnson (1985) Contact mechanics, Cambridge Univ. Press.
"""

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, special
from scipy.interpolate import CubicSpline


# ---------------------------------------------------------------- the medium

def rayleigh_function(c, vp, vs):
    """(2 - c^2/vs^2)^2 - 4 sqrt(1 - c^2/vp^2) sqrt(1 - c^2/vs^2), zero at
    c = c_R; real for 0 <= c <= vs."""
    xi2 = (np.asarray(c, dtype=float) / vs) ** 2
    r = (vs / vp) ** 2
    return (2.0 - xi2) ** 2 - 4.0 * np.sqrt(1.0 - r * xi2) * np.sqrt(1.0 - xi2)


def rayleigh_speed(vp, vs):
    """The Rayleigh wave speed c_R (0 < c_R < vs) for P and S speeds vp, vs."""
    if not 0.0 < vs < vp:
        raise ValueError("need 0 < vs < vp")

    # The function vanishes like -2 (1 - vs^2/vp^2) xi^2 at xi = c/vs = 0 as
    # well: divide that trivial root out so that the bracket is clean.
    def reduced(xi):
        return rayleigh_function(xi * vs, vp, vs) / xi ** 2

    xi = optimize.brentq(reduced, 1.0e-3, 1.0, xtol=1.0e-16, rtol=4.0 * np.finfo(float).eps)
    return xi * vs


@dataclass(frozen=True)
class HalfSpace:
    """The medium: density and wave speeds, and the derived constants."""
    rho: float
    vp: float
    vs: float

    @property
    def mu(self):
        return self.rho * self.vs ** 2

    @property
    def lam(self):
        return self.rho * self.vp ** 2 - 2.0 * self.mu

    @property
    def poisson(self):
        return self.lam / (2.0 * (self.lam + self.mu))

    @functools.cached_property
    def cr(self):
        return rayleigh_speed(self.vp, self.vs)


# ---------------------------------------------------------------- load histories

class Pulse:
    """A load history F(t) per unit length (> 0 pushes down): zero for
    t <= 0, varying on [0, duration] only, ``final_value`` after it (0 for
    a pulse, the plateau of a ramp). ``value(t)`` and ``rate(t)`` (F') are
    vectorised functions used on 0 < t < duration only."""

    def __init__(self, value, rate, duration, final_value=0.0):
        self._value, self._rate = value, rate
        self.duration, self.final_value = float(duration), float(final_value)

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        inside = (t > 0.0) & (t < self.duration)
        out = np.where(t >= self.duration, self.final_value, 0.0)
        out[inside] = self._value(t[inside])
        return out

    def rate(self, t):
        """F'(t): zero outside (0, duration)."""
        t = np.asarray(t, dtype=float)
        inside = (t > 0.0) & (t < self.duration)
        out = np.zeros(t.shape)
        out[inside] = self._rate(t[inside])
        return out


def ricker_pulse(peak_frequency, amplitude=1.0, delay=None):
    """Ricker wavelet amplitude (1 - 2a) exp(-a), a = (pi f (t - delay))^2,
    delay 1.8 / f by default (then |F| < 1e-12 amplitude at t = 0 and at
    t = 2 delay, where it is cut off); zero net impulse."""
    f = float(peak_frequency)
    delay = 1.8 / f if delay is None else float(delay)

    def value(t):
        a = (math.pi * f * (t - delay)) ** 2
        return amplitude * (1.0 - 2.0 * a) * np.exp(-a)

    def rate(t):
        a = (math.pi * f * (t - delay)) ** 2
        da = 2.0 * (math.pi * f) ** 2 * (t - delay)
        return amplitude * (2.0 * a - 3.0) * da * np.exp(-a)

    return Pulse(value, rate, 2.0 * delay)


def sine_power_pulse(duration, power=2, amplitude=1.0):
    """amplitude sin^power(pi t / duration) on [0, duration]: power 2 is the
    usual sin^2 pulse (F' has kinks at both ends), higher powers are smoother."""
    w = math.pi / duration

    def value(t):
        return amplitude * np.sin(w * t) ** power

    def rate(t):
        return amplitude * power * w * np.sin(w * t) ** (power - 1) * np.cos(w * t)

    return Pulse(value, rate, duration)


def sin2_pulse(duration, amplitude=1.0):
    """amplitude sin^2(pi t / duration) on [0, duration]."""
    return sine_power_pulse(duration, 2, amplitude)


def smooth_ramp(rise_time, amplitude=1.0):
    """0 -> amplitude over rise_time with a sin^2 rate (F' = 2 amplitude
    sin^2(pi t / rise_time) / rise_time), held after it (for static limits)."""
    T = float(rise_time)

    def value(t):
        return amplitude * (t / T - np.sin(2.0 * math.pi * t / T) / (2.0 * math.pi))

    def rate(t):
        return amplitude * 2.0 * np.sin(math.pi * t / T) ** 2 / T

    return Pulse(value, rate, T, final_value=amplitude)


def sampled_pulse(times, values):
    """A history from samples (times from 0 up, values[0] = 0): a cubic
    spline, zero before times[0] = 0 and held at values[-1] after the last."""
    times, values = np.asarray(times, dtype=float), np.asarray(values, dtype=float)
    spline = CubicSpline(times, values)
    return Pulse(spline, spline.derivative(), times[-1], final_value=values[-1])


def _fourth_order_rate(force, h):
    """F' by a fourth-order central difference of step h (for a bare callable)."""
    def rate(t):
        return (8.0 * (force(t + h) - force(t - h)) - (force(t + 2 * h) - force(t - 2 * h))) \
            / (12.0 * h)
    return rate


def _support_end(force, t_max, samples=4001):
    """Where a bare callable's F stops changing within [0, t_max] (sampled)."""
    grid = np.linspace(0.0, t_max, samples)
    f = np.asarray(force(grid), dtype=float)
    moving = np.abs(np.diff(f)) > 1.0e-13 * max(np.abs(f).max(), 1e-300)
    if not moving.any():
        return t_max, float(f[-1])
    last = min(np.nonzero(moving)[0][-1] + 2, samples - 1)
    return grid[last], float(f[last])


def as_pulse(force, t_max=None, duration=None):
    """A :class:`Pulse` from a Pulse, a pair (times, values) of samples or a
    bare callable F(t) (F = 0 for t <= 0). For a callable, F' is a fourth
    order difference and ``duration`` (where F stops changing) is found by
    sampling [0, t_max] unless given."""
    if isinstance(force, Pulse):
        return force
    if isinstance(force, tuple) and len(force) == 2:
        return sampled_pulse(*force)
    if not callable(force):
        raise TypeError("force must be a Pulse, a callable F(t) or (times, values)")
    if duration is None:
        duration, final = _support_end(force, float(t_max))
    else:
        final = float(np.asarray(force(np.array([duration]))).ravel()[0])
    def value(t):
        return np.asarray(force(t), dtype=float)
    return Pulse(value, _fourth_order_rate(value, 1.0e-4 * duration), duration, final)


# ---------------------------------------------------------------- (a) Cagniard-de Hoop

def _edge_radicals(p, medium):
    """a, b on the side p - i0 of their cuts: sqrt(1/v^2 - p^2), +i sqrt(p^2 - 1/v^2)
    beyond the branch point (numpy's sqrt of a negative real + 0j)."""
    p2 = np.asarray(p, dtype=float) ** 2
    a = np.sqrt((1.0 / medium.vp ** 2 - p2) + 0j)
    b = np.sqrt((1.0 / medium.vs ** 2 - p2) + 0j)
    return a, b


def _rayleigh_quadratic(medium):
    """Q(P), P = p^2, with (P - p_R^2) Q(P) = q^4 - 16 P^2 (P - 1/vp^2)(P - 1/vs^2),
    the Rayleigh determinant rationalised (a cubic in P) with its root divided
    out, so that D = q^2 - 4 p^2 A B = (p - p_R)(p + p_R) Q / (q^2 + 4 p^2 A B)
    beyond 1/vs carries no cancellation near the pole."""
    sa, sb = 1.0 / medium.vp ** 2, 1.0 / medium.vs ** 2
    cubic = [-16.0 * (sb - sa), 8.0 * sb * (3.0 * sb - 2.0 * sa), -8.0 * sb ** 3, sb ** 4]
    root = 1.0 / medium.cr ** 2
    c2 = cubic[0]                                           # synthetic division
    c1 = cubic[1] + c2 * root
    c0 = cubic[2] + c1 * root
    return lambda big_p: (c2 * big_p + c1) * big_p + c0


def _green_regular(lag, x, medium):
    """The regular parts of the impulse responses G_x, G_y at the time lag
    (p = lag / x), times pi x (see the module docstring): zero for p < 1/vp,
    G_x's also beyond 1/vs (where only its delta remains). Beyond 1/vs,
    G_y = A / D is written with D factored at the pole, p - p_R taken as
    (lag - x/c_R) / x."""
    p = lag / x
    a, b = _edge_radicals(p, medium)
    q = 1.0 / medium.vs ** 2 - 2.0 * p ** 2
    rayleigh = q ** 2 + 4.0 * p ** 2 * a * b
    horizontal = np.imag(-p * (q - 2.0 * a * b) / rayleigh) / medium.mu
    vertical = np.imag(a / rayleigh)
    beyond = p > 1.0 / medium.vs
    pb, qb, big_a, big_b = p[beyond], q[beyond], a[beyond].imag, b[beyond].imag
    p_r = 1.0 / medium.cr
    to_pole = (lag[beyond] - x / medium.cr) / x                 # as in the pole subtraction
    vertical[beyond] = big_a * (qb ** 2 + 4.0 * pb ** 2 * big_a * big_b) \
        / (to_pole * (pb + p_r) * _rayleigh_quadratic(medium)(pb ** 2))
    return horizontal, vertical / (medium.mu * medium.vs ** 2)


def rayleigh_pole_amplitudes(rho, vp, vs):
    """(C_x, C_y): the Rayleigh pole's parts of the impulse response,
    C_x delta(t - x/c_R) and C_y / (t - x/c_R) (per unit impulse)."""
    m = HalfSpace(rho, vp, vs)
    p = 1.0 / m.cr
    big_a, big_b = math.sqrt(p * p - 1.0 / vp ** 2), math.sqrt(p * p - 1.0 / vs ** 2)
    q = 1.0 / vs ** 2 - 2.0 * p * p
    # D(p) = q^2 - 4 p^2 A B on the real axis beyond 1/vs; its slope at p_R:
    slope = 2.0 * p * _rayleigh_quadratic(m)(p * p) / (q * q + 4.0 * p * p * big_a * big_b)
    c_x = -p * (q + 2.0 * big_a * big_b) / (m.mu * slope)
    c_y = big_a / (math.pi * m.mu * vs ** 2 * slope)
    return c_x, c_y


def _cosine_gauss(nodes):
    """Gauss-Legendre on [0, 1] after s = (1 - cos(pi u)) / 2: nodes and
    weights that cluster at both ends, so sqrt(s) ends integrate spectrally."""
    u, w = np.polynomial.legendre.leggauss(nodes)
    theta = 0.5 * math.pi * (u + 1.0)
    return 0.5 * (1.0 - np.cos(theta)), 0.25 * math.pi * np.sin(theta) * w


def _segments(t, x, medium, duration):
    """Edges (len(t), 5) splitting s in [0, t - x/vp], the time since the
    load began, at the load's end and at the S and Rayleigh arrivals."""
    span = np.maximum(t - x / medium.vp, 0.0)[:, None]
    inner = np.stack([t - x / medium.vs, t - x / medium.cr, np.full_like(t, duration)], 1)
    inner = np.clip(inner, 0.0, span)
    return np.sort(np.concatenate([np.zeros_like(span), inner, span], 1), axis=1)


def _convolve_green(x, t, history, duration, medium, nodes):
    """u(t) = int_0^{t - x/vp} h(s) G(x, t - s) ds for one receiver x and a
    history h (F for displacement, F' for velocity); see the docstring."""
    c_x, c_y = rayleigh_pole_amplitudes(medium.rho, medium.vp, medium.vs)
    t_p, t_r = x / medium.vp, x / medium.cr
    edges = _segments(t, x, medium, duration)
    unit_s, unit_w = _cosine_gauss(nodes)
    lo, width = edges[:, :-1, None], np.diff(edges, axis=1)[:, :, None]
    s = lo + width * unit_s                                 # (times, 4, nodes)
    weight = width * unit_w
    lag = t[:, None, None] - s                              # x/vp < lag <= t
    # Empty (or rounding-thin) segments can put nodes on the pole itself:
    # drop them (their weight is zero or negligible) and move them off.
    weight = np.where(lag == t_r, 0.0, weight)
    lag = np.where(weight > 0.0, lag, t_p + 0.5 * (t_r - t_p))
    g_x, g_y = _green_regular(lag, x, medium)
    h = history(s)
    h_at_pole = history(t - t_r)                            # h(s_R), 0 before t_R
    # The pole's principal value: subtract C_y h(s_R) / (lag - t_R), add its integral.
    pole = c_y * h_at_pole[:, None, None] / (lag - t_r)
    u_x = np.sum(weight * h * g_x, axis=(1, 2)) / (math.pi * x) + c_x * h_at_pole
    u_y = np.sum(weight * (h * g_y / (math.pi * x) - pole), axis=(1, 2))
    after = h_at_pole != 0.0                                # then t > t_R
    u_y[after] += c_y * h_at_pole[after] * np.log((t[after] - t_r) / (t_r - t_p))
    return u_x, u_y


def _closed_form(x, t, force, rho, vp, vs, nodes, derivative):
    medium = HalfSpace(float(rho), float(vp), float(vs))
    x = np.atleast_1d(np.asarray(x, dtype=float))
    t = np.atleast_1d(np.asarray(t, dtype=float))
    if np.any(x <= 0.0):
        raise ValueError("receivers need x > 0")
    pulse = as_pulse(force, t_max=max(t.max(), 1e-300))
    history = pulse.rate if derivative else pulse
    out_x, out_y = np.zeros((x.size, t.size)), np.zeros((x.size, t.size))
    for i, xi in enumerate(x):
        out_x[i], out_y[i] = _convolve_green(xi, t, history, pulse.duration, medium, nodes)
    return out_x, out_y


def surface_displacement(x, t, force, rho, vp, vs, nodes=64):
    """Surface displacement (u_x, u_y), arrays (len(x), len(t)), at x > 0
    (u_x away from the load, u_y up) under the downward line load F(t) per
    unit length at x = 0, by the closed-form Green's function (method a)."""
    return _closed_form(x, t, force, rho, vp, vs, nodes, derivative=False)


def surface_velocity(x, t, force, rho, vp, vs, nodes=64):
    """Surface velocity (v_x, v_y), arrays (len(x), len(t)): as
    :func:`surface_displacement`, convolving G with F'."""
    return _closed_form(x, t, force, rho, vp, vs, nodes, derivative=True)


# ---------------------------------------------------------------- the Rayleigh pulse alone

def hilbert_transform(history, t, duration, nodes=256):
    """(1/pi) PV int_0^duration h(s) / (t - s) ds for a history vanishing
    outside [0, duration]: h(t) subtracted under the integral, its log added."""
    t = np.asarray(t, dtype=float)
    unit_s, unit_w = _cosine_gauss(nodes)
    s, w = duration * unit_s, duration * unit_w
    h_t = history(t)
    with np.errstate(divide="ignore", invalid="ignore"):
        quotient = (history(s)[None, :] - h_t[:, None]) / (t[:, None] - s[None, :])
        log_term = np.where(h_t != 0.0, h_t * np.log(np.abs(t / (t - duration))), 0.0)
    # A t on a node itself leaves 0/0 there: drop that node (weight ~ 1/nodes^2).
    return (np.nan_to_num(quotient) @ w + log_term) / math.pi


def _rayleigh_wave(x, t, force, rho, vp, vs, derivative):
    x = np.atleast_1d(np.asarray(x, dtype=float))
    t = np.atleast_1d(np.asarray(t, dtype=float))
    pulse = as_pulse(force, t_max=max(t.max(), 1e-300))
    if pulse.final_value != 0.0:
        raise ValueError("the Rayleigh pulse's Hilbert transform needs a pulse load")
    history = pulse.rate if derivative else pulse
    c_x, c_y = rayleigh_pole_amplitudes(rho, vp, vs)
    lag = t[None, :] - x[:, None] / rayleigh_speed(vp, vs)
    hilbert = hilbert_transform(history, lag.ravel(), pulse.duration).reshape(lag.shape)
    return c_x * history(lag), math.pi * c_y * hilbert


def rayleigh_wave_displacement(x, t, force, rho, vp, vs):
    """The Rayleigh pulse alone, (u_x, u_y) = (C_x F, pi C_y Hilbert[F]) at
    t - x/c_R: the far field of :func:`surface_displacement` (body waves
    fall like 1/x); F must be a pulse (zero after its duration)."""
    return _rayleigh_wave(x, t, force, rho, vp, vs, derivative=False)


def rayleigh_wave_velocity(x, t, force, rho, vp, vs):
    """The Rayleigh pulse's velocity, as :func:`rayleigh_wave_displacement` with F'."""
    return _rayleigh_wave(x, t, force, rho, vp, vs, derivative=True)


# ---------------------------------------------------------------- (b) wavenumber-frequency

def wavenumber_kernels(k, s, medium):
    """(U_x, U_y): the surface displacement's transforms per unit load
    transform, u~ = U F^(s), for wavenumber k and Laplace variable s
    (Re s > 0, or s = i w off the branch points)."""
    k2, sb2 = k * k, s * s / medium.vs ** 2
    g_a = np.sqrt(k2 + s * s / medium.vp ** 2)
    g_b = np.sqrt(k2 + sb2)
    rayleigh = (2.0 * k2 + sb2) ** 2 - 4.0 * k2 * g_a * g_b
    u_x = -1j * k * (2.0 * k2 + sb2 - 2.0 * g_a * g_b) / (medium.mu * rayleigh)
    u_y = -g_a * sb2 / (medium.mu * rayleigh)
    return u_x, u_y


def _real_product(table, vector):
    """real table @ complex vector as one real product (numpy would cast the
    table to complex): the vector's (re, im) pairs are a real (n, 2) array."""
    pairs = table @ np.ascontiguousarray(vector).view(float).reshape(-1, 2)
    return pairs[:, 0] + 1j * pairs[:, 1]


class _WavenumberSum:
    """(H_x, H_y)(x, s) = (1/2 pi) int U e^{ikx} dk for the receivers x, as
    the discrete sum over k_n = n dk (U_x odd and U_y even in k; the tables
    sin, cos(k_n x) are built once) ended by a smooth taper
    erfc((k - k_c) / delta) / 2: 1 to 1e-17 over |k| < 2 |s| / c_R, which
    holds the waves (branch points and the Rayleigh pole), and wide enough,
    delta >= 12 / min x, for its error, ~exp(-(x delta)^2 / 4), to vanish."""

    def __init__(self, x, medium, dk, s_max):
        self.x, self.medium, self.dk = x, medium, dk
        self.k = dk * np.arange(1, self._taper(s_max)[2] + 1)
        phase = np.outer(x, self.k)
        self.sin, self.cos = np.sin(phase), np.cos(phase)

    def _taper(self, s):
        flat = 2.0 * abs(s) / self.medium.cr
        delta = max(0.25 * flat, 12.0 / self.x.min())
        centre = flat + 6.0 * delta
        return centre, delta, int(math.ceil((centre + 6.5 * delta) / self.dk))

    def transfer(self, s):
        centre, delta, n = self._taper(s)
        k = self.k[:n]
        taper = 0.5 * special.erfc((k - centre) / delta)
        u_x, u_y = wavenumber_kernels(k, s, self.medium)
        m = self.medium
        u_y0 = -m.vs ** 2 / (m.mu * m.vp * s)                  # U_y(0, s)
        h_x = 2j * _real_product(self.sin[:, :n], taper * u_x)
        h_y = u_y0 + 2.0 * _real_product(self.cos[:, :n], taper * u_y)
        return self.dk / (2.0 * math.pi) * h_x, self.dk / (2.0 * math.pi) * h_y


def _load_transform(pulse, s, omega_max):
    """F^(s) = int_0^inf F e^{-st} dt: Gauss-Legendre over [0, duration]
    plus the held final value's final_value e^{-s T} / s."""
    nodes = int(omega_max * pulse.duration / 2.0) + 80
    u, w = np.polynomial.legendre.leggauss(nodes)
    tau, w = 0.5 * pulse.duration * (u + 1.0), 0.5 * pulse.duration * w
    spectrum = np.exp(-np.outer(s, tau)) @ (w * pulse(tau))
    if pulse.final_value != 0.0:
        spectrum += pulse.final_value * np.exp(-s * pulse.duration) / s
    return spectrum


def _frequency_grid(pulse, period, eps, cycles, floor):
    """s_n = eps + i n 2 pi / period up to where |s F^| falls below floor of
    its peak (at most cycles / duration Hz)."""
    d_omega = 2.0 * math.pi / period
    omega = d_omega * np.arange(int(2.0 * math.pi * cycles / pulse.duration / d_omega) + 2)
    s = eps + 1j * omega
    spectrum = _load_transform(pulse, s, omega[-1])
    size = np.abs(s * spectrum)
    last = np.nonzero(size > floor * size.max())[0][-1]
    return s[:last + 2], spectrum[:last + 2]


def _wavenumber_solution(x, t, force, rho, vp, vs, derivative, period_factor=6.0,
                         alias_decades=12.0, cycles=40.0, floor=1e-11):
    medium = HalfSpace(float(rho), float(vp), float(vs))
    x = np.atleast_1d(np.asarray(x, dtype=float))
    t = np.atleast_1d(np.asarray(t, dtype=float))
    window = t.max()
    pulse = as_pulse(force, t_max=window)
    period = period_factor * window
    eps = alias_decades * math.log(10.0) / period
    s, spectrum = _frequency_grid(pulse, period, eps, cycles, floor)
    # Images of the source L apart must not reach a receiver within the window.
    spacing = 1.1 * (x.max() + medium.vp * window)
    wavenumbers = _WavenumberSum(x, medium, 2.0 * math.pi / spacing, s[-1])
    out = np.zeros((2, x.size, s.size), dtype=complex)
    for n, s_n in enumerate(s):
        out[:, :, n] = wavenumbers.transfer(s_n)
    out *= spectrum * (s if derivative else 1.0)
    # Trapezoid over w >= 0 of a real signal's transform: halve the w = 0 term.
    out[:, :, 0] *= 0.5
    d_omega = s[1].imag - s[0].imag
    waves = np.exp(1j * np.outer(s.imag, t))
    motion = (out @ waves).real * np.exp(eps * t) * d_omega / math.pi
    return motion[0], motion[1]


def surface_displacement_wavenumber(x, t, force, rho, vp, vs, **options):
    """(u_x, u_y) as :func:`surface_displacement`, by wavenumber-frequency
    integration (method b); t from 0 up (the window is [0, max t])."""
    return _wavenumber_solution(x, t, force, rho, vp, vs, False, **options)


def surface_velocity_wavenumber(x, t, force, rho, vp, vs, **options):
    """(v_x, v_y) as :func:`surface_velocity`, by wavenumber-frequency integration."""
    return _wavenumber_solution(x, t, force, rho, vp, vs, True, **options)
