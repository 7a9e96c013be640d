"""What a plane-strain model writes into its result file, under the names
of :mod:`vstpetsc.results.plane_layout`: the same functions as
:mod:`vstpetsc.line.layout` for the recorder, the writer and the restart
(``vstpetsc.geometry.layout``)."""

import numpy as np

from vstpetsc.errors import InputError

from vstpetsc.plane.energy import centre_stress
from vstpetsc.plane.principal import read_saved, stress_operator
from vstpetsc.results.layout import ENERGY, SOIL_STATE, SOLVER, TIME
from vstpetsc.results.plane_layout import DIMENSION, MESH, PAIR_SERIES, field_path
from vstpetsc.runner import energy as energy_mod


# meshes up to this many cells keep their centre stresses' operator D B on
# rank 0 (24 numbers a cell: 58 MB at 2e5 cells)
CACHED_CELLS = 200_000


def series(model):
    nn, ne = model.nnodes, model.ncells
    out = [(TIME, ()), (field_path("u"), (nn, 2)), (field_path("v"), (nn, 2)),
           (field_path("stress"), (ne, 3))]
    out += model.gauges.shapes()
    for record in model.recorded:
        m = record.info.pairs.stop - record.info.pairs.start
        out += [(f"{record.group}/{key}", (m,)) for key in PAIR_SERIES]
    for water in model.waters:
        out += [(f"{water.group}/pressure", water.nodes.shape), (f"{water.group}/force", (2,))]
    return out + [(name, ()) for name in ENERGY + SOLVER]


def statics(model):
    mesh = model.mesh
    out = {f"{MESH}/coordinates": mesh.coordinates, f"{MESH}/cells": mesh.cells,
           f"{MESH}/region": mesh.region}
    for record in model.recorded:
        s, p = record.info.pairs, model.pairs
        out.update({f"{record.group}/nodes": p.nodes[s], f"{record.group}/normal": p.normal[s],
                    f"{record.group}/tangent": p.tangent[s],
                    f"{record.group}/length": p.length[s]})
    out.update({f"{water.group}/nodes": water.nodes for water in model.waters})
    return out


def group_attrs(model):
    names = model.mesh.region_names if model.mesh is not None else ()
    return {f"{MESH}/region": {"names": list(names)}, **model.gauges.attrs(),
            **{record.group: record.attrs() for record in model.recorded}}


def gauges(model):
    return model.gauges


def envelope_count(model):
    return 0


def event_sets(model):
    return []


def formulation(model):
    return "none"


def root_attrs():
    """The root attributes that mark a 2-D file (a 1-D file has none)."""
    return {DIMENSION: 2}


def envelope_snapshots(model, principal, _=None):
    """The cells' principal stress envelopes (``principal``: the solver's,
    gathered on rank 0: /field/principal_max, ...) and a yielding zone's
    /field/strain_max and strain_max_time (rank 0), rewritten with every
    block (copies: a block may be written after the next slab)."""
    out = {field_path(name): values.copy() for name, values in (principal or {}).items()}
    zone = model.zone
    if zone is not None:
        out.update({field_path("strain_max"): zone.strain_max.copy(),
                    field_path("strain_max_time"): zone.strain_time.copy()})
    return out


def read_envelopes(f, model):
    """The principal stress envelopes a restart continues (every rank
    reads them; vstpetsc.plane.principal.read_saved)."""
    return read_saved(f, int(f["solver/slab"][-1]), field_path)


class RowFiller:
    """Kept rows of a plane-strain run from the state (u, v) (nn, 2) on
    rank 0: the fields, the cells' centre stresses, energies, solver."""

    def __init__(self, model):
        self.dt = model.case.dt
        self.model = model
        self.series = series(model)
        self.energy = [(f"energy/{key}", key) for key in energy_mod.KEYS]
        self.stress_operator = None

    def offload(self, *args):
        pass

    def fill(self, buffers, i, k, u, v, its, wall, energy, d=None):
        buffers[TIME][i], buffers["solver/slab"][i] = k * self.dt, k
        buffers["solver/wall_time"][i] = wall
        buffers["solver/newton_iterations"][i], buffers["solver/linear_iterations"][i] = its
        for name, key in self.energy:
            buffers[name][i] = energy[key]
        buffers[field_path("u")][i] = u
        buffers[field_path("v")][i] = v
        for record in self.model.recorded:
            for key, value in record.values().items():
                buffers[f"{record.group}/{key}"][i] = value
        self._water(buffers, i, k, v)
        stress = buffers[field_path("stress")][i]
        stress[...] = self._centre_stress(np.ravel(u))
        zone = self.model.zone
        if zone is not None:         # a yielding cell's own: its points' mean
            stress[zone.cells] = zone.cell_stress()[zone.cells]

    def _centre_stress(self, u):
        """The cells' centre stresses (ne, 3) from u: up to CACHED_CELLS
        cells through D B formed once (0.5 against 7.6 ms a row at 15 808
        cells), beyond formed anew each row (D B would hold 24 numbers a
        cell)."""
        mesh, mat = self.model.mesh, self.model.cell_materials
        if mesh.ncells > CACHED_CELLS:
            return centre_stress(mesh, u, mat["lam"], mat["mu"])
        if self.stress_operator is None:
            self.stress_operator = stress_operator(mesh, mat["lam"], mat["mu"],
                                                   np.arange(mesh.ncells),
                                                   np.arange(mesh.nnodes), u.size)
        return (self.stress_operator @ u).reshape(-1, 3)

    def _water(self, buffers, i, k, v):
        """The water's pressure and resultant at t = k dt (g(t) times
        their patterns per unit g: the loads the slabs carry; an acoustic
        water's dynamic part from the velocities v)."""
        if not self.model.waters:
            return
        g = float(self.model.case.gravity.g(np.array([k * self.dt]))[0])
        for water in self.model.waters:
            for key, value in water.values(g, np.asarray(v).reshape(-1, 2)).items():
                buffers[f"{water.group}/{key}"][i] = value

    def row(self, k, u, v, its, wall, energy, d=None):
        out = {name: np.zeros((1,) + tail) for name, tail in self.series}
        self.fill(out, 0, k, u, v, its, wall, energy, d)
        return {name: value[0] for name, value in out.items()}


def last_state(f, model):
    """(slab, u, v, {interface group: its pairs' state}, energies of the
    first row, of the last row)."""
    k = int(f["solver/slab"][-1])
    state = f.get(SOIL_STATE)
    if model.zone is not None and (state is None or int(state.attrs.get("slab", -1)) != k):
        raise InputError(f"--restart: the file keeps no yielding zone state at its last row "
                         f"(slab {k}); run the case from the start")
    u, v = f[field_path("u")][-1], f[field_path("v")][-1]
    energies = [{key.split("/")[1]: f[key][i] for key in ENERGY} for i in (0, -1)]
    pairs = {r.group: {key: f[f"{r.group}/{key}"][-1] for key in PAIR_SERIES}
             for r in model.recorded}
    return k, u, v, pairs, energies[0], energies[1]


def compiled_gauges(gauges, solver, order):
    """No compiled gauge row in 2-D: the Python path fills it."""
    return None
