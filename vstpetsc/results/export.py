"""Exports of a result file: CSV time series and an XDMF index for ParaView.

CSV (:func:`to_csv`): one file per group, a header line, numbers written
with 17 significant digits (read back, they are the HDF5 values bit for
bit):

- ``gauge.csv``: ``time`` and ``<gauge>.u``, ``.v``, ``.stress``,
  ``.strain`` of every gauge (and ``.shear_u``, ... on a body with a shear
  component), a row per slab; a plane-strain gauge's ``<gauge>.u_x``,
  ``.u_y``, ``.v_x``, ``.v_y``;
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

A plane-strain result's XDMF is one temporal collection, ``mesh``: the
geometry (x, y) is /mesh/coordinates, the cells /mesh/cells (all
quadrilaterals) or its first three columns (all triangles) by reference,
or, for a mix, a Mixed topology written inline (the one copy: the two
kinds interleave in the file); ``region`` (cells) is /mesh/region; u, v
(nodes, 2 components) and stress (cells, 3 components: sigma_xx,
sigma_yy, sigma_xy) of each kept time are hyperslabs of /field; a
yielding run's strain_max and strain_max_time, and the principal stress
envelopes principal_max, principal_min and their times (cells, over the
run) are attributes of the first grid, shared like region.
tests/test_plane_outputs.py opens it with VTK's vtkXdmfReader (ParaView's
XDMF reader) and finds the datasets bit for bit.  Each interface adds a
temporal collection ``interface-<name>``: a Polyvertex cell per node pair
at its first-side node (column 0 of /interface/<name>/nodes into
/mesh/coordinates, by reference), the cell values length and, per kept
time, gap, normal_force, shear_force and slip by hyperslab
(tests/test_plane_interface_outputs.py reads them back bit for bit).
"""

import os
from xml.sax.saxutils import quoteattr

import numpy as np

from vstpetsc.results.layout import GAUGE_SERIES, SHEAR
from vstpetsc.results.plane_layout import COMPONENTS
from vstpetsc.results import layout, plane_layout

KEPT_GROUPS = ("energy", "solver")
SHEAR_GROUP = "shear"       # /body/<name>/shear: the shear component's datasets
PLANE_GRID = "mesh"         # the name of a plane-strain result's temporal collection
PLANE_FIELDS = (("u", "Node"), ("v", "Node"), ("stress", "Cell"))
# per cell over the run: a yielding run's strain_max; every run's
# principal stress envelopes (a file of an earlier version: absent)
ENVELOPES = ("strain_max", "strain_max_time", "principal_max", "principal_max_time",
             "principal_min", "principal_min_time")
# an interface's series in its XDMF grid (stretch, a law's inner state, stays in the file)
INTERFACE_FIELDS = ("gap", "normal_force", "shear_force", "slip")
XDMF_TRIANGLE, XDMF_QUADRILATERAL = 4, 5     # XDMF's codes of cells in a Mixed topology


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
            for key in keys:
                columns.update(_gauge_columns(f"{name}.{key}", g[key]))
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


def _gauge_columns(header, values):
    """{header: values} of a gauge's series on a line; a plane-strain
    gauge's (n, 2) series as two columns, ``header``_x and ``header``_y."""
    if np.ndim(values) == 1:
        return {header: values}
    return {f"{header}_{axis}": values[:, k] for k, axis in enumerate(COMPONENTS)}


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


def _slab(h5, dataset, row, shape):
    """A DataItem of row ``row`` of the float dataset of ``h5`` of ``shape``
    (rows first: (rows, width) on a line, (rows, nn, 2) in the plane)."""
    return _hyperslab(h5, dataset, shape, [row] + [0] * (len(shape) - 1), (1, *shape[1:]))


def _hyperslab(h5, dataset, shape, start, count, dtype=np.float64):
    """A DataItem of the block ``count`` from ``start`` of the dataset of
    ``h5`` of ``shape``."""
    corner = list(start) + [1] * len(shape) + list(count)
    return (f'<DataItem ItemType="HyperSlab" Dimensions="{_numbers(count, "%d")}" '
            'Type="HyperSlab">'
            f'<DataItem Dimensions="3 {len(shape)}" Format="XML">{_numbers(corner, "%d")}'
            f'</DataItem>{_hdf(h5, dataset, shape, dtype)}</DataItem>')


def _hdf(h5, dataset, shape, dtype=np.float64):
    """A DataItem of the whole dataset of ``h5`` of ``shape`` and numpy
    ``dtype`` (the file's floats and integers are 8 bytes)."""
    dtype = np.dtype(dtype)
    number = "Int" if dtype.kind in "iu" else "Float"
    return (f'<DataItem Dimensions="{_numbers(shape, "%d")}" NumberType="{number}" '
            f'Precision="{dtype.itemsize}" Format="HDF">{h5}:/{dataset}</DataItem>')


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
                         + _slab(h5, layout.body_path(body, key), i, (times.size, width))
                         + "</Attribute>")
        lines.append("</Grid>")
    return lines + ["</Grid>"]


def plane_topology(cells, h5):
    """The Topology of a plane-strain mesh (``cells`` (ne, 4), -1 pads a
    triangle): the file's own /mesh/cells when every cell is a
    quadrilateral, its first three columns when every one is a triangle,
    else a Mixed list inline (each cell's XDMF code, then its nodes):
    triangles and quadrilaterals interleave in the file, so no hyperslab
    picks either kind."""
    ne = len(cells)
    triangle = cells[:, 3] < 0
    path = f"{plane_layout.MESH}/cells"
    if not triangle.any():
        kind, item = "Quadrilateral", _hdf(h5, path, cells.shape, cells.dtype)
    elif triangle.all():
        kind, item = "Triangle", _hyperslab(h5, path, cells.shape, (0, 0), (ne, 3), cells.dtype)
    else:
        codes = np.where(triangle, XDMF_TRIANGLE, XDMF_QUADRILATERAL)
        listed = np.c_[codes, cells][np.c_[np.ones((ne, 4), bool), ~triangle]]
        kind = "Mixed"
        item = (f'<DataItem Dimensions="{listed.size}" NumberType="Int" Format="XML">'
                f'{_numbers(listed, "%d")}</DataItem>')
    return f'<Topology TopologyType="{kind}" NumberOfElements="{ne}">{item}</Topology>'


def _plane_mesh(result, h5):
    """(XML, nodes, cells) of a plane-strain result's mesh: the XML its
    Topology, its Geometry (x, y: /mesh/coordinates) and the cells' region
    index (/mesh/region) as a cell attribute, all but a Mixed list by
    reference."""
    mesh = result.mesh
    coordinates, cells, region = mesh.coordinates, mesh.cells, mesh.region
    return (plane_topology(cells, h5)
            + f'<Geometry GeometryType="XY">'
            f'{_hdf(h5, f"{plane_layout.MESH}/coordinates", coordinates.shape)}</Geometry>'
            '<Attribute Name="region" AttributeType="Scalar" Center="Cell">'
            f'{_hdf(h5, f"{plane_layout.MESH}/region", region.shape, region.dtype)}'
            '</Attribute>'), len(coordinates), len(cells)


def _plane_grids(result, h5):
    """The XML lines of a plane-strain result's temporal collection: the
    mesh in the first step, included by the others; u, v (nodes, x and y)
    and stress (cells: sigma_xx, sigma_yy, sigma_xy) of each kept time by
    hyperslab into /field."""
    mesh, nn, ne = _plane_mesh(result, h5)
    times = result.time
    shapes = {"Node": (times.size, nn, 2), "Cell": (times.size, ne, 3)}
    first = f"{PLANE_GRID}-0"
    once = ["region"]
    for name in ENVELOPES:               # the envelopes over the run
        if plane_layout.field_path(name) in result:
            mesh += (f'<Attribute Name="{name}" AttributeType="Scalar" Center="Cell">'
                     f'{_hdf(h5, plane_layout.field_path(name), (ne,))}</Attribute>')
            once.append(name)
    named = " or ".join(f"@Name='{name}'" for name in once)
    shared = (f'<xi:include xpointer="xpointer(//Grid[@Name=\'{first}\']/*[self::Topology or '
              f'self::Geometry or self::Attribute[{named}]])"/>')
    return _temporal(PLANE_GRID, times, mesh, shared, lambda i: [
        f'<Attribute Name="{name}" AttributeType="Vector" Center="{center}">'
        + _slab(h5, plane_layout.field_path(name), i, shapes[center]) + "</Attribute>"
        for name, center in PLANE_FIELDS])


def _temporal(grid, times, first, shared, attributes):
    """A temporal collection ``grid`` of a grid per time: the first with
    the parts ``first``, the others including them (``shared``), each with
    the lines ``attributes(i)``."""
    lines = [f'<Grid Name={quoteattr(grid)} GridType="Collection" CollectionType="Temporal">']
    for i, t in enumerate(times):
        lines.append(f'<Grid Name={quoteattr(f"{grid}-{i}")} GridType="Uniform">'
                     + (first if i == 0 else shared) + f'<Time Value="{float(t)!r}"/>')
        lines += attributes(i)
        lines.append("</Grid>")
    return lines + ["</Grid>"]


def _interface_grids(result, name, h5):
    """The XML lines of interface ``name``'s temporal collection,
    ``interface-<name>``: a Polyvertex cell per node pair at its first
    side's node (the topology column 0 of /interface/<name>/nodes, the
    geometry /mesh/coordinates, both by reference), and per kept time
    the pairs' gap, normal_force, shear_force and slip (cell values) by
    hyperslab into /interface/<name>; the pairs' tributary length once."""
    group = f"{plane_layout.INTERFACE}/{name}"
    pairs = result.interface(name).nodes
    m, times = pairs.shape[0], result.time
    coordinates = f"{plane_layout.MESH}/coordinates"
    grid = f"interface-{name}"
    mesh = (f'<Topology TopologyType="Polyvertex" NodesPerElement="1" NumberOfElements="{m}">'
            + _hyperslab(h5, f"{group}/nodes", pairs.shape, (0, 0), (m, 1), pairs.dtype)
            + '</Topology><Geometry GeometryType="XY">'
            + _hdf(h5, coordinates, result.mesh.coordinates.shape) + "</Geometry>"
            + '<Attribute Name="length" AttributeType="Scalar" Center="Cell">'
            + _hdf(h5, f"{group}/length", (m,)) + "</Attribute>")
    shared = (f'<xi:include xpointer="xpointer(//Grid[@Name=\'{grid}-0\']/*[self::Topology or '
              'self::Geometry or self::Attribute[@Name=\'length\']])"/>')
    return _temporal(grid, times, mesh, shared, lambda i: [
        f'<Attribute Name="{key}" AttributeType="Scalar" Center="Cell">'
        + _slab(h5, f"{group}/{key}", i, (times.size, m)) + "</Attribute>"
        for key in INTERFACE_FIELDS])


def to_xdmf(result, path=None):
    """Write the XDMF index of ``result`` (default: RESULT.xdmf beside the
    file); returns its path.  The HDF5 file is named relative to it."""
    path = path or os.path.splitext(result.path)[0] + ".xdmf"
    h5 = os.path.relpath(os.path.abspath(result.path), os.path.dirname(os.path.abspath(path)))
    lines = ['<?xml version="1.0"?>',
             '<Xdmf Version="3.0" xmlns:xi="http://www.w3.org/2001/XInclude">', "<Domain>"]
    if result.dimension == 2:
        lines += _plane_grids(result, h5)
        for name in result.interfaces:
            lines += _interface_grids(result, name, h5)
    for body in result.bodies:
        lines += _body_grids(result, body, h5)
    lines += ["</Domain>", "</Xdmf>"]
    temp = path + ".part"
    with open(temp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(temp, path)
    return path
