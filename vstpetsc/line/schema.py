"""The tables of a case of bodies on a line and their validation
(docs/case-file.md): [[body]], [[contact]], [[bc]], [[gauge]], [[soil]];
the tables every case has are :mod:`vstpetsc.input.tables`, the reading
of a whole document :mod:`vstpetsc.input.schema`.  Laws validate their own
keys through the registries of :mod:`vstpetsc.line.laws`.  Nothing here
imports PETSc.
"""

from dataclasses import dataclass, field

from vstpetsc import materials
from vstpetsc.input.checker import MISSING, is_number, show
from vstpetsc.input.tables import named_table, read_gravity
from vstpetsc.line import laws, layers, shear
from vstpetsc.spacetime.history import History

WALL = "wall"
ENDS = ("left", "right")
TOP = ("time", "output", "body", "contact", "bc", "units", "gravity", "gauge", "soil")
GAUGE_KEYS = ("name", "body", "x")
BODY_KEYS = ("name", "x", "elements", "E", "rho", "area", "v0", "u0", "damping", "foundation",
             "mass", "layers") + shear.BODY_KEYS + materials.BODY_KEYS
# the element mass matrix rho A h / 12 [[6 - o, o], [o, 6 - o]] by its off-diagonal o
MASSES = {"consistent": 2.0, "averaged": 1.0, "lumped": 0.0}
DEFAULT_MASS = "averaged"
MAX_ELEMENTS = 10**8      # per body


@dataclass
class Body:
    """A [[body]]: E, rho and area are profiles along x (History of x;
    constant for a number), damping = (alpha, beta) of Rayleigh's
    C = alpha M + beta K, foundation = (stiffness, damping) per length.
    G, v0_shear, u0_shear: the shear component (issue 27; G a profile of x,
    :class:`vstpetsc.line.shear.ShearModulus` when Vs was given), all None for a
    body without one.  cells: ((x_left, x_right, elements), ...) of a body
    given by ``layers`` (:mod:`vstpetsc.line.layers`), () for equal elements."""

    name: str
    x: tuple
    elements: int
    E: History
    rho: History
    area: History = field(default_factory=lambda: History(value=1.0))
    v0: History = field(default_factory=History)
    u0: History = field(default_factory=History)
    damping: tuple = (0.0, 0.0)
    foundation: tuple = (0.0, 0.0)
    mass: str = DEFAULT_MASS
    G: object = None
    v0_shear: History | None = None
    u0_shear: History | None = None
    cells: tuple = ()
    shear_law: list | None = None

    @property
    def has_shear(self):
        return self.G is not None

    def node_x(self):
        """The body's node coordinates (a node on every layer boundary)."""
        return layers.node_coordinates(self.x, self.elements, self.cells)


@dataclass
class GaugeSpec:
    """A [[gauge]]: a point ``x`` (global coordinate) of body number ``body``."""

    name: str
    body: int
    x: float


@dataclass
class ContactSpec:
    """A [[contact]]: ``left`` body's right end against ``right`` body's
    left end; one of them None for a rigid wall at ``wall``.  ``friction``:
    Coulomb's mu (None: no shear resistance); ``wall_shear_velocity``: the
    wall's shear velocity history (a wall pair with friction, else None)."""

    left: int | None
    right: int | None
    formulation: str
    params: dict
    wall: float | None = None
    friction: float | None = None
    wall_shear_velocity: History | None = None


@dataclass
class BoundarySpec:
    """A [[bc]] at an ``end`` of body number ``body``, acting on its
    ``component`` ("axial" or "shear") motion."""

    body: int
    end: str
    type: str
    params: dict
    component: str = "axial"


def read_start(chk, doc):
    """The parts a 1-D case has before the shared tables: its top-level
    keys checked."""
    chk.unknown(doc, TOP, "")
    return {"plane": None}


def read_rest(chk, doc, parts):
    """The bodies, pairs, ends, gravity, gauges and soils into ``parts``."""
    bodies, names = read_bodies(chk, doc)
    contacts = read_contacts(chk, chk.tables(doc, "contact"), bodies, names)
    bcs = read_bcs(chk, chk.tables(doc, "bc"), bodies, names, contacts)
    parts["gravity"] = read_gravity(chk, chk.table(doc, "gravity", "gravity", required=False),
                                    bodies)
    parts["gauges"] = read_gauges(chk, chk.tables(doc, "gauge"), bodies, names)
    parts["soils"] = [laws.soil.read(chk, tbl, f"soil[{i}]", bodies, names)
                      for i, tbl in enumerate(chk.tables(doc, "soil"))]
    materials.check_alone(chk, bodies, contacts, parts["soils"])
    parts.update(bodies=bodies, contacts=contacts, bcs=bcs)


def read_gauges(chk, tables, bodies, names):
    """[[gauge]] tables: a list of GaugeSpec."""
    gauges, seen = [], {}
    for i, tbl in enumerate(tables):
        name, where = named_table(chk, tbl, "gauge", i, GAUGE_KEYS, seen)
        if name is not None:
            seen[name] = i
        body = chk.string(tbl, "body", where)
        if body is not None and body not in names:
            chk.add(f"{where}.body", f"unknown body {body!r} (bodies: {', '.join(names) or 'none'})")
            body = None
        x = chk.number(tbl, "x", where)
        b = None if body is None else bodies[names[body]]
        if b is not None and x is not None and not b.x[0] <= x <= b.x[1]:
            chk.add(f"{where}.x", f"{x:g} lies outside body {body!r}, which spans "
                    f"[{b.x[0]:g}, {b.x[1]:g}]")
            x = None
        if None not in (name, b, x):
            gauges.append(GaugeSpec(name, names[body], float(x)))
    return gauges


def read_bodies(chk, doc):
    tables = chk.tables(doc, "body")
    if not tables and "body" not in doc:
        chk.add("body", "at least one [[body]] table is required")
    bodies, names = [], {}
    for i, tbl in enumerate(tables):
        name, body = _body(chk, tbl, i, names)
        bodies.append(body)
        if name is not None:
            names[name] = i
    good = [(i, b) for i, b in enumerate(bodies) if b is not None]
    for (i, a), (j, b) in zip(good, good[1:]):
        if b.x[0] < a.x[1]:
            chk.add(f"body[{j}] ({b.name}).x",
                    f"overlaps or precedes body[{i}] ({a.name}) ending at {a.x[1]:g}; "
                    f"bodies must be listed left to right without overlap")
    return bodies, names


def _body(chk, tbl, i, names):
    """(its usable name or None, the Body or None after reporting)."""
    name, where = named_table(chk, tbl, "body", i, BODY_KEYS, names, reserved=WALL)
    x = _interval(chk, tbl, where)
    ne = chk.integer(tbl, "elements", where)
    if ne is not None and ne > MAX_ELEMENTS:
        chk.add(f"{where}.elements", f"at most {MAX_ELEMENTS}, got {ne}")
        ne = None
    profile = layers.read(chk, tbl, where, x, ne) if "layers" in tbl else None
    if "layers" in tbl:
        E, rho = (None, None) if profile is None else (profile.E, profile.rho)
    else:
        E, rho = (_material(chk, tbl, where, key, x, None) for key in ("E", "rho"))
    area = _material(chk, tbl, where, "area", x, 1.0)
    fields = (name, x, ne, E, rho, area,
              chk.history(tbl, "v0", where, "x"), chk.history(tbl, "u0", where, "x"),
              _pair_of(chk, tbl, "damping", where, ("alpha", "beta")),
              _pair_of(chk, tbl, "foundation", where, ("stiffness", "damping")),
              chk.string(tbl, "mass", where, required=False, default=DEFAULT_MASS,
                         choices=tuple(MASSES)))
    sheared = None if "layers" in tbl and profile is None else shear.read_body(
        chk, tbl, where, rho, lambda key: _material(chk, tbl, where, key, x, None),
        G=profile and profile.G)
    # a failed shear component was reported: its shear_law is not read
    law = None if sheared is None else materials.read(chk, tbl, where, x, sheared[0] is not None)
    if sheared is None or law is False or any(f is None for f in fields):
        return name, None
    body = Body(*fields, *sheared, cells=profile.cells if profile else (), shear_law=law)
    return name, (body if materials.covers(chk, body, where) else None)


def _material(chk, tbl, where, key, x, default):
    """A material profile that covers the body (a table must span it)."""
    prof = chk.profile(tbl, key, where, default)
    if prof is None or prof.t.size == 1 or x is None:
        return prof
    if prof.t[0] > x[0] or prof.t[-1] < x[1]:
        chk.add(f"{where}.{key}", f"the table covers x in [{prof.t[0]:g}, {prof.t[-1]:g}]; "
                f"the body spans [{x[0]:g}, {x[1]:g}]")
        return None
    return prof


def _pair_of(chk, tbl, key, where, names):
    """Two non-negative numbers of an inline table (0 when absent)."""
    sub = chk.table(tbl, key, f"{where}.{key}", required=False)
    chk.unknown(sub, names, f"{where}.{key}")
    vals = [chk.number(sub, n, f"{where}.{key}", required=False, default=0.0, minimum=0.0)
            for n in names]
    return None if None in vals else tuple(vals)


def _interval(chk, tbl, where):
    """The body's [left, right] end coordinates, or None."""
    if "x" not in tbl:
        chk.add(f"{where}.x", "missing required key")
        return None
    x = tbl["x"]
    if not isinstance(x, list) or len(x) != 2 or not all(map(is_number, x)):
        chk.add(f"{where}.x", f"must be [left, right] numbers, got {show(x)}")
    elif any(chk.real(f"{where}.x", c) is None for c in x):
        pass
    elif x[1] <= x[0]:
        chk.add(f"{where}.x", f"right end must exceed left end (length must be "
                f"positive), got {x}")
    else:
        return (float(x[0]), float(x[1]))
    return None


def read_contacts(chk, tables, bodies, names):
    contacts, ends_used = [], {}
    for i, tbl in enumerate(tables):
        where = f"contact[{i}]"
        form = chk.string(tbl, "formulation", where, required=False,
                          default=laws.penalty.DEFAULT_FORMULATION,
                          choices=tuple(laws.CONTACT))
        allowed = ("pair", "formulation", "wall") + (laws.CONTACT[form].KEYS if form else ()) \
            + shear.CONTACT_KEYS
        chk.unknown(tbl, allowed, where)
        params = laws.CONTACT[form].read(chk, tbl, where) if form else None
        friction = shear.read_friction(chk, tbl, where, form)
        pair = _pair(chk, tbl, where, bodies, names)
        if pair is None or params is None or friction is None:
            continue
        left, right, wall = pair
        friction = shear.check_pair(chk, where, bodies, left, right, friction)
        if friction is None:
            continue
        ends = [(left, "right"), (right, "left")]
        dup = [(e, ends_used[e]) for e in ends if e[0] is not None and e in ends_used]
        if dup:
            (body, side), other = dup[0]
            chk.add(f"{where}.pair", f"the {side} end of {bodies[body].name!r} is "
                    f"already in contact[{other}]")
            continue
        ends_used.update({e: i for e in ends if e[0] is not None})
        if _penetrates(chk, where, bodies, left, right, wall):
            continue
        contacts.append(ContactSpec(left, right, form, params, wall, *friction))
    return contacts


def _penetrates(chk, where, bodies, left, right, wall):
    """Whether the bodies' initial displacements u0 close the pair's gap
    below zero (reported); rounding of 1e-12 of the bodies' length is let
    pass."""
    ends = [(bodies[left], 1, 1.0)] if left is not None else []
    ends += [(bodies[right], 0, -1.0)] if right is not None else []
    gap = (bodies[right].x[0] if right is not None else wall) - \
        (bodies[left].x[1] if left is not None else wall)
    shut = sum(sign * float(body.u0(body.x[side])) for body, side, sign in ends)
    scale = max(body.x[1] - body.x[0] for body, _, _ in ends)
    if gap - shut >= -1e-12 * scale:
        return False
    chk.add(f"{where}.pair", f"the initial displacements (u0) make the bodies overlap by "
            f"{shut - gap:g} (the initial gap must be >= 0)")
    return True


def _pair(chk, tbl, where, bodies, names):
    """(left, right, wall) body numbers (None: the wall) of a pair, or None."""
    pair = chk.take(tbl, "pair", where, required=True)
    if pair is MISSING:
        return None
    if not isinstance(pair, list) or len(pair) != 2 or not all(isinstance(p, str) for p in pair):
        chk.add(f"{where}.pair", f"must be two names [\"left\", \"right\"], got {show(pair)}")
        return None
    a, b = pair
    missing = [p for p in pair if p != WALL and p not in names]
    if missing:
        chk.add(f"{where}.pair", f"unknown body {missing[0]!r} "
                f"(bodies: {', '.join(names) or 'none'})")
        return None
    if a == WALL and b == WALL:
        chk.add(f"{where}.pair", "needs at least one body")
        return None
    if any(p != WALL and bodies[names[p]] is None for p in pair):
        return None                 # that body's own problem is reported already
    left = None if a == WALL else names[a]
    right = None if b == WALL else names[b]
    if left is None or right is None:
        wall = chk.number(tbl, "wall", where)
        return None if wall is None else _wall_pair(chk, where, bodies, left, right, wall)
    if "wall" in tbl:
        chk.add(f"{where}.wall", "only for a pair with \"wall\"")
    elif right != left + 1:
        chk.add(f"{where}.pair", f"{a!r} and {b!r} are not neighbours listed left to "
                "right (a pair joins the right end of one body to the left end of the next)")
    else:
        gap = bodies[right].x[0] - bodies[left].x[1]
        return _checked_gap(chk, where, gap, (left, right, None))
    return None


def _wall_pair(chk, where, bodies, left, right, wall):
    """Check a wall's position against its body and the next body."""
    if right is None:                         # wall on the right of `left`
        body, nxt = bodies[left], bodies[left + 1] if left + 1 < len(bodies) else None
        if wall < body.x[1]:
            chk.add(f"{where}.wall", f"a wall on the right of {body.name!r} must be at "
                    f">= {body.x[1]:g} (its right end), got {wall:g}")
        elif nxt is not None and wall > nxt.x[0]:
            chk.add(f"{where}.wall", f"lies inside or beyond body {nxt.name!r} "
                    f"(which starts at {nxt.x[0]:g})")
        else:
            return _checked_gap(chk, where, wall - body.x[1], (left, None, wall))
        return None
    body, prv = bodies[right], bodies[right - 1] if right > 0 else None
    if wall > body.x[0]:
        chk.add(f"{where}.wall", f"a wall on the left of {body.name!r} must be at "
                f"<= {body.x[0]:g} (its left end), got {wall:g}")
    elif prv is not None and wall < prv.x[1]:
        chk.add(f"{where}.wall", f"lies inside or before body {prv.name!r} "
                f"(which ends at {prv.x[1]:g})")
    else:
        return _checked_gap(chk, where, body.x[0] - wall, (None, right, wall))
    return None


def _checked_gap(chk, where, gap, pair):
    if gap < 0:
        chk.add(f"{where}.pair", f"initial gap is negative ({gap:g})")
        return None
    return pair


def read_bcs(chk, tables, bodies, names, contacts):
    contact_ends = {}
    for k, c in enumerate(contacts):
        contact_ends[(c.left, "right")] = k
        contact_ends[(c.right, "left")] = k
    bcs, seen = [], {}
    for i, tbl in enumerate(tables):
        where = f"bc[{i}]"
        name = chk.string(tbl, "body", where)
        end = chk.string(tbl, "end", where, choices=ENDS)
        typ = chk.string(tbl, "type", where, choices=tuple(laws.BOUNDARY))
        component = chk.string(tbl, "component", where, required=False, default="axial",
                               choices=shear.COMPONENTS)
        law = laws.BOUNDARY.get(typ)
        chk.unknown(tbl, ("body", "end", "type", "component") + (law.KEYS if law else ()), where)
        params = law.read(chk, tbl, where) if law else None
        if name is not None and name not in names:
            chk.add(f"{where}.body", f"unknown body {name!r} "
                    f"(bodies: {', '.join(names) or 'none'})")
            continue
        if None in (name, end, typ, params, component) or bodies[names[name]] is None:
            continue
        key = (names[name], end, component)
        if _end_taken(chk, where, key, bodies, seen, contacts, contact_ends):
            continue
        seen[key] = i
        bcs.append(BoundarySpec(names[name], end, typ, params, component))
    return bcs


def _end_taken(chk, where, key, bodies, seen, contacts, contact_ends):
    """Whether the (body, end, component) of a bc cannot take it (reported):
    an end takes one bc per component; an axial bc or, with friction, a
    shear bc, not at a contact; a shear bc only on a body with a shear
    component."""
    body, end, component = key
    name = bodies[body].name
    pair = contact_ends.get((body, end))
    shear_bc = component == "shear"
    if shear_bc and not bodies[body].has_shear:
        chk.add(f"{where}.component", shear.no_shear_message(name))
    elif key in seen:
        chk.add(f"{where}.end", f"the {end} end of {name!r} already has "
                f"{'a shear bc, ' if shear_bc else ''}bc[{seen[key]}]")
    elif pair is not None and not shear_bc:
        chk.add(f"{where}.end", f"the {end} end of {name!r} is in "
                f"contact[{pair}]; an end takes a bc or a contact, not both")
    elif pair is not None and contacts[pair].friction is not None:
        chk.add(f"{where}.end", f"the {end} end of {name!r} is in contact[{pair}] with "
                "friction, which sets its shear; it takes no shear bc")
    else:
        return False
    return True
