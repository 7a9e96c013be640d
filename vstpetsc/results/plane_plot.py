"""The figure of a plane-strain result (`vstpetsc plot` of a 2-D file):
(a) the deformed mesh coloured by the speed |v| at chosen kept times, the
displacements magnified by one factor for every panel, (b) the gauges'
v_x and v_y over time, (c) the energy terms, then a row per interface
(:mod:`vstpetsc.results.interface_plot`).  Every cell is drawn at once
(matplotlib's tripcolor and a PolyCollection), no loop over cells."""

import numpy as np

from vstpetsc.errors import InputError
from vstpetsc.results import plane_layout

MAGNIFIED = 0.05        # the largest displacement is drawn as this part of the mesh's size
EDGES_UP_TO = 5000      # cell edges drawn up to this many cells: beyond they blacken the mesh
MAX_TIMES = 6           # mesh panels at most (the figure's width is fixed)
# what the mesh panels may be coloured by: the speed at the nodes, a
# stress component at the cells' centres (its column in /field/stress), or
# an envelope per cell over the run (the same in every panel): a yielding
# run's largest equivalent shear strain, the largest s1 and smallest s2 of
# the principal stresses
ENVELOPE_LABELS = {"strain_max": "largest shear strain over the run",
                   "principal_max": "largest principal stress over the run",
                   "principal_min": "smallest principal stress over the run"}
COLOURS = {"speed": None, "sxx": 0, "syy": 1, "sxy": 2, **{k: k for k in ENVELOPE_LABELS}}
STRESS_NAMES = {"sxx": "sigma_xx", "syy": "sigma_yy", "sxy": "sigma_xy"}


def speed(v):
    """|v| = sqrt(v_x^2 + v_y^2) of velocities ``v`` (..., 2)."""
    return np.sqrt(v[..., 0] ** 2 + v[..., 1] ** 2)


def magnification(coordinates, displacements):
    """The factor that draws the largest |u| of ``displacements`` (k, nn,
    2) as MAGNIFIED of the mesh's size (the longer side of its bounding
    box); 1 when nothing moved."""
    largest = speed(displacements).max(initial=0.0)
    size = np.ptp(coordinates, axis=0).max()
    return MAGNIFIED * size / largest if largest > 0 else 1.0


def times_problem(kept, times):
    """Why ``times`` cannot be drawn from a run whose kept times are
    ``kept``, or None: each must lie within the run (a rounding of its
    length beyond either end is allowed)."""
    times = np.asarray(times, dtype=float)
    if times.size == 0 or times.size > MAX_TIMES:
        return f"1 to {MAX_TIMES} times, got {times.size}"
    slack = 1e-9 * max(kept[-1] - kept[0], abs(kept[-1]))
    outside = times[~((times >= kept[0] - slack) & (times <= kept[-1] + slack))]
    if outside.size:
        return f"{outside[0]:g} is outside the run ({kept[0]:g} .. {kept[-1]:g})"
    return None


def chosen_rows(r, times=None):
    """The kept rows drawn: those nearest ``times``, by default the row of
    the largest kinetic energy and the last row (increasing, no repeats)."""
    kept = r.time
    if times is None:
        return sorted({int(np.argmax(r.energy["kinetic"])), kept.size - 1})
    why = times_problem(kept, times)
    if why:
        raise InputError(f"times: {why}")
    nearest = np.abs(kept[None, :] - np.asarray(times, dtype=float)[:, None]).argmin(axis=1)
    return sorted(set(nearest.tolist()))


def triangles(cells):
    """The cells (ne, 4; -1 pads a triangle) as triangles for tripcolor:
    each triangle, and each quadrilateral cut along its diagonal 0-2."""
    quads = cells[cells[:, 3] >= 0]
    return np.vstack([cells[:, :3], quads[:, [0, 2, 3]]])


def outlines(cells):
    """The cells as 4-corner polygons: a triangle's third node repeated."""
    return np.where(cells < 0, cells[:, [2]], cells)


def mesh_panel(ax, coordinates, cells, displacement, values, factor, limits):
    """The mesh moved by ``factor`` x ``displacement``, coloured by
    ``values``: per node (the speed, shaded between nodes) or per cell (a
    stress, each cell flat) within ``limits``; returns the coloured
    collection."""
    from matplotlib.collections import PolyCollection

    xy = coordinates + factor * displacement
    edges = dict(edgecolors="0.15", linewidths=0.3) if len(cells) <= EDGES_UP_TO \
        else dict(edgecolors="none")
    if len(values) == len(cells):
        shade = PolyCollection(xy[outlines(cells)], array=values, cmap="RdBu_r", **edges)
        shade.set_clim(*limits)
        ax.add_collection(shade)
    else:
        shade = ax.tripcolor(xy[:, 0], xy[:, 1], triangles(cells), values,
                             shading="gouraud", cmap="viridis", vmin=limits[0], vmax=limits[1])
        if len(cells) <= EDGES_UP_TO:
            ax.add_collection(PolyCollection(xy[outlines(cells)], facecolors="none", **edges))
    ax.set_aspect("equal")
    ax.autoscale_view()
    return shade


def panel_values(r, rows, colour):
    """(values per panel, their limits, their label): the speed at the
    nodes (0 .. largest), or a stress component at the cells (symmetric
    about 0), one scale for every panel."""
    if COLOURS[colour] is None:
        values = speed(r.read(plane_layout.field_path("v"), np.s_[rows]))
        return values, (0.0, float(np.nanmax(values, initial=0.0)) or 1.0), "speed |v|"
    if colour in ENVELOPE_LABELS:
        return envelope_values(r, rows, colour)
    values = r.read(plane_layout.field_path("stress"), np.s_[rows])[..., COLOURS[colour]]
    top = float(np.nanmax(np.abs(values), initial=0.0)) or 1.0
    return values, (-top, top), STRESS_NAMES[colour]


def envelope_values(r, rows, colour):
    """panel_values of an envelope over the run: the same values in every
    panel, 0 .. largest (a strain) or symmetric about 0 (a stress)."""
    path = plane_layout.field_path(colour)
    if path not in r:
        why = "no yielding region" if colour == "strain_max" else \
            "no principal stress envelopes (an earlier version's file)"
        raise InputError(f"color {colour}: the result has {why} (/{path})")
    values = r.read(path)
    top = float(np.nanmax(np.abs(values), initial=0.0)) or 1.0
    limits = (0.0, top) if colour == "strain_max" else (-top, top)
    return [values] * len(rows), limits, ENVELOPE_LABELS[colour]


def gauge_velocities(ax, r, u):
    """(b) every gauge's v_x (solid) and v_y (dashed) over time."""
    for k, name in enumerate(r.gauges):
        g = r.gauge(name)
        v, (x, y), colour = g.v, g.attrs["x"], f"C{k % 10}"
        ax.plot(g.time, v[:, 0], color=colour, lw=0.8, label=f"{name} ({x:g}, {y:g}) v_x")
        ax.plot(g.time, v[:, 1], "--", color=colour, lw=0.8, label=f"{name} v_y")
    ax.set_xlabel(f"t [{u['time']}]")
    ax.set_ylabel(f"velocity [{u['velocity']}]")
    ax.set_title("(b) gauge velocities (v_x solid, v_y dashed)")
    ax.legend(fontsize=8)
    return ax


def mesh_panels(fig, spec, r, rows, colour, u):
    """(a) the mesh panels in grid cell ``spec``, one per kept row of
    ``rows``, coloured by ``colour`` with one colour bar; returns the
    magnification."""
    coordinates, cells = r.mesh.coordinates, r.mesh.cells
    displacements = r.read(plane_layout.field_path("u"), np.s_[rows])
    values, limits, label = panel_values(r, rows, colour)
    factor = magnification(coordinates, displacements)
    top = spec.subgridspec(1, len(rows))
    axes = [fig.add_subplot(top[0, k]) for k in range(len(rows))]
    for k, (ax, row) in enumerate(zip(axes, rows)):
        shade = mesh_panel(ax, coordinates, cells, displacements[k], values[k], factor, limits)
        ax.set_title(f"(a{k + 1}) {label} at t = {r.time[row]:.6g} {u['time']}", fontsize=10)
        ax.set_xlabel(f"x [{u['length']}]")
    axes[0].set_ylabel(f"y [{u['length']}]")
    unit = {"speed": u["velocity"], "strain_max": "-"}.get(colour, "Pa")
    fig.colorbar(shade, ax=axes, label=f"{label} [{unit}]")
    return factor


def plane_figure(r, times=None, colour="speed"):
    """The figure of plane-strain Result ``r``: a mesh panel per chosen
    time (:func:`chosen_rows`) coloured by ``colour`` (a key of COLOURS)
    with one colour bar, then the gauges (if any) and the energies, then
    a row per interface (:mod:`vstpetsc.results.interface_plot`)."""
    from vstpetsc.results.figure_parts import energy_panel, pyplot, units
    from vstpetsc.results.interface_plot import INTERFACE_ROW, interface_rows

    if colour not in COLOURS:
        raise InputError(f"color: one of {', '.join(COLOURS)}, got {colour!r}")
    plt = pyplot()
    u = units(r.attrs)
    rows = chosen_rows(r, times)
    coordinates, cells = r.mesh.coordinates, r.mesh.cells
    interfaces = r.interfaces
    width, height = np.ptp(coordinates, axis=0)
    panel = np.clip(10.5 / len(rows) * height / max(width, 1e-300), 2.0, 6.0)
    fig = plt.figure(figsize=(11, panel + 4.2 + INTERFACE_ROW * len(interfaces)),
                     constrained_layout=True)
    grid = fig.add_gridspec(2 + len(interfaces), 1,
                            height_ratios=[panel, 3.8] + [INTERFACE_ROW - 0.4] * len(interfaces))
    factor = mesh_panels(fig, grid[0], r, rows, colour, u)
    fig.suptitle(f"plane strain, {len(cells)} cells ({r.status}): the mesh deformed by u "
                 f"magnified {factor:.4g} times", fontsize=11)
    bottom = grid[1].subgridspec(1, 2 if r.gauges else 1)
    if r.gauges:
        gauge_velocities(fig.add_subplot(bottom[0, 0]), r, u)
    energy = energy_panel(fig.add_subplot(bottom[0, -1]), r, u)
    energy.set_title("(c) energy" if r.gauges else "(b) energy")
    interface_rows(fig, [grid[2 + k] for k in range(len(interfaces))], r, rows, u,
                   "d" if r.gauges else "c")
    return fig
