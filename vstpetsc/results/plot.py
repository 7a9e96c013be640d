"""One figure of a result file: (a) velocity over space and time, (b) contact
force, (c) energies.  The only module that imports matplotlib."""

import numpy as np

from vstpetsc.results import layout
from vstpetsc.results.reader import Result, text


def units(attrs):
    """Axis units from the result's root attributes (SI by default)."""
    get = lambda k, d: text(attrs.get(k, d))
    L, T, M = get("unit_length", "m"), get("unit_time", "s"), get("unit_mass", "kg")
    si = (L, T, M) == ("m", "s", "kg")
    return {"length": L, "time": T, "velocity": f"{L}/{T}",
            "force": "N" if si else f"{M} {L}/{T}^2",
            "energy": "J" if si else f"{M} {L}^2/{T}^2"}


def plot_result(result, out, max_rows=800):
    """Write the three-panel figure of ``result`` (a Result or a path) to
    ``out`` (PNG)."""
    import matplotlib.pyplot as plt

    fig = result_figure(result, max_rows)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def result_figure(result, max_rows=800):
    """The three-panel figure of ``result`` (a Result or a path; a
    matplotlib Figure)."""
    import matplotlib
    if matplotlib.get_backend().lower() not in ("agg", "pdf", "svg", "cairo"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    r = result if isinstance(result, Result) else Result(result)
    u = units(r.attrs)
    fig = plt.figure(figsize=(11, 8.5), constrained_layout=True)
    grid = fig.add_gridspec(2, 2, height_ratios=[1.35, 1])
    velocity_map(fig, fig.add_subplot(grid[0, :]), r, u, max_rows)
    axes = (contact_panel(fig.add_subplot(grid[1, 0]), r, u),
            energy_panel(fig.add_subplot(grid[1, 1]), r, u))
    for ax in axes:
        ax.xaxis.set_major_locator(MaxNLocator(5))
    return fig


def velocity_map(fig, ax, r, u, max_rows):
    """(a) velocity over reference position and time, walls drawn."""
    t = r.time
    rows = np.unique(np.linspace(0, t.size - 1, min(t.size, max_rows)).astype(int))
    bodies = [(r.body(name).x, r.read(layout.body_path(name, "v"), np.s_[rows, :]), name)
              for name in r.bodies]
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


def contact_panel(ax, r, u):
    """(b) slab-mean contact force of every pair."""
    t = r.time
    for k in range(r.ncontacts):
        pair = r.contact(k)
        name = text(pair.attrs.get("pair", str(k)))
        ax.step(t, pair.force, where="pre", label=f"[{k}] {name.replace(',', ' | ')}")
    if r.ncontacts:
        ax.legend(fontsize=8, loc="upper left")
    else:
        ax.text(0.5, 0.5, "no contact pairs", ha="center", transform=ax.transAxes)
    ax.set_xlabel(f"t [{u['time']}]")
    ax.set_ylabel(f"slab-mean contact force [{u['force']}]")
    ax.set_title("(b) contact force (compressive positive)")
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
    ax.set_title("(b) contact force (compressive positive) and slip")


def energy_panel(ax, r, u):
    """(c) the energy balance: kinetic, strain (+ springs), and the sums of
    external work, dashpot work and numerical dissipation where not zero."""
    t, e = r.time, r.energy
    names = set(e.keys())
    kin, strain = e["kinetic"], e["strain"]
    if "spring" in names and np.abs(e["spring"]).max() > 0:
        strain = strain + e["spring"]
    ax.plot(t, kin, label="kinetic")
    ax.plot(t, strain, label="strain")
    ax.plot(t, kin + strain, "k", lw=1.5, label="total")
    for key, style in (("external", "--"), ("damping", ":"), ("numerical", "-.")):
        if key in names and np.abs(e[key]).max() > 0:
            ax.plot(t, e[key], style, label=f"{key} (summed)")
    ax.set_xlabel(f"t [{u['time']}]")
    ax.set_ylabel(f"energy [{u['energy']}]")
    ax.set_title("(c) energy")
    ax.legend(fontsize=8)
    return ax


def plot_sweep(path, out, x=None, y=None):
    """A sweep's summary.csv: quantity ``y`` against swept key ``x``
    (defaults: the first column, the first quantity after ``wall_time``);
    failed runs are left out.  Returns ``out``."""
    import matplotlib.pyplot as plt

    from vstpetsc.errors import InputError
    from vstpetsc.sweep import read_summary

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
