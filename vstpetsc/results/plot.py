"""Figures of a result file: the overview of `vstpetsc plot` (velocity over
space and time, then the panels the case has data for: contact force,
energies, gauge accelerations and the top gauge's response spectrum, peak
profiles over x), the response spectrum and the transfer function (`vstpetsc
spectrum`, `transfer`); a plane-strain result's figure is
:mod:`vstpetsc.results.plane_plot`'s.  These two and
:mod:`vstpetsc.results.figure_parts` (what they share) are the only modules
that import matplotlib."""

import numpy as np

from vstpetsc.results import layout
from vstpetsc.results.figure_parts import (energy_panel, labelled as _labelled, pyplot as _pyplot,
    units)
from vstpetsc.results.layout import text
from vstpetsc.results.reader import Result


def plot_result(result, out, max_rows=800, times=None, colour=None):
    """Write the overview figure of ``result`` (a Result or a path) to
    ``out`` (PNG); ``times``: the times of a 2-D result's mesh panels
    (:func:`vstpetsc.results.plane_plot.chosen_rows`)."""
    import matplotlib.pyplot as plt

    fig = result_figure(result, max_rows, times, colour)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def panels(r):
    """The small panels the case has something for, in order: (title, draw
    (ax, r, u, profiles)); every case has energies."""
    from vstpetsc.results import seismic

    out = []
    if r.ncontacts:
        out.append(("contact force", contact_panel))
    out.append(("energy", energy_panel))
    if r.gauges:
        out += [("gauge acceleration", gauge_panel), ("response spectrum", spectrum_panel)]
    if r.gauges or any(seismic.body_has_shear(r, b) for b in r.bodies):
        out += [("peak strain", strain_profile), ("peak stress", stress_profile),
                ("peak acceleration", acceleration_profile)]
    return out


def result_figure(result, max_rows=800, times=None, colour=None):
    """The overview figure of ``result`` (a Result or a path; a matplotlib
    Figure): the velocity map on top, the small panels of :func:`panels`
    two a row below it; a 2-D result's is
    :func:`vstpetsc.results.plane_plot.plane_figure` (``times`` its mesh
    panels' times, an InputError on a 1-D result)."""
    from matplotlib.ticker import MaxNLocator

    from vstpetsc.errors import InputError
    from vstpetsc.results import seismic

    plt = _pyplot()
    r = result if isinstance(result, Result) else Result(result)
    if r.dimension == 2:
        from vstpetsc.results.plane_plot import plane_figure
        return plane_figure(r, times, colour or "speed")
    if colour is not None:
        raise InputError("color: only a 2-D result's mesh panels have colours to choose")
    if times is not None:
        raise InputError("times: only a 2-D result's figure has times to choose "
                         "(a 1-D one shows every time)")
    u = units(r.attrs)
    small = panels(r)
    rows = (len(small) + 1) // 2
    fig = plt.figure(figsize=(11, 4.7 + 3.8 * rows), constrained_layout=True)
    grid = fig.add_gridspec(1 + rows, 2, height_ratios=[1.35] + [1] * rows)
    velocity_map(fig, fig.add_subplot(grid[0, :]), r, u, max_rows)
    profiles = {b: seismic.peak_profiles(r, b) for b in r.bodies} \
        if any(title.startswith("peak") for title, _ in small) else {}
    for k, (title, draw) in enumerate(small):
        ax = fig.add_subplot(grid[1 + k // 2, k % 2])
        draw(ax, r, u, profiles)
        ax.set_title(f"({chr(ord('b') + k)}) {ax.get_title()}")
        if ax.get_xscale() == "linear":
            ax.xaxis.set_major_locator(MaxNLocator(5))
    return fig


def velocity_map(fig, ax, r, u, max_rows):
    """(a) velocity over reference position and time, walls drawn."""
    t = r.time
    rows = np.unique(np.linspace(0, t.size - 1, min(t.size, max_rows)).astype(int))
    bodies = [(r.body(name).x, *_moving_field(r, name, rows)) for name in r.bodies]
    vmax = max(np.abs(v).max() for _, v, _ in bodies) or 1.0
    for x, v, name in bodies:
        mesh = ax.pcolormesh(x, t[rows], v, cmap="RdBu_r", vmin=-vmax, vmax=vmax,
                             shading="gouraud")
        ax.text(0.5 * (x[0] + x[-1]), 0.985, name, ha="center", va="top", fontsize=9,
                transform=ax.get_xaxis_transform(),
                bbox=dict(boxstyle="round", fc="white", alpha=0.8, lw=0))
        for end in (x[0], x[-1]):
            ax.axvline(end, color="0.3", lw=0.6)
    for k in range(r.ncontacts):
        wall = r.contact(k).attrs.get("wall", np.nan)
        if np.isfinite(wall):
            ax.axvline(wall, color="k", lw=3)
    fig.colorbar(mesh, ax=ax, label=f"velocity [{u['velocity']}]")
    ax.set_xlabel(f"x [{u['length']}] (reference position)")
    ax.set_ylabel(f"t [{u['time']}]")
    ax.set_title(f"(a) velocity over space and time ({r.status})")


def _moving_field(r, name, rows):
    """(velocity rows, label) of body ``name``: its axial field, or its
    shear field when only that one moves (a site-response column)."""
    v = r.read(layout.body_path(name, "v"), np.s_[rows, :])
    shear = layout.body_path(name, "shear/v")
    if not np.abs(v).max() and shear in r:
        return r.read(shear, np.s_[rows, :]), f"{name} (shear)"
    return v, name


def contact_panel(ax, r, u, profiles=None):
    """Slab-mean contact force of every pair."""
    t = r.time
    for k in range(r.ncontacts):
        pair = r.contact(k)
        name = text(pair.attrs.get("pair", str(k)))
        ax.step(t, pair.force, where="pre", label=f"[{k}] {name.replace(',', ' | ')}")
    ax.legend(fontsize=8, loc="upper left")
    ax.set_xlabel(f"t [{u['time']}]")
    ax.set_ylabel(f"slab-mean contact force [{u['force']}]")
    ax.set_title("contact force (compressive positive)")
    slip_axis(ax, r, u)
    return ax


def slip_axis(ax, r, u):
    """The slip of every pair with friction over time, on a second axis."""
    sliding = [k for k in range(r.ncontacts) if "slip" in r.contact(k).keys()]
    if not sliding:
        return
    twin = ax.twinx()
    for k in sliding:
        twin.plot(r.time, r.contact(k).slip, "--", label=f"[{k}] slip")
    twin.set_ylabel(f"slip [{u['length']}] (dashed)")
    twin.legend(fontsize=8, loc="lower right")
    ax.set_title("contact force (compressive positive) and slip")


def gauge_panel(ax, r, u, profiles=None):
    """Every gauge's acceleration over time (shear where its body has it)."""
    from vstpetsc.results import seismic

    for name in r.gauges:
        g = r.gauge(name)
        component = seismic.moving_component(g)
        ax.plot(g.time, seismic.gauge_acceleration(g, component), lw=0.7,
                label=f"{name} (x = {float(g.attrs['x']):g}, {component})")
    return _labelled(ax, f"t [{u['time']}]", f"acceleration [{u['length']}/{u['time']}^2]",
                     "gauge acceleration")


def spectrum_panel(ax, r, u, profiles=None):
    """The 5 % response spectrum (psa) of the top gauge (largest x)."""
    from vstpetsc.results import seismic
    from vstpetsc.results.spectrum import response_spectrum

    name = seismic.top_gauge(r)
    g = r.gauge(name)
    component = seismic.moving_component(g)
    spec = response_spectrum(seismic.gauge_acceleration(g, component), g.dt)
    spectrum_axes(ax, spec, u)
    ax.set_title(f"response spectrum, 5 % damping: gauge {name} ({component})")
    return ax


def spectrum_axes(ax, spec, u):
    """psa over period, log axes."""
    ax.loglog(spec["period"], spec["psa"])
    ax.set_xlabel(f"period T [{u['time']}]")
    ax.set_ylabel(f"psa [{u['length']}/{u['time']}^2]")
    ax.grid(True, which="both", alpha=0.3)


def _profile_label(p):
    return "shear" if p["shear"] else "axial"


def strain_profile(ax, r, u, profiles):
    """The largest |strain| of every element over x."""
    for name, p in profiles.items():
        if p["strain"] is not None:
            ax.step(p["x"], np.append(p["strain"], p["strain"][-1]), where="post",
                    label=f"{name} ({_profile_label(p)})")
    ax.set_xlabel(f"x [{u['length']}]")
    ax.set_ylabel("peak |strain|")
    ax.set_title("peak |strain| (du/dx, or dw/dx for shear)")
    ax.legend(fontsize=8)
    return ax


def stress_profile(ax, r, u, profiles):
    """The stress envelopes (smallest and largest over every slab end)."""
    for name, p in profiles.items():
        for key, style in (("stress_min", "--"), ("stress_max", "-")):
            ax.step(p["x"], np.append(p[key], p[key][-1]), style, where="post",
                    label=f"{name} {key[7:]} ({_profile_label(p)})")
    return _profile_axes(ax, u, f"stress [{u['force']}/{u['length']}^2]",
                         "peak stress (envelopes)")


def acceleration_profile(ax, r, u, profiles):
    """The largest |acceleration| of every node over the kept rows."""
    for name, p in profiles.items():
        ax.plot(p["x"], p["acceleration"], label=f"{name} ({_profile_label(p)})")
    return _profile_axes(ax, u, f"peak |acceleration| [{u['length']}/{u['time']}^2]",
                         "peak acceleration (kept rows)")


def _profile_axes(ax, u, ylabel, title):
    """x along the bodies, ``ylabel``, ``title``, a legend."""
    return _labelled(ax, f"x [{u['length']}]", ylabel, title)


def plot_spectrum(spec, out, result, title):
    """The response spectrum ``spec`` (psa over period, log axes) as ``out``."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6, 4.5), constrained_layout=True)
    spectrum_axes(ax, spec, units(result.attrs))
    ax.set_title(title, fontsize=10)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def plot_transfer(freq, amp, out, result, title):
    """The transfer function (amplitude ratio over frequency > 0) as ``out``."""
    plt = _pyplot()
    u = units(result.attrs)
    fig, ax = plt.subplots(figsize=(6, 4.5), constrained_layout=True)
    ax.semilogx(freq[1:], amp[1:])
    ax.set_xlabel(f"frequency [1/{u['time']}]")
    ax.set_ylabel("amplitude ratio")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def plot_sweep(path, out, x=None, y=None):
    """A sweep's summary.csv: quantity ``y`` against swept key ``x``
    (defaults: the first column, the first quantity after ``wall_time``);
    failed runs are left out.  Returns ``out``."""
    import matplotlib.pyplot as plt

    from vstpetsc.errors import InputError
    from vstpetsc.runner.sweep import read_summary

    header, data = read_summary(path)
    if x is None and y is None and "blow_count_0" in header and "capacity" in header[0]:
        return bearing_graph(header, data, out)
    after = header[header.index("wall_time") + 1:]
    x = x or header[0]
    # a sweep with friction is about the permanent slip (D(ky) of a sliding block)
    y = y or ("slip_0" if "slip_0" in after else next((c for c in after if c != "message"),
                                                       None))
    for name, what in ((x, "--x"), (y, "--y")):
        if name not in header:
            raise InputError(f"{what} {name}: no such column (columns: {', '.join(header)})")
    keep = [i for i, s in enumerate(data["status"]) if s == "completed"]
    for name, what in ((x, "--x"), (y, "--y")):
        words = [data[name][i] for i in keep if isinstance(data[name][i], str)]
        if words:
            raise InputError(f"{what} {name}: a column of numbers is needed, got {words[0]!r}")
    xs, ys = (np.array([data[c][i] for i in keep], dtype=float) for c in (x, y))
    order = np.argsort(xs, kind="stable")
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(xs[order], ys[order], "o-")
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    ax.set_title(f"{len(keep)} of {len(data['status'])} runs completed")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def bearing_graph(header, data, out):
    """The bearing graph of a capacity sweep: capacity, and the largest
    compressive and tensile stresses, against the blow count."""
    import matplotlib.pyplot as plt

    keep = [i for i, s in enumerate(data["status"]) if s == "completed"]
    pick = lambda c: np.array([data[c][i] for i in keep], dtype=float)
    blows = pick("blow_count_0")
    order = np.argsort(blows)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ax1.plot(blows[order], pick(header[0])[order], "o-")
    ax1.set_xlabel("blow count (blows per length unit)")
    ax1.set_ylabel(header[0])
    for c in header:
        if c.startswith(("stress_min_", "stress_max_")):
            kind = "compression" if c.startswith("stress_min_") else "tension"
            ax2.plot(blows[order], np.abs(pick(c))[order], "o-",
                     label=f"{kind}, {c.split('_', 2)[2]}")
    ax2.set_xlabel("blow count (blows per length unit)")
    ax2.set_ylabel("largest stress (magnitude)")
    ax2.legend(fontsize=8)
    for ax in (ax1, ax2):
        ax.grid(True, alpha=0.3)
    fig.suptitle(f"bearing graph ({len(keep)} of {len(data['status'])} runs completed)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out
