"""The energy balance of a run (docs/loads.md section 4): the energies of
the state (kinetic, strain, spring) and the sums over the slabs of the
dashpots' work, the external work and what the contact laws and the soil
took; ``numerical`` is what is left, the energy of the velocity jumps at
slab starts.  Pure numpy."""

import numpy as np


SUMMED = ("damping", "external", "contact", "soil", "transferred", "friction", "hysteretic")
# the solver's global running sums; "wall": a moving wall's work through
# friction, a part of "external"
SUMS = ("damping", "contact", "soil", "transferred", "friction", "wall")
SUMS_BEFORE_FRICTION = SUMS[:4]     # the restart state of files written before friction
HELD = ("kinetic", "strain", "spring")       # the energy the bodies hold
KEYS = HELD + SUMMED + ("numerical",)
# the terms numerical is a difference of (transferred is an exchange, not one)
BALANCE = HELD + ("damping", "external", "contact", "soil", "friction", "hysteretic")
# what the model itself dissipates (the run's last line, `info`)
DISSIPATED = ("damping", "soil", "friction", "hysteretic")
# numerical below -NEGATIVE times the largest term of the balance so far
# fails the run: the time discretisation cannot create energy, and the
# balance's rounding stays far below (docs/troubleshooting.md, "The
# energy balance"; tests/test_run_honesty.py)
NEGATIVE = 1e-6
# "transferred": the work of a cushion on the pile head (pile driving), an
# exchange between bodies, not a term of the balance; "friction": the
# energy dissipated by sliding; "hysteretic": by a soil's Masing loops
# (its elements hold A h tau^2 / (2 G), counted in "strain"; the solver
# reports both, the sum of the loops' work kept with the soil's own state)


class EnergyBook:
    """Turns the solver's running sums into the energy datasets of a row:
    the balance, restarts and the guard, for both geometries; the state's
    energies are each geometry's (``state``, ``start``)."""

    def __init__(self, model):
        self.model = model
        self.initial = 0.0              # the balance's start: state + stored contact energy
        self.held0 = 0.0                # kinetic + strain + spring at t = 0
        self.largest = 0.0              # largest |term| of the balance at the kept rows
        self.offset = dict.fromkeys(SUMMED, 0.0)
        self.beyond0 = 0.0      # a soil's strain energy beyond 1/2 u^T K u at t = 0

    def state(self, u, v, d=None, known=None):
        """{"kinetic", "strain", "spring"} of the state (u, v): each
        geometry's book (vstpetsc.line.energy, vstpetsc.plane.energy)."""
        raise NotImplementedError

    def start(self, u, v):
        """t = 0: the initial total, stored contact energy included."""
        raise NotImplementedError

    def restore(self, first, last, continued=False, largest=0.0):
        """Continue a run from its file: ``first`` and ``last`` map the
        energy datasets to their values in the first and the last row,
        ``largest`` is the largest |term| of the balance at its rows
        (:func:`largest_term`: the whole run's, not the restarted part's);
        ``continued``: the solver took its running sums back (the restart
        state), so only the stored contact energy of t = 0 is added, as in
        the run itself (bit for bit); otherwise the sums start from the
        rows' totals (equal to rounding)."""
        self.held0 = sum(float(first[k]) for k in HELD)
        self.initial = self.held0 + float(first["contact"])
        self.largest = max(float(largest), abs(self.initial))
        if continued:
            self.offset = dict.fromkeys(SUMMED, 0.0)
            self.offset["contact"] = float(first["contact"])
        else:
            self.offset = {k: float(last.get(k, 0.0)) for k in SUMMED}
        # the soil's loops are summed with its own state (restored with it)
        self.offset["hysteretic"] = 0.0

    def balance_problem(self, row, k):
        """Why slab k's ``row`` cannot be kept (a message), or None: a
        numerical energy below -NEGATIVE times the largest term of the
        balance at the kept rows so far (this row's included)."""
        self.largest = max(self.largest, largest_term({key: row[key] for key in BALANCE
                                                       if key in row}))
        numerical = row["numerical"]
        if numerical >= -NEGATIVE * self.largest:
            return None
        return (f"slab {k}: the energy balance went negative (numerical energy {numerical:.3g} "
                f"against terms up to {self.largest:.3g}; rounding stays within {NEGATIVE:g} of "
                "them): the solution lost its accuracy, e.g. a penalty too stiff for double "
                "precision")

    def row(self, u, v, totals, d=None, known=None):
        """{energy dataset: value} for the state (u, v) (d, known: see
        :meth:`state`) and the solver's sums ``totals`` since this run
        started."""
        out = self.state(u, v, d, known)
        out["strain"] += totals.get("strain_beyond_linear", self.beyond0)
        for key in SUMMED:
            out[key] = self.offset[key] + totals.get(key, 0.0)
        held = (out["kinetic"] + out["strain"] + out["spring"] + out["damping"]
                + out["contact"] + out["soil"] + out["friction"] + out["hysteretic"])
        out["numerical"] = self.initial + out["external"] - held
        return out


def largest_term(rows):
    """The largest magnitude in ``rows`` ({term: value or array})."""
    return max((float(np.max(np.abs(v), initial=0.0)) for v in rows.values()), default=0.0)
