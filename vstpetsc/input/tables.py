"""The tables every case has, whatever its geometry: [time], [output],
[units], [gravity]; and the naming rule of a named table (docs/case-file.md).
Each reader reports through the checker and returns its parts."""

from dataclasses import dataclass

from vstpetsc.input.checker import name_problem
from vstpetsc.spacetime.history import History

UNITS = {"length": "m", "time": "s", "mass": "kg"}
INITIAL = ("rest", "static")
MAX_SLABS = 1e12          # beyond any run; guards int() and memory against typos
DT_RANGE = (1e-150, 1e150)  # dt^2 must neither underflow nor overflow


@dataclass
class GravitySpec:
    """[gravity]: the acceleration g(t) along +x, and the initial state."""

    g: History
    initial: str = "rest"


def read_gravity(chk, tbl, bodies):
    """[gravity] (None if absent)."""
    if not tbl:
        return None
    chk.unknown(tbl, ("g", "initial"), "gravity")
    g = chk.history(tbl, "g", "gravity", "t", required=True, records=True)
    initial = chk.string(tbl, "initial", "gravity", required=False, default="rest",
                         choices=INITIAL)
    if initial == "static":
        moved = [b.name for b in bodies if b is not None and not b.u0.is_zero]
        if moved:
            chk.add("gravity.initial", f"\"static\" computes the initial displacements; "
                    f"body {moved[0]!r} gives u0 as well")
            return None
    return None if g is None or initial is None else GravitySpec(g, initial)


def read_time(chk, tm):
    chk.unknown(tm, ("dt", "end"), "time")
    dt = chk.number(tm, "dt", "time", positive=True)
    if dt is not None and not DT_RANGE[0] <= dt <= DT_RANGE[1]:
        chk.add("time.dt", f"must lie in [{DT_RANGE[0]:g}, {DT_RANGE[1]:g}] (dt^2 enters "
                f"the slab matrix and must be a normal double), got {dt:g}")
        dt = None
    end = chk.number(tm, "end", "time", positive=True, tiny=True)     # compared with dt only
    nslabs = None
    if dt is not None and end is not None:
        if end <= dt:
            chk.add("time.end", f"must be greater than time.dt ({dt:g}), got {end:g}")
        elif end / dt > MAX_SLABS:
            chk.add("time.end", f"end / dt = {end / dt:.3g} slabs is more than {MAX_SLABS:.0e}")
        else:
            nslabs = int(round(end / dt))
    return {"dt": dt, "nslabs": nslabs}


def read_output(chk, out):
    chk.unknown(out, ("path", "every"), "output")
    path = chk.string(out, "path", "output", required=False, default="result.h5")
    if path == "":
        chk.add("output.path", "must not be empty")
    every = chk.integer(out, "every", "output", required=False, default=1)
    return {"output_path": path, "every": every}


def read_units(chk, un):
    chk.unknown(un, tuple(UNITS), "units")
    return {k: chk.string(un, k, "units", required=False, default=d) for k, d in UNITS.items()}


def named_table(chk, tbl, kind, i, keys, taken, reserved=None):
    """(its usable name or None, where to report) of table ``i`` of
    ``[[kind]]`` with the allowed ``keys``, names ``taken`` so far
    ({name: index}) and a ``reserved`` name, after reporting."""
    where = f"{kind}[{i}]"
    chk.unknown(tbl, keys, where)
    name = chk.string(tbl, "name", where)
    if name is None:
        return None, where
    where = f"{kind}[{i}] ({name})"
    problem = name_problem(name)
    if problem is None and name == reserved:
        problem = f"{reserved!r} is reserved for rigid walls"
    if problem is None and name in taken:
        problem = f"duplicate name (also {kind}[{taken[name]}])"
    if problem:
        chk.add(f"{where}.name", problem)
        return None, where
    return name, where
