"""The uplift of a [[water]] table in an [[interface]] (issue 47,
docs/water.md "Uplift"): the block dam of tests/test_water_hydrostatic.py
at rest on its joint with the reservoir's uplift (and with a tailwater)
carries sum(normal_force) = W - U and sum(shear_force) = the net thrust;
a block whose mu W holds the thrust but whose mu (W - U) does not slides
from rest at the rigid block's acceleration, a higher friction holds it;
two ranks against one, a restart bit for bit, `vstpetsc info`'s sliding
factor of safety, and the bad inputs (exit 2, one line naming the key)."""

import io

import numpy as np
import pytest

import vstpetsc
from test_plane_run import mpirun_against_one_rank, run_cli
from test_water_hydrostatic import restarted_as_whole
from test_water_hydrostatic import B, D, G, H, LEVEL, RHO, RHO_W, THRUST, WEIGHT, block_case

TAIL = 4.0                                          # the tailwater's level (y)
LIFT = RHO_W * G * LEVEL / 2 * B                    # U: p_a = rho g LEVEL at x = 0, 0 at x = B
LIFT_TAIL = RHO_W * G * (LEVEL + TAIL) / 2 * B      # with the tailwater: p_b = rho g TAIL
TAIL_WATER = f"""
[[water]]
name = "tail"
level = {TAIL}
faces = ["right"]
"""


def lifted_case(tmp_path, name="lifted", tail=False, **kw):
    """The block case with the reservoir's uplift in its joint (and with
    ``tail`` a tailwater: its own [[water]] on the right face and the
    reservoir's uplift falling to rho g TAIL at the joint's right end)."""
    path = block_case(tmp_path, name, **kw)
    text = path.read_text() + 'uplift = "joint"\n'
    if tail:
        text += f"tailwater = {TAIL}\n" + TAIL_WATER
    path.write_text(text)
    return path


def sliding_case(tmp_path, friction, end=0.5, name="sliding"):
    """The lifted block from rest under constant g (the uplift is g(0)'s:
    g must not ramp from 0), stiffness-damped so that the drop onto the
    joint dies out in about 0.15 s."""
    return lifted_case(tmp_path, name, end=end, dt=2e-3, friction=friction, initial="rest",
                       damping="damping = { beta = 5.0e-3 }")


def run(path, tmp_path, name="out"):
    return vstpetsc.run(vstpetsc.Case.from_toml(path), output=str(tmp_path / f"{name}.h5"),
                        quiet=True, out=io.StringIO())


@pytest.mark.parametrize("tail", [False, True], ids=["uplift", "tailwater"])
def test_a_lifted_block_rests_on_w_minus_u(tmp_path, tail):
    """From the static start, every slab: sum(normal_force) = W - U, U the
    closed-form trapezoid (p_a + p_b) B / 2 of the linear uplift (the
    pairs' forces are the trapezoid rule on the joint's nodes, exact for
    a linear p), and sum(shear_force) = -(the net thrust on the block
    above the joint), within 1e-9 of W: the static LU solve and the
    slabs' solves of a 120-dof system round at 1e-14 (measured 1e-14)."""
    r = run(lifted_case(tmp_path, tail=tail), tmp_path)
    joint = r.interface("joint")
    normal = joint.normal_force[1:].sum(axis=1)
    shear = joint.shear_force[1:].sum(axis=1)
    lift = LIFT_TAIL if tail else LIFT
    thrust = THRUST - (RHO_W * G * TAIL ** 2 / 2 if tail else 0.0)
    print("tail" if tail else "no tail", "normal against W - U",
          np.abs(normal - (WEIGHT - lift)).max() / WEIGHT,
          "shear against the thrust", np.abs(shear + thrust).max() / WEIGHT,
          "largest v", np.abs(r.field.v).max())
    assert np.abs(normal - (WEIGHT - lift)).max() <= 1e-9 * WEIGHT
    assert np.abs(shear + thrust).max() <= 1e-9 * WEIGHT
    assert np.abs(r.field.v).max() <= 1e-12


def test_the_pairs_uplift_is_linear_from_the_wetted_end():
    """Each pair's force on the split block mesh: p_u L along its normal
    (+y, from the foundation to the block), pushing the sides apart,
    p_u = rho |g| LEVEL (1 - x / B) from the wetted end x = 0, and with
    the tailwater rising to rho |g| TAIL at x = B; the ends' pairs have
    half the others' tributary length."""
    from vstpetsc.plane import mesh as plane_mesh
    from vstpetsc.plane.interfaces import split
    from vstpetsc.plane.schema import WaterSpec
    from vstpetsc.plane.uplift import nodal_forces, pair_pressures

    whole = plane_mesh.rectangle((0.0, B), (-D, H), 4, 10, joints={"joint": 2})
    mesh, pairs = split(whole, "joint")
    x = mesh.coordinates[pairs.nodes[:, 0], 0]
    for tail, p_b in ((None, 0.0), (TAIL, RHO_W * G * TAIL)):
        spec = WaterSpec("r", LEVEL, RHO_W, ("left",), uplift="joint", tailwater=tail)
        p, (a, b, total) = pair_pressures(mesh, spec, pairs.nodes[:, 0], -G)
        exact = RHO_W * G * LEVEL + (p_b - RHO_W * G * LEVEL) * x / B
        assert np.allclose(p, exact, rtol=1e-14, atol=0) and total == B and b == p_b
        forces = nodal_forces(pairs.nodes, (p * pairs.length)[:, None] * pairs.normal,
                              mesh.nnodes)
        assert np.allclose(pairs.normal, [0.0, 1.0])
        assert np.allclose(pairs.length, np.where((x == 0) | (x == B), B / 8, B / 4))
        up, down = forces[pairs.nodes[:, 1]], forces[pairs.nodes[:, 0]]
        assert np.array_equal(up, -down) and np.all(up[:, 1] >= 0) and not up[:, 0].any()
        assert np.isclose(forces[pairs.nodes[:, 1], 1].sum(), (a + b) / 2 * B, rtol=1e-14)


def test_uplift_makes_a_held_block_slide_and_more_friction_holds_it(tmp_path):
    """Friction 0.29: mu W (1.37e6) holds the thrust (1.26e6) but mu (W - U)
    (1.14e6) does not, so the lifted block slides from rest; after the
    drop onto the joint has died out its mean velocity (block nodes,
    y > 0) grows between 0.3 and 0.5 s at a rigid block's acceleration
    (thrust - mu (W - U)) / (rho B H) within 2 % (the rocking left by
    the drop: measured 0.7 %); friction 0.4 holds it: its joint's mean
    slip changes over 0.3 - 0.5 s by less than 1 % of the sliding one's
    (what is left is the rocking on the joint's undamped springs:
    measured 0.2 %)."""
    assert 0.29 * WEIGHT > THRUST > 0.29 * (WEIGHT - LIFT)
    slides, stays = (run(sliding_case(tmp_path, mu, name=f"mu{mu}"), tmp_path, f"mu{mu}")
                     for mu in (0.29, 0.4))
    t = slides.time
    block = slides.mesh.coordinates[:, 1] > 0
    i, k = np.searchsorted(t, [0.3 - 1e-9, 0.5 - 1e-9])
    speed = lambda r: r.field.v[:][:, block, 0].mean(axis=1)
    fast = speed(slides)
    rigid = (THRUST - 0.29 * (WEIGHT - LIFT)) / (RHO * B * H)
    measured = (fast[k] - fast[i]) / (t[k] - t[i])
    slip = lambda r: np.ptp(r.interface("joint").slip[i:k + 1].mean(axis=1))
    print("acceleration", measured, "rigid", rigid, "error", abs(measured / rigid - 1),
          "held slip late", slip(stays), "sliding", slip(slides))
    assert abs(measured / rigid - 1) <= 0.02
    assert slip(stays) <= 1e-2 * slip(slides)


def test_uplift_on_two_ranks_equals_one(tmp_path):
    two = mpirun_against_one_rank(tmp_path, sliding_case(tmp_path, 0.29, end=0.1))
    assert np.abs(vstpetsc.Result(two).interface("joint").slip[:]).max() > 1e-4


def test_a_restart_with_uplift_continues_bit_for_bit(tmp_path):
    restarted_as_whole(
        tmp_path, lambda end, name: sliding_case(tmp_path, 0.29, end=end, name=name), 0.1)


def test_info_prints_the_sliding_factor_of_safety(tmp_path):
    """The block at rest from the static start: info's factor is
    mu (W - U) / thrust (0.6 x 3.924e6 / 1.25568e6 = 1.875) to its six
    printed digits."""
    out = tmp_path / "one.h5"
    assert run_cli("run", lifted_case(tmp_path), "-o", out, "-q").returncode == 0
    p = run_cli("info", out)
    assert p.returncode == 0, p.stderr
    line = [x for x in p.stdout.splitlines() if "sliding factor of safety" in x]
    factor = 0.6 * (WEIGHT - LIFT) / THRUST
    assert line and f"mu sum(N) / |sum(T)| {factor:.6g} " in line[0], p.stdout


def test_info_prints_inf_without_shear(tmp_path):
    """No water: the joint carries no shear, the factor is inf."""
    path = block_case(tmp_path, "dry")
    path.write_text(path.read_text().split("[[water]]")[0])
    out = tmp_path / "dry.h5"
    assert run_cli("run", path, "-o", out, "-q").returncode == 0
    p = run_cli("info", out)
    line = [x for x in p.stdout.splitlines() if "sliding factor of safety" in x]
    assert line and "|sum(T)| inf " in line[0], p.stdout


WATER = '[[water]]\nname = "reservoir"\nlevel = 16.0\nfaces = ["left"]\n'
BAD = [
    ("unknown interface", WATER + 'uplift = "base"\n',
     "water[0] (reservoir).uplift: 'base' is not an [[interface]] of the case (interfaces: "
     "joint)"),
    ("uplift not a name", WATER + "uplift = 3\n",
     "water[0] (reservoir).uplift: must be a string"),
    ("tailwater without uplift", WATER + "tailwater = 2.0\n",
     "water[0] (reservoir).tailwater: needs uplift"),
    ("tailwater not a number", WATER + 'uplift = "joint"\ntailwater = "low"\n',
     "water[0] (reservoir).tailwater: must be a number"),
    ("tailwater nan", WATER + 'uplift = "joint"\ntailwater = nan\n',
     "water[0] (reservoir).tailwater: must be finite"),
]


@pytest.mark.parametrize("what, water, message", BAD, ids=[b[0] for b in BAD])
def test_bad_uplift_exits_2_with_one_line(tmp_path, what, water, message):
    case = tmp_path / "bad.toml"
    case.write_text(block_case(tmp_path).read_text().split("[[water]]")[0] + water)
    p = run_cli("run", case, "-o", tmp_path / "bad.h5", "-q")
    assert p.returncode == 2, (p.stdout, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], p.stderr
    assert not (tmp_path / "bad.h5").exists()
