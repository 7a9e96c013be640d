"""The interface panels of a plane-strain result's figure (`vstpetsc plot`
of a 2-D file with /interface/<name>): per interface one row of two
panels, (1) its slip and opening (the gap, positive open) along the curve
at the mesh panels' times, (2) over time the largest |slip| and the
largest opening over its pairs, and the length open (the pairs' tributary
lengths where the gap is positive, as `vstpetsc info` counts it).

Along the curve: the pairs are ordered by walking the polyline of their
first-side nodes (the mesh's cell edges joining two of them), each piece
of it drawn along the pairs' mean tangent, the pieces in the order of
their first node's projection on it; a curve whose nodes branch (or no
edges) falls back on the projection of every first-side node on the mean
tangent.  The distance is the length of the polyline so ordered from its
first pair (a jump between pieces counted as the straight line)."""

import numpy as np

from vstpetsc.results import plane_layout

INTERFACE_ROW = 3.4       # the height (inches) of an interface's row of panels


def curve_segments(cells, first):
    """The cell edges (k, 2) that join two of the nodes ``first`` (m,) (a
    curve's first-side nodes), as positions into ``first``: the curve's
    own edges, each once.  ``cells`` (ne, 4), -1 pads a triangle."""
    outline = np.where(cells < 0, cells[:, [0]], cells)      # a triangle closes on its first node
    a, b = outline.ravel(), np.roll(outline, -1, axis=1).ravel()
    where = np.full(max(int(cells.max(initial=0)), int(first.max(initial=0))) + 1, -1)
    where[first] = np.arange(first.size)
    pa, pb = where[a], where[b]
    keep = (pa >= 0) & (pb >= 0) & (pa != pb)
    pairs = np.sort(np.column_stack([pa[keep], pb[keep]]), axis=1)
    return np.unique(pairs, axis=0).reshape(-1, 2)


def walked_pieces(m, segments):
    """The pieces of the polyline of ``m`` points joined by ``segments``
    (k, 2), each as its points in walking order (from an end, or from any
    point of a loop); None when a point has more than two neighbours."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components, depth_first_order

    ones = np.ones(len(segments))
    graph = sp.coo_matrix((ones, (segments[:, 0], segments[:, 1])), shape=(m, m))
    graph = ((graph + graph.T) > 0).tocsr()
    degree = np.diff(graph.indptr)
    if m == 0 or degree.max() > 2:
        return None
    count, labels = connected_components(graph, directed=False)
    pieces = []
    for label in range(count):
        members = np.flatnonzero(labels == label)
        ends = members[degree[members] < 2]
        start = ends[0] if ends.size else members[0]
        pieces.append(depth_first_order(graph, start, directed=False,
                                        return_predecessors=False))
    return pieces


def curve_order(points, tangents, segments=None):
    """(order, distance): the pairs in their order along the curve and
    the distance along it of each (from 0 at the first), from their
    first-side ``points`` (m, 2), unit ``tangents`` (m, 2) and the
    curve's ``segments`` (:func:`curve_segments`; None: the order of the
    projections on the mean tangent)."""
    points = np.asarray(points, dtype=float)
    mean = np.asarray(tangents, dtype=float).sum(axis=0)
    along = points @ mean
    pieces = None if segments is None else walked_pieces(len(points), np.asarray(segments))
    if pieces is None:
        order = np.argsort(along, kind="stable")
    else:
        pieces = [p[::-1] if along[p[-1]] < along[p[0]] else p for p in pieces]
        pieces.sort(key=lambda p: along[p[0]])
        order = np.concatenate(pieces)
    steps = np.linalg.norm(np.diff(points[order], axis=0), axis=1)
    return order, np.concatenate([[0.0], np.cumsum(steps)])[:len(order)]


def interface_order(r, name):
    """(order, distance, first point) of interface ``name`` of Result
    ``r``: :func:`curve_order` on its pairs' first-side nodes."""
    g = r.interface(name)
    first = g.nodes[:][:, 0]
    points = r.mesh.coordinates[first]
    order, distance = curve_order(points, g.tangent[:], curve_segments(r.mesh.cells, first))
    return order, distance, points[order[0]] if len(order) else (np.nan, np.nan)


def along_curve_panel(ax, r, name, rows, u):
    """(1) slip (solid) and opening (dashed) of interface ``name`` along
    its curve at the kept ``rows``, a colour per time."""
    order, distance, (x0, y0) = interface_order(r, name)
    group = f"{plane_layout.INTERFACE}/{name}"
    slip = r.read(f"{group}/slip", np.s_[rows])[:, order]
    gap = r.read(f"{group}/gap", np.s_[rows])[:, order]
    for k, row in enumerate(rows):
        colour, when = f"C{k % 10}", f"t = {r.time[row]:.6g} {u['time']}"
        ax.plot(distance, slip[k], ".-", color=colour, lw=1.0, ms=3, label=when)
        ax.plot(distance, gap[k], ".--", color=colour, lw=1.0, ms=3)
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.set_xlabel(f"distance along the curve from ({x0:g}, {y0:g}) [{u['length']}]")
    ax.set_ylabel(f"slip, opening [{u['length']}]")
    ax.legend(fontsize=8)
    return ax


def over_time_panel(ax, r, name, u):
    """(2) over time: the largest |slip| and the largest opening over the
    pairs of interface ``name``, and the length open (a second axis)."""
    g = r.interface(name)
    slip, gap, length = g.slip[:], g.gap[:], g.length[:]
    t = r.time
    ax.plot(t, np.abs(slip).max(axis=1, initial=0.0), color="C0", label="largest |slip|")
    ax.plot(t, gap.max(axis=1, initial=-np.inf), "--", color="C1", label="largest opening")
    ax.set_xlabel(f"t [{u['time']}]")
    ax.set_ylabel(f"slip, opening [{u['length']}]")
    right = ax.twinx()
    right.plot(t, (gap > 0) @ length, ":", color="C2", lw=1.5, label="length open")
    right.set_ylim(0.0, 1.05 * max(float(length.sum()), 1e-300))
    right.set_ylabel(f"length open [{u['length']}]")
    lines = ax.get_lines() + right.get_lines()
    ax.legend(lines, [line.get_label() for line in lines], fontsize=8)
    return ax


def interface_rows(fig, specs, r, rows, u, letter):
    """An interface's row of panels in each of the grid cells ``specs``
    (one per interface of ``r``), lettered from ``letter``; returns
    their axes [(along the curve, over time)]."""
    out = []
    for k, (spec, name) in enumerate(zip(specs, r.interfaces)):
        row = spec.subgridspec(1, 2)
        tag = chr(ord(letter) + k)
        along = along_curve_panel(fig.add_subplot(row[0, 0]), r, name, rows, u)
        along.set_title(f"({tag}1) interface {name} along the curve: slip solid, "
                        "opening dashed", fontsize=10)
        timed = over_time_panel(fig.add_subplot(row[0, 1]), r, name, u)
        timed.set_title(f"({tag}2) interface {name} over time", fontsize=10)
        out.append((along, timed))
    return out
