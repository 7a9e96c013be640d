"""Lysmer's absorbing end: a dashpot Z (a half-space of that impedance
beyond the end) that lets waves leave, and an incoming wave of particle
velocity v_in(t): the end receives Z (2 v_in - v) along +x at either end
(docs/loads.md section 1).

Z is given as ``impedance``, or as the elastic ``rock`` beyond the end
(Z = rho_rock V_rock A with A the end element's area, V the rock's Vs for a
shear end and Vp for an axial one), or by default the end element's own
rho c A: no reflection of the body's own waves, but not the impedance of
rock stiffer than the body, whose motion an outcrop record is.

``motion`` says what the ``incident`` history is: the incident wave itself
(default), or an outcrop motion (the free surface of the rock doubles the
incident wave, so the incident wave is half of it).  A within (borehole)
motion is the total motion at the base, incident and reflected waves
together: it is prescribed at a rigid base (a velocity bc), never fed to a
dashpot."""

import numpy as np

from vstpetsc.line.laws.base import Load
from vstpetsc.line.laws.end import EndLaw

KEYS = ("impedance", "rock", "incident", "motion")
ROCK_KEYS = ("rho", "Vs", "Vp")
# the rock's wave speed that an end of each component feels
ROCK_SPEED = {"axial": "Vp", "shear": "Vs"}
# what the incident history is -> the factor that gives the incident wave
# (0.5 is exact in binary: outcrop equals scale = 0.5 bit for bit)
MOTIONS = {"incident": 1.0, "outcrop": 0.5, "within": None}
WITHIN = ("a within (borehole) motion is the total motion at the base, not an incident "
          "wave: prescribe it with a type = \"velocity\" bc (rigid base)")


def read(chk, tbl, where):
    impedance = chk.number(tbl, "impedance", where, required=False, positive=True)
    if impedance is None and "impedance" in tbl:
        return None
    rock = read_rock(chk, tbl, where) if "rock" in tbl else None
    if "rock" in tbl and (rock is None or "impedance" in tbl):
        if rock is not None:
            chk.add(f"{where}.rock", "give impedance or rock, not both")
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
    return {"impedance": impedance, "rock": rock, "incident": wave, "motion": motion}


def read_rock(chk, tbl, where):
    """(rho, speed, speed's name) of ``rock = { rho, Vs }`` (a shear end) or
    ``{ rho, Vp }`` (an axial end), or None after reporting."""
    name = f"{where}.rock"
    sub = chk.table(tbl, "rock", name, required=False)
    if not isinstance(tbl["rock"], dict):
        return None
    chk.unknown(sub, ROCK_KEYS, name)
    component = tbl.get("component", "axial")
    speed_key = ROCK_SPEED.get(component)
    if speed_key is None:               # the bad component is reported by the bc
        return None
    other = [k for k in ROCK_SPEED.values() if k != speed_key and k in sub]
    if other:
        article = "an" if component == "axial" else "a"
        chk.add(f"{name}.{other[0]}", f"{article} {component} absorbing end takes the rock's "
                f"{speed_key}, not {other[0]}")
        return None
    rho = chk.number(sub, "rho", name, positive=True)
    speed = chk.number(sub, speed_key, name, positive=True)
    return None if None in (rho, speed) or set(sub) - set(ROCK_KEYS) else (rho, speed, speed_key)


class Absorbing(EndLaw):
    def __init__(self, spec, index, case, mesh):
        super().__init__(spec, index, case, mesh)
        self.impedance, self.source = end_impedance(spec.params, mesh, self.element)
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
        return f"{super().describe()} (impedance {self.impedance:.6g} {self.source}{wave})"


def end_impedance(params, mesh, e):
    """(Z, where it came from) of an absorbing end at element ``e``."""
    area = float(mesh.A[e])
    if params["impedance"] is not None:
        return params["impedance"], "given"
    if params["rock"] is not None:
        rho, speed, key = params["rock"]
        return rho * speed * area, f"= rho {key} A of the rock, {rho:g} x {speed:g} x {area:g}"
    # rho c A of the end element; built on the shear field (issue 27: its
    # mesh has E := G), the same line gives a shear end's rho Vs A, since
    # sqrt(G rho) = rho Vs
    return float(np.sqrt(mesh.E[e] * mesh.rho[e]) * area), \
        "= rho c A of the end element (the default: the body's own, no rock given)"


def build(spec, index, case, mesh):
    return Absorbing(spec, index, case, mesh)
