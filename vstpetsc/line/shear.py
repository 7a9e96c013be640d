"""The shear component (docs/shear.md): its case keys (a body's ``G`` or
``Vs``, ``v0_shear`` and ``u0_shear``; a bc's ``component``; a contact's
``friction`` and ``wall_shear_velocity``) and the field that carries it.

The shear motion w(x, t) of a body obeys the axial equation with E := G, so
the field is a second set of bodies: each body with a shear component gets
a twin (:func:`shear_twin`) meshed after every axial body, with the same
elements, density, area, damping and foundation, G for E and the shear
initial state.  A twin shares no element with anything, so the slab matrix
is block diagonal (axial | shear) and every part of the solver (the slab
solve, restarts, ranks, envelopes, energies) treats the two fields alike;
what joins them is only Coulomb friction (laws/friction.py), whose limit
reads the axial pair's normal force.  Nothing here imports PETSc.
"""

import dataclasses

from vstpetsc.input.checker import MAGNITUDE
from vstpetsc.spacetime.history import History

BODY_KEYS = ("G", "Vs", "v0_shear", "u0_shear")
CONTACT_KEYS = ("friction", "wall_shear_velocity")
COMPONENTS = ("axial", "shear")
FRICTION_FORMULATIONS = ("seed", "power")
NO_SHEAR = (None, None, None)
SUFFIX = "/shear"       # a twin's name: its datasets are /body/<name>/shear/...


class ShearModulus:
    """G(x) = rho(x) Vs(x)^2 of a body that gives its shear-wave speed,
    evaluated where the mesh asks (element midpoints, as E): the product of
    two tables is not a table, so it is not made one."""

    def __init__(self, rho, Vs):
        self.rho, self.Vs = rho, Vs

    def __call__(self, x):
        return self.rho(x) * self.Vs(x) ** 2

    def __eq__(self, other):
        return isinstance(other, ShearModulus) and (self.rho, self.Vs) == (other.rho, other.Vs)

    def __repr__(self):
        return f"ShearModulus(rho={self.rho!r}, Vs={self.Vs!r})"


def no_shear_message(name):
    return f"body {name!r} has no shear component (give it G or Vs)"


def read_body(chk, tbl, where, rho, material, G=None):
    """(G, v0_shear, u0_shear) of a [[body]] (all None without G or Vs), or
    None after reporting; ``material(key)`` reads a positive profile that
    covers the body (as E); ``G`` the modulus of a layered body (its
    layers give Vs)."""
    if G is not None:
        fields = (G, chk.history(tbl, "v0_shear", where, "x"),
                  chk.history(tbl, "u0_shear", where, "x"))
        return None if None in fields else fields
    given = [k for k in ("G", "Vs") if k in tbl]
    if len(given) == 2:
        chk.add(f"{where}.Vs", "give G or Vs (G = rho Vs^2), not both")
        return None
    if not given:
        extra = [k for k in ("v0_shear", "u0_shear") if k in tbl]
        for key in extra:
            chk.add(f"{where}.{key}", "only for a body with a shear component (give G or Vs)")
        return None if extra else NO_SHEAR
    profile = material(given[0])
    fields = (_modulus(chk, where, given[0], profile, rho),
              chk.history(tbl, "v0_shear", where, "x"), chk.history(tbl, "u0_shear", where, "x"))
    return None if None in fields else fields


def _modulus(chk, where, key, profile, rho):
    """G itself, or rho Vs^2 when its bounds keep it a normal double (as
    every modulus of a case: squares and products stay finite)."""
    if key == "G":
        return profile
    if profile is None or rho is None:
        return None
    high, low = rho.f.max() * profile.f.max() ** 2, rho.f.min() * profile.f.min() ** 2
    if not MAGNITUDE[0] <= low <= high <= MAGNITUDE[1]:
        chk.add(f"{where}.Vs", f"G = rho Vs^2 must lie in {MAGNITUDE[0]:g} .. "
                f"{MAGNITUDE[1]:g}, got values up to {high:g} and down to {low:g}")
        return None
    return ShearModulus(rho, profile)


def read_friction(chk, tbl, where, formulation):
    """(friction or None, wall_shear_velocity or None) of a [[contact]], or
    None after reporting."""
    mu = chk.number(tbl, "friction", where, required=False, minimum=0.0)
    ok = mu is not None or "friction" not in tbl
    if mu is not None and formulation not in FRICTION_FORMULATIONS:
        chk.add(f"{where}.friction", f"not available with formulation {formulation!r} "
                f"(only {' and '.join(map(repr, FRICTION_FORMULATIONS))})")
        ok = False
    wall_v = None
    if "wall_shear_velocity" in tbl:
        wall_v = chk.history(tbl, "wall_shear_velocity", where, "t", records=True)
        ok = ok and wall_v is not None
        if "friction" not in tbl:
            chk.add(f"{where}.wall_shear_velocity", "only for a pair with friction")
            ok = False
    return (mu, wall_v) if ok else None


def check_pair(chk, where, bodies, left, right, friction):
    """``friction`` (mu, wall velocity) of a resolved pair after checking its
    bodies; a wall pair with friction gets the wall velocity 0 by default;
    None after reporting."""
    mu, wall_v = friction
    wall = left is None or right is None
    if wall_v is not None and not wall:
        chk.add(f"{where}.wall_shear_velocity", "only for a pair with \"wall\"")
        return None
    if mu is None:
        return friction
    bare = [bodies[b].name for b in (left, right) if b is not None and not bodies[b].has_shear]
    if bare:
        chk.add(f"{where}.friction", no_shear_message(bare[0]))
        return None
    if wall and wall_v is None:
        wall_v = History()
    return mu, wall_v


def shear_twin(body):
    """The body that carries ``body``'s shear motion in the mesh."""
    return dataclasses.replace(body, name=body.name + SUFFIX, E=body.G,
                               v0=body.v0_shear or History(), u0=body.u0_shear or History(),
                               G=None, v0_shear=None, u0_shear=None, shear_law=None)


def field_bodies(bodies):
    """The mesh's bodies: every axial body, then the shear twins of those
    with a shear component; and {axial body: its twin's index}."""
    twins = {b: len(bodies) + j for j, b in enumerate(
        [i for i, body in enumerate(bodies) if body.has_shear])}
    return list(bodies) + [shear_twin(bodies[b]) for b in twins], twins


def is_twin(name):
    return name.endswith(SUFFIX)
