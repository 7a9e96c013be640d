"""TOML text of a case document (nested dicts and lists of numbers, strings
and booleans), written the way people write case files: a ``[table]`` per
table, a ``[[table]]`` per element of an array of tables, inline values
otherwise.  ``tomllib.loads(dumps(doc)) == doc`` for every case document.

Debian's tomli-w writes arrays of tables inline (``body = [{...}]``), which
is valid but unreadable in a result file's ``case`` attribute.
"""

import math


def dumps(doc):
    """The TOML text of ``doc``."""
    out = []
    scalars = {k: v for k, v in doc.items() if not _is_table(v) and not _is_tables(v)}
    out += [f"{_key(k)} = {value(v)}" for k, v in scalars.items()]
    for key, val in doc.items():
        if _is_table(val):
            out += ["", f"[{_key(key)}]"] + [f"{_key(k)} = {value(v)}" for k, v in val.items()]
        elif _is_tables(val):
            for item in val:
                out += ["", f"[[{_key(key)}]]"]
                out += [f"{_key(k)} = {value(v)}" for k, v in item.items()]
    return "\n".join(out).lstrip("\n") + "\n"


def _is_table(v):
    return isinstance(v, dict)


def _is_tables(v):
    return isinstance(v, list) and len(v) > 0 and all(isinstance(t, dict) for t in v)


def _key(k):
    k = str(k)
    if k and all(c.isascii() and (c.isalnum() or c in "_-") for c in k):
        return k
    return _string(k)


def value(v):
    """An inline TOML value."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return _string(v)
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(k)} = {value(x)}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} as TOML")


def _string(s):
    escapes = {'"': '\\"', "\\": "\\\\", "\n": "\\n", "\t": "\\t", "\r": "\\r",
               "\b": "\\b", "\f": "\\f"}
    body = "".join(escapes.get(c, c if c.isprintable() else _unicode_escape(c)) for c in s)
    return f'"{body}"'


def _unicode_escape(c):
    return f"\\u{ord(c):04x}" if ord(c) <= 0xFFFF else f"\\U{ord(c):08x}"
