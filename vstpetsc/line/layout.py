"""What a model of bodies on a line writes into its result file, under the
names of :mod:`vstpetsc.results.layout` (docs/result-file.md): its series,
statics, attributes, envelopes, the kept rows (:class:`RowFiller`) and the
state a restart reads back; the same functions as
:mod:`vstpetsc.plane.layout` for the recorder, the writer and the restart
(``vstpetsc.geometry.layout``)."""

import numpy as np

from vstpetsc.line.gauges import Gauges
from vstpetsc.results.layout import ELONGATION, ENERGY, EVENTS, SOLVER, TIME, body_path, by_group
from vstpetsc.runner import energy as energy_mod


def gauges(model):
    """The model's gauges (:class:`vstpetsc.line.gauges.Gauges`)."""
    return Gauges(model)


def envelope_count(model):
    """Elements whose envelopes the solver keeps."""
    return model.mesh.elem_node.size


def series(model):
    """[(dataset name, shape of one row)] of every series, in the order the
    file creates them."""
    mesh, out = model.mesh, [(TIME, ())]
    for b, body in enumerate(model.bodies):
        nn = mesh.nodes(b).stop - mesh.nodes(b).start
        out += [(body_path(body.name, "u"), (nn,)), (body_path(body.name, "v"), (nn,)),
                (body_path(body.name, "stress"), (body.elements,))]
    for law in model.recorded:
        shape = getattr(law, "series_shape", lambda key: ())
        out += [(f"{law.group}/{key}", shape(key)) for key in law.series]
    out += [(name, ()) for name, _ in Gauges(model).series()]
    return out + [(name, ()) for name in ENERGY + SOLVER]


def event_sets(model):
    """[(law, dataset name)] of the pairs that record contact events."""
    return [(law, f"{law.group}/{EVENTS}") for law in model.recorded if hasattr(law, "track")]


def statics(model):
    """{dataset name: array} written once: the reference node coordinates."""
    mesh = model.mesh
    return {body_path(b.name, "x"): mesh.x[mesh.nodes(i)]
            for i, b in enumerate(model.case.bodies)}


def group_attrs(model):
    """{group: attributes} of the laws that report."""
    return {**by_group(model.recorded, lambda law: law.attrs()), **Gauges(model).attrs()}


def root_attrs():
    """The root attributes of the geometry: none for bodies on a line (a
    2-D file has ``dimension``, results/plane_layout.py)."""
    return {}


def formulation(model):
    """The root attribute ``formulation``: the pairs' formulations."""
    forms = sorted({law.formulation for law in model.recorded if law.formulation})
    return ",".join(forms) if forms else "none"


def envelope_snapshots(model, lo, hi):
    """{dataset name: array}: the stress envelopes of every body from the
    elongation envelopes (lo, hi) of all elements, and those."""
    mesh = model.mesh
    factor = mesh.E / mesh.h
    out = {ELONGATION[0]: lo, ELONGATION[1]: hi}
    smin, smax = lo * factor, hi * factor
    soil = model.soil
    if soil is not None:            # a hysteretic soil's own stress envelopes
        smin[soil.elements], smax[soil.elements] = soil.tau_min, soil.tau_max
    strain_max = np.maximum(np.abs(lo), np.abs(hi)) / mesh.h
    for b, body in enumerate(model.bodies):
        el = mesh.elements(b)
        out[body_path(body.name, "stress_min")] = smin[el]
        out[body_path(body.name, "stress_max")] = smax[el]
        if b >= len(model.case.bodies):          # a shear twin
            out[body_path(body.name, "strain_max")] = strain_max[el]
    return out


def read_envelopes(f, model):
    """The elongation envelopes (lo, hi) of all elements from an open
    result file (None if absent)."""
    if not all(n in f for n in ELONGATION):
        return None
    return f[ELONGATION[0]][...], f[ELONGATION[1]][...]


class RowFiller:
    """Writes kept rows (the series of :func:`series`) straight into a
    writer's buffers from the state on rank 0: a pass per body and dataset
    into the buffer's row, no intermediate arrays.  Stress is the elongation
    times E / h (as the envelopes), from the solver's elongation when it has
    one (one rank)."""

    def __init__(self, model):
        mesh = model.mesh
        self.dt = model.case.dt
        self.bodies = []
        for b, body in enumerate(model.bodies):
            nodes = mesh.nodes(b)
            self.bodies.append((body_path(body.name, "u"), body_path(body.name, "v"),
                                body_path(body.name, "stress"), nodes,
                                slice(nodes.start, nodes.stop - 1),
                                (mesh.E / mesh.h)[mesh.elements(b)]))
        self.laws = [(law, [(f"{law.group}/{key}", key) for key in law.series])
                     for law in model.recorded]
        self.energy = [(f"energy/{key}", key) for key in energy_mod.KEYS]
        self.d = None                   # u_{i+1} - u_i when the solver has none
        self.nnodes = mesh.nnodes
        self.soil = _soil_rows(model)
        self._soil = model.soil
        self.series = series(model)
        self._buffers = self._state = None
        self._copier = self._copier_buffers = None
        self._copied = (None, None, None)

    def offload(self, u, v, d, copier_of):
        """Copy the bodies' rows of u, v and stress (d times E / h) out of
        these arrays (the solver's own, on one rank) with the copier that
        ``copier_of([(values, factor or None)])`` makes (bind, post;
        :class:`vstpetsc.native.rows.RowCopier`) instead of numpy."""
        if self.soil:               # the soil's stress overwrites the row's
            return
        sources = []
        for _, _, _, nodes, pairs, factor in self.bodies:
            sources += [(u[nodes], None), (v[nodes], None),
                        (d[pairs], np.ascontiguousarray(factor, dtype=np.float64))]
        self._copier = copier_of(sources)
        self._copied = (u, v, d)

    def _bind(self, buffers):
        """The target arrays of ``buffers``, looked up once per buffer set."""
        self._buffers = buffers
        self._scalars = [buffers[n] for n in (TIME, "solver/slab", "solver/newton_iterations",
                                              "solver/linear_iterations", "solver/wall_time")]
        self._energy = [(buffers[name], key) for name, key in self.energy]
        self._bodies = [(buffers[nu], buffers[nv], buffers[ns], nodes, pairs, factor)
                        for nu, nv, ns, nodes, pairs, factor in self.bodies]
        self._laws = [(law, [(buffers[name], key) for name, key in names])
                      for law, names in self.laws]

    def _views(self, u, v, d):
        """Per body (u, v, d) views, kept while the arrays are the same (on
        one rank the solver's own, every row)."""
        if self._state is None or self._state[0] is not u or self._state[1] is not v \
                or self._state[2] is not d:
            views = [(u[nodes], v[nodes], d[pairs]) for _, _, _, nodes, pairs, _ in self.bodies]
            self._state = (u, v, d, views)
        return self._state[3]

    def fill(self, buffers, i, k, u, v, its, wall, energy, d=None):
        """Row ``i`` of ``buffers`` ({series name: array}) for the kept slab
        ``k``: nodal u and v of all nodes, (Newton, linear) iterations,
        the wall time, the energies (an EnergyBook row) and the elongation
        d of every node pair (computed from u when None)."""
        if buffers is not self._buffers:
            self._bind(buffers)
        time_, slab, newton, linear, wall_ = self._scalars
        time_[i], slab[i], wall_[i] = k * self.dt, k, wall
        newton[i], linear[i] = its
        for target, key in self._energy:
            target[i] = energy[key]
        if d is None:
            if self.d is None:
                self.d = np.empty(max(self.nnodes - 1, 0))
            d = np.subtract(u[1:], u[:-1], out=self.d)
        copied = self._copied
        if self._copier is not None and copied[0] is u and copied[1] is v and copied[2] is d:
            self._post(buffers, i)
        else:
            for (bu, bv, bs, _, _, factor), (vu, vv, vd) in zip(self._bodies,
                                                                self._views(u, v, d)):
                bu[i] = vu
                bv[i] = vv
                np.multiply(vd, factor, out=bs[i])
        for name, where, pos in self.soil:
            buffers[name][i][where] = self._soil.stress[pos]
        for law, targets in self._laws:
            values = law.values(u)
            for target, key in targets:
                target[i] = values[key]

    def _post(self, buffers, i):
        """The bodies' row i to the copier, bound to ``buffers`` first."""
        if self._copier_buffers is not buffers:
            self._copier.bind([a for bu, bv, bs, *_ in self._bodies for a in (bu, bv, bs)])
            self._copier_buffers = buffers
        self._copier.post(i)

    def row(self, k, u, v, its, wall, energy, d=None):
        """{series name: value} of one row (for a single row; the run fills
        the writer's buffers)."""
        out = {name: np.zeros((1,) + tail) for name, tail in self.series}
        self.fill(out, 0, k, u, v, its, wall, energy, d)
        return {name: value[0] for name, value in out.items()}


def _soil_rows(model):
    """[(stress dataset, its columns, positions in the soil's elements)] of
    the bodies a hysteretic soil governs."""
    soil, mesh, out = model.soil, model.mesh, []
    if soil is None:
        return out
    for b, body in enumerate(model.bodies):
        el = mesh.elements(b)
        inside = (soil.elements >= el.start) & (soil.elements < el.stop)
        if inside.any():
            out.append((body_path(body.name, "stress"), soil.elements[inside] - el.start,
                        np.flatnonzero(inside)))
    return out


def last_state(f, model):
    """(slab, u, v, {group: {series: last value}}, energies of the first
    row, of the last row) of an open result file, for a restart."""
    k = int(f["solver/slab"][-1])
    u = np.concatenate([f[body_path(b.name, "u")][-1] for b in model.bodies])
    v = np.concatenate([f[body_path(b.name, "v")][-1] for b in model.bodies])
    laws = by_group(model.recorded, lambda law: {key: f[f"{law.group}/{key}"][-1]
                                                 for key in law.series})
    for law, name in event_sets(model):
        # the last row's count of events: a block killed midway may have
        # written events of later slabs (the writer cuts them on reopening)
        count = int(laws[law.group]["event_count"])
        laws[law.group]["closed"] = count > 0 and f[name][count - 1, 1] > 0
    energies = [{key.split("/")[1]: f[key][i] for key in ENERGY} for i in (0, -1)]
    return k, u, v, laws, energies[0], energies[1]


def compiled_gauges(gauges, solver, order):
    """The compiled gauge row (vstpetsc.line.native.gauge_row), or None
    where the Python path must run."""
    from vstpetsc.line.native.gauge_row import GaugeRow
    return GaugeRow.of(gauges, solver, order)
