"""Boundary and interface laws, one module each (protocol: :mod:`.base`).

A module offers ``KEYS`` (its own keys in the case table), ``read(chk, tbl,
where)`` (validates them; a dict of parameters or None) and ``build(spec,
index, case, mesh)`` (the :class:`~vstpetsc.line.laws.base.Law`).  A new law is a
new module and an entry in one of these registries.
"""

import dataclasses

from vstpetsc.line.laws import (absorbing, cushion, fixed, friction, gravity, penalty, soil,
    support, traction, velocity)

BOUNDARY = {"fixed": fixed, "velocity": velocity, "traction": traction, "support": support,
            "absorbing": absorbing}
CONTACT = {"seed": penalty, "power": penalty, "cushion": cushion}


def build_laws(case, mesh):
    """Every law of ``case``: its contact pairs in order, the friction of
    those with ``friction`` (after them: it reads their normal force), its
    [[bc]]s (a shear bc on the body's shear twin), its [[soil]] tables,
    then gravity."""
    laws = [CONTACT[c.formulation].build(c, k, case, mesh)
            for k, c in enumerate(case.contacts)]
    laws += [friction.build(c, k, case, mesh, laws[k])
             for k, c in enumerate(case.contacts) if c.friction is not None]
    laws += [BOUNDARY[b.type].build(on_field(b, mesh), k, case, mesh)
             for k, b in enumerate(case.bcs)]
    for k, spec in enumerate(case.soils):
        laws += soil.build(spec, k, case, mesh)
        soil.mark_head(laws, spec, mesh)
    if case.gravity is not None:
        laws.append(gravity.build(case.gravity, mesh))
    return laws


def on_field(spec, mesh):
    """A [[bc]] with its body the mesh body that carries its component."""
    if spec.component == "shear":
        return dataclasses.replace(spec, body=mesh.twins[spec.body])
    return spec
