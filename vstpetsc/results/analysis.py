"""Readings of a result that engineers ask for: contact episodes and flight
times, transfer functions (spectral ratios).  Pure numpy; they take arrays,
e.g. ``Result.time`` and ``Result.contact(0).impulse``."""

import numpy as np


def episodes(t, impulse):
    """(start, end) of every run of consecutive kept slabs with contact: the
    start of the first slab and the end of the last one.  With ``every >
    1`` the times are those of kept rows only."""
    on = np.diff(np.r_[0, (np.asarray(impulse)[1:] > 0).astype(int), 0])
    starts, ends = np.nonzero(on == 1)[0], np.nonzero(on == -1)[0]
    return [(float(t[s]), float(t[e])) for s, e in zip(starts, ends)]


def flights(t, impulse):
    """(lift-off, landing) of every interval without contact between two
    contact episodes (the times of kept rows)."""
    eps = episodes(t, impulse)
    return [(a[1], b[0]) for a, b in zip(eps, eps[1:])]


def transfer_function(t, response, excitation, smoothing=0.1):
    """(f, |R(f)| / |E(f)|): the ratio of the amplitude spectra of two
    signals sampled at the times t (uniform), each smoothed over a
    relative bandwidth ``smoothing`` (a running mean over f (1 +- s/2)),
    as a site-response analysis reads a surface and an outcrop record."""
    t = np.asarray(t, dtype=float)
    dt = t[1] - t[0]
    if not np.allclose(np.diff(t), dt, rtol=1e-6, atol=0):
        raise ValueError("transfer_function needs uniformly sampled signals")
    f = np.fft.rfftfreq(t.size, dt)
    spectra = [np.abs(np.fft.rfft(np.asarray(x) - np.mean(x))) for x in (response, excitation)]
    smooth = [_smooth(f, s, smoothing) for s in spectra]
    with np.errstate(divide="ignore", invalid="ignore"):
        return f[1:], smooth[0][1:] / smooth[1][1:]


def _smooth(f, spectrum, width):
    """Running mean of ``spectrum`` over f (1 - w/2) .. f (1 + w/2)."""
    cumulative = np.concatenate(([0.0], np.cumsum(spectrum)))
    lo = np.searchsorted(f, f * (1 - width / 2), side="left")
    hi = np.searchsorted(f, f * (1 + width / 2), side="right")
    return (cumulative[hi] - cumulative[lo]) / np.maximum(hi - lo, 1)


def layer_amplification(f, height, speed, ratio):
    """Closed-form steady surface-to-outcrop amplification of an undamped
    layer (thickness ``height``, wave speed ``speed``) on elastic rock,
    impedance ratio ``ratio`` = Z_layer / Z_rock: 1 / sqrt(cos^2 kH +
    a^2 sin^2 kH), k = 2 pi f / c."""
    kh = 2 * np.pi * np.asarray(f) / speed * height
    return 1.0 / np.sqrt(np.cos(kh) ** 2 + ratio ** 2 * np.sin(kh) ** 2)
