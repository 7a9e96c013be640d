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
from vstpetsc.plane import mesh_checks
from vstpetsc.plane.gmsh_file import write_gmsh22
from vstpetsc.plane.rigidity import free_part
from vstpetsc import Result

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


# -- 3, 4, 5: what a mesh file holds -------------------------------------------

MESHED = "file = 'm.msh'"


def square(nx=2, ny=2, triangles=False, **curves):
    m = plane_mesh.rectangle((0.0, 1.0), (0.0, 1.0), nx, ny, triangles)
    return plane_mesh.PlaneMesh(m.coordinates.copy(), m.cells.copy(), m.region, m.region_names,
                                {**m.curves, **curves})


def mesh_refused(tmp_path, mesh, *words, regions=("domain",), extra=""):
    write_gmsh22(tmp_path / "m.msh", mesh)
    return refused(tmp_path, case_text(MESHED, regions, extra), "mesh.file: m.msh: ", *words)


def test_a_flat_triangle_is_refused(tmp_path):
    m = square(triangles=True)
    m.cells[0, :3] = [0, 1, 2]                     # three nodes along y = 0
    mesh_refused(tmp_path, m, "cell 0 about (0.5, 0) has no area")


def test_a_mesh_on_a_line_is_refused(tmp_path):
    m = square(triangles=True)
    m.coordinates[:, 1] = 0.0
    mesh_refused(tmp_path, m, "has no area", "8 such cells")


@pytest.mark.parametrize("shift, words", [
    (0.0, "has no area"),                       # a symmetric bow-tie: its halves cancel
    (0.2, "is not convex"),
])
def test_a_bow_tie_quadrilateral_is_refused(tmp_path, shift, words):
    """It was refused as "the mesh's region 'bottom' has no [[region]]
    table": its sides are not the curve's line elements."""
    m = square()
    m.cells[0] = m.cells[0][[0, 2, 1, 3]]
    m.coordinates[3, 1] += shift                   # unequal halves
    mesh_refused(tmp_path, m, "cell 0 about", words)


def test_a_dart_is_refused(tmp_path):
    m = square()
    m.coordinates[4] = [0.2, 0.2]                  # the middle node pulled into cell 0
    mesh_refused(tmp_path, m, "cell 0 about (0.175, 0.175) is not convex")


def test_a_curve_across_cells_is_refused(tmp_path):
    """An interface curve from corner to corner of a cell (PETSc labels the
    cell instead of an edge; it read as a region)."""
    m = square(diagonal=np.array([[0, 4], [4, 8]]))
    mesh_refused(tmp_path, m, "the physical curve 'diagonal' has line elements that are no "
                 "side of a cell", extra="[[interface]]\nname = 'diagonal'\n")


P2 = """$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
1 1 "bottom"
2 2 "domain"
$EndPhysicalNames
$Nodes
9
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 0.5 0 0
6 1 0.5 0
7 0.5 1 0
8 0 0.5 0
9 0.5 0.5 0
$EndNodes
$Elements
3
1 8 2 1 1 1 2 5
2 9 2 2 2 1 2 3 5 6 9
3 9 2 2 2 1 3 4 9 7 8
$EndElements
"""


def test_six_node_triangles_are_refused(tmp_path):
    """They were blamed on the solver ("Matrix is missing diagonal entry")."""
    (tmp_path / "m.msh").write_text(P2)
    refused(tmp_path, case_text(MESHED), "mesh.file: m.msh: cells of higher order",
            "linear triangles and 4-node quadrilaterals only")


def test_a_duplicate_node_is_refused(tmp_path):
    """An unmerged node cracked the mesh silently (its energy 3.87 against
    3.54 merged)."""
    m = square()
    m.coordinates = np.vstack([m.coordinates, m.coordinates[4]])
    m.cells[3][m.cells[3] == 4] = 9
    mesh_refused(tmp_path, m, "nodes 4 and 9 lie at one point (0.5, 0.5)", "[[interface]]")


@pytest.mark.parametrize("name", ["x/y", "a b", "."])
def test_a_mesh_files_names_follow_the_naming_rules(tmp_path, name):
    """A curve named x/y became nested groups, and info, plot and export
    failed on the file."""
    m = square()
    m.curves[name] = m.curves["top"]
    mesh_refused(tmp_path, m, f"the curve name {name!r}")
    m = square()
    write_gmsh22(tmp_path / "m.msh", plane_mesh.PlaneMesh(m.coordinates, m.cells, m.region,
                                                         (name,), m.curves))
    refused(tmp_path, case_text(MESHED, regions=("domain",)), f"the region name {name!r}")


@pytest.mark.parametrize("table, words", [
    ("[[region]]\nname = 'x/y'\nE = 1.0e9\nnu = 0.25\nrho = 2000.0\n", "region[1].name: may hold"),
    ("[[boundary]]\nname = ''\ntype = 'fixed'\n", "boundary[0].name: must not be empty"),
    ("[[interface]]\nname = '.'\n", "interface[0].name: '.' is not a name"),
])
def test_a_case_files_names_follow_the_naming_rules(tmp_path, table, words):
    refused(tmp_path, case_text(SQUARE, extra=table), words)


@pytest.mark.parametrize("joints, words", [
    ("{ '' = 0.5 }", "mesh.rectangle.joints.: the joint's name must not be empty"),
    ("{ j = nan }", "mesh.rectangle.joints.j: must be the y of a grid row"),
    ("{ j = inf }", "mesh.rectangle.joints.j: must be the y of a grid row"),
])
def test_bad_joints_are_refused(tmp_path, joints, words):
    """nan and inf ended in a traceback."""
    mesh = f"rectangle = {{ x = [0.0, 1.0], y = [0.0, 1.0], nx = 2, ny = 2, joints = {joints} }}"
    refused(tmp_path, case_text(mesh), words)


# -- 6: meshes too big to run -------------------------------------------------

@pytest.mark.parametrize("mesh, words", [
    ("rectangle = { x = [0.0, 1.0], y = [0.0, 1.0], nx = 100000, ny = 10000 }",
     "mesh.rectangle: 1e+09 cells: at most 1e+07"),
    ("dam = { height = 40.0, crest = 8.0, upstream = 0.1, downstream = 0.8, "
     "foundation_depth = 40.0, foundation_width = 200.0, h = 1e-3 }", "mesh.dam.h: "),
])
def test_a_mesh_beyond_petscs_indices_is_refused(tmp_path, mesh, words):
    """A numpy MemoryError traceback before."""
    refused(tmp_path, case_text(mesh, regions=("domain", "dam", "foundation")), words,
            "cells: at most 1e+07")


def test_a_mesh_beyond_the_machines_memory_is_refused(tmp_path):
    """Below PETSc's limit but more memory than the machine has (the bound
    is mesh_checks.BYTES_PER_NODE a node against its physical memory)."""
    nodes = mesh_checks.machine_memory() / mesh_checks.BYTES_PER_NODE
    n = int(np.sqrt(1.2 * nodes)) + 1
    if n * n > mesh_checks.MAX_CELLS:
        pytest.skip("this machine's memory holds any mesh PETSc's indices can")
    mesh = f"rectangle = {{ x = [0.0, 1.0], y = [0.0, 1.0], nx = {n}, ny = {n} }}"
    refused(tmp_path, case_text(mesh), "mesh.rectangle: ", "more than this machine's")


# -- 7: regions that start an interface overlapping ------------------------------

def two_blocks(tmp_path):
    """A 1 x 2 column of 0.25 m cells, regions "lower" and "upper" across
    the joint at y = 1 (the upper's cells above it)."""
    m = plane_mesh.rectangle((0.0, 1.0), (0.0, 2.0), 4, 8, joints={"joint": 4})
    region = m.coordinates[m.cells].mean(axis=1)[:, 1] > 1.0
    write_gmsh22(tmp_path / "m.msh", plane_mesh.PlaneMesh(m.coordinates, m.cells,
                                                         region.astype(int), ("lower", "upper"),
                                                         m.curves))


def pressed(overlap, penalty=1.0e9):
    upper = REGION.format(name="upper") + f"u0 = [0.0, {-overlap}]\n"
    return ("[time]\ndt = 1e-4\nend = 2e-3\n[mesh]\n" + MESHED + "\n" +
            REGION.format(name="lower") + upper + fixed("bottom") +
            f"[[interface]]\nname = 'joint'\npenalty = {penalty}\n")


def test_regions_that_start_interpenetrating_are_refused(tmp_path):
    """u0 = -0.1 m against cells of 0.25 m ran and blew apart."""
    two_blocks(tmp_path)
    refused(tmp_path, pressed(0.1), "region[1] (upper).u0: starts interface 'joint' "
            "overlapping against region 'lower' by 0.1 at (0, 1), more than 0.1 of the cells")


def test_a_joint_may_start_pressed(tmp_path):
    """A shallower overlap is a joint that starts pressed: its penalty's
    energy w g^2 / 2 (w the penalty per unit length times the curve's
    length) is the initial energy."""
    two_blocks(tmp_path)
    out = runs(tmp_path, pressed(1e-3))
    r = Result(out)
    e = r.energy
    assert np.isclose(e["contact"][0], 0.5 * 1.0e9 * 1.0 * 1e-3 ** 2, rtol=1e-12)
    # a rigid offset strains nothing (K u at rounding)
    assert e["kinetic"][0] == 0.0 and e["strain"][0] <= 1e-12 * e["contact"][0]
    # released at once, it rings: the scheme damps the ringing (numerical
    # >= 0, 1 % here) and creates nothing
    assert 0.0 <= e["numerical"][-1] <= 0.05 * e["contact"][0]


# -- 8: what the docs left unclear ---------------------------------------------

BARE = """$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
$EndNodes
$Elements
2
1 2 0 1 2 3
2 2 0 1 3 4
$EndElements
"""


def test_a_file_without_physical_groups_is_one_region_named_domain(tmp_path):
    """Documented (plane-strain.md): no physical surface at all, one region
    "domain"; with physical surfaces, every cell must be in one."""
    (tmp_path / "m.msh").write_text(BARE)
    text = case_text(MESHED).replace("[[region]]", "[[region]]\nv0 = [1.0, 0.0]", 1)
    r = Result(runs(tmp_path, text))
    assert r.mesh.region_names == ["domain"] and r.mesh.cells.shape == (2, 4)
    assert np.allclose(r.field.v[-1], [1.0, 0.0], rtol=0, atol=1e-12)    # in free flight


def crossed():
    """A 4 x 4 square of unit cells with curves "h" (y = 2) and "v" (x = 2),
    each from one side to the other."""
    m = plane_mesh.rectangle((0.0, 4.0), (0.0, 4.0), 4, 4)
    node = np.arange(25).reshape(5, 5)
    line = lambda nodes: np.column_stack([nodes[:-1], nodes[1:]])
    return plane_mesh.PlaneMesh(m.coordinates, m.cells, m.region, m.region_names,
                                {**m.curves, "h": line(node[2]), "v": line(node[:, 2])})


def test_crossing_interfaces_split_the_same_in_either_order():
    """The static strain energy of two crossing interfaces depended on the
    order of their tables (1.22 against 1.03): the crossing node was split
    one interface after the other.  Now at once: four copies, a pair of each
    interface on each side of the crossing (half an edge each), the same
    split mesh whatever the order."""
    from vstpetsc.plane.interfaces import split_along

    m = crossed()
    a, (ah, av) = split_along(m, ["h", "v"])
    b, (bv, bh) = split_along(m, ["v", "h"])
    assert np.array_equal(a.cells, b.cells) and np.array_equal(a.coordinates, b.coordinates)
    for p, q in ((ah, bh), (av, bv)):
        assert np.array_equal(p.nodes, q.nodes) and np.array_equal(p.normal, q.normal)
    centre = 12
    copies = np.flatnonzero((a.coordinates == m.coordinates[centre]).all(axis=1))
    assert copies.size == 4
    for pairs in (ah, av):
        here = np.isin(pairs.nodes, copies).all(axis=1)
        assert here.sum() == 2 and np.allclose(pairs.length[here], 0.5)
    assert np.allclose(ah.normal, [0.0, 1.0]) and np.allclose(av.normal, [-1.0, 0.0])


def test_crossing_interfaces_settle_the_same_in_either_order(tmp_path):
    m = crossed()
    write_gmsh22(tmp_path / "m.msh", m)
    joint = "[[interface]]\nname = '{}'\nfriction = 0.6\n"
    energies = []
    for order in (("h", "v"), ("v", "h")):
        text = case_text(MESHED, extra=fixed("bottom") + "".join(joint.format(n) for n in order)
                         + STATIC)
        energies.append(Result(runs(tmp_path, text)).energy["strain"][0])
    assert energies[0] > 0 and abs(energies[0] - energies[1]) <= 1e-12 * energies[0]


def test_an_interface_runs_one_way_whatever_the_cells_order(tmp_path):
    """PETSc gives each edge the direction of the first cell that holds it:
    with the cells above and below a joint interleaved in the file, half
    its edges ran each way and the split paired half edges with opposite
    normals.  A curve runs from its lower end to its upper (left to right
    where level): the joint's second side is above it."""
    from vstpetsc.plane.solver.dmplex import read_gmsh
    from vstpetsc.plane.interfaces import split_along

    m = plane_mesh.rectangle((0.0, 3.0), (0.0, 2.0), 6, 4, joints={"j": 2})
    first = np.r_[np.arange(12, 18, 2), np.arange(7, 12, 2)]       # above, below, alternately
    order = np.r_[first, np.setdiff1d(np.arange(m.ncells), first)]
    write_gmsh22(tmp_path / "m.msh", plane_mesh.PlaneMesh(m.coordinates, m.cells[order],
                                                         m.region, m.region_names, m.curves))
    read = read_gmsh(tmp_path / "m.msh")
    s, (pairs,) = split_along(read, ["j"])
    assert len(pairs.nodes) == 7 and np.allclose(pairs.normal, [0.0, 1.0])
    assert np.allclose(np.sort(pairs.length), [0.25, 0.25] + [0.5] * 5)
    above = s.coordinates[s.cells[s.cells[:, 0] >= 0]].mean(axis=1)[:, 1] > 1.0
    assert not np.isin(pairs.nodes[:, 0], s.cells[above]).any()


def test_a_closed_curve_runs_counter_clockwise():
    from vstpetsc.plane.interfaces import oriented

    x = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    loop = np.array([[1, 0], [2, 1], [2, 3], [0, 3]])          # every way
    out = oriented(x, loop)
    assert sorted(map(tuple, out)) == [(0, 1), (1, 2), (2, 3), (3, 0)]


def test_a_restart_after_the_mesh_changed_names_the_mesh_file(tmp_path):
    """It called the mesh a "history file"."""
    m = square()
    write_gmsh22(tmp_path / "m.msh", m)
    case = tmp_path / "c.toml"
    case.write_text(case_text(MESHED, extra=fixed("bottom")))
    assert cli("run", case, "-o", tmp_path / "r.h5", "-q").returncode == 0
    m.coordinates[4] += 0.01
    write_gmsh22(tmp_path / "m.msh", m)
    case.write_text(case.read_text().replace("end = 0.005", "end = 0.01"))
    p = cli("run", case, "--restart", tmp_path / "r.h5")
    assert p.returncode == 2 and one_clean_line(p.stderr), p.stderr
    assert "--restart: the mesh file m.msh changed since" in p.stderr
