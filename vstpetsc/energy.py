"""The energy balance of a run (docs/loads.md section 4): the energies of
the state (kinetic, strain, spring) and the sums over the slabs of the
dashpots' work, the external work and what the contact laws and the soil
took; ``numerical`` is what is left, the energy of the velocity jumps at
slab starts.  Pure numpy."""

from vstpetsc import model as model_mod

SUMMED = ("damping", "external", "contact", "soil")
KEYS = ("kinetic", "strain", "spring") + SUMMED + ("numerical",)


class EnergyBook:
    """Turns the solver's running sums into the energy datasets of a row."""

    def __init__(self, model):
        self.model = model
        self.initial = 0.0
        self.offset = dict.fromkeys(SUMMED, 0.0)

    def state(self, u, v):
        ops = self.model.ops
        return {"kinetic": model_mod.kinetic_energy(ops, v),
                "strain": model_mod.strain_energy(ops, u),
                "spring": model_mod.spring_energy(ops, u)}

    def start(self, u, v):
        """t = 0: the initial total, stored contact energy included."""
        stored = sum(law.stored_energy(u) for law in self.model.recorded
                     if hasattr(law, "stored_energy"))
        self.offset["contact"] = stored
        self.initial = sum(self.state(u, v).values()) + stored

    def restore(self, first, last):
        """Continue a run from its file: ``first`` and ``last`` map the
        energy datasets to their values in the first and the last row."""
        self.initial = sum(float(first[k]) for k in ("kinetic", "strain", "spring", "contact"))
        self.offset = {k: float(last[k]) for k in SUMMED}

    def row(self, u, v, totals):
        """{energy dataset: value} for the state (u, v) and the solver's
        sums ``totals`` since this run started."""
        out = self.state(u, v)
        out.update({k: self.offset[k] + totals.get(k, 0.0) for k in SUMMED})
        held = sum(out[k] for k in KEYS if k not in ("external", "numerical"))
        out["numerical"] = self.initial + out["external"] - held
        return out
