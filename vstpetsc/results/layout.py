"""The layout of a result file (docs/result-file.md): every dataset name and
what goes into it.  The writer, the reader, the summary and the plot take
their names from here.

    /time                          (nt,)
    /body/<name>/x, u, v, stress   (nn,), (nt, nn), (nt, nn), (nt, ne)
    /body/<name>/stress_min, stress_max   (ne,) envelopes, rewritten with every block
    /<law group>/<series>          (nt,)   e.g. /contact/0/gap
    /energy/kinetic, strain, spring, damping, external, contact, soil, numerical   (nt,)
    /solver/newton_iterations, linear_iterations, wall_time, slab   (nt,)
"""

import numpy as np

from vstpetsc import energy as energy_mod
from vstpetsc import model as model_mod

TIME = "time"
BODY = "body"
CONTACT = "contact"
ENERGY = tuple(f"energy/{k}" for k in energy_mod.KEYS)
ENVELOPES = ("stress_min", "stress_max")
ELONGATION = ("solver/elongation_min", "solver/elongation_max")   # the envelopes' exact state
SOLVER = ("solver/newton_iterations", "solver/linear_iterations", "solver/wall_time",
          "solver/slab")
INTEGER_SERIES = ("solver/newton_iterations", "solver/linear_iterations", "solver/slab")
BODY_SERIES = ("u", "v", "stress")
RHS_STATE = "solver/rhs_state"
NEWTON_STATE = "solver/newton_state"    # [acted, the laws' terms f] of the last slab
RESTART_STATE = (RHS_STATE, NEWTON_STATE)
REQUIRED = ("time", "body", "contact", "energy", "solver")


def body_path(name, key=None):
    return f"{BODY}/{name}" if key is None else f"{BODY}/{name}/{key}"


def series(model):
    """[(dataset name, shape of one row)] of every series, in the order the
    file creates them."""
    mesh, out = model.mesh, [(TIME, ())]
    for b, body in enumerate(model.case.bodies):
        nn = mesh.nodes(b).stop - mesh.nodes(b).start
        out += [(body_path(body.name, "u"), (nn,)), (body_path(body.name, "v"), (nn,)),
                (body_path(body.name, "stress"), (body.elements,))]
    for law in model.recorded:
        out += [(f"{law.group}/{key}", ()) for key in law.series]
    return out + [(name, ()) for name in ENERGY + SOLVER]


def statics(model):
    """{dataset name: array} written once: the reference node coordinates."""
    mesh = model.mesh
    return {body_path(b.name, "x"): mesh.x[mesh.nodes(i)]
            for i, b in enumerate(model.case.bodies)}


def group_attrs(model):
    """{group: attributes} of the laws that report."""
    return {law.group: law.attrs() for law in model.recorded}


def formulation(model):
    """The root attribute ``formulation``: the pairs' formulations."""
    forms = sorted({law.formulation for law in model.recorded if law.formulation})
    return ",".join(forms) if forms else "none"


def envelope_snapshots(model, lo, hi):
    """{dataset name: array}: the stress envelopes of every body from the
    elongation envelopes (lo, hi) of all elements, and those."""
    factor = model.mesh.E / model.mesh.h
    out = {ELONGATION[0]: lo, ELONGATION[1]: hi}
    for b, body in enumerate(model.case.bodies):
        el = model.mesh.elements(b)
        out[body_path(body.name, "stress_min")] = lo[el] * factor[el]
        out[body_path(body.name, "stress_max")] = hi[el] * factor[el]
    return out


def read_envelopes(f, model):
    """The elongation envelopes (lo, hi) of all elements from an open
    result file (None if absent)."""
    if not all(n in f for n in ELONGATION):
        return None
    return f[ELONGATION[0]][...], f[ELONGATION[1]][...]


def row(model, k, dt, u, v, its, wall, energy):
    """{dataset name: value} of the kept slab ``k`` from the nodal u and v
    and the energies (an EnergyBook row)."""
    mesh = model.mesh
    out = {TIME: k * dt, "solver/slab": k,
           "solver/newton_iterations": its[0], "solver/linear_iterations": its[1],
           "solver/wall_time": wall}
    out.update({f"energy/{key}": val for key, val in energy.items()})
    stress = model_mod.element_stress(mesh, u)
    for b, body in enumerate(model.case.bodies):
        nodes = mesh.nodes(b)
        out[body_path(body.name, "u")] = u[nodes]
        out[body_path(body.name, "v")] = v[nodes]
        out[body_path(body.name, "stress")] = stress[mesh.elements(b)]
    for law in model.recorded:
        for key, val in law.values(u).items():
            out[f"{law.group}/{key}"] = val
    return out


def last_state(f, model):
    """(slab, u, v, {group: {series: last value}}, energies of the first
    row, of the last row) of an open result file, for a restart."""
    k = int(f["solver/slab"][-1])
    u = np.concatenate([f[body_path(b.name, "u")][-1] for b in model.case.bodies])
    v = np.concatenate([f[body_path(b.name, "v")][-1] for b in model.case.bodies])
    laws = {law.group: {key: f[f"{law.group}/{key}"][-1] for key in law.series}
            for law in model.recorded}
    energies = [{key.split("/")[1]: f[key][i] for key in ENERGY} for i in (0, -1)]
    return k, u, v, laws, energies[0], energies[1]
