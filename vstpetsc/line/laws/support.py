"""A point support at a body end: a spring (against the end's displacement),
a dashpot (against its velocity) and a lumped mass moving with it, any
subset.  Linear: they enter S, C and M (docs/loads.md)."""

from vstpetsc.line.laws.end import EndLaw

KEYS = ("stiffness", "damping", "mass")


def read(chk, tbl, where):
    if not any(k in tbl for k in KEYS):
        chk.add(where, "a support needs stiffness, damping and/or mass")
        return None
    vals = {k: chk.number(tbl, k, where, required=False, default=0.0, minimum=0.0)
            for k in KEYS}
    return None if None in vals.values() else vals


class Support(EndLaw):
    def add_operators(self, ops):
        p = self.spec.params
        ops.add_node("s", self.node, p["stiffness"])
        ops.add_node("c", self.node, p["damping"])
        ops.add_node("m", self.node, p["mass"])

    def describe(self):
        p = self.spec.params
        parts = [f"{k} {p[k]:g}" for k in KEYS if p[k]]
        return f"{super().describe()} ({', '.join(parts) or 'nothing'})"


def build(spec, index, case, mesh):
    return Support(spec, index, case, mesh)
