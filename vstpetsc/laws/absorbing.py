"""Lysmer's absorbing end: a dashpot Z = rho c A (a half-space of that
impedance beyond the end) that lets waves leave, and an incoming wave of
particle velocity v_in(t): the end receives Z (2 v_in - v) along +x at
either end (docs/loads.md section 1).

``motion`` says what the ``incident`` history is: the incident wave itself
(default), or an outcrop motion (the free surface of the rock doubles the
incident wave, so the incident wave is half of it).  A within (borehole)
motion is the total motion at the base, incident and reflected waves
together: it is prescribed at a rigid base (a velocity bc), never fed to a
dashpot."""

import numpy as np

from vstpetsc.laws.base import Load
from vstpetsc.laws.end import EndLaw

KEYS = ("impedance", "incident", "motion")
# what the incident history is -> the factor that gives the incident wave
# (0.5 is exact in binary: outcrop equals scale = 0.5 bit for bit)
MOTIONS = {"incident": 1.0, "outcrop": 0.5, "within": None}
WITHIN = ("a within (borehole) motion is the total motion at the base, not an incident "
          "wave: prescribe it with a type = \"velocity\" bc (rigid base)")


def read(chk, tbl, where):
    impedance = chk.number(tbl, "impedance", where, required=False, positive=True)
    if impedance is None and "impedance" in tbl:
        return None
    incident = chk.history(tbl, "incident", where, "t", records=True)
    motion = chk.string(tbl, "motion", where, required=False, default="incident",
                        choices=tuple(MOTIONS))
    if motion == "within":
        chk.add(f"{where}.motion", WITHIN)
        return None
    if motion is not None and "motion" in tbl and "incident" not in tbl:
        chk.add(f"{where}.motion", "only with an incident history")
        return None
    if incident is None or motion is None:
        return None
    factor = MOTIONS[motion]
    wave = incident if factor == 1.0 else incident.scaled(factor)
    return {"impedance": impedance, "incident": wave, "motion": motion}


class Absorbing(EndLaw):
    def __init__(self, spec, index, case, mesh):
        super().__init__(spec, index, case, mesh)
        e = self.element
        given = spec.params["impedance"]
        # rho c A of the end element; built on the shear field (issue 27:
        # its mesh has E := G), the same line gives a shear absorbing end's
        # default rho Vs A, since sqrt(G rho) = rho Vs
        self.impedance = given if given is not None else \
            float(np.sqrt(mesh.E[e] * mesh.rho[e]) * mesh.A[e])
        self.incident = spec.params["incident"]

    def add_operators(self, ops):
        ops.add_node("c", self.node, self.impedance)

    def loads(self):
        if self.incident.is_zero:
            return []
        return [Load(self.node, 2.0 * self.impedance, self.incident)]

    def held_nodes(self):
        return [self.node]

    def static_loads(self):
        """None: the incident wave is a motion of the rock below, not a
        load the static state carries (the rock carries the static load,
        see HeldReactions)."""
        return []

    def describe(self):
        wave = "" if self.incident.is_zero else \
            ", incident wave" + (" = outcrop / 2" if self.spec.params["motion"] == "outcrop" else "")
        return f"{super().describe()} (impedance {self.impedance:.6g}{wave})"


def build(spec, index, case, mesh):
    return Absorbing(spec, index, case, mesh)
