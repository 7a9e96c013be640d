"""The MKZ backbone (modified Kondner-Zelasko; Matasovic & Vucetic 1993):

    tau = G gamma / (1 + beta (|gamma| / gamma_ref)^s),

G the body's small-strain shear modulus: its keys and their validation.
The unload-reload rules are Masing's (:mod:`vstpetsc.materials.masing`).
"""

from dataclasses import dataclass

import numpy as np

from vstpetsc.input.checker import show
from vstpetsc.spacetime.history import History

NAME = "mkz"
PARAMETERS = ("gamma_ref", "beta", "s")
DEFAULTS = {"beta": 1.0, "s": 1.0}
KEYS = ("model",) + PARAMETERS + ("from", "to")


@dataclass
class MKZPart:
    """One table of a body's ``shear_law``: the parameters (profiles of x)
    on the elements whose midpoint lies in [x_from, x_to]."""

    gamma_ref: History
    beta: History
    s: History
    x_from: float
    x_to: float

    def covers(self, mid):
        return (mid >= self.x_from) & (mid <= self.x_to)


def read_part(chk, tbl, where, x):
    """An MKZPart from one table (its model already checked), or None."""
    chk.unknown(tbl, KEYS, where)
    params = {}
    for key in PARAMETERS:
        if key not in tbl and key in DEFAULTS:
            params[key] = History(value=DEFAULTS[key])
        else:
            params[key] = chk.profile(tbl, key, where)
    span = [chk.number(tbl, key, where, required=False, default=default)
            for key, default in (("from", x[0]), ("to", x[1]))] if x else [None, None]
    if None in params.values() or None in span:
        return None
    if span[0] > span[1]:
        chk.add(f"{where}.to", f"must be >= from ({span[0]:g}), got {span[1]:g}")
        return None
    if x and (span[1] < x[0] or span[0] > x[1]):
        chk.add(f"{where}.from", f"[{span[0]:g}, {span[1]:g}] covers no part of the body "
                f"([{x[0]:g}, {x[1]:g}])")
        return None
    if params["s"].f.max() > 1.0:
        # beyond 1 the backbone turns down at large strain (its slope
        # 1 + beta (1 - s) X changes sign): no unique response
        chk.add(f"{where}.s", f"must be <= 1 (the backbone would soften beyond its peak), "
                f"got {params['s'].f.max():g}")
        return None
    return MKZPart(**params, x_from=span[0], x_to=span[1])


def describe(value):
    return f"must be a table {{ model = \"{NAME}\", gamma_ref = ... }} or a list of them, " \
           f"got {show(value)}"


def parameters(parts, mid):
    """Per element (midpoints ``mid``): (mask of the elements a part covers,
    gamma_ref, beta, s); a later part wins where two overlap."""
    mask = np.zeros(mid.size, dtype=bool)
    out = {key: np.ones(mid.size) for key in PARAMETERS}
    for part in parts:
        here = part.covers(mid)
        mask |= here
        for key in PARAMETERS:
            out[key][here] = getattr(part, key)(mid[here])
    return mask, out["gamma_ref"], out["beta"], out["s"]
