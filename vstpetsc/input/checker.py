"""Validation of case tables: one :class:`Checker` collects every problem as
``table.key: what is wrong``; its readers return a usable value or None.

Every reader starts with the same prologue (:meth:`Checker.take`): a missing
key is reported when required and gives the default otherwise.
"""

import difflib
import math
import numbers
import os

import numpy as np

from vstpetsc.spacetime import history as hist
from vstpetsc.spacetime.history import History

MISSING = object()
RECORD_KEYS = ("file", "table", "column", "scale", "integrate")
# Every number of a case is 0 or of a magnitude in this range (smaller ones
# only where a value multiplies: histories): squares and products of two
# such numbers stay normal doubles, so no input overflows or underflows to 0
# before the solver has a chance to report anything.
MAGNITUDE = (1e-150, 1e150)
INT64 = 2**63 - 1             # TOML's integers (and HDF5's attributes) are 64-bit
BEYOND_INT64 = f"an integer beyond the 64-bit range TOML allows (at most {INT64})"


class HistoryChecks:
    """The readers of histories and profiles (part of :class:`Checker`)."""

    def history(self, tbl, key, where, axis, required=False, records=False):
        """A number, a [[axis, value], ...] table with increasing axis, or
        (``records``) a {file/table, column, scale, integrate} table; an
        absent optional key is the constant 0."""
        val = self.take(tbl, key, where, required)
        if val is MISSING:
            return None if required else History()
        name = f"{where}.{key}"
        if is_number(val):
            val = self.real(name, val, tiny=True)
            return None if val is None else History(value=val)
        if isinstance(val, dict) and records:
            return self.record(val, name)
        if not isinstance(val, list):
            forms = "a number, a [[t, value], ...] table or {file = ...}" if records else \
                f"a number or a [[{axis}, value], ...] table"
            self.add(name, f"must be {forms}, got {show(val)}")
            return None
        rows = self.rows(val, name, axis)
        return None if rows is None else History(rows)

    def record(self, val, name):
        """A history from {file = ..., column, scale, integrate} or
        {table = [[t, v], ...], scale, integrate}."""
        self.unknown(val, RECORD_KEYS, name)
        scale = self.number(val, "scale", name, required=False, default=1.0)
        integrate = self.boolean(val, "integrate", name)
        if integrate is None:
            return None
        if ("file" in val) == ("table" in val):
            self.add(name, "give either file = \"...\" or table = [[t, value], ...]")
            return None
        samples = self._samples(val, name)
        if samples is None or scale is None:
            return None
        history = hist.from_samples(*samples, scale=scale, integrate=integrate)
        if not history.finite:
            how = f"scaled by {scale:g}" + (" and integrated" if integrate else "")
            self.add(name, f"{how}, the record goes beyond the range of a double "
                           f"(largest sample {np.abs(samples[1]).max():g})")
            return None
        return history

    def _samples(self, val, name):
        """(t, values) of a record's table or file, or None."""
        if "table" in val:
            rows = self.rows(val["table"], f"{name}.table", "t") \
                if isinstance(val["table"], list) else None
            if rows is None and not isinstance(val["table"], list):
                self.add(f"{name}.table", f"must be [[t, value], ...], got {show(val['table'])}")
            return None if rows is None else ([r[0] for r in rows], [r[1] for r in rows])
        path = self.string(val, "file", name)
        column = val.get("column", 2)
        if path is None:
            return None
        if isinstance(column, bool) or not isinstance(column, (str, int)):
            self.add(f"{name}.column", f"must be a header name or a column number, got "
                     f"{show(column)}")
            return None
        full = os.path.join(self.folder, os.path.expanduser(path))
        self.inputs.append(full)
        try:
            if path.upper().endswith(".AT2"):
                return hist.read_at2(full, MAGNITUDE)
            return hist.read_csv(full, column, MAGNITUDE)
        except hist.RecordError as exc:
            self.add(f"{name}.file", str(exc))
            return None

    def profile(self, tbl, key, where, default=None):
        """A positive number or a [[x, value], ...] table along the body
        (x non-decreasing; a repeated x marks a step); a History."""
        val = self.take(tbl, key, where, default is None, default)
        if val is MISSING:
            return None
        name = f"{where}.{key}"
        if is_number(val):
            val = self.real(name, val)
            if val is None:
                pass
            elif val <= 0:
                self.add(name, f"must be positive, got {val:g}")
            else:
                return History(value=float(val))
            return None
        if not isinstance(val, list):
            self.add(name, f"must be a number or a [[x, value], ...] table, got {show(val)}")
            return None
        rows = self.rows(val, name, "x", steps=True)
        if rows is not None and min(r[1] for r in rows) <= 0:
            self.add(name, "values must be positive")
            return None
        return None if rows is None else History(rows)

    def rows(self, val, name, axis, steps=False):
        """Rows [[axis, value], ...] with a strictly increasing axis (with
        ``steps``: non-decreasing, an axis value at most twice), or None."""
        if len(val) < 2:
            self.add(name, f"a table needs at least two [{axis}, value] rows, got {len(val)}")
            return None
        for i, row in enumerate(val):
            if not isinstance(row, list) or len(row) != 2 or not all(map(is_number, row)):
                self.add(name, f"row {i} must be a pair of numbers [{axis}, value], "
                         f"got {show(row)}")
                return None
            # profiles (steps) are E, rho, area: divisors, no tiny values
            if any(self.real(f"{name} row {i}", c, tiny=not steps) is None for c in row):
                return None
        a = [r[0] for r in val]
        if steps:
            if any(y < x for x, y in zip(a, a[1:])) or any(x == z for x, z in zip(a, a[2:])):
                self.add(name, f"the {axis} column must not decrease, and an {axis} appears "
                         "at most twice (a step)")
                return None
        elif any(y <= x for x, y in zip(a, a[1:])):
            self.add(name, f"the {axis} column must be strictly increasing")
            return None
        return [[float(x), float(y)] for x, y in val]


class Checker(HistoryChecks):
    """Collects problems; each reader returns a usable value or None.
    ``folder`` is where relative file names point; ``inputs`` collects the
    files read."""

    def __init__(self, folder=None):
        self.problems = []
        self.folder = folder or os.getcwd()
        self.inputs = []

    def add(self, where, msg):
        self.problems.append(f"{where}: {msg}")

    def real(self, name, val, tiny=False):
        """``val`` as a float, or None after reporting a value that is not
        finite or outside :data:`MAGNITUDE` (a TOML integer such as 10**400
        does not even convert to a float); with ``tiny``, magnitudes below
        the range are accepted (a value that only multiplies, never divides)."""
        if isinstance(val, numbers.Integral) and abs(val) > INT64:
            self.add(name, BEYOND_INT64)
            return None
        val = float(val)
        if not math.isfinite(val):
            self.add(name, f"must be finite, got {val}")
        elif abs(val) > MAGNITUDE[1] or (not tiny and 0 < abs(val) < MAGNITUDE[0]):
            self.add(name, f"must lie in {MAGNITUDE[0]:g} .. {MAGNITUDE[1]:g} in magnitude "
                           f"(or be 0), got {val:g}")
        else:
            return val
        return None

    def take(self, tbl, key, where, required, default=None):
        """The value of ``key`` or MISSING (reported when required)."""
        if key in tbl:
            return tbl[key]
        if required:
            self.add(f"{where}.{key}", "missing required key")
            return MISSING
        return default if default is not None else MISSING

    def table(self, doc, key, where, required):
        val = doc.get(key)
        if val is None:
            if required:
                self.add(where, "missing table")
            return {}
        if not isinstance(val, dict):
            self.add(where, f"must be a table, got {show(val)}")
            return {}
        return val

    def tables(self, doc, key):
        """An array of tables ([[key]]), or [] after reporting."""
        val = doc.get(key, [])
        if not isinstance(val, list) or not all(isinstance(t, dict) for t in val):
            self.add(key, f"must be an array of tables ([[{key}]]), got {show(val)}")
            return []
        return val

    def unknown(self, tbl, allowed, where):
        for k in tbl:
            if k not in allowed:
                close = difflib.get_close_matches(str(k), allowed, n=1)
                hint = f"did you mean {close[0]!r}? " if close else ""
                self.add(f"{where}.{k}" if where else str(k),
                         f"unknown key ({hint}allowed: {', '.join(allowed)})")

    def number(self, tbl, key, where, required=True, default=None, positive=False,
               minimum=None, maximum=None, tiny=False):
        val = self.take(tbl, key, where, required, default)
        if val is MISSING:
            return None
        name = f"{where}.{key}"
        if not is_number(val):
            self.add(name, f"must be a number, got {show(val)}")
            return None
        val = self.real(name, val, tiny)
        if val is None:
            pass
        elif positive and val <= 0:
            self.add(name, f"must be positive, got {val:g}")
        elif minimum is not None and val < minimum:
            self.add(name, f"must be >= {minimum:g}, got {val:g}")
        elif maximum is not None and val > maximum:
            self.add(name, f"must be <= {maximum:g}, got {val:g}")
        else:
            return val
        return None

    def integer(self, tbl, key, where, required=True, default=None, minimum=1):
        val = self.take(tbl, key, where, required, default)
        if val is MISSING:
            return None
        if isinstance(val, bool) or not isinstance(val, numbers.Integral):
            self.add(f"{where}.{key}", f"must be a whole number, got {show(val)}")
            return None
        if abs(val) > INT64:
            self.add(f"{where}.{key}", BEYOND_INT64)
            return None
        if val < minimum:
            self.add(f"{where}.{key}", f"must be >= {minimum}, got {val}")
            return None
        return int(val)

    def boolean(self, tbl, key, where, default=False):
        """An optional true or false (None after reporting another value)."""
        val = tbl.get(key, default)
        if not isinstance(val, bool):
            self.add(f"{where}.{key}", f"must be true or false, got {show(val)}")
            return None
        return val

    def string(self, tbl, key, where, required=True, default=None, choices=None):
        val = self.take(tbl, key, where, required, default)
        if val is MISSING:
            return None
        if not isinstance(val, str):
            self.add(f"{where}.{key}", f"must be a string, got {show(val)}")
            return None
        if choices and val not in choices:
            self.add(f"{where}.{key}",
                     f"must be one of {', '.join(map(repr, choices))}, got {val!r}")
            return None
        return val


def name_problem(name):
    """Why ``name`` cannot name a body or a gauge (None if it can): it
    becomes an HDF5 group name and a CSV file name."""
    if name == "":
        return "must not be empty"
    if name in (".", ".."):
        return f"{name!r} is not a name"
    bad = [c for c in name if not (c.isalnum() or c in "_-.")]
    if bad:
        return (f"may hold letters, digits, '_', '-' and '.' only, got {bad[0]!r} "
                f"in {name!r}")
    return None


def is_number(val):
    return isinstance(val, numbers.Real) and not isinstance(val, bool)


def show(val):
    kind = {str: "a string", bool: "a boolean", list: "an array", dict: "a table"}
    for typ, word in kind.items():
        if isinstance(val, typ):
            return f"{word} {val!r}" if typ is not dict else word
    return repr(val)
