"""What a run reports about itself (issue 44): an interface penalty stiffer
than double precision resolves is refused (exit 2, one line naming the
key and the limit; docs/interfaces.md)."""

import numpy as np
import pytest

import vstpetsc
from conftest import cli, solve, write_case
from vstpetsc.plane import pairs as pairs_mod

E, NU, RHO = 1.0e8, 0.3, 2000.0
M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))          # lambda + 2 mu
# the column's cells are 0.5 wide and 1 high, the joint horizontal: h = 1
# on both sides, their series stiffness M / 2 per unit length
SERIES = M / 2.0


def pressed(penalty=None, formulation="power", dt=1.0, end=20.0, gravity=False):
    """A column of 2 x 2 cells split by a horizontal joint at half height,
    its bottom fixed, its top pressed slowly (a traction rising to 1e5 Pa,
    dt = 1: the issue's quasi-static press); or at rest under gravity from
    a static start (``gravity``)."""
    interface = {"name": "j", "formulation": formulation}
    if penalty is not None:
        interface["penalty"] = penalty
    boundary = [{"name": "bottom", "type": "fixed"}]
    doc = {"time": {"dt": dt, "end": end},
           "mesh": {"rectangle": {"x": [0.0, 1.0], "y": [0.0, 2.0], "nx": 2, "ny": 2,
                                  "joints": {"j": 1.0}}},
           "region": [{"name": "domain", "E": E, "nu": NU, "rho": RHO}],
           "boundary": boundary, "interface": [interface]}
    if gravity:
        doc["gravity"] = {"g": -9.81, "initial": "static"}
    else:
        boundary.append({"name": "top", "type": "traction",
                         "value": {"y": [[0.0, 0.0], [end, -1.0e5]]}})
    return vstpetsc.Case.from_dict(doc)


def limit(formulation, dt=1.0):
    """The documented limit: a spring (the power penalty, the seed's
    penalty dt / 2) of 1e8 times the cells' series stiffness."""
    spring = 1e8 * SERIES
    return spring if formulation == "power" else 2.0 * spring / dt


# ---- (A) the penalty's limit ---------------------------------------------

BAD = [
    ("power 1e40", dict(penalty=1e40), "interface[0] (j).penalty: 1e+40 is stiffer than"),
    ("seed 1e40", dict(penalty=1e40, formulation="seed"),
     "interface[0] (j).penalty: 1e+40 is stiffer than"),
    ("power 1e150", dict(penalty=1e150), "interface[0] (j).penalty: 1e+150 is stiffer than"),
    ("power just beyond", dict(penalty=1.01 * limit("power")),
     f"at most {limit('power'):.3g} (1e+08 times"),
    ("seed just beyond", dict(penalty=1.01 * limit("seed"), formulation="seed"),
     f"at most {limit('seed'):.3g} (1e+08 times"),
]


@pytest.mark.parametrize("what, keys, message", BAD, ids=[b[0] for b in BAD])
def test_a_penalty_beyond_the_limit_is_refused(tmp_path, what, keys, message):
    """exit 2, one line naming interface[0] (j).penalty and the limit, no
    result file (the issue: 1e40 completed with a numerical energy of
    -1.34e6 J; 1e150 gave forces of 5.7e136 from a gap of -2.3e-13)."""
    case = write_case(tmp_path, pressed(**keys), "bad")
    p = cli("run", case, "-o", tmp_path / "bad.h5", "--quiet")
    assert p.returncode == 2, (p.stdout, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], p.stderr
    assert "Traceback" not in p.stderr and not (tmp_path / "bad.h5").exists()


@pytest.mark.parametrize("formulation", ["power", "seed"])
def test_a_penalty_just_within_the_limit_is_taken(tmp_path, formulation):
    """The limit is the documented rule of the cells beside the curve, not
    a round number: 0.99 of it runs (and its balance holds)."""
    case = pressed(0.99 * limit(formulation), formulation, dt=1e-4, end=2e-3)
    r = solve(tmp_path, case)
    assert r.interface("j").attrs["penalty"] == 0.99 * limit(formulation)
    assert r.status == "completed"


def test_the_limit_follows_the_softest_cells_beside_the_curve():
    """penalty_limit: per edge of the curve the series stiffness
    1 / (h_1 / M_1 + h_2 / M_2) of its two cells (M = lambda + 2 mu), the
    softest edge's, times 1e8 (the seed's as its slab-mean penalty dt / 2):
    a stiffer cell above one edge leaves the other edge's the limit."""
    from vstpetsc.plane.model import cell_materials, read_mesh

    plane = pressed().plane
    mesh = read_mesh(plane.mesh)
    materials = cell_materials(plane.regions, mesh.region)
    edges = mesh.curves["j"]
    got, series = pairs_mod.penalty_limit(mesh, materials, edges, "power", 1.0)
    assert series == pytest.approx(SERIES, rel=1e-12) and got == pytest.approx(1e8 * SERIES)
    seed, _ = pairs_mod.penalty_limit(mesh, materials, edges, "seed", 0.01)
    assert seed == pytest.approx(2e8 * SERIES / 0.01)
    # the cell above the first edge four times as stiff: that edge's series
    # stiffness rises to 4/5 M, the other edge's stays M / 2
    centre = mesh.coordinates[mesh.cells].mean(axis=1)
    above_first = np.flatnonzero((centre[:, 1] > 1.0) & (centre[:, 0] < 0.5))
    for key in ("lam", "mu"):
        materials[key][above_first] *= 4.0
    _, series = pairs_mod.penalty_limit(mesh, materials, edges, "power", 1.0)
    assert series == pytest.approx(SERIES, rel=1e-12)
    # every cell above four times as stiff: 4/5 M on both edges
    above = np.flatnonzero((centre[:, 1] > 1.0) & (centre[:, 0] > 0.5))
    for key in ("lam", "mu"):
        materials[key][above] *= 4.0
    _, stiffer = pairs_mod.penalty_limit(mesh, materials, edges, "power", 1.0)
    assert stiffer == pytest.approx(0.8 * M, rel=1e-12)
