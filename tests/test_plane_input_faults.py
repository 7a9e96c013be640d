"""The faults a red team found in the plane-strain path (issue 44): each
bad input refused with one line naming the key, exit 2, no traceback, no
result file.  The Gmsh files the tests need are written here
(vstpetsc.plane.gmsh_file, or as text for what that writer cannot
express)."""

import numpy as np
import pytest

from conftest import cli, make_case, bar, write_case
from faults import one_clean_line
from test_parallel import mpirun
from vstpetsc.plane import mesh as plane_mesh
from vstpetsc.plane.rigidity import free_part

REGION = "[[region]]\nname = '{name}'\nE = 1.0e9\nnu = 0.25\nrho = 2000.0\n"
STATIC = "[gravity]\ng = -9.81\ninitial = 'static'\n"


def case_text(mesh, regions=("domain",), extra=""):
    return ("[time]\ndt = 1e-3\nend = 0.005\n[mesh]\n" + mesh + "\n" +
            "".join(REGION.format(name=r) for r in regions) + extra)


def refused(tmp_path, text, *words, ranks=1):
    """The case ``text`` is refused: exit 2, one line holding ``words``,
    no result file (on ``ranks`` ranks)."""
    case, out = tmp_path / "bad.toml", tmp_path / "bad.h5"
    case.write_text(text)
    args = ("run", case, "-o", out, "-q")
    p = cli(*args) if ranks == 1 else mpirun(*args, n=ranks)
    # mpirun adds its own lines about the exit status: ours is one line, once
    ours = [l for l in p.stderr.splitlines() if l.startswith("vstpetsc:")]
    assert p.returncode == 2 and "Traceback" not in p.stderr, (p.returncode, p.stderr)
    assert one_clean_line(p.stderr) if ranks == 1 else len(ours) == 1, p.stderr
    assert all(w in p.stderr for w in words), p.stderr
    assert not out.exists()
    return p.stderr


def runs(tmp_path, text):
    case, out = tmp_path / "good.toml", tmp_path / "good.h5"
    case.write_text(text)
    p = cli("run", case, "-o", out, "-q")
    assert p.returncode == 0, p.stderr
    return out


# -- 1: a static start that nothing holds ------------------------------------

SQUARE = "rectangle = { x = [0.0, 1.0], y = [0.0, 1.0], nx = 4, ny = 4 }"
JOINTED = "rectangle = { x = [0.0, 1.0], y = [0.0, 2.0], nx = 2, ny = 4, joints = { j = 1.0 } }"


def fixed(curve):
    return f"[[boundary]]\nname = '{curve}'\ntype = 'fixed'\n"


INTERFACE = "[[interface]]\nname = 'j'\n{friction}"


@pytest.mark.parametrize("ranks", [1, 2])
def test_a_static_start_that_nothing_holds_is_refused(tmp_path, ranks):
    """No fixed, velocity or absorbing curve: every rigid motion is free
    (it ran to energies of 1e13 J); on two ranks every rank refuses."""
    refused(tmp_path, case_text(SQUARE, extra=STATIC), "gravity.initial", "free to move",
            "region 'domain' of 16 cells", ranks=ranks)


@pytest.mark.parametrize("friction, words", [
    ("friction = 0.5\n", "3 of 3 pairs open"),         # it hangs, the pairs open
    ("", "every pair taken closed and sticking"),     # frictionless: free along x at once
])
def test_a_part_hanging_below_an_interface_is_refused(tmp_path, friction, words):
    text = case_text(JOINTED, extra=fixed("top") + INTERFACE.format(friction=friction) + STATIC)
    refused(tmp_path, text, "gravity.initial", words, "of 4 cells about (0.5, 0.5)")


def test_a_block_on_a_frictionless_interface_is_free_along_it(tmp_path):
    """The block rests on the held part (pairs closed) but nothing holds it
    along the joint: free along x; with friction it sticks and runs."""
    text = case_text(JOINTED, extra=fixed("bottom") + INTERFACE.format(friction="") + STATIC)
    refused(tmp_path, text, "gravity.initial", "free to move along x",
            "of 4 cells about (0.5, 1.5)")
    runs(tmp_path, case_text(JOINTED, extra=fixed("bottom") +
                             INTERFACE.format(friction="friction = 0.5\n") + STATIC))


def test_a_held_mesh_runs(tmp_path):
    runs(tmp_path, case_text(SQUARE, extra=fixed("bottom") + STATIC))


def test_a_free_bar_without_a_static_load_is_refused(tmp_path):
    """1-D: g(0) = 0 left nothing to solve and the free bar was accepted;
    held, it runs."""
    gravity = {"g": [[0.0, 0.0], [1.0, -9.81]], "initial": "static"}
    case = make_case(1e-5, 1e-4, [bar("bar", (0.0, 1.0), 10)], gravity=gravity)
    out = tmp_path / "bar.h5"
    p = cli("run", write_case(tmp_path, case), "-o", out)
    assert p.returncode == 2 and one_clean_line(p.stderr), p.stderr
    assert "gravity.initial" in p.stderr and "body 'bar' is free" in p.stderr
    assert not out.exists()
    held = make_case(1e-5, 1e-4, [bar("bar", (0.0, 1.0), 10)], gravity=gravity,
                     bc=[dict(body="bar", end="left", type="fixed")])
    assert cli("run", write_case(tmp_path, held), "-o", out).returncode == 0


def unit_square(nx=2, ny=2):
    return plane_mesh.rectangle((0.0, 1.0), (0.0, 1.0), nx, ny)


def held(nodes, components=(0, 1)):
    return np.array([2 * n + c for n in nodes for c in components])


def test_one_held_node_leaves_a_rotation_about_it():
    """Held at one node (both components): the rotation about that node is
    the free motion, whatever the node."""
    m = unit_square()
    for node in (0, 4, 8):
        words = free_part(m, held([node]))
        x, y = m.coordinates[node]
        assert f"rotate about ({x:.6g}, {y:.6g})" in words, words


def test_two_held_nodes_hold_a_part_and_one_component_does_not():
    m = unit_square()
    assert free_part(m, held([0, 2])) is None
    assert free_part(m, held([0, 2], components=(1,))) .endswith("free to move along x")
    assert free_part(m, held([0]) .tolist() + [2 * 2 + 1]) is None     # a roller at (1, 0)


def test_cells_that_share_a_lone_node_are_two_parts():
    """Two squares touching at one corner: a hinge.  Holding one square
    leaves the other free to rotate about the shared corner."""
    coordinates = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 1], [2, 2], [1, 2]], float)
    cells = np.array([[0, 1, 2, 3], [2, 4, 5, 6]])
    m = plane_mesh.PlaneMesh(coordinates, cells, np.zeros(2, int))
    words = free_part(m, held([0, 1]))
    assert "rotate about (1, 1)" in words and "of 1 cells about (1.5, 1.5)" in words
    assert free_part(m, held([0, 1, 5])) is None


def test_pair_springs_hold_the_second_part():
    """Two squares side by side, not joined: springs between their facing
    nodes hold the second along the springs' direction only."""
    coordinates = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [1, 0], [2, 0], [2, 1], [1, 1]],
                           float)
    m = plane_mesh.PlaneMesh(coordinates, np.array([[0, 1, 2, 3], [4, 5, 6, 7]]),
                             np.zeros(2, int))
    nodes = np.array([[1, 4], [2, 7]])
    normal, tangent = np.array([[1.0, 0.0]] * 2), np.array([[0.0, -1.0]] * 2)
    first = held([0, 3])
    assert free_part(m, first, nodes, normal).endswith("free to move along y")
    assert free_part(m, first, np.concatenate([nodes, nodes]),
                     np.concatenate([normal, tangent])) is None
