"""What earthquake engineers read from a record (docs/seismic-outputs.md):
the response spectrum of an acceleration, the transfer function between
two, and the acceleration of a gauge from its slab-end velocities.  Pure
numpy; no PETSc.

The oscillator u'' + 2 z w u' + w^2 u = -a(t) is solved exactly for an
excitation a(t) linear between samples (the recurrence of Nigam &
Jennings 1969): the state (u, u') after a step is A (u, u') + B (a_i,
a_{i+1}), A and B the exact step of w, z and dt (:func:`step_matrices`).  The time recursion loops over the samples; every
period advances at once (numpy over periods).
"""

import numpy as np

from vstpetsc.errors import InputError

PERIODS = (0.01, 10.0, 200)       # the default periods: log-spaced, both ends included
KO_BLOCK = 1 << 22                # Konno-Ohmachi weights computed this many at a time


def default_periods():
    return np.geomspace(*PERIODS)


def damping_problem(damping):
    """Why ``damping`` is no damping ratio for the exact recurrence (which
    needs an underdamped oscillator), or None."""
    if not (isinstance(damping, (int, float, np.floating)) and 0.0 <= damping < 1.0):
        return f"a damping ratio in [0, 1) (0.05 is 5 %), got {damping!r}"
    return None


def periods_problem(periods):
    """Why ``periods`` are no periods (positive, finite, at least one), or None."""
    p = np.asarray(periods, dtype=float)
    if p.ndim != 1 or p.size == 0 or not np.all(np.isfinite(p)) or np.any(p <= 0):
        return "positive finite periods are needed"
    return None


def bandwidth_problem(b):
    """Why ``b`` is no Konno-Ohmachi bandwidth (a positive number), or None."""
    if not (isinstance(b, (int, float, np.floating)) and np.isfinite(b) and b > 0):
        return f"a positive bandwidth b (40 is usual), got {b!r}"
    return None


def _check(dt, damping, periods):
    for problem, key in ((damping_problem(damping), "damping"),
                         (periods_problem(periods), "periods"),
                         (None if np.isfinite(dt) and dt > 0 else f"positive, got {dt!r}",
                          "dt")):
        if problem:
            raise InputError(f"{key}: {problem}")


def step_matrices(periods, dt, damping):
    """(A, B): each (2, 2, P), the exact step of the oscillators of
    ``periods`` (u'' + 2 z w u' + w^2 u = -a) under an excitation linear
    over a step dt: (u, u')_{i+1} = A (u, u')_i + B (a_i, a_{i+1}).

    Nigam & Jennings (1969) write A and B in closed form; those forms lose
    digits by cancellation when w dt is small (B is off by 1e-7 relative at
    dt = 1e-3, T = 10, by 0.3 at dt = 1e-5), and vstpetsc's slabs are
    short.  So A and B are taken from the exponential of the augmented
    matrix of (u, u', a, a_{i+1} - a_i), which is the same exact step
    computed stably (scaling and squaring)."""
    import scipy.linalg          # here: `import vstpetsc` stays light

    w = 2.0 * np.pi / np.asarray(periods, dtype=float)
    m = np.zeros((w.size, 4, 4))
    m[:, 0, 1] = dt
    m[:, 1, 0] = -w * w * dt
    m[:, 1, 1] = -2.0 * damping * w * dt
    m[:, 1, 2] = -dt                # u'' = ... - a
    m[:, 2, 3] = 1.0                # a(s) = a_i + (a_{i+1} - a_i) s / dt
    e = scipy.linalg.expm(m)
    a = np.moveaxis(e[:, :2, :2], 0, -1)
    slope = e[:, :2, 3]
    b = np.moveaxis(np.stack([e[:, :2, 2] - slope, slope], axis=-1), 0, -1)
    return a, b


def peak_displacement(acc, dt, periods, damping):
    """max |u| over the samples of each oscillator, from rest at the first
    sample, under ``acc`` linear between samples."""
    acc = np.asarray(acc, dtype=float)
    ((a11, a12), (a21, a22)), ((b11, b12), (b21, b22)) = step_matrices(periods, dt, damping)
    u = np.zeros(np.size(periods))
    v = np.zeros_like(u)
    peak = np.zeros_like(u)
    for a0, a1 in zip(acc[:-1], acc[1:]):
        u, v = (a11 * u + a12 * v + (b11 * a0 + b12 * a1),
                a21 * u + a22 * v + (b21 * a0 + b22 * a1))
        np.maximum(peak, np.abs(u), out=peak)
    return peak


def response_spectrum(acc, dt, periods=None, damping=0.05):
    """The response spectrum of the acceleration record ``acc`` (samples
    dt apart, linear between them).

    Returns {"period", "sd", "psv", "psa"}: arrays over ``periods``
    (default 200 log-spaced from 0.01 to 10): sd the largest |u| of the
    oscillator of that period and damping ratio over the samples, from
    rest, psv = (2 pi / T) sd, psa = (2 pi / T)^2 sd (the units of acc).
    :class:`vstpetsc.InputError` for a damping ratio outside [0, 1), a
    period <= 0, dt <= 0.
    """
    periods = default_periods() if periods is None else np.asarray(periods, dtype=float)
    _check(dt, damping, periods)
    if np.size(acc) < 1:
        raise InputError("acc: no samples")
    sd = peak_displacement(acc, dt, periods, damping)
    w = 2.0 * np.pi / periods
    return {"period": periods.copy(), "sd": sd, "psv": w * sd, "psa": w * w * sd}


def acceleration(v, dt):
    """The derivative of slab-end velocities ``v`` (dt apart; (n,), or
    (n, k) for k components such as a plane-strain gauge's v_x, v_y: each
    column on its own, along axis 0): central differences, (v1 - v0) / dt
    and (v_n - v_{n-1}) / dt at the ends."""
    v = np.asarray(v, dtype=float)
    if v.ndim == 0:                       # one sample given as a number
        v = v.reshape(1)
    if v.shape[0] < 2:
        return np.zeros(v.shape)
    out = np.empty(v.shape)
    out[1:-1] = (v[2:] - v[:-2]) / (2.0 * dt)
    out[0] = (v[1] - v[0]) / dt
    out[-1] = (v[-1] - v[-2]) / dt
    return out


def fourier_amplitude(acc, dt):
    """(frequency k / (N dt), |DFT|) for k = 0 .. N // 2; no taper, no
    detrending."""
    acc = np.asarray(acc, dtype=float)
    return np.arange(acc.size // 2 + 1) / (acc.size * dt), np.abs(np.fft.rfft(acc))


def konno_ohmachi(frequency, amplitude, b=40.0):
    """``amplitude`` ((n,) or (n, k): k spectra) smoothed with the
    Konno-Ohmachi window of bandwidth ``b``: at each fc > 0 the mean over
    f > 0 weighted by (sin(b log10(f/fc)) / (b log10(f/fc)))^4 (1 at f =
    fc); the value at f = 0 is kept.  Sums over every frequency, no cut-off
    (O(n^2): 1 s for 8000 frequencies; the weights computed a block of rows
    at a time)."""
    f = np.asarray(frequency, dtype=float)
    amp = np.asarray(amplitude, dtype=float)
    if bandwidth_problem(b):
        raise InputError(f"smooth: {bandwidth_problem(b)}")
    out = amp.copy()
    pos = np.flatnonzero(f > 0)
    x = b * np.log10(f[pos])
    # sin(x_j - x_c) from the sines and cosines of each x: no sine per weight
    sin, cos = np.sin(x), np.cos(x)
    rows = max(1, KO_BLOCK // max(pos.size, 1))
    for start in range(0, pos.size, rows):
        c = slice(start, start + rows)
        w = ko_weights(x[None, :] - x[c, None], sin[None, :] * cos[c, None]
                       - cos[None, :] * sin[c, None])
        out[pos[c]] = (w @ amp[pos]) / w.sum(axis=1).reshape((-1,) + (1,) * (amp.ndim - 1))
    return out


def ko_weights(x, sin_x):
    """(sin x / x)^4, 1 at x = 0, in place of ``sin_x``."""
    centre = x == 0
    np.divide(sin_x, x, out=sin_x, where=~centre)
    sin_x[centre] = 1.0
    sin_x *= sin_x
    sin_x *= sin_x
    return sin_x


def transfer_function(acc_from, acc_to, dt, smooth=None):
    """(frequency, amplitude): |DFT(acc_to)| / |DFT(acc_from)| at k / (N dt),
    k = 0 .. N // 2, over the whole records (equal lengths; no taper or
    detrending); with ``smooth`` = b both Fourier amplitudes are smoothed
    (:func:`konno_ohmachi`) before the ratio.  NaN where the input's
    amplitude is 0."""
    if np.size(acc_from) != np.size(acc_to) or np.size(acc_from) < 2:
        raise InputError(f"acc_to: the records need equal lengths >= 2, got "
                         f"{np.size(acc_from)} and {np.size(acc_to)}")
    freq, lower = fourier_amplitude(acc_from, dt)
    upper = fourier_amplitude(acc_to, dt)[1]
    if smooth is not None:          # one set of weights for both spectra
        lower, upper = konno_ohmachi(freq, np.column_stack([lower, upper]), smooth).T
    ratio = np.full(freq.size, np.nan)
    np.divide(upper, lower, out=ratio, where=lower > 0)
    return freq, ratio
