"""Material laws of the shear field (docs/nonlinear-soil.md): a body's
``shear_law`` makes the stress of its shear twin's elements a nonlinear,
hysteretic function of the strain.  The protocol beside the boundary laws:

| member | what |
|---|---|
| ``elements``, ``left``, ``nodes`` | the mesh elements it governs, their nodes |
| ``start(u)``, ``snapshot()``, ``restore(flat)`` | its state at t = 0, for a restart |
| ``slab(D1, D2, dt, tangent)`` | correction integrals Q (ne, 2), dQ/dD (ne, 2, 2) |
| ``finish(D1, D2, Q, dt)`` | take the last evaluated slab as converged |
| ``stress``, ``tau_min``, ``tau_max``, ``energies()`` | what it reports |

Only the registry here knows the models by name; nothing imports PETSc.
"""

from vstpetsc.input.checker import show
from vstpetsc.materials import mkz
from vstpetsc.materials.soil import HystereticSoil

MODELS = {mkz.NAME: mkz}
BODY_KEYS = ("shear_law",)


def read(chk, tbl, where, x, has_shear):
    """A body's ``shear_law``: None when absent, else a list of parts (a
    single table is a list of one); False after reporting."""
    if "shear_law" not in tbl:
        return None
    name = f"{where}.shear_law"
    value = tbl["shear_law"]
    tables = [value] if isinstance(value, dict) else value
    if not isinstance(tables, list) or not tables or \
            not all(isinstance(t, dict) for t in tables):
        chk.add(name, mkz.describe(value))
        return False
    if not has_shear:
        chk.add(name, "only for a body with a shear component (give it G or Vs)")
        return False
    parts = []
    for i, tbl_i in enumerate(tables):
        where_i = name if isinstance(value, dict) else f"{name}[{i}]"
        model = tbl_i.get("model")
        if model not in MODELS:
            chk.add(f"{where_i}.model", f"must be one of {', '.join(map(repr, MODELS))}, "
                    f"got {show(model) if model is not None else 'nothing'}")
            return False
        parts.append(MODELS[model].read_part(chk, tbl_i, where_i, x))
    return False if None in parts else parts


def covers(chk, body, where):
    """Whether every table of the body's shear_law governs an element (a
    table between two element midpoints would be dropped without a word);
    reported otherwise."""
    if not body.shear_law:
        return True
    x = body.node_x()
    mid = 0.5 * (x[1:] + x[:-1])
    empty = [i for i, part in enumerate(body.shear_law) if not part.covers(mid).any()]
    for i in empty:
        part = body.shear_law[i]
        name = f"{where}.shear_law" + (f"[{i}]" if len(body.shear_law) > 1 or i else "")
        chk.add(name, f"[{part.x_from:g}, {part.x_to:g}] holds no element midpoint "
                f"(elements of {x[1] - x[0]:g} from x = {x[0]:g})")
    return not empty


def check_alone(chk, bodies, contacts, soils):
    """A hysteretic soil's Newton on the whole slab hosts contact pairs and
    friction (vstpetsc.line.solver.hosted_laws) but not Smith soil, whose
    compiled slab keeps its laws' state itself: a case takes a shear_law or
    [[soil]] (reported on the first body with a shear_law)."""
    first = next((i for i, b in enumerate(bodies) if b is not None and b.shear_law), None)
    if first is None or not soils:
        return
    chk.add(f"body[{first}] ({bodies[first].name}).shear_law",
            "a hysteretic soil cannot yet share a case with [[soil]] (Smith soil's "
            "Newton keeps its laws' state itself; the soil's Newton hosts [[contact]] only)")


def build(model_bodies, mesh):
    """The shear field's material law of the mesh (None when no body has
    one)."""
    parts = {}
    for axial, twin in mesh.twins.items():
        law = getattr(model_bodies[axial], "shear_law", None)
        if law:
            parts[twin] = law
    soil = HystereticSoil.of(parts, mesh) if parts else None
    return soil if soil is not None and soil.elements.size else None
