"""Exports of a result file: CSV time series and an XDMF index for ParaView.

CSV (:func:`to_csv`): one file per group, a header line, numbers written
with 17 significant digits (read back, they are the HDF5 values bit for
bit):

- ``gauge.csv``: ``time`` and ``<gauge>.u``, ``.v``, ``.stress``,
  ``.strain`` of every gauge (and ``.shear_u``, ... on a body with a shear
  component), a row per slab;
- ``contact-<k>.csv`` (and one per other law group that reports, its path
  with ``-`` for ``/``), ``energy.csv``, ``solver.csv``: ``time`` and the
  group's one-value series, a row per kept slab (a series with a value per
  node, such as ``/soil/<k>/slip``, stays in the HDF5 file);
- ``contact-<k>-events.csv``: ``time`` and ``change`` (+1 close, -1
  open) of every event of pair k (``/contact/<k>/events``);
- ``envelope-<body>.csv``: ``x_left``, ``x_right``, ``stress_min``,
  ``stress_max`` of every element.

XDMF (:func:`to_xdmf`): ``RESULT.xdmf`` beside the file, a temporal
collection per body whose u, v (nodes) and stress (elements), and on a body
with a shear component shear_u, shear_v (nodes) and shear_stress
(elements, the datasets ``shear/u``, ``shear/v``, ``shear/stress``), point into
the result file's own datasets by hyperslab: nothing is copied, so the
index costs kilobytes whatever the run's size.  meshio's XDMF writer was
not used: it copies every array into a new HDF5 file named after the XDMF
file (here the result file itself), and its reader does not resolve
hyperslabs; the test checks the index against the HDF5 datasets instead.
"""

import os
from xml.sax.saxutils import quoteattr

import numpy as np

from vstpetsc.gauges import SERIES as GAUGE_SERIES, SHEAR
from vstpetsc.results import layout

KEPT_GROUPS = ("energy", "solver")
SHEAR_GROUP = "shear"       # /body/<name>/shear: the shear component's datasets


def _write_csv(path, columns):
    """``columns`` ({header: 1-D array}, equal lengths) as a CSV file."""
    data = np.column_stack([np.asarray(c, dtype=float) for c in columns.values()])
    np.savetxt(path, data, delimiter=",", header=",".join(columns), comments="",
               fmt="%.17g")
    return path


def law_groups(result):
    """Paths of the groups of laws that report a series per kept slab
    (``contact/0``, ...)."""
    out = []
    for top in result.keys():
        if top in (layout.TIME, layout.BODY, "gauge", *KEPT_GROUPS):
            continue
        out += [f"{top}/{sub}" for sub in result.keys(top) if result.series(f"{top}/{sub}")]
    return out


def to_csv(result, folder):
    """Write the CSV files of ``result`` (a Result) into ``folder`` (made
    if missing); returns their paths."""
    os.makedirs(folder, exist_ok=True)
    paths = []
    if result.gauges:
        columns = {"time": result.gauge(result.gauges[0]).time}
        for name in result.gauges:
            g = result.gauge(name)
            keys = [p + key for p in ("", SHEAR) for key in GAUGE_SERIES
                    if p + key in g.keys()]
            columns.update((f"{name}.{key}", g[key]) for key in keys)
        paths.append(_write_csv(os.path.join(folder, "gauge.csv"), columns))
    for group in law_groups(result) + list(KEPT_GROUPS):
        columns = {"time": result.time, **result.series(group)}
        name = group.replace("/", "-") + ".csv"
        paths.append(_write_csv(os.path.join(folder, name), columns))
    paths += _events_csv(result, folder)
    for body in result.bodies:
        b = result.body(body)
        if "stress_min" in b.keys():
            x = b.x
            paths.append(_write_csv(os.path.join(folder, f"envelope-{body}.csv"), {
                "x_left": x[:-1], "x_right": x[1:], "stress_min": b.stress_min,
                "stress_max": b.stress_max}))
    return paths


def _events_csv(result, folder):
    """contact-<k>-events.csv of every pair whose file has events."""
    paths = []
    for k in range(result.ncontacts):
        name = f"{layout.CONTACT}/{k}/{layout.EVENTS}"
        if name in result:
            events = result[name]
            paths.append(_write_csv(os.path.join(folder, f"contact-{k}-events.csv"),
                                    {"time": events[:, 0], "change": events[:, 1]}))
    return paths


def _numbers(values, fmt):
    return " ".join(fmt % v for v in np.ravel(values))


def _slab(h5, dataset, row, rows, width):
    """A DataItem of row ``row`` of the (rows, width) dataset of ``h5``."""
    return (f'<DataItem ItemType="HyperSlab" Dimensions="1 {width}" Type="HyperSlab">'
            f'<DataItem Dimensions="3 2" Format="XML">{row} 0 1 1 1 {width}</DataItem>'
            f'<DataItem Dimensions="{rows} {width}" NumberType="Float" Precision="8" '
            f'Format="HDF">{h5}:/{dataset}</DataItem></DataItem>')


def body_fields(result, body):
    """[(XDMF attribute name, dataset under /body/<body>, "Node" or
    "Cell")] of a body: u, v, stress, and shear_u, shear_v, shear_stress
    (``shear/u``, ...) for a body with a shear component."""
    out = [("u", "u", "Node"), ("v", "v", "Node"), ("stress", "stress", "Cell")]
    if SHEAR_GROUP in result.body(body).keys():
        out += [(SHEAR + key, f"{SHEAR_GROUP}/{key}", center) for _, key, center in out]
    return out


def _body_grids(result, body, h5):
    """The XML lines of the temporal collection of ``body``: the mesh inline
    in the first step, referenced by the others."""
    x = result.body(body).x
    nn, ne, times = x.size, x.size - 1, result.time
    first = f"{body}-0"
    mesh = (f'<Topology TopologyType="Polyline" NodesPerElement="2" NumberOfElements="{ne}">'
            f'<DataItem Dimensions="{ne} 2" NumberType="Int" Format="XML">'
            f'{_numbers(np.c_[np.arange(ne), np.arange(1, nn)], "%d")}</DataItem></Topology>'
            f'<Geometry GeometryType="XYZ"><DataItem Dimensions="{nn} 3" NumberType="Float" '
            f'Precision="8" Format="XML">{_numbers(np.c_[x, 0 * x, 0 * x], "%.17g")}'
            '</DataItem></Geometry>')
    # names hold letters, digits, '_', '-' and '.' only (case validation)
    shared = (f'<xi:include xpointer="xpointer(//Grid[@Name=\'{first}\']'
              '/*[self::Topology or self::Geometry])"/>')
    lines = [f'<Grid Name={quoteattr(body)} GridType="Collection" CollectionType="Temporal">']
    fields = body_fields(result, body)
    for i, t in enumerate(times):
        lines.append(f'<Grid Name={quoteattr(f"{body}-{i}")} GridType="Uniform">'
                     + (mesh if i == 0 else shared) + f'<Time Value="{float(t)!r}"/>')
        for name, key, center in fields:
            width = nn if center == "Node" else ne
            lines.append(f'<Attribute Name="{name}" AttributeType="Scalar" Center="{center}">'
                         + _slab(h5, layout.body_path(body, key), i, times.size, width)
                         + "</Attribute>")
        lines.append("</Grid>")
    return lines + ["</Grid>"]


def to_xdmf(result, path=None):
    """Write the XDMF index of ``result`` (default: RESULT.xdmf beside the
    file); returns its path.  The HDF5 file is named relative to it."""
    path = path or os.path.splitext(result.path)[0] + ".xdmf"
    h5 = os.path.relpath(os.path.abspath(result.path), os.path.dirname(os.path.abspath(path)))
    lines = ['<?xml version="1.0"?>',
             '<Xdmf Version="3.0" xmlns:xi="http://www.w3.org/2001/XInclude">', "<Domain>"]
    for body in result.bodies:
        lines += _body_grids(result, body, h5)
    lines += ["</Domain>", "</Xdmf>"]
    temp = path + ".part"
    with open(temp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(temp, path)
    return path
