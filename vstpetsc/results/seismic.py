"""The seismic outputs of a result file (docs/seismic-outputs.md): a gauge's
acceleration by component, the response spectrum and transfer function
tables and their one-screen summaries, and the peak profiles over x that
`vstpetsc plot` draws.  Pure numpy (the spectra: vstpetsc.results.spectrum)."""

import numpy as np

from vstpetsc.results import layout
# a plane-strain gauge's columns of v
from vstpetsc.results.plane_layout import COMPONENTS as PLANE_COMPONENTS

COMPONENTS = ("shear", "axial")
BAND = 0.01                          # the summary's band: input amplitude >= 1 % of its peak
STRAIN_MAX = "shear/strain_max"      # the largest |dw/dx| per element, when the law writes it


def has_shear(gauge):
    return "shear_v" in gauge.keys()


def moving_component(gauge):
    """The component a plot shows: shear where the gauge has one, unless
    only the axial field moves there."""
    if not has_shear(gauge):
        return "axial"
    return "axial" if not np.abs(gauge.shear_v).max() and np.abs(gauge.v).max() else "shear"


def gauge_acceleration(gauge, component):
    """The gauge's acceleration at every slab end, of ``component``: shear
    or axial on a line, x or y in the plane (that column of the (n, 2)
    accelerations)."""
    if component in PLANE_COMPONENTS:
        return gauge.acceleration[:, PLANE_COMPONENTS.index(component)]
    return gauge.shear_acceleration if component == "shear" else gauge.acceleration


def top_gauge(result):
    """The name of the gauge of largest x (the surface of a soil column
    with x up), None without gauges."""
    if not result.gauges:
        return None
    return max(result.gauges, key=lambda n: (float(result.gauge(n).attrs["x"]), n))


def spectrum_summary(spec, acc, dt, u):
    """Lines for the screen: the record's peak and where the spectrum peaks
    (``u``: plot.units of the result)."""
    L, T = u["length"], u["time"]
    at = lambda key: int(np.argmax(spec[key]))
    p = spec["period"]
    return [f"peak acceleration {np.abs(acc).max():.6g} {L}/{T}^2 over "
            f"{acc.size} slab ends (dt = {dt:g} {T})",
            f"psa peak {spec['psa'][at('psa')]:.6g} {L}/{T}^2 at T = {p[at('psa')]:.4g} {T}; "
            f"psv peak {spec['psv'][at('psv')]:.6g} {L}/{T} at T = {p[at('psv')]:.4g} {T}; "
            f"sd peak {spec['sd'][at('sd')]:.6g} {L} at T = {p[at('sd')]:.4g} {T}",
            f"{p.size} periods {p[0]:g} .. {p[-1]:g} {T}; --csv FILE writes the table, "
            "-o FIGURE.png the plot"]


def transfer_summary(freq, amp, lower, u):
    """Lines for the screen: the largest ratio where the input's Fourier
    amplitude ``lower`` is at least BAND of its largest (elsewhere the
    ratio divides noise), and the frequencies covered."""
    T = u["time"]
    band = np.flatnonzero((lower >= BAND * lower[1:].max()) & np.isfinite(amp))
    band = band[band > 0]
    lines = [f"{freq.size} frequencies 0 .. {freq[-1]:.6g} 1/{T} (df = {freq[1]:.6g} 1/{T})"]
    if band.size:
        k = band[np.argmax(amp[band])]
        lines.insert(0, f"largest amplitude ratio {amp[k]:.6g} at f = {freq[k]:.6g} 1/{T} "
                     f"(where the input's Fourier amplitude is >= {BAND:g} of its peak)")
    return lines + ["--csv FILE writes the table, -o FIGURE.png the plot"]


def kept_acceleration(v, t):
    """d v / dt of the kept rows ``v`` (rows at times ``t``): central
    differences over the neighbouring rows, one-sided at the first and last."""
    v = np.asarray(v, dtype=float)
    if v.shape[0] < 2:
        return np.zeros_like(v)
    out = np.empty_like(v)
    out[1:-1] = (v[2:] - v[:-2]) / (t[2:] - t[:-2])[:, None]
    out[0] = (v[1] - v[0]) / (t[1] - t[0])
    out[-1] = (v[-1] - v[-2]) / (t[-1] - t[-2])
    return out


def body_has_shear(result, body):
    return f"{layout.body_path(body)}/shear" in result


def element_modulus(result, body, shear):
    """E (or G with ``shear``) of each element of ``body``, from the
    result's case as the run meshed it; None if the case cannot be read
    (a moved result whose input files are gone)."""
    from vstpetsc import geometry
    from vstpetsc.errors import CaseError, InputError

    try:
        case = result.case()
    except (CaseError, InputError, OSError):
        return None
    return geometry.room(case).element_modulus(case, body, shear)


def peak_profiles(result, body):
    """{x, x_mid, strain, stress_min, stress_max, acceleration, shear} of
    ``body``, of its shear component when it has one: the largest |strain|
    per element (shear/strain_max when the file has it, else the stress
    envelopes over the modulus; None when the modulus is unknown), the
    stress envelopes, and the largest |acceleration| per node over the
    kept rows (:func:`kept_acceleration`)."""
    shear = body_has_shear(result, body)
    g = result.body(body)
    part = g.shear if shear else g
    x = g.x
    lo, hi = part.stress_min, part.stress_max
    if shear and f"{layout.body_path(body)}/{STRAIN_MAX}" in result:
        strain = g[STRAIN_MAX]
    else:
        modulus = element_modulus(result, body, shear)
        strain = None if modulus is None else np.maximum(np.abs(lo), np.abs(hi)) / modulus
    acc = np.abs(kept_acceleration(part.v, result.time)).max(axis=0)
    return {"x": x, "x_mid": 0.5 * (x[1:] + x[:-1]), "strain": strain, "stress_min": lo,
            "stress_max": hi, "acceleration": acc, "shear": shear}
