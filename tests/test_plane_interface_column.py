"""A column one cell wide split across its width by an interface, run
from its case file, against the 1-D solver's two bars and their contact
pair (interface.md: "a one-cell-wide column split across its width
equals the 1-D pair of bars of unit area").  The defaults' penalties are
the 1-D rules' (the same numbers).

Normal contact: nu = 0 keeps plane strain laterally uniform with free
sides (lambda = 0, no lateral stress): the column is the 1-D bar of
E = lambda + 2 mu.  The top is driven down, then up: the joint closes,
presses and opens again.

Friction: a laterally uniform shear needs the complementary shear on the
sides, so the sides hold v_y (the column is the 1-D shear bar of G = mu)
and the joint's normal force stays what it starts with: the upper
region starts pressed into the lower by u0, by the gap of the 1-D
column's static start under the upper bar's weight (there, too, N is
constant: the axial field is static, its top free).  The top is driven sideways: the joint sticks,
then slides once the shear reaches mu N.

Both Newtons converge to their tolerances: the runs agree to 1e-9."""

import numpy as np
import pytest

import vstpetsc
from conftest import bar, make_case, solve
from vstpetsc.plane import mesh as plane_mesh
from vstpetsc.plane.gmsh_file import write_gmsh22

E, RHO, HEIGHT, CELLS, WIDTH = 1.0e8, 2000.0, 20.0, 20, 1.0
G = E / 2.0                                   # nu = 0
DT, END = 2.0e-4, 0.16
GRAVITY = -9.81
DRIVE_Y = [[0.0, -0.5], [0.07, -0.5], [0.0702, 0.8], [END, 0.8]]


def _errors(checks):
    return {k: np.abs(a - b).max() / max(np.abs(b).max(), 1e-300) for k, (a, b) in checks.items()}


def _energies(two, one, keys, since=()):
    largest = max(np.abs(one.energy[k]).max() for k in one.energy)
    shift = lambda r, k: r.energy[k] - (r.energy[k][0] if k in since else 0.0)
    return {f"energy {k}": np.abs(shift(two, k) - shift(one, k)).max() / largest for k in keys}


def normal_cases(folder, formulation):
    two = vstpetsc.Case.from_dict({
        "time": {"dt": DT, "end": END},
        "mesh": {"rectangle": {"x": [0.0, WIDTH], "y": [0.0, HEIGHT], "nx": 1, "ny": CELLS,
                               "joints": {"joint": HEIGHT / 2}}},
        "region": [{"name": "domain", "E": E, "nu": 0.0, "rho": RHO}],
        "boundary": [{"name": "bottom", "type": "fixed"},
                     {"name": "top", "type": "velocity", "value": {"y": DRIVE_Y}}],
        "interface": [{"name": "joint", "formulation": formulation}]}, folder=str(folder))
    bodies = [bar(n, x, CELLS // 2, E=E, rho=RHO, area=WIDTH)
              for n, x in (("lower", (0.0, HEIGHT / 2)), ("upper", (HEIGHT / 2, HEIGHT)))]
    one = make_case(DT, END, bodies, [{"pair": ["lower", "upper"], "formulation": formulation}],
                    [{"body": "lower", "end": "left", "type": "fixed"},
                     {"body": "upper", "end": "right", "type": "velocity", "value": DRIVE_Y}])
    return two, one


@pytest.mark.parametrize("formulation", ["power", "seed"])
def test_split_column_is_the_1d_pair_in_normal_contact(tmp_path, formulation):
    two_case, one_case = normal_cases(tmp_path, formulation)
    two, one = solve(tmp_path, two_case, "two"), solve(tmp_path, one_case, "one")
    joint, pair = two.interface("joint"), one.contact(0)
    xy = two.mesh.coordinates
    at = lambda y: np.flatnonzero(np.isclose(xy[:, 1], y))
    errors = _errors({
        "gap": (joint.gap[:], pair.gap[:][:, None]),
        "normal force": (joint.normal_force[:].sum(axis=1), pair.force[:]),
        "v_y at y = 5": (two.field.v[:, at(5.0), 1], one.body("lower").v[:, 5][:, None]),
        "u_y at y = 15": (two.field.u[:, at(15.0), 1], one.body("upper").u[:, 5][:, None])})
    errors.update(_energies(two, one, ("kinetic", "strain", "external", "contact",
                                       "numerical")))
    print(formulation, {k: f"{v:.2g}" for k, v in errors.items()})
    gap = pair.gap[:]
    assert gap.min() < 0 and gap[-1] > 0 and pair.force[:].max() > 1e5   # closes, opens
    open_slab = (gap[1:] > 0) & (gap[:-1] > 0)          # open through the slab before the row
    assert open_slab.any() and np.all(joint.normal_force[1:][open_slab] == 0.0)
    assert max(errors.values()) <= 1e-9, errors


def two_region_column(folder):
    """The column of the friction test as a Gmsh file: regions "lower",
    "upper" on either side of its joint."""
    m = plane_mesh.rectangle((0.0, WIDTH), (0.0, HEIGHT), 1, CELLS, joints={"joint": CELLS // 2})
    centre = m.coordinates[m.cells].mean(axis=1)[:, 1]
    m = plane_mesh.PlaneMesh(m.coordinates, m.cells, (centre > HEIGHT / 2).astype(int),
                             ("lower", "upper"), m.curves)
    write_gmsh22(folder / "column.msh", m)
    return {"file": "column.msh"}


def friction_cases(folder, friction, law=None):
    """(the 2-D case of a gap, the 1-D case); ``law`` a shear_law table
    for the lower side (issue 46: yielding under the joint, one Newton)."""
    yielding = {} if law is None else {"shear_law": law}
    bodies = [bar(n, x, CELLS // 2, E=E, rho=RHO, area=WIDTH, G=G,
                  **(yielding if n == "lower" else {}))
              for n, x in (("lower", (0.0, HEIGHT / 2)), ("upper", (HEIGHT / 2, HEIGHT)))]
    drive = [[0.0, 0.0], [0.01, 0.3], [END, 0.3]]
    one = make_case(DT, END, bodies, [{"pair": ["lower", "upper"], "friction": friction}],
                    [{"body": "lower", "end": "left", "type": "fixed"},
                     {"body": "lower", "end": "left", "type": "fixed", "component": "shear"},
                     {"body": "upper", "end": "right", "type": "velocity", "value": drive,
                      "component": "shear"}],
                    gravity={"g": GRAVITY, "initial": "static"})
    held_y = {"type": "velocity", "value": {"y": 0.0}}
    region = {"E": E, "nu": 0.0, "rho": RHO}

    def two(gap0):
        return vstpetsc.Case.from_dict({
            "time": {"dt": DT, "end": END}, "mesh": two_region_column(folder),
            "region": [{"name": "lower", **region, **yielding},
                       {"name": "upper", **region, "u0": [0.0, gap0]}],
            "boundary": [{"name": "bottom", "type": "fixed"},
                         {"name": "top", "type": "velocity", "value": {"x": drive, "y": 0.0}},
                         {"name": "left", **held_y}, {"name": "right", **held_y}],
            "interface": [{"name": "joint", "friction": friction}]}, folder=str(folder))
    return two, one


# yielding under the joint (issue 46): the lower half carries mu N = 0.2 x
# the upper half's weight at about 3 gamma_ref, and the joint slides
MKZ = {"model": "mkz", "gamma_ref": 1.0e-3, "beta": 1.0, "s": 0.919}


@pytest.mark.parametrize("friction, law", [(0.2, None), (0.4, None), (0.2, MKZ)],
                         ids=["0.2", "0.4", "0.2-mkz"])
def test_split_column_is_the_1d_frictional_pair(tmp_path, friction, law):
    two_case, one_case = friction_cases(tmp_path, friction, law)
    one = solve(tmp_path, one_case, "one")
    pair = one.contact(0)
    two = solve(tmp_path, two_case(float(pair.gap[0])), "two")
    joint = two.interface("joint")
    xy = two.mesh.coordinates
    at = lambda y: np.flatnonzero(np.isclose(xy[:, 1], y))
    normal = pair.force[:]               # slab means: row 0 (t = 0) has none
    assert np.ptp(normal[1:]) <= 1e-9 * normal[1] and normal[1] > 0    # the 1-D N is constant
    errors = _errors({
        "normal force": (joint.normal_force[:].sum(axis=1), normal),
        "shear force": (joint.shear_force[:].sum(axis=1), pair.shear_force[:]),
        "slip": (joint.slip[:], pair.slip[:][:, None]),
        "v_x at y = 5": (two.field.v[:, at(5.0), 0], one.body("lower").shear.v[:, 5][:, None]),
        "u_x at y = 15": (two.field.u[:, at(15.0), 0],
                          one.body("upper").shear.u[:, 5][:, None])})
    errors.update(_energies(two, one, ("kinetic", "external", "contact", "friction",
                                       "numerical"), since=("strain",)))
    errors.update(_energies(two, one, ("strain",), since=("strain",)))
    if law is not None:            # the lower half yields, and both dissipate alike
        errors.update(_energies(two, one, ("hysteretic",)))
        assert two.field.strain_max.max() > 2.0 * law["gamma_ref"]
        assert two.energy["hysteretic"][-1] > 1e-3 * two.energy["external"][-1]
    print(friction, {k: f"{v:.2g}" for k, v in errors.items()})
    assert np.abs(pair.slip[:]).max() > 1e-3 and one.energy["friction"][-1] > 0   # it slides
    # sliding one way under a constant N dissipates mu N |slip|
    slip = np.abs(joint.slip[-1]).mean()
    dissipated = friction * normal[1] * slip
    assert abs(two.energy["friction"][-1] - dissipated) <= 1e-9 * dissipated
    assert max(errors.values()) <= 1e-9, errors
