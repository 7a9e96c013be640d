"""Gauges: u, v, stress and strain at points of the bars after every slab,
whatever ``output.every`` is (docs/result-file.md, "/gauge").

u and v are interpolated linearly between the two nodes around x (as the
finite element field is); stress and strain are those of the element
holding x: the left one at an interior node, the first one at the body's
left end.  Stress is the elongation times E / h, computed as the body's
stress series is, so the two agree where both exist.  A gauge on a body
with a shear component also reads it, at the same point of the body's
shear twin: ``shear_u``, ``shear_v``, ``shear_stress`` (G dw/dx),
``shear_strain`` (dw/dx).  Pure numpy.
"""

import numpy as np

from vstpetsc.results.layout import GAUGE_SERIES as SERIES, SHEAR, gauge_path


def element_at(xs, x):
    """(element, weight) of point ``x`` on the nodes ``xs`` of one body:
    the element holding x (the left one at an interior node, the first at
    the left end) and x's weight of its right node (exactly 0 or 1 at
    nodes)."""
    e = int(np.clip(np.searchsorted(xs, x, side="left") - 1, 0, xs.size - 2))
    if x == xs[e + 1]:
        return e, 1.0
    return e, (x - xs[e]) / (xs[e + 1] - xs[e])


class Gauges:
    """The gauges of a model: which nodes they read and their values.

    Attributes
    ----------
    names : list of str
    nodes : ndarray of int
        The global nodes whose u and v the gauges need (sorted, unique).
    """

    def __init__(self, model):
        specs, mesh = model.case.gauges, model.mesh
        self.names = [g.name for g in specs]
        self.bodies = [model.case.bodies[g.body].name for g in specs]
        self.specs = specs
        # a channel: (gauge name, series prefix, mesh body, x), axial then shear
        self.channels = [(g.name, "", g.body, g.x) for g in specs]
        self.channels += [(g.name, SHEAR, mesh.twins[g.body], g.x) for g in specs
                          if g.body in mesh.twins]
        left, w, factor, inv_h, els = [], [], [], [], []
        for _, _, body, x in self.channels:
            nodes, elements = mesh.nodes(body), mesh.elements(body)
            e, weight = element_at(mesh.x[nodes], x)
            left.append(nodes.start + e)
            w.append(weight)
            el = elements.start + e
            els.append(el)
            factor.append(mesh.E[el] / mesh.h[el])
            inv_h.append(1.0 / mesh.h[el])
        left = np.asarray(left, dtype=int)
        self.nodes = np.unique(np.concatenate([left, left + 1]))
        self.lpos = np.searchsorted(self.nodes, left)
        self.rpos = np.searchsorted(self.nodes, left + 1)
        self.w = np.asarray(w)
        self.factor, self.inv_h = np.asarray(factor), np.asarray(inv_h)
        # channels on a hysteretic soil read its stress (not G dw/dx)
        self.soil = model.soil
        governed = self.soil.elements if self.soil is not None else np.zeros(0, dtype=int)
        els = np.asarray(els, dtype=int)
        self.soil_channels = np.flatnonzero(np.isin(els, governed))
        self.soil_pos = np.searchsorted(governed, els[self.soil_channels])

    def __len__(self):
        """The number of channels (a gauge on a body with a shear component
        has two); a row of :meth:`fill` holds 4 per channel."""
        return len(self.channels)

    def series(self):
        """[(dataset name, column)]: the layout of a row of :meth:`fill`."""
        n = len(self.channels)
        return [(gauge_path(name, prefix + key), j * n + i)
                for j, key in enumerate(SERIES)
                for i, (name, prefix, _, _) in enumerate(self.channels)]

    def fill(self, u, v, row):
        """``row`` (4 x channels, flat: all u, all v, all stress, all strain)
        from ``u`` and ``v`` at :attr:`nodes`."""
        out = row.reshape(4, -1)
        w = self.w
        for k, field in enumerate((u, v)):
            a, b = field[self.lpos], field[self.rpos]
            np.add((1.0 - w) * a, w * b, out=out[k])
        d = u[self.rpos] - u[self.lpos]
        np.multiply(d, self.factor, out=out[2])
        np.multiply(d, self.inv_h, out=out[3])
        if self.soil_channels.size:
            out[2][self.soil_channels] = self.soil.stress[self.soil_pos]

    def attrs(self):
        """{group: attributes} of every gauge."""
        return {gauge_path(g.name): {"body": body, "x": g.x}
                for g, body in zip(self.specs, self.bodies)}
