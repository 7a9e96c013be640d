"""Hydrostatic water against a plane-strain dam ([[water]], issue 47's
first step, docs/water.md): the nodal pattern against the exact
integrals of the pressure (a slanted face cut by the level), a block dam
at rest on a frictional joint under its weight and a reservoir (the
joint carries the thrust rho g level^2 / 2 and the weight W), a block
that slides when mu W is below the thrust and stays when above, two
ranks against one, a restart bit for bit, `vstpetsc info`, and the bad
inputs (exit 2, one line naming the key)."""

import io

import numpy as np
import pytest

import vstpetsc
from test_plane_run import mpirun_against_one_rank, run_cli

G, RHO_W, RHO, B, H, D = 9.81, 1000.0, 2400.0, 10.0, 20.0, 5.0
LEVEL = 16.0            # between two grid rows (15, 17.5): an edge crosses the level
BLOCK = f"""
[time]
dt = {{dt}}
end = {{end}}
[mesh]
rectangle = {{{{ x = [0.0, {B}], y = [-{D}, {H}], nx = 4, ny = 10, joints = {{{{ joint = 0.0 }}}} }}}}
[[region]]
name = "domain"
E = 2.0e10
nu = 0.2
rho = {RHO}
{{damping}}
[[interface]]
name = "joint"
friction = {{friction}}
[[boundary]]
name = "bottom"
type = "fixed"
[gravity]
g = {{g}}
initial = "{{initial}}"
[[water]]
name = "reservoir"
level = {LEVEL}
faces = ["left"]
"""
THRUST = RHO_W * G * LEVEL ** 2 / 2          # on the block above the joint
WEIGHT = RHO * G * B * H
RAMP = 0.3                                   # g from 0 to -9.81 over RAMP (the sliding runs)


def block_case(tmp_path, name="block", end=0.01, dt=1e-3, friction=0.6, g="-9.81",
               initial="static", damping=""):
    path = tmp_path / f"{name}.toml"
    path.write_text(BLOCK.format(end=end, dt=dt, friction=friction, g=g, initial=initial,
                                 damping=damping))
    return path


def ramped_case(tmp_path, friction, end=0.5, name="ramped"):
    """The block under g ramped from 0 over RAMP (nearly static loading:
    the block's lowest period is 0.05 s), lightly damped, from rest."""
    return block_case(tmp_path, name, end=end, dt=2e-3, friction=friction,
                      g=f"[[0.0, 0.0], [{RAMP}, -9.81], [10.0, -9.81]]", initial="rest",
                      damping="damping = { beta = 1.0e-3 }")


def run(path, tmp_path, name="out"):
    return vstpetsc.run(vstpetsc.Case.from_toml(path), output=str(tmp_path / f"{name}.h5"),
                        quiet=True, out=io.StringIO())


def restarted_as_whole(tmp_path, case_to, end):
    """A run to ``end`` and the same cut at end / 2 and continued with
    --restart (``case_to(end, name)``: the case file): every dataset of
    the two bit for bit (but the wall time); their names."""
    from test_plane_yielding import assert_same_bits

    whole = run(case_to(end, "whole"), tmp_path, "whole")
    part = str(tmp_path / "part.h5")
    for stop, restart in ((0.5 * end, False), (end, True)):
        vstpetsc.run(vstpetsc.Case.from_toml(case_to(stop, "half")), output=part, quiet=True,
                     restart=restart, out=io.StringIO())
    return assert_same_bits(whole.path, part)


# --- the nodal pattern against the exact integrals ---------------------------------------

def exact_resultant(p, q, level, rho):
    """(force (2,) per unit g, moment about the origin) of the pressure
    rho (level - y)+ on the straight face p -> q, whose outward normal is
    n (closed forms: the wet piece's trapezoid, its centroid)."""
    p, q = np.asarray(p, float), np.asarray(q, float)
    t = (q - p) / np.linalg.norm(q - p)
    n = np.array([t[1], -t[0]])
    if p[1] > q[1]:
        p, q = q, p
    top = p + (q - p) * min(1.0, (level - p[1]) / (q[1] - p[1]))     # where the level cuts it
    length = np.linalg.norm(top - p)
    hp, ht = level - p[1], level - top[1]
    total = rho * length * (hp + ht) / 2
    centre = p + (top - p) * (hp + 2 * ht) / (3 * (hp + ht))        # the trapezoid's centroid
    force = total * n
    return force, centre[0] * force[1] - centre[1] * force[0]


@pytest.mark.parametrize("level", [2.0, 1.0, 3.5, 0.2])
def test_the_nodal_pattern_is_the_exact_resultant_and_moment(level):
    """One triangle (0, 0), (4, 0), (1, 3) whose slanted face (4, 0)-(1, 3)
    is wet up to ``level`` (cut by it, or wholly under it at 3.5): the
    pattern's sum and first moment sum x_a x F_a are the exact force and
    moment of the pressure (linear shape functions reproduce x along the
    edge, so the consistent loads' moment is the load's), to rounding; the
    unwetted corner (0, 0) takes nothing and the force points into the
    solid under g < 0."""
    from vstpetsc.plane.mesh import PlaneMesh
    from vstpetsc.plane.schema import WaterSpec
    from vstpetsc.plane.water import nodal_pattern

    xy = np.array([[0.0, 0.0], [4.0, 0.0], [1.0, 3.0]])
    for edge in ([1, 2], [2, 1]):               # either direction of the curve's edge
        mesh = PlaneMesh(xy, np.array([[0, 1, 2, -1]]), np.zeros(1, int), ("domain",),
                         {"slope": np.array([edge])})
        pattern = nodal_pattern(mesh, WaterSpec("w", level, RHO_W, ("slope",)))
        force, moment = exact_resultant(xy[1], xy[2], level, RHO_W)
        got_force = pattern.sum(axis=0)
        got_moment = np.sum(xy[:, 0] * pattern[:, 1] - xy[:, 1] * pattern[:, 0])
        scale = np.abs(force).max()
        print(level, edge, "force error", np.abs(got_force - force).max() / scale,
              "moment error", abs(got_moment - moment) / (scale * 4))
        assert np.abs(got_force - force).max() <= 1e-14 * scale
        assert abs(got_moment - moment) <= 1e-14 * scale * 4
        assert not pattern[0].any()
        assert (got_force * -G) @ np.array([-1.0, -1.0]) > 0         # into the solid: along -n


def test_the_pattern_of_a_vertical_face_crossing_the_level():
    """A vertical face's edges from y = 0 to 4 in steps of 1, wet to 2.5
    (an edge cut in its middle): the nodal forces are the closed form of
    each node's share, int N_a rho (level - y)+ dy, along -x (the face
    is the cell's left side: outward normal -x)."""
    from vstpetsc.plane.mesh import rectangle
    from vstpetsc.plane.schema import WaterSpec
    from vstpetsc.plane.water import nodal_pattern

    mesh = rectangle((0.0, 1.0), (0.0, 4.0), 1, 4)
    pattern = nodal_pattern(mesh, WaterSpec("w", 2.5, RHO_W, ("left",)))
    left = np.flatnonzero(mesh.coordinates[:, 0] == 0.0)
    y = mesh.coordinates[left, 1]
    h = lambda s: np.maximum(2.5 - s, 0.0)
    # each node's share of the piecewise linear pressure: exact by Simpson on the pieces
    exact = np.zeros(left.size)
    for k, yk in enumerate(y):
        for lo, hi in ((yk - 1, yk), (yk, yk + 1)):
            if lo < 0 or hi > 4:
                continue
            for a, b in ((lo, min(hi, 2.5)), (max(lo, 2.5), hi)):
                if b > a:
                    N = lambda s: 1 - np.abs(s - yk)
                    f = lambda s: N(s) * h(s)
                    exact[k] += (b - a) / 6 * (f(a) + 4 * f((a + b) / 2) + f(b))
    print("vertical face: largest error", np.abs(pattern[left, 0] + RHO_W * exact).max())
    assert np.allclose(pattern[left, 0], -RHO_W * exact, rtol=0, atol=1e-12 * RHO_W)
    assert not pattern[:, 1].any() and not pattern[mesh.coordinates[:, 0] > 0].any()


# --- a block dam on a frictional joint ----------------------------------------------------

def test_a_block_dam_rests_on_its_joint_under_weight_and_reservoir(tmp_path):
    """The block (B x H, above the joint at y = 0) on its foundation (the
    rectangle's part below, its bottom fixed), water on the left face up
    to LEVEL (the "left" curve also wets the foundation's side below the
    joint, which does not load the joint), friction 0.6 > thrust / W =
    0.27.  From the static start, every slab: the joint's pairs carry
    sum(shear_force) = -rho g LEVEL^2 / 2 (the friction on the block
    holds it against the thrust, along -x) and sum(normal_force) = W to
    1e-9 of W (the static solve by LU and the slabs' solves: rounding of
    a 120-dof system, measured 1e-14); /water/reservoir/force is the
    closed form on the whole wetted side (rho g (LEVEL + D)^2 / 2, 0),
    its pressure rho g (LEVEL - y)+ at its nodes; the block stays at rest."""
    r = run(block_case(tmp_path), tmp_path)
    joint = r.interface("joint")
    shear = joint.shear_force[1:].sum(axis=1)
    normal = joint.normal_force[1:].sum(axis=1)
    water = r.water("reservoir")
    nodes, force, pressure = water.nodes[:], water.force[:], water.pressure[:]
    y = r.mesh.coordinates[nodes, 1]
    side = RHO_W * G * (LEVEL + D) ** 2 / 2
    print("shear against the thrust", np.abs(shear + THRUST).max() / THRUST,
          "normal against W", np.abs(normal - WEIGHT).max() / WEIGHT,
          "force against the closed form", np.abs(force - [side, 0.0]).max() / side,
          "largest v", np.abs(r.field.v).max())
    assert np.abs(shear + THRUST).max() <= 1e-9 * WEIGHT
    assert np.abs(normal - WEIGHT).max() <= 1e-9 * WEIGHT
    assert np.abs(force - [side, 0.0]).max() <= 1e-12 * side
    assert np.allclose(pressure, RHO_W * G * np.maximum(LEVEL - y, 0.0)[None, :], rtol=1e-14,
                       atol=0)
    # in order along the face, up from the foundation's corner; the joint's node once per side
    assert np.all(np.diff(y) >= 0) and y[0] == -D and np.sum(y == 0.0) == 2
    assert np.abs(r.field.v).max() <= 1e-10 * THRUST / (RHO * B * H) * r.case().dt


def test_a_block_slides_when_mu_w_is_below_the_thrust_and_stays_above(tmp_path):
    """g ramped from 0 (weight and thrust grow together): with friction
    0.2 < thrust / W = 0.267 the block slides from the start, its mean
    slip that of a rigid block under (thrust - mu W) g(t) / 9.81 (closed
    form, within 1e-3: the block's and the foundation's elastic strains
    are 1e-5 m of 4e-2 m); with 0.6 its slip is the springs' and a few
    pairs' local sliding during the ramp (below 1e-3 of the other) and
    stops: constant over the last 0.1 s while the other's grows."""
    slides, stays = (run(ramped_case(tmp_path, mu, name=f"mu{mu}"), tmp_path, f"mu{mu}")
                     for mu in (0.2, 0.6))
    t = slides.time
    a = (THRUST - 0.2 * WEIGHT) / (RHO * B * H)
    rigid = np.where(t < RAMP, a * t ** 3 / (6 * RAMP),
                     a * (RAMP ** 2 / 6 + RAMP / 2 * (t - RAMP) + (t - RAMP) ** 2 / 2))
    slip = slides.interface("joint").slip[:].mean(axis=1)
    held = stays.interface("joint").slip[:].mean(axis=1)
    late = t >= t[-1] - 0.1 - 1e-12
    print("sliding: slip", slip[-1], "rigid", rigid[-1], "error", abs(slip[-1] / rigid[-1] - 1),
          "held slip", held[-1], "its change late", np.ptp(held[late]))
    assert abs(slip[-1] / rigid[-1] - 1) <= 1e-3
    assert np.all(np.diff(slip[late]) > 0) and np.ptp(slip[late]) > 1e-2
    assert np.abs(held).max() <= 1e-3 * slip[-1]
    assert np.ptp(held[late]) <= 1e-12


# --- parallel, restart, info ---------------------------------------------------------------

def test_water_on_two_ranks_equals_one(tmp_path):
    two = mpirun_against_one_rank(tmp_path, ramped_case(tmp_path, 0.2, end=0.1))
    r = vstpetsc.Result(two)
    assert np.abs(r.water("reservoir").force[:]).max() > 0
    assert np.abs(r.interface("joint").slip[:]).max() > 1e-5


def test_a_restart_with_water_continues_bit_for_bit(tmp_path):
    names = restarted_as_whole(
        tmp_path, lambda end, name: ramped_case(tmp_path, 0.2, end=end, name=name), 0.1)
    assert "water/reservoir/force" in names


def test_info_prints_the_largest_resultant(tmp_path):
    out = tmp_path / "one.h5"
    assert run_cli("run", ramped_case(tmp_path, 0.6, end=0.1), "-o", out, "-q").returncode == 0
    p = run_cli("info", out)
    assert p.returncode == 0, p.stderr
    force = vstpetsc.Result(out).water("reservoir").force[:]
    fx = force[np.hypot(*force.T).argmax(), 0]
    line = [x for x in p.stdout.splitlines() if x.strip().startswith("water reservoir")]
    assert line and f"largest resultant ({fx:.6g}, 0)" in line[0], p.stdout


# --- bad inputs -----------------------------------------------------------------------------

WATER = '[[water]]\nname = "reservoir"\nlevel = 16.0\nfaces = ["left"]\n'
BAD = [
    ("unknown key", WATER + "levle = 3.0\n", "water[0].levle: unknown key"),
    ("not a curve", WATER.replace('"left"', '"upstream"'),
     "water[0] (reservoir).faces: 'upstream' is not a curve of the mesh"),
    ("inner curve", WATER.replace('"left"', '"joint"'),
     "water[0] (reservoir).faces: 'joint' runs between two cells"),
    ("empty faces", WATER.replace('["left"]', "[]"), "water[0] (reservoir).faces: must be a "
     "non-empty list of curve names"),
    ("level below", WATER.replace("16.0", "-6.0"),
     "water[0] (reservoir).level: -6 is not above the faces' lowest point (y = -5)"),
    ("nan level", WATER.replace("16.0", "nan"), "water[0] (reservoir).level: must be finite"),
    ("text level", WATER.replace("16.0", '"high"'),
     "water[0] (reservoir).level: must be a number"),
    ("rho", WATER + "rho = 0.0\n", "water[0] (reservoir).rho"),
    ("text rho", WATER + 'rho = "fresh"\n', "water[0] (reservoir).rho: must be a number"),
    ("duplicate", WATER + WATER, "water[1].name: a second [[water]] named 'reservoir'"),
    ("acoustic without region", WATER + 'hydrodynamic = "acoustic"\n',
     "water[0] (reservoir).region: missing"),
    ("acoustic region", WATER + 'region = "water"\n',
     "water[0] (reservoir).region: is the acoustic water's (hydrodynamic = \"acoustic\"), "
     "not the 'none' water's"),
    ("hydrodynamic name", WATER + 'hydrodynamic = "added"\n',
     "water[0] (reservoir).hydrodynamic: must be one of 'none', 'westergaard', 'acoustic'"),
    ("no gravity", "NOGRAVITY", "water[0] (reservoir): needs [gravity]"),
    ("upward g", "UP", "gravity.g: water 'reservoir' needs g <= 0"),
]


@pytest.mark.parametrize("what, water, message", BAD, ids=[b[0] for b in BAD])
def test_bad_water_exits_2_with_one_line(tmp_path, what, water, message):
    text = block_case(tmp_path).read_text().split("[[water]]")[0]
    if water == "NOGRAVITY":
        text, water = text.split("[gravity]")[0], WATER
    elif water == "UP":
        text, water = text.replace("g = -9.81", "g = [[0.0, -9.81], [1.0, 1.0]]"), WATER
    case = tmp_path / "bad.toml"
    case.write_text(text + water)
    p = run_cli("run", case, "-o", tmp_path / "bad.h5", "-q")
    assert p.returncode == 2, (p.stdout, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], p.stderr
    assert not (tmp_path / "bad.h5").exists()
