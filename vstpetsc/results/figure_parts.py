"""What the figures of a 1-D result (:mod:`vstpetsc.results.plot`) and of
a 2-D one (:mod:`vstpetsc.results.plane_plot`) share: the axis units of a
result, pyplot on a file backend, the energy panel."""

import numpy as np

from vstpetsc.results.layout import text


def units(attrs):
    """Axis units from the result's root attributes (SI by default)."""
    get = lambda k, d: text(attrs.get(k, d))
    L, T, M = get("unit_length", "m"), get("unit_time", "s"), get("unit_mass", "kg")
    si = (L, T, M) == ("m", "s", "kg")
    return {"length": L, "time": T, "velocity": f"{L}/{T}",
            "force": "N" if si else f"{M} {L}/{T}^2",
            "energy": "J" if si else f"{M} {L}^2/{T}^2"}


def pyplot():
    """matplotlib.pyplot, on the Agg backend unless a file backend is set
    (figures are written to files, never shown)."""
    import matplotlib
    if matplotlib.get_backend().lower() not in ("agg", "pdf", "svg", "cairo"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def energy_panel(ax, r, u, profiles=None):
    """The energy balance: kinetic, strain (+ springs), and the sums of
    external work, dashpot work, sliding, a soil's hysteresis and
    numerical dissipation where not zero."""
    t, e = r.time, r.energy
    names = set(e.keys())
    kin, strain = e["kinetic"], e["strain"]
    if "spring" in names and np.abs(e["spring"]).max() > 0:
        strain = strain + e["spring"]
    ax.plot(t, kin, label="kinetic")
    ax.plot(t, strain, label="strain")
    ax.plot(t, kin + strain, "k", lw=1.5, label="total")
    for key, style in (("external", "--"), ("damping", ":"), ("friction", (0, (3, 1))),
                       ("hysteretic", (0, (5, 1, 1, 1))), ("numerical", "-.")):
        if key in names and np.abs(e[key]).max() > 0:
            ax.plot(t, e[key], ls=style, label=f"{key} (summed)")
    return labelled(ax, f"t [{u['time']}]", f"energy [{u['energy']}]", "energy")


def labelled(ax, xlabel, ylabel, title):
    """The axes' labels and title, and a legend."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(fontsize=8)
    return ax
