"""Penalty contact in velocity: the seed's formulation and the variationally
consistent ("power") one (formulation.md sections 4 and 5).

Node ``n_k`` of the pair gets the residual ``-c_k w G_a`` with
``G_a = int min(0, g) phi_a dt`` over the slab, integrated exactly over the
active part {g < 0} (:mod:`vstpetsc.kernels.gap`); ``phi_a`` is I_a for "seed"
(w = eps) and T_a for "power" (w = k).

With ``redistribute_mass`` ("power" only) the mass of the pair's contact
nodes moves to their inner neighbours (Khenous, Laborde & Renard 2008),
all but KEPT_FRACTION of it: a nearly massless contact node cannot ring on
the penalty spring at a frequency the slabs resolve, and the contact force
follows the arriving wave (docs/accuracy.md).
"""

from vstpetsc.kernels.coulomb import penalty_normal
from vstpetsc.kernels.gap import active_intervals, closed_on_slab, gap_coefficients, pair_integrals
from vstpetsc.kernels.stiffness import default_penalty
from vstpetsc.line.laws.pair import PairLaw

KEYS = ("penalty", "redistribute_mass")
DEFAULT_FORMULATION = "power"
# the share of a contact node's mass that redistribution leaves on it: a
# massless node has no velocity jump term, so nothing ties its velocity
# across slab ends and it chatters (periodic-impacts at c dt / h = 0.25: 138
# closes in nine impacts); a hundredth rings far above 1 / dt, where the
# scheme damps it, and the nine impacts close nine times
KEPT_FRACTION = 0.01


def read(chk, tbl, where):
    """The formulation's own keys: an optional positive ``penalty`` and an
    optional boolean ``redistribute_mass`` (default false)."""
    penalty = chk.number(tbl, "penalty", where, required=False, positive=True)
    if penalty is None and "penalty" in tbl:
        return None
    moved = chk.boolean(tbl, "redistribute_mass", where)
    if moved is None:
        return None
    if moved and tbl.get("formulation", DEFAULT_FORMULATION) == "seed":
        chk.add(f"{where}.redistribute_mass", "the seed formulation does not conserve energy "
                "with a massless contact node (it gains energy at every impact); use "
                "formulation = \"power\"")
        return None
    return {"penalty": penalty, "redistribute_mass": moved}


class PenaltyContact(PairLaw):
    """A seed or power penalty pair (``spec.formulation``)."""

    def __init__(self, spec, index, case, mesh):
        super().__init__(spec, index, case, mesh)
        self.given = spec.params["penalty"] is not None
        stiffnesses = [mesh.body_stiffness(b) for b in (spec.left, spec.right)
                       if b is not None]
        self.penalty = spec.params["penalty"] if self.given else \
            default_penalty(spec.formulation, stiffnesses, case.dt)
        self.power = spec.formulation == "power"
        self.redistribute = bool(spec.params.get("redistribute_mass"))
        self.inner = [inner_neighbour(mesh, b, end) for b, end in
                      ((spec.left, "right"), (spec.right, "left")) if b is not None]
        self.last = None
        self.rates = None           # the closing rates of the last force() that acted
        # its active pieces of the slab when the compiled slab found them
        # (vstpetsc.line.native.penalty.PenaltySlab), else None: finish_slab finds them
        self.pieces = None

    def add_operators(self, ops):
        """Move each contact node's mass (its row of M) to its inner
        neighbour, keeping the total, but for KEPT_FRACTION of it on the
        node's diagonal: M's entries of the node go to the neighbour's
        diagonal."""
        if not self.redistribute:
            return
        for node, inner in self.inner:
            if inner is None:
                continue
            edge = min(node, inner)
            row = ops.m_diag[node] + 2.0 * ops.m_off[edge]
            ops.m_diag[inner] += (1.0 - KEPT_FRACTION) * row
            ops.m_diag[node] = KEPT_FRACTION * row
            ops.m_off[edge] = 0.0

    def acts(self, d1, d2):
        return closed_on_slab(self.gn, d1, d2, self.dt)

    def force(self, d1, d2):
        """The pair's terms for the closing rates (d1, d2): (f1, f2, df1/dd1,
        df1/dd2, df2/dd1, df2/dd2) with f_a = -w G_a, or None when the gap
        stays open over the whole slab."""
        integrals = self.last = pair_integrals(self.gn, d1, d2, self.dt, self.power)
        self.pieces = None
        if integrals is None:
            return None
        self.rates = (d1, d2)
        G1, G2, W11, W12, W21, W22 = integrals
        w = self.penalty
        return (-w * G1, -w * G2, w * W11, w * W12, w * W21, w * W22)

    def normal_force(self):
        """The normal force of the last force() inside the slab: (n0, n1, n2)
        of N = n0 + n1 theta + n2 theta^2 and its pieces [(p, q)] of [0, 1],
        or None without contact.  "power": k max(0, -g); "seed": its
        slab mean J / dt on the whole slab (what its residual weighs)."""
        if self.last is None:
            return None
        if self.power:
            return penalty_normal(*gap_coefficients(self.gn, *self.rates, self.dt),
                                  self.penalty)
        return (-self.penalty * (self.last[0] + self.last[1]) / self.dt, 0.0, 0.0), [(0.0, 1.0)]

    @property
    def static_stiffness(self):
        """The slab-mean force per unit penetration: k ("power"), or
        eps dt / 2 ("seed", formulation.md section 4)."""
        return self.penalty if self.formulation == "power" else 0.5 * self.penalty * self.dt

    def finish_slab(self, t0, dt):
        """Record the converged slab (the last force() was at its solution)."""
        last = self.last
        self.add_impulse(-self.penalty * (last[0] + last[1]) if last else 0.0, t0, dt)
        if not (last or self.closed):   # free slabs after an open cost nothing more
            return
        pieces = self.pieces
        if last and pieces is None:
            pieces = active_intervals(*gap_coefficients(self.gn, *self.rates, dt))
        self.track(t0, dt, pieces if last else ())

    def attrs(self):
        return {**super().attrs(), "penalty": self.penalty,
                "redistribute_mass": int(self.redistribute)}

    def describe(self):
        given = "given" if self.given else "default"
        moved = ", contact nodes' mass moved inward" if self.redistribute else ""
        return (f"{super().describe()}, {self.formulation} penalty {self.penalty:.6g} "
                f"({given}){moved}")


def inner_neighbour(mesh, body, end):
    """(the end node, its neighbour inside the body), the neighbour None for
    a body of one element (both its nodes are ends: nothing to move)."""
    node = mesh.end_node(body, end)
    if mesh.first[body + 1] - mesh.first[body] < 3:
        return node, None
    return node, node - 1 if end == "right" else node + 1


def build(spec, index, case, mesh):
    return PenaltyContact(spec, index, case, mesh)
