"""Reading and validating a case file (TOML, see docs/case-file.md).

Every problem is reported as ``table.key: what is wrong``; all problems of a
file are collected before :class:`CaseError` is raised, so a user fixes them
in one go.  Nothing here imports PETSc.
"""

import math
import os
import tomllib
from dataclasses import dataclass, field

from vstpetsc.history import History

WALL = "wall"
FORMULATIONS = ("seed", "power")
BC_TYPES = ("fixed", "velocity", "traction")
ENDS = ("left", "right")
UNITS = {"length": "m", "time": "s", "mass": "kg"}
MAX_SLABS = 1e12          # beyond any run; guards int() and memory against typos
MAX_ELEMENTS = 10**8      # per body


class CaseError(ValueError):
    """A case file that cannot be run; ``problems`` holds one line per defect."""

    def __init__(self, problems):
        self.problems = list(problems)
        super().__init__("\n".join(self.problems))


@dataclass
class Body:
    name: str
    x: tuple
    elements: int
    E: float
    rho: float
    area: float = 1.0
    v0: History = field(default_factory=History)
    u0: History = field(default_factory=History)


@dataclass
class Contact:
    """A pair of facing ends: ``left`` body's right end against ``right``
    body's left end; one side may be a rigid wall (``None``) at ``wall``."""

    left: int | None
    right: int | None
    penalty: float | None = None
    formulation: str = "seed"
    wall: float | None = None


@dataclass
class BC:
    body: int
    end: str
    type: str
    value: History


@dataclass
class Case:
    dt: float
    end: float
    nslabs: int
    bodies: list
    contacts: list
    bcs: list
    output_path: str
    every: int
    units: dict = field(default_factory=lambda: dict(UNITS))
    text: str = ""
    source: str = ""


class _Checker:
    """Collects problems; its helpers return a usable value or None."""

    def __init__(self):
        self.problems = []

    def add(self, where, msg):
        # one line per problem, whatever characters the case file put in names
        text = f"{where}: {msg}"
        self.problems.append("".join(c if c.isprintable() else repr(c)[1:-1] for c in text))

    def table(self, doc, key, where, required):
        val = doc.get(key)
        if val is None:
            if required:
                self.add(where, "missing table")
            return {}
        if not isinstance(val, dict):
            self.add(where, f"must be a table, got {_show(val)}")
            return {}
        return val

    def unknown(self, tbl, allowed, where):
        for k in tbl:
            if k not in allowed:
                self.add(f"{where}.{k}" if where else k,
                         f"unknown key (allowed: {', '.join(allowed)})")

    def number(self, tbl, key, where, required=True, default=None, positive=False):
        if key not in tbl:
            if required:
                self.add(f"{where}.{key}", "missing required key")
            return default
        val = tbl[key]
        if isinstance(val, bool) or not isinstance(val, (int, float)):
            self.add(f"{where}.{key}", f"must be a number, got {_show(val)}")
            return None
        if not math.isfinite(val):
            self.add(f"{where}.{key}", f"must be finite, got {val}")
            return None
        if positive and val <= 0:
            self.add(f"{where}.{key}", f"must be positive, got {val}")
            return None
        return float(val)

    def integer(self, tbl, key, where, required=True, default=None, minimum=1):
        if key not in tbl:
            if required:
                self.add(f"{where}.{key}", "missing required key")
            return default
        val = tbl[key]
        if isinstance(val, bool) or not isinstance(val, int):
            self.add(f"{where}.{key}", f"must be a whole number, got {_show(val)}")
            return None
        if val < minimum:
            self.add(f"{where}.{key}", f"must be >= {minimum}, got {val}")
            return None
        return val

    def string(self, tbl, key, where, required=True, default=None, choices=None):
        if key not in tbl:
            if required:
                self.add(f"{where}.{key}", "missing required key")
            return default
        val = tbl[key]
        if not isinstance(val, str):
            self.add(f"{where}.{key}", f"must be a string, got {_show(val)}")
            return None
        if choices and val not in choices:
            self.add(f"{where}.{key}",
                     f"must be one of {', '.join(map(repr, choices))}, got {val!r}")
            return None
        return val

    def history(self, tbl, key, where, axis, required=False):
        """A number or a [[axis, value], ...] table with increasing axis."""
        if key not in tbl:
            if required:
                self.add(f"{where}.{key}", "missing required key")
            return History() if not required else None
        val = tbl[key]
        name = f"{where}.{key}"
        if isinstance(val, (int, float)) and not isinstance(val, bool):
            if not math.isfinite(val):
                self.add(name, f"must be finite, got {val}")
                return None
            return History(value=val)
        if not isinstance(val, list):
            self.add(name, f"must be a number or a [[{axis}, value], ...] table, "
                     f"got {_show(val)}")
            return None
        if len(val) < 2:
            self.add(name, f"a table needs at least two [{axis}, value] rows, got {len(val)}")
            return None
        rows = []
        for i, row in enumerate(val):
            if (not isinstance(row, list) or len(row) != 2
                    or any(isinstance(c, bool) or not isinstance(c, (int, float))
                           for c in row)):
                self.add(name, f"row {i} must be a pair of numbers [{axis}, value], "
                         f"got {_show(row)}")
                return None
            if not all(math.isfinite(c) for c in row):
                self.add(name, f"row {i} must be finite, got {row}")
                return None
            rows.append(row)
        axis_vals = [r[0] for r in rows]
        if any(b <= a for a, b in zip(axis_vals, axis_vals[1:])):
            self.add(name, f"the {axis} column must be strictly increasing")
            return None
        return History(rows)


def _show(val):
    kind = {str: "a string", bool: "a boolean", list: "an array", dict: "a table"}
    for typ, word in kind.items():
        if isinstance(val, typ):
            return f"{word} {val!r}" if typ is not dict else word
    return repr(val)


def load_case(path):
    """Read and validate the case file at ``path``; raise :class:`CaseError`."""
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except OSError as exc:
        raise CaseError([f"{path}: cannot read case file ({exc.strerror})"]) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise CaseError([f"{path}: not a UTF-8 text file"]) from None
    case = parse_case(text, source=path)
    return case


def parse_case(text, source="<case>"):
    """Validate the TOML ``text`` of a case; return a :class:`Case`."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CaseError([f"{source}: TOML syntax error: {exc}"]) from None
    chk = _Checker()
    chk.unknown(doc, ("time", "output", "body", "contact", "bc", "units"), "")

    tm = chk.table(doc, "time", "time", required=True)
    chk.unknown(tm, ("dt", "end"), "time")
    dt = chk.number(tm, "dt", "time", positive=True)
    end = chk.number(tm, "end", "time", positive=True)
    nslabs = None
    if dt is not None and end is not None:
        if end <= dt:
            chk.add("time.end", f"must be greater than time.dt ({dt:g}), got {end:g}")
        elif end / dt > MAX_SLABS:
            chk.add("time.end", f"end / dt = {end / dt:.3g} slabs is more than {MAX_SLABS:.0e}")
        else:
            nslabs = int(round(end / dt))

    out = chk.table(doc, "output", "output", required=False)
    chk.unknown(out, ("path", "every"), "output")
    out_path = chk.string(out, "path", "output", required=False, default="result.h5")
    if out_path == "":
        chk.add("output.path", "must not be empty")
    every = chk.integer(out, "every", "output", required=False, default=1)

    un = chk.table(doc, "units", "units", required=False)
    chk.unknown(un, tuple(UNITS), "units")
    units = {k: chk.string(un, k, "units", required=False, default=d) for k, d in UNITS.items()}

    bodies, names = _bodies(chk, doc)
    contacts = _contacts(chk, doc, bodies, names)
    bcs = _bcs(chk, doc, names, contacts)

    if chk.problems:
        raise CaseError(chk.problems)
    if source != "<case>" and not os.path.isabs(out_path):
        out_path = os.path.join(os.path.dirname(os.path.abspath(source)), out_path)
    return Case(dt=dt, end=end, nslabs=nslabs, bodies=bodies, contacts=contacts,
                bcs=bcs, output_path=out_path, every=every, units=units, text=text,
                source=source)


def _array_of_tables(chk, doc, key):
    val = doc.get(key, [])
    if not isinstance(val, list) or not all(isinstance(t, dict) for t in val):
        chk.add(key, f"must be an array of tables ([[{key}]]), got {_show(val)}")
        return []
    return val


def _bodies(chk, doc):
    tables = _array_of_tables(chk, doc, "body")
    if not tables and "body" not in doc:
        chk.add("body", "at least one [[body]] table is required")
    bodies, seen, names = [], {}, {}
    allowed = ("name", "x", "elements", "E", "rho", "area", "v0", "u0")
    for i, tbl in enumerate(tables):
        where = f"body[{i}]"
        chk.unknown(tbl, allowed, where)
        name = chk.string(tbl, "name", where)
        if name is not None:
            where = f"body[{i}] ({name})"
            if name == WALL:
                chk.add(f"{where}.name", f"{WALL!r} is reserved for rigid walls")
            elif name in seen:
                chk.add(f"{where}.name", f"duplicate name (also body[{seen[name]}])")
            elif name == "":
                chk.add(f"{where}.name", "must not be empty")
            else:
                seen[name] = i
        x = None
        if "x" not in tbl:
            chk.add(f"{where}.x", "missing required key")
        elif (not isinstance(tbl["x"], list) or len(tbl["x"]) != 2
              or any(isinstance(c, bool) or not isinstance(c, (int, float))
                     for c in tbl["x"])):
            chk.add(f"{where}.x", f"must be [left, right] numbers, got {_show(tbl['x'])}")
        elif not all(math.isfinite(c) for c in tbl["x"]):
            chk.add(f"{where}.x", f"must be finite, got {tbl['x']}")
        elif tbl["x"][1] <= tbl["x"][0]:
            chk.add(f"{where}.x", f"right end must exceed left end (length must be "
                    f"positive), got {tbl['x']}")
        else:
            x = (float(tbl["x"][0]), float(tbl["x"][1]))
        ne = chk.integer(tbl, "elements", where)
        if ne is not None and ne > MAX_ELEMENTS:
            chk.add(f"{where}.elements", f"at most {MAX_ELEMENTS}, got {ne}")
            ne = None
        E = chk.number(tbl, "E", where, positive=True)
        rho = chk.number(tbl, "rho", where, positive=True)
        area = chk.number(tbl, "area", where, required=False, default=1.0, positive=True)
        v0 = chk.history(tbl, "v0", where, "x")
        u0 = chk.history(tbl, "u0", where, "x")
        fields = (name, x, ne, E, rho, area, v0, u0)
        if name is not None and name != WALL:
            names.setdefault(name, i)
        bodies.append(None if any(f is None for f in fields) or name == WALL
                      else Body(name, x, ne, E, rho, area, v0, u0))
    good = [(i, b) for i, b in enumerate(bodies) if b is not None]
    for (i, a), (j, b) in zip(good, good[1:]):
        if b.x[0] < a.x[1]:
            chk.add(f"body[{j}] ({b.name}).x",
                    f"overlaps or precedes body[{i}] ({a.name}) ending at {a.x[1]:g}; "
                    f"bodies must be listed left to right without overlap")
    return bodies, names


def _contacts(chk, doc, bodies, names):
    contacts, ends_used = [], {}
    for i, tbl in enumerate(_array_of_tables(chk, doc, "contact")):
        where = f"contact[{i}]"
        chk.unknown(tbl, ("pair", "penalty", "formulation", "wall"), where)
        penalty = chk.number(tbl, "penalty", where, required=False, positive=True)
        form = chk.string(tbl, "formulation", where, required=False, default="seed",
                          choices=FORMULATIONS)
        pair = tbl.get("pair")
        if pair is None:
            chk.add(f"{where}.pair", "missing required key")
            continue
        if (not isinstance(pair, list) or len(pair) != 2
                or not all(isinstance(p, str) for p in pair)):
            chk.add(f"{where}.pair", f"must be two names [\"left\", \"right\"], got "
                    f"{_show(pair)}")
            continue
        a, b = pair
        missing = [p for p in pair if p != WALL and p not in names]
        if missing:
            known = ", ".join(names) or "none"
            chk.add(f"{where}.pair", f"unknown body {missing[0]!r} (bodies: {known})")
            continue
        if a == WALL and b == WALL:
            chk.add(f"{where}.pair", "needs at least one body")
            continue
        if any(p != WALL and bodies[names[p]] is None for p in pair):
            continue    # that body's own problem is reported already
        wall = None
        if WALL in pair:
            wall = chk.number(tbl, "wall", where)
            if wall is None:
                continue
        elif "wall" in tbl:
            chk.add(f"{where}.wall", "only for a pair with \"wall\"")
            continue
        left = None if a == WALL else names[a]
        right = None if b == WALL else names[b]
        if left is not None and right is not None:
            if right != left + 1:
                chk.add(f"{where}.pair", f"{a!r} and {b!r} are not neighbours "
                        "listed left to right (a pair joins the right end of one body "
                        "to the left end of the next)")
                continue
            gap = bodies[right].x[0] - bodies[left].x[1]
        elif right is None:     # wall to the right of body `left`
            body = bodies[left]
            nxt = bodies[left + 1] if left + 1 < len(bodies) else None
            if wall < body.x[1]:
                chk.add(f"{where}.wall", f"a wall on the right of {a!r} must be at "
                        f">= {body.x[1]:g} (its right end), got {wall:g}")
                continue
            if nxt is not None and wall > nxt.x[0]:
                chk.add(f"{where}.wall", f"lies inside or beyond body {nxt.name!r} "
                        f"(which starts at {nxt.x[0]:g})")
                continue
            gap = wall - body.x[1]
        else:                   # wall to the left of body `right`
            body = bodies[right]
            prv = bodies[right - 1] if right > 0 else None
            if wall > body.x[0]:
                chk.add(f"{where}.wall", f"a wall on the left of {b!r} must be at "
                        f"<= {body.x[0]:g} (its left end), got {wall:g}")
                continue
            if prv is not None and wall < prv.x[1]:
                chk.add(f"{where}.wall", f"lies inside or before body {prv.name!r} "
                        f"(which ends at {prv.x[1]:g})")
                continue
            gap = body.x[0] - wall
        if gap < 0:
            chk.add(f"{where}.pair", f"initial gap is negative ({gap:g})")
            continue
        clash = [ends_used.get((left, "right")), ends_used.get((right, "left"))]
        ends = [(left, "right"), (right, "left")]
        dup = [(e, c) for e, c in zip(ends, clash) if e[0] is not None and c is not None]
        if dup:
            (body, side), other = dup[0]
            chk.add(f"{where}.pair", f"the {side} end of {bodies[body].name!r} is "
                    f"already in contact[{other}]")
            continue
        for e in ends:
            if e[0] is not None:
                ends_used[e] = i
        if penalty is not None or "penalty" not in tbl:
            if form is not None:
                contacts.append(Contact(left, right, penalty, form, wall))
    return contacts


def _bcs(chk, doc, names, contacts):
    contact_ends = {}
    for k, c in enumerate(contacts):
        if c.left is not None:
            contact_ends[(c.left, "right")] = k
        if c.right is not None:
            contact_ends[(c.right, "left")] = k
    bcs, seen = [], {}
    for i, tbl in enumerate(_array_of_tables(chk, doc, "bc")):
        where = f"bc[{i}]"
        chk.unknown(tbl, ("body", "end", "type", "value"), where)
        name = chk.string(tbl, "body", where)
        end = chk.string(tbl, "end", where, choices=ENDS)
        typ = chk.string(tbl, "type", where, choices=BC_TYPES)
        if typ == "fixed":
            value = chk.history(tbl, "value", where, "t")
            if value is not None and not value.is_zero:
                chk.add(f"{where}.value", "a fixed end takes no value other than 0 "
                        "(use type = \"velocity\" for a prescribed motion)")
                value = None
        else:
            value = chk.history(tbl, "value", where, "t", required=True)
        if name is not None and name not in names:
            chk.add(f"{where}.body", f"unknown body {name!r} "
                    f"(bodies: {', '.join(names) or 'none'})")
            continue
        if None in (name, end, typ, value):
            continue
        key = (names[name], end)
        if key in seen:
            chk.add(f"{where}.end", f"the {end} end of {name!r} already has bc[{seen[key]}]")
            continue
        if key in contact_ends:
            chk.add(f"{where}.end", f"the {end} end of {name!r} is in "
                    f"contact[{contact_ends[key]}]; an end takes a bc or a contact, "
                    "not both")
            continue
        seen[key] = i
        bcs.append(BC(names[name], end, typ, value))
    return bcs


def restart_key(text):
    """What must match for a restart: the case without time.end and
    output.path (a run may be extended and its file moved)."""
    doc = tomllib.loads(text)
    doc.get("time", {}).pop("end", None)
    doc.get("output", {}).pop("path", None)
    return doc
