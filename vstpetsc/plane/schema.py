"""The tables of a plane-strain case (interface.md, "Plane strain (2-D)"):
[mesh], [[region]], [[boundary]], [[interface]], [[gauge]] with x = [x, y],
[gravity] along y, and [[water]] (hydrostatic, uplift, Westergaard:
docs/water.md).  A case
with a [mesh] table is 2-D; the 1-D tables are refused in it.  Names of regions and curves are checked against the
mesh when the model reads it (vstpetsc.plane.model); nothing here reads
the mesh or imports PETSc."""

import math
import os
from dataclasses import dataclass, field

import numpy as np

from vstpetsc.results.plane_layout import COMPONENTS
from vstpetsc.input.checker import is_number, name_problem, show
from vstpetsc.input.tables import read_gravity
from vstpetsc.materials import mkz
from vstpetsc.spacetime.history import History

ONE_D = ("body", "contact", "bc", "soil")
TOP = ("time", "output", "units", "gravity", "gauge", "mesh", "region", "boundary", "interface",
       "water")
GENERATED = {"rectangle": ("x", "y", "nx", "ny", "triangles", "joints"),
             "dam": ("height", "crest", "upstream", "downstream", "foundation_depth",
                     "foundation_width", "h", "reservoir")}
RESERVOIR_KEYS = ("level", "length")
REGION_KEYS = ("name", "E", "nu", "Vs", "Vp", "rho", "damping", "mass", "v0", "u0", "shear_law",
               "confinement")
BOUNDARY_KEYS = ("name", "type", "value", "rock", "incident", "motion")
TYPES = ("fixed", "velocity", "traction", "absorbing")
CONFINEMENT = ("p_ref", "exponent")
MASSES = ("averaged", "consistent", "lumped")
MOTIONS = ("incident", "outcrop")
INTERFACE_KEYS = ("name", "friction", "formulation", "penalty")
FORMULATIONS = ("power", "seed")
WATER_KEYS = ("name", "level", "rho", "faces", "hydrodynamic", "uplift", "tailwater")
HYDRODYNAMIC = ("none", "westergaard", "acoustic")
# the acoustic water's own keys (its region of the mesh)
ACOUSTIC_KEYS = ("region", "bulk", "far", "bottom")
WATER_BULK = 2.2e9          # fresh water's bulk modulus near 10 C (Pa): c = 1483 m/s at rho 1000


@dataclass
class MeshSpec:
    """[mesh]: a Gmsh ``file`` (absolute path), or a generated mesh:
    ``kind`` "rectangle" or "dam" with its ``params``."""

    kind: str
    file: str | None = None
    params: dict = field(default_factory=dict)


@dataclass
class RegionSpec:
    """A [[region]]: Lame's lambda, mu and rho; damping (alpha, beta);
    uniform initial velocity and displacement (x, y)."""

    name: str
    lam: float
    mu: float
    rho: float
    damping: tuple = (0.0, 0.0)
    mass: str = "averaged"
    v0: tuple = (0.0, 0.0)
    u0: tuple = (0.0, 0.0)
    shear_law: dict = None      # {"gamma_ref", "beta", "s"} of MKZ (issue 46), None: linear
    confinement: dict = None    # {"p_ref", "exponent"} (vstpetsc.plane.confinement), None: none
    bulk: float = 0.0           # > 0: an acoustic water's stand-in (vstpetsc.plane.reservoir)

    @property
    def vp(self):
        return ((self.lam + 2 * self.mu) / self.rho) ** 0.5

    @property
    def vs(self):
        return (self.mu / self.rho) ** 0.5


@dataclass
class CurveSpec:
    """A [[boundary]] along the curve ``name``: ``values`` {component:
    History} (velocity, traction; fixed: both 0), or for "absorbing" the
    ``rock`` (rho, Vp, Vs; None: the adjacent cells') and the ``incident``
    wave's particle velocity {component: History} (outcrop records halved)."""

    name: str
    type: str
    values: dict = field(default_factory=dict)
    rock: tuple | None = None
    incident: dict = field(default_factory=dict)


@dataclass
class InterfaceSpec:
    """An [[interface]] along the curve ``name``: the Coulomb coefficient
    ``friction`` (None: no shear), the penalty's ``formulation`` and its
    ``penalty`` per unit length of the curve (None: the default rule)."""

    name: str
    friction: float | None = None
    formulation: str = "power"
    penalty: float | None = None


@dataclass
class WaterSpec:
    """A [[water]] table: the free surface's y ``level``, the water's
    ``rho`` and the curves ``faces`` it wets; ``hydrodynamic`` "none",
    "westergaard" or "acoustic"; ``uplift`` the [[interface]] it enters
    (None: none) with the ``tailwater`` level at its other end (None: no
    water there); an acoustic water's ``acoustic`` (AcousticSpec)."""

    name: str
    level: float
    rho: float
    faces: tuple
    hydrodynamic: str = "none"
    uplift: str | None = None
    tailwater: float | None = None
    acoustic: object = None


@dataclass
class AcousticSpec:
    """The acoustic water's region of the mesh, its ``bulk`` modulus, the
    curve ``far`` that absorbs plane waves (None: none) and the ``bottom``
    curve with its reflection coefficient ``alpha`` (None: none)."""

    region: str
    bulk: float
    far: str | None = None
    bottom: str | None = None
    alpha: float = 1.0

    def sound(self, rho):
        """The speed of sound c = sqrt(bulk / rho)."""
        return math.sqrt(self.bulk / rho)


@dataclass
class PlaneSpec:
    mesh: MeshSpec
    regions: list
    boundaries: list
    interfaces: list = field(default_factory=list)
    waters: list = field(default_factory=list)


@dataclass
class PlaneGauge:
    """A [[gauge]] of a 2-D case: a point (x, y)."""

    name: str
    x: tuple


def is_plane(doc):
    return isinstance(doc, dict) and "mesh" in doc


def read_start(chk, doc):
    """{"plane": PlaneSpec, "gauges": [...], "gravity_axis": "y"} after
    reporting every problem of the 2-D tables."""
    for key in ONE_D:
        if key in doc:
            chk.add(key, f"[[{key}]] is a 1-D table; a case with [mesh] is plane strain "
                    "(use [[region]] and [[boundary]])")
    chk.unknown({k: v for k, v in doc.items() if k not in ONE_D}, TOP, "")
    mesh = read_mesh(chk, chk.table(doc, "mesh", "mesh", required=True))
    regions = read_regions(chk, chk.tables(doc, "region"))
    boundaries = read_boundaries(chk, chk.tables(doc, "boundary"))
    interfaces = read_interfaces(chk, chk.tables(doc, "interface"), boundaries)
    return {"plane": PlaneSpec(mesh, regions, boundaries, interfaces),
            "gauges": read_gauges(chk, chk.tables(doc, "gauge"))}


def read_rest(chk, doc, parts):
    """The rest of a plane-strain case's parts (no bodies, pairs, ends or
    soil) into ``parts``."""
    parts["gravity"] = read_gravity(chk, chk.table(doc, "gravity", "gravity", required=False),
                                    [])
    moved = [r.name for r in parts["plane"].regions if any(r.u0)]
    if parts["gravity"] is not None and parts["gravity"].initial == "static" and moved:
        chk.add("gravity.initial", f"\"static\" computes the initial displacements; "
                f"region {moved[0]!r} gives u0 as well")
    static = parts["gravity"] is not None and parts["gravity"].initial == "static"
    for i, r in enumerate(parts["plane"].regions):
        if r.confinement is not None and not static:
            chk.add(f"region[{i}] ({r.name}).confinement", "needs [gravity] with initial = "
                    "\"static\" (each cell's moduli come from its mean stress there)")
    parts["plane"].waters = read_waters(chk, chk.tables(doc, "water"), parts["gravity"],
                                        "gravity" in doc, _interface_names(doc))
    parts.update(bodies=[], contacts=[], bcs=[], soils=[])


def read_mesh(chk, tbl):
    chk.unknown(tbl, ("file",) + tuple(GENERATED), "mesh")
    given = [k for k in ("file",) + tuple(GENERATED) if k in tbl]
    if len(given) != 1:
        chk.add("mesh", "give exactly one of file, rectangle, dam" +
                (f" (got {', '.join(given)})" if given else ""))
        return None
    kind = given[0]
    if kind == "file":
        name = chk.string(tbl, "file", "mesh")
        if name is None:
            return None
        path = os.path.join(chk.folder, os.path.expanduser(name))
        if not os.path.isfile(path):
            chk.add("mesh.file", f"no such file: {name}")
            return None
        chk.inputs.append(path)
        return MeshSpec("file", file=path)
    params = tbl[kind]
    where = f"mesh.{kind}"
    if not isinstance(params, dict):
        chk.add(where, f"must be a table, got {show(params)}")
        return None
    chk.unknown(params, GENERATED[kind], where)
    return (_rectangle if kind == "rectangle" else _dam)(chk, params, where)


def _rectangle(chk, p, where):
    out = {}
    for key in ("x", "y"):
        pair = _numbers(chk, p.get(key), f"{where}.{key}", "[low, high]")
        if pair is None:
            return None
        if not pair[0] < pair[1]:
            chk.add(f"{where}.{key}", f"must be [low, high] with low < high, got {list(pair)}")
            return None
        out[key] = pair
    out["nx"], out["ny"] = (chk.integer(p, k, where) for k in ("nx", "ny"))
    out["triangles"] = chk.boolean(p, "triangles", where)
    if None in out.values():
        return None
    nx, ny = out["nx"], out["ny"]
    if _too_big(chk, where, nx * ny * (2 if out["triangles"] else 1), (nx + 1) * (ny + 1)):
        return None
    out["joints"] = _joints(chk, p.get("joints", {}), f"{where}.joints", out)
    return None if out["joints"] is None else MeshSpec("rectangle", params=out)


def _joints(chk, joints, where, p):
    """{name: y} of horizontal inner curves (interfaces' curves) along the
    rectangle's grid rows strictly inside it."""
    if not isinstance(joints, dict):
        chk.add(where, f"must be a table {{name = y}}, got {show(joints)}")
        return None
    (y0, y1), ny = p["y"], p["ny"]
    out = {}
    for name, y in joints.items():
        if name_problem(name):
            chk.add(f"{where}.{name}", f"the joint's name {name_problem(name)}")
            return None
        row = (y - y0) / (y1 - y0) * ny if is_number(y) and math.isfinite(y) else None
        if row is None or not 0 < round(row) < ny or abs(row - round(row)) > 1e-9 * ny:
            chk.add(f"{where}.{name}", f"must be the y of a grid row inside the rectangle "
                    f"(y0 + k (y1 - y0) / ny, 0 < k < ny), got {show(y)}")
            return None
        if name in ("left", "right", "bottom", "top"):
            chk.add(f"{where}.{name}", "is a name of the rectangle's own curves")
            return None
        out[name] = int(round(row))
    return out


def _dam(chk, p, where):
    """[mesh] dam: the numbers, the faces (slopes or polylines), the
    optional reservoir, then the profile's geometry (one line naming the
    key: vstpetsc.plane.dam_mesh's checks, those the mesh would fail) and
    the mesh's size."""
    from vstpetsc.plane import dam_mesh

    before = len(chk.problems)
    # with two polylines the crest is theirs
    polylines = all(isinstance(p.get(k), list) for k in ("upstream", "downstream"))
    out = {k: _dam_face(chk, p, k, where) if k in ("upstream", "downstream") else
           chk.number(p, k, where, required=k != "crest" or not polylines,
                      positive=k != "crest", minimum=0.0)
           for k in GENERATED["dam"] if k != "reservoir"}
    out["reservoir"] = _reservoir(chk, p.get("reservoir"), f"{where}.reservoir")
    if len(chk.problems) > before:
        return None
    try:
        up, down = dam_mesh.faces(*(out[k] for k in ("height", "crest", "upstream",
                                                      "downstream")))
        dam_mesh.check_fit(up, down, out["foundation_width"], out["reservoir"])
    except dam_mesh.ProfileError as exc:
        chk.add(f"{where}.{exc.key}", exc.message)
        return None
    # about a node an h^2 of area; the dam's (and the water's) triangles two a node
    solid, water = dam_mesh.areas(up, down, out["reservoir"])
    above = (solid + water) / out["h"] ** 2
    rock = out["foundation_width"] * out["foundation_depth"] / out["h"] ** 2
    if _too_big(chk, f"{where}.h", 2 * above + rock, above + rock):
        return None
    return MeshSpec("dam", params=out)


def _dam_face(chk, p, key, where):
    """A dam's face: a slope (a number > 0, horizontal : vertical) or a
    polyline, a list of at least two [x, y] points (their heights
    vstpetsc.plane.dam_mesh checks); None after reporting."""
    val, name = p.get(key), f"{where}.{key}"
    if not isinstance(val, list):
        return chk.number(p, key, where, positive=True)
    if len(val) < 2 or not all(isinstance(q, list) and len(q) == 2 and all(map(is_number, q))
                               for q in val):
        chk.add(name, "must be a slope (a number) or a list of at least two [x, y] points, "
                f"got {show(val)}")
        return None
    points = [_numbers(chk, q, f"{name}[{i}]", "[x, y]") for i, q in enumerate(val)]
    return None if None in points else [list(q) for q in points]


def _reservoir(chk, val, where):
    """The optional reservoir { level, length } (None when absent or after
    reporting)."""
    if val is None:
        return None
    if not isinstance(val, dict):
        chk.add(where, f"must be a table {{ level = y, length = m }}, got {show(val)}")
        return None
    chk.unknown(val, RESERVOIR_KEYS, where)
    out = {k: chk.number(val, k, where, positive=True) for k in RESERVOIR_KEYS}
    return None if None in out.values() else out


def _too_big(chk, where, cells, nodes):
    """Whether a generated mesh of about ``cells`` cells and ``nodes``
    nodes is too big to run here (reported)."""
    from vstpetsc.plane.mesh_checks import size_problem

    problem = size_problem(cells, nodes)
    if problem:
        chk.add(where, problem)
    return problem is not None


def _named(chk, tbl, kind, i, keys, seen, twice):
    """(name, where to report) of table i of [[kind]] after checking its
    keys and that no earlier table had its name (``twice``: the message)."""
    where = f"{kind}[{i}]"
    chk.unknown(tbl, keys, where)
    name = chk.string(tbl, "name", where)
    problem = None if name is None else name_problem(name)
    if problem:                 # it names an HDF5 group and files
        chk.add(f"{where}.name", problem)
        name = None
    elif name in seen:
        chk.add(f"{where}.name", f"{twice} {name!r}")
    seen.add(name)
    return name, f"{where} ({name})"


def read_regions(chk, tables):
    if not tables:
        chk.add("region", "at least one [[region]] table is required")
    out, seen = [], set()
    for i, tbl in enumerate(tables):
        name, where = _named(chk, tbl, "region", i, REGION_KEYS, seen, "duplicate region")
        rho = chk.number(tbl, "rho", where, positive=True)
        lame = _lame(chk, tbl, where, rho)
        damping = _pair(chk, tbl, "damping", where, ("alpha", "beta"), (0.0, 0.0))
        mass = chk.string(tbl, "mass", where, required=False, default="averaged",
                          choices=MASSES)
        v0, u0 = (_vector(chk, tbl, key, where) for key in ("v0", "u0"))
        law = _shear_law(chk, tbl, where)
        confinement = _confinement(chk, tbl, where)
        parts = (name, rho, lame, damping, mass, v0, u0)
        if None not in parts and law is not False and confinement is not False:
            out.append(RegionSpec(name, *lame, rho, damping, mass, v0, u0, law, confinement))
    return out


def _shear_law(chk, tbl, where):
    """A region's ``shear_law`` (docs/nonlinear-soil.md section 7): None
    when absent, {gamma_ref, beta, s} of the MKZ backbone, or False after
    reporting."""
    if "shear_law" not in tbl:
        return None
    name, value = f"{where}.shear_law", tbl["shear_law"]
    if not isinstance(value, dict):
        chk.add(name, f"must be a table {{ model = \"{mkz.NAME}\", gamma_ref = ... }}, "
                f"got {show(value)}")
        return False
    model = value.get("model")
    if model != mkz.NAME:
        chk.add(f"{name}.model", f"must be {mkz.NAME!r}, got "
                f"{show(model) if model is not None else 'nothing'}")
        return False
    chk.unknown(value, ("model",) + mkz.PARAMETERS, name)
    law = {key: chk.number(value, key, name, positive=True, required=key not in mkz.DEFAULTS,
                           default=mkz.DEFAULTS.get(key)) for key in mkz.PARAMETERS}
    if None in law.values():
        return False
    if law["s"] > 1.0:
        chk.add(f"{name}.s", f"must be <= 1 (the backbone would soften beyond its peak), "
                f"got {law['s']:g}")
        return False
    return law


def _confinement(chk, tbl, where):
    """A region's ``confinement`` (docs/nonlinear-soil.md section 8): None
    when absent, {p_ref, exponent}, or False after reporting."""
    if "confinement" not in tbl:
        return None
    name, value = f"{where}.confinement", tbl["confinement"]
    if not isinstance(value, dict):
        chk.add(name, f"must be a table {{ p_ref = ..., exponent = ... }}, got {show(value)}")
        return False
    chk.unknown(value, CONFINEMENT, name)
    p_ref = chk.number(value, "p_ref", name, positive=True)
    exponent = chk.number(value, "exponent", name, minimum=0.0, maximum=1.0)
    if None in (p_ref, exponent):
        return False
    return {"p_ref": p_ref, "exponent": exponent}


def _lame(chk, tbl, where, rho):
    """(lambda, mu) from E with nu, Vs with Vp, or Vs with nu."""
    given = tuple(k for k in ("E", "nu", "Vs", "Vp") if k in tbl)
    if given not in (("E", "nu"), ("Vs", "Vp"), ("nu", "Vs")):
        chk.add(where, f"give E with nu, Vs with Vp, or Vs with nu (got {', '.join(given) or 'none'})")
        return None
    nu = chk.number(tbl, "nu", where, minimum=-0.999, maximum=0.4999) if "nu" in tbl else None
    if "E" in tbl:
        E = chk.number(tbl, "E", where, positive=True)
        if None in (E, nu):
            return None
        return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    vs = chk.number(tbl, "Vs", where, positive=True)
    if vs is None or rho is None:
        return None
    mu = rho * vs * vs
    if "Vp" in tbl:
        vp = chk.number(tbl, "Vp", where, positive=True)
        if vp is not None and vp <= 2 ** 0.5 * vs:
            chk.add(f"{where}.Vp", f"must exceed sqrt(2) Vs = {2 ** 0.5 * vs:g} "
                    f"(lambda > 0 ... a positive Poisson's ratio), got {vp:g}")
            return None
        return None if vp is None else (rho * vp * vp - 2 * mu, mu)
    return None if nu is None else (2 * mu * nu / (1 - 2 * nu), mu)


def _pair(chk, tbl, key, where, names, default):
    val = tbl.get(key)
    if val is None:
        return default
    if not isinstance(val, dict):
        chk.add(f"{where}.{key}", f"must be a table {{{', '.join(names)}}}, got {show(val)}")
        return None
    chk.unknown(val, names, f"{where}.{key}")
    got = [chk.number(val, n, f"{where}.{key}", required=False, default=0.0, minimum=0.0)
           for n in names]
    return None if None in got else tuple(got)


def _numbers(chk, val, name, form):
    """Two finite numbers in the range of doubles as a tuple (None after
    reporting)."""
    if not (isinstance(val, list) and len(val) == 2 and all(map(is_number, val))):
        chk.add(name, f"must be {form} (two numbers), got {show(val)}")
        return None
    out = tuple(chk.real(name, a) for a in val)
    return None if None in out else out


def _vector(chk, tbl, key, where):
    return _numbers(chk, tbl.get(key, [0.0, 0.0]), f"{where}.{key}", "[x, y]")


def read_boundaries(chk, tables):
    out, seen = [], set()
    for i, tbl in enumerate(tables):
        name, where = _named(chk, tbl, "boundary", i, BOUNDARY_KEYS, seen,
                             "a second [[boundary]] on curve")
        kind = chk.string(tbl, "type", where, choices=TYPES)
        spec = None if kind is None else _boundary(chk, tbl, where, name, kind)
        if name is not None and spec is not None:
            out.append(spec)
    return out


def read_interfaces(chk, tables, boundaries):
    out, seen = [], set()
    bounded = {b.name for b in boundaries}
    for i, tbl in enumerate(tables):
        name, where = _named(chk, tbl, "interface", i, INTERFACE_KEYS, seen,
                             "a second [[interface]] on curve")
        if name in bounded:
            chk.add(f"{where}.name", f"curve {name!r} has a [[boundary]]: an interface lies "
                    "inside the mesh, between two cells")
        mu = chk.number(tbl, "friction", where, required=False, minimum=0.0)
        form = chk.string(tbl, "formulation", where, required=False, default="power",
                          choices=FORMULATIONS)
        penalty = chk.number(tbl, "penalty", where, required=False, positive=True)
        bad = (("friction" in tbl and mu is None) or ("penalty" in tbl and penalty is None))
        if name is not None and form is not None and not bad:
            out.append(InterfaceSpec(name, mu, form, penalty))
    return out


def read_waters(chk, tables, gravity, given, interfaces):
    """The [[water]] tables (docs/water.md): hydrostatic on named faces,
    which the model checks against the mesh (vstpetsc.plane.water.check),
    with Westergaard's added masses and an interface's uplift.
    ``gravity``: the [gravity] read (None: absent or bad, ``given`` says
    which); ``interfaces``: the [[interface]] tables' names."""
    out, seen = [], set()
    for i, tbl in enumerate(tables):
        name, where = _named(chk, tbl, "water", i, WATER_KEYS + ACOUSTIC_KEYS, seen,
                             "a second [[water]] named")
        kind = chk.string(tbl, "hydrodynamic", where, required=False, default="none",
                          choices=HYDRODYNAMIC)
        acoustic = _acoustic(chk, tbl, where, kind)
        level = chk.number(tbl, "level", where)
        rho = chk.number(tbl, "rho", where, required=False, default=1000.0, positive=True)
        faces = _faces(chk, tbl.get("faces"), f"{where}.faces")
        uplift = _uplift(chk, tbl, where, interfaces)
        if gravity is None and not given:
            chk.add(where, "needs [gravity] (g along y): the water's weight is what loads "
                    "the dam")
        elif gravity is not None and np.any(gravity.g.f > 0):
            chk.add("gravity.g", f"water {name!r} needs g <= 0 (downward along y) at every "
                    "point of its history")
        if None not in (name, level, rho, faces, kind, uplift, acoustic):
            out.append(WaterSpec(name, level, rho, faces, kind, *uplift,
                                 acoustic=acoustic if kind == "acoustic" else None))
    return out


def _interface_names(doc):
    """The names the [[interface]] tables give (whatever else is wrong
    with them: that is reported on its own)."""
    tables = doc.get("interface", [])
    return [t.get("name") for t in tables if isinstance(t, dict)] \
        if isinstance(tables, list) else []


def _acoustic(chk, tbl, where, kind):
    """The AcousticSpec of an acoustic [[water]] (False for another kind,
    whose table may not hold the acoustic keys; None after reporting)."""
    if kind != "acoustic":
        for key in ACOUSTIC_KEYS:
            if key in tbl:
                chk.add(f"{where}.{key}", f"is the acoustic water's (hydrodynamic = "
                        f"\"acoustic\"), not the {kind!r} water's")
                return None
        return False
    if "region" not in tbl:
        chk.add(f"{where}.region", "missing: the acoustic water is a region of the mesh "
                "(its cells, without a [[region]] table)")
        return None
    region = chk.string(tbl, "region", where)
    bulk = chk.number(tbl, "bulk", where, required=False, default=WATER_BULK, positive=True)
    far = chk.string(tbl, "far", where, required=False)
    bottom = _bottom(chk, tbl.get("bottom"), f"{where}.bottom")
    if None in (region, bulk, bottom) or ("far" in tbl and far is None):
        return None
    return AcousticSpec(region, bulk, far, *bottom)


def _bottom(chk, val, where):
    """(curve or None, alpha) of an acoustic water's bottom table, or None
    after reporting."""
    if val is None:
        return None, 1.0
    if not isinstance(val, dict):
        chk.add(where, f"must be a table {{ name = \"curve\", alpha = 0.8 }}, got {show(val)}")
        return None
    for key in val:
        if key not in ("name", "alpha"):
            chk.add(f"{where}.{key}", "unknown key (name, alpha)")
            return None
    name = chk.string(val, "name", where)
    # alpha < 0 (a bottom softer than water, Fenves and Chopra) is refused: the
    # dashpot rho c (1 - alpha) / (1 + alpha) grows without bound towards -1
    alpha = chk.number(val, "alpha", where, required=False, default=1.0, minimum=0.0,
                       maximum=1.0)
    return None if None in (name, alpha) else (name, alpha)


def _uplift(chk, tbl, where, interfaces):
    """(uplift interface or None, tailwater or None), or None after
    reporting: an interface that no [[interface]] names, a tailwater
    without uplift or not a number."""
    uplift = chk.string(tbl, "uplift", where, required=False)
    if "uplift" in tbl and uplift is None:
        return None
    if uplift is not None and uplift not in interfaces:
        chk.add(f"{where}.uplift", f"{uplift!r} is not an [[interface]] of the case "
                f"(interfaces: {', '.join(map(str, interfaces)) or 'none'})")
        return None
    if "tailwater" in tbl and uplift is None:
        chk.add(f"{where}.tailwater", "needs uplift (the interface whose far end the "
                "tailwater reaches)")
        return None
    tailwater = chk.number(tbl, "tailwater", where, required=False)
    if "tailwater" in tbl and tailwater is None:
        return None
    return uplift, tailwater


def _faces(chk, val, where):
    """A non-empty list of distinct curve names as a tuple (None after
    reporting)."""
    if not (isinstance(val, list) and val and all(isinstance(v, str) for v in val)):
        chk.add(where, f"must be a non-empty list of curve names, got "
                f"{show(val) if val is not None else 'nothing'}")
        return None
    if len(set(val)) < len(val):
        chk.add(where, f"names a curve twice: {val}")
        return None
    return tuple(val)


def _boundary(chk, tbl, where, name, kind):
    allowed = {"fixed": (), "velocity": ("value",), "traction": ("value",),
               "absorbing": ("rock", "incident", "motion")}[kind]
    for key in ("value", "rock", "incident", "motion"):
        if key in tbl and key not in allowed:
            chk.add(f"{where}.{key}", f"not a key of a {kind!r} boundary")
            return None
    if kind == "fixed":
        return CurveSpec(name, kind, {c: History() for c in COMPONENTS})
    if kind != "absorbing":
        values = _components(chk, tbl, "value", where, required=True)
        return None if values is None else CurveSpec(name, kind, values)
    rock = _rock(chk, tbl.get("rock"), f"{where}.rock")
    incident = _components(chk, tbl, "incident", where, required=False)
    motion = chk.string(tbl, "motion", where, required=False, default="incident",
                        choices=MOTIONS)
    if rock is False or incident is None or motion is None:
        return None
    if motion == "outcrop":
        if not incident:
            chk.add(f"{where}.motion", "\"outcrop\" halves an incident record: give incident")
            return None
        incident = {c: h.scaled(0.5) for c, h in incident.items()}
    return CurveSpec(name, kind, rock=rock, incident=incident)


def _components(chk, tbl, key, where, required):
    """{component: History} of a {x = ..., y = ...} table (None after
    reporting; {} when absent and optional)."""
    val = tbl.get(key)
    name = f"{where}.{key}"
    if val is None:
        if required:
            chk.add(name, "missing required key ({ x = HISTORY, y = HISTORY })")
            return None
        return {}
    if not isinstance(val, dict) or not val:
        chk.add(name, f"must be a table {{ x = HISTORY, y = HISTORY }}, got {show(val)}")
        return None
    chk.unknown(val, COMPONENTS, name)
    out = {c: chk.history(val, c, name, "t", records=True) for c in COMPONENTS if c in val}
    return None if None in out.values() else out


def _rock(chk, val, where):
    """(rho, Vp, Vs), None when absent, False after reporting."""
    if val is None:
        return None
    if not isinstance(val, dict):
        chk.add(where, f"must be a table {{ rho, Vs, Vp }}, got {show(val)}")
        return False
    chk.unknown(val, ("rho", "Vs", "Vp"), where)
    got = [chk.number(val, k, where, positive=True) for k in ("rho", "Vp", "Vs")]
    return False if None in got else tuple(got)


def read_gauges(chk, tables):
    out, seen = [], set()
    for i, tbl in enumerate(tables):
        where = f"gauge[{i}]"
        chk.unknown(tbl, ("name", "x"), where)
        name = chk.string(tbl, "name", where)
        problem = None if name is None else name_problem(name)
        if problem is None and name in seen:
            problem = "duplicate name"
        if problem:
            chk.add(f"{where}.name", problem)
            continue
        seen.add(name)
        x = _vector(chk, {"x": tbl.get("x")}, "x", where)
        if name is not None and x is not None:
            out.append(PlaneGauge(name, x))
    return out
