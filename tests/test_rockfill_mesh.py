"""The zoned rockfill dam mesh (vstpetsc.plane.rockfill_mesh): the four
regions' areas exact, every cell counter-clockwise and in its zone,
conforming (the outer boundary exactly "base", "left", "right", "faces";
every inner curve between the two regions it names, on the documented
sides), cells of about h; split along "contact", then "core_upstream",
then "core_downstream" (vstpetsc.plane.interfaces.split), the four
regions share no node, the two triple nodes at the core's base are three
nodes with a pair of each interface, and, tied back, the split mesh's M
and K are the original's; the bundled Gmsh file is the generator's and
reads back as it."""

import math
import os

import numpy as np
import pytest
import scipy.sparse as sp

from vstpetsc.plane import assembly
from vstpetsc.plane.interfaces import split, split_along
from vstpetsc.plane.rockfill_mesh import REGIONS, rockfill_mesh

P = dict(height=40.0, crest=8.0, upstream=2.0, downstream=1.8, core_crest=4.0,
         core_slope=0.25, foundation_depth=30.0, foundation_width=300.0, h=2.0)
H, W, D = P["height"], P["foundation_width"], P["foundation_depth"]
X_A = -(P["crest"] / 2 + P["upstream"] * H)
X_B = P["crest"] / 2 + P["downstream"] * H
CORE_BASE = P["core_crest"] / 2 + P["core_slope"] * H          # the core's half width at y = 0


@pytest.fixture(scope="module")
def rock():
    return rockfill_mesh(**P)


def left_cell(m, edges):
    """The cell on the left of each directed edge (a, b) (-1: none)."""
    cells, a, b = m.edges()                        # counter-clockwise: the cell on the left
    key = a.astype(np.int64) * m.nnodes + b
    order = np.argsort(key)
    want = edges[:, 0].astype(np.int64) * m.nnodes + edges[:, 1]
    at = np.minimum(np.searchsorted(key[order], want), key.size - 1)
    return np.where(key[order][at] == want, cells[order[at]], -1)


def region_of(m, cells):
    return np.array([REGIONS[r] if c >= 0 else None for c, r in zip(cells, m.region[cells])])


def length(m, edges):
    return float(np.linalg.norm(np.diff(m.coordinates[edges], axis=1)[:, 0], axis=1).sum())


def test_areas_are_the_sections(rock):
    a = rock.areas()
    core = (P["core_crest"] / 2 + CORE_BASE) * H
    upstream = (P["crest"] / 2 - X_A) / 2 * H - core / 2
    downstream = (P["crest"] / 2 + X_B) / 2 * H - core / 2
    expected = {"core": core, "upstream_shell": upstream, "downstream_shell": downstream,
                "foundation": W * D}
    for name, value in expected.items():
        assert a[rock.region == REGIONS.index(name)].sum() == pytest.approx(value, rel=1e-12)
    dam = (P["crest"] + X_B - X_A) / 2 * H
    assert a.sum() == pytest.approx(W * D + dam, rel=1e-12)


def test_every_cell_counter_clockwise_and_in_its_zone(rock):
    a = rock.areas()
    for r, name in enumerate(REGIONS):
        assert a[rock.region == r].min() > 0, name
    foundation = rock.region == REGIONS.index("foundation")
    assert (rock.cells[foundation, 3] >= 0).all() and (rock.cells[~foundation, 3] < 0).all()
    # each triangle's centroid inside its zone's trapezoid
    c = rock.coordinates[rock.cells[~foundation, :3]].mean(axis=1)
    x, below = c[:, 0], H - c[:, 1]
    core = P["core_crest"] / 2 + P["core_slope"] * below
    zone = np.where(x < -core, 1, np.where(x > core, 2, 0))
    assert np.array_equal(zone, rock.region[~foundation])
    assert (x > -(P["crest"] / 2 + P["upstream"] * below)).all()
    assert (x < P["crest"] / 2 + P["downstream"] * below).all()


def test_conforming_with_the_named_boundary(rock):
    _, a, b = rock.edges()
    keys, uses = np.unique(rock.edge_keys(a, b), return_counts=True)
    assert set(uses.tolist()) == {1, 2}
    named = np.concatenate([rock.curves[n] for n in ("base", "left", "right", "faces")])
    named = np.unique(rock.edge_keys(named[:, 0], named[:, 1]))
    assert np.array_equal(keys[uses == 1], named)


@pytest.mark.parametrize("name, left, right", [
    ("contact", {"upstream_shell", "core", "downstream_shell"}, {"foundation"}),
    ("core_upstream", {"upstream_shell"}, {"core"}),
    ("core_downstream", {"core"}, {"downstream_shell"})])
def test_inner_curves_between_their_regions(rock, name, left, right):
    edges = rock.curves[name]
    assert set(region_of(rock, left_cell(rock, edges))) == left
    assert set(region_of(rock, left_cell(rock, edges[:, ::-1]))) == right
    step = np.diff(rock.coordinates[edges], axis=1)[:, 0]
    assert (step[:, 0] > 0).all() if name == "contact" else (step[:, 1] > 0).all()


def test_curves_have_their_lengths(rock):
    u, d = P["upstream"], P["downstream"]
    faces = P["crest"] + H * (math.hypot(u, 1.0) + math.hypot(d, 1.0)) + W - (X_B - X_A)
    core = H * math.hypot(P["core_slope"], 1.0)
    expected = {"base": W, "left": D, "right": D, "contact": X_B - X_A, "faces": faces,
                "core_upstream": core, "core_downstream": core}
    assert set(rock.curves) == set(expected)
    for name, value in expected.items():
        edges = rock.curves[name]
        assert ((left_cell(rock, edges) >= 0) | (left_cell(rock, edges[:, ::-1]) >= 0)).all()
        assert length(rock, edges) == pytest.approx(value, rel=1e-12), name


def test_cells_are_about_h(rock):
    _, a, b = rock.edges()
    sides = np.linalg.norm(rock.coordinates[a] - rock.coordinates[b], axis=1)
    h = P["h"]
    assert sides.min() >= 0.5 * h
    assert sides.max() <= math.hypot(h, h * max(P["upstream"], P["downstream"])) * 1.01


def at(m, x, y):
    """The nodes at (x, y), with the regions of their cells."""
    nodes = np.flatnonzero(np.all(np.isclose(m.coordinates, (x, y)), axis=1))
    return {int(n): {REGIONS[r] for r in m.region[(m.cells == n).any(axis=1)]} for n in nodes}


def node_in(nodes, region):
    return next(n for n, regions in nodes.items() if regions == {region})


def pair_at(pairs, nodes):
    return pairs.nodes[np.isin(pairs.nodes, list(nodes)).all(axis=1)].tolist()


def test_three_splits_in_sequence(rock):
    s1, contact = split(rock, "contact")
    s2, upstream = split(s1, "core_upstream")
    s3, downstream = split(s2, "core_downstream")
    # every node of each curve doubled, the ends on the boundary too
    assert [len(p.nodes) for p in (contact, upstream, downstream)] == [81, 21, 21]
    assert s3.nnodes == rock.nnodes + 81 + 21 + 21
    nodes = [np.unique(s3.cells[(s3.region == r)[:, None] & (s3.cells >= 0)]) for r in range(4)]
    for i in range(4):
        for j in range(i + 1, 4):
            assert not np.intersect1d(nodes[i], nodes[j]).size, (REGIONS[i], REGIONS[j])
    # the core's base corners: three nodes; the contact pairs the foundation
    # with the node the dam had after the first split, which the later split
    # leaves to its first side (the core upstream, the shell downstream)
    up = at(s3, -CORE_BASE, 0.0)
    assert sorted(map(sorted, up.values())) == [["core"], ["foundation"], ["upstream_shell"]]
    f, c, s = (node_in(up, r) for r in ("foundation", "core", "upstream_shell"))
    assert pair_at(contact, up) == [[f, c]] and pair_at(upstream, up) == [[c, s]]
    down = at(s3, CORE_BASE, 0.0)
    f, c, s = (node_in(down, r) for r in ("foundation", "core", "downstream_shell"))
    assert pair_at(contact, down) == [[f, s]] and pair_at(downstream, down) == [[s, c]]
    # the core's faces end on the crest: a pair there too
    for pairs, x in ((upstream, -P["core_crest"] / 2), (downstream, P["core_crest"] / 2)):
        assert len(pair_at(pairs, at(s3, x, H))) == 1
    assert np.allclose(contact.normal, [0.0, 1.0])
    n = np.array([-1.0, P["core_slope"]]) / math.hypot(1.0, P["core_slope"])
    assert np.allclose(upstream.normal, n) and np.allclose(downstream.normal, n * [1, -1])
    # every curve of the split mesh still edges of its cells
    for name, edges in s3.curves.items():
        assert ((left_cell(s3, edges) >= 0) | (left_cell(s3, edges[:, ::-1]) >= 0)).all(), name
    tied(rock, s3, (contact, upstream, downstream))


def test_the_run_splits_the_three_at_once(rock):
    """What a run does (interfaces.split_along, issue 44): at the core's
    base corners the contact pairs the foundation with the core and with
    the shell (half an edge each), and the core's face pairs the two; the
    same nodes as in sequence, and the same mesh in any order."""
    names = ["contact", "core_upstream", "core_downstream"]
    s, (contact, upstream, downstream) = split_along(rock, names)
    assert [len(p.nodes) for p in (contact, upstream, downstream)] == [83, 21, 21]
    assert s.nnodes == rock.nnodes + 81 + 21 + 21
    for x, face in ((-CORE_BASE, upstream), (CORE_BASE, downstream)):
        corner = at(s, x, 0.0)
        shell = "upstream_shell" if x < 0 else "downstream_shell"
        f, c, sh = (node_in(corner, r) for r in ("foundation", "core", shell))
        assert sorted(pair_at(contact, corner)) == sorted([[f, c], [f, sh]])
        assert len(pair_at(face, corner)) == 1 and set(pair_at(face, corner)[0]) == {c, sh}
        halves = contact.length[np.isin(contact.nodes, [c, sh]).any(axis=1) &
                                np.isin(contact.nodes, [f]).any(axis=1)]
        assert np.allclose(halves, halves[0])
    other, _ = split_along(rock, names[::-1])
    assert np.array_equal(other.cells, s.cells)
    tied(rock, s, (contact, upstream, downstream))


def tied(m, s, pairs):
    """The split mesh's M and K tied back (each pair's second node given its
    first's original dofs, in the splits' order) are the original's."""
    original = np.arange(s.nnodes)
    for p in pairs:
        original[p.nodes[:, 1]] = original[p.nodes[:, 0]]
    rows = np.arange(2 * s.nnodes)
    cols = (2 * original[:, None] + np.arange(2)).ravel()
    T = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(rows.size, 2 * m.nnodes))
    for a, b in zip(assembly.matrices(s, 1e8, 5e7, 2000.0), assembly.matrices(m, 1e8, 5e7, 2000.0)):
        assert abs(T.T @ a @ T - b).max() <= 1e-12 * abs(b).max()


def test_the_bundled_file_is_the_generators(rock, tmp_path):
    from vstpetsc.plane.solver.dmplex import read_gmsh
    from vstpetsc.plane.gmsh_file import write_gmsh22

    bundled = os.path.join(os.path.dirname(__file__), "..", "vstpetsc", "examples",
                           "rockfill-dam-section.msh")
    with open(bundled) as f:
        assert f.read() == write_gmsh22(tmp_path / "r.msh", rock).read_text()
    read = read_gmsh(bundled)
    assert np.array_equal(read.coordinates, rock.coordinates)
    canonical = lambda m: sorted((tuple(sorted(c[c >= 0])), m.region_names[r])
                                 for c, r in zip(m.cells, m.region))
    assert canonical(read) == canonical(rock)
    assert {k: sorted(map(sorted, v.tolist())) for k, v in read.curves.items()} == \
        {k: sorted(map(sorted, v.tolist())) for k, v in rock.curves.items()}


@pytest.mark.parametrize("change, message", [
    ({"core_crest": 8.0}, "strictly inside the dam"),
    ({"core_crest": 0.0}, "strictly inside the dam"),
    ({"core_slope": 2.1}, "strictly inside the dam"),
    ({"foundation_width": 150.0}, "wider than its foundation")])
def test_a_core_outside_the_dam_is_refused(change, message):
    with pytest.raises(ValueError, match=message):
        rockfill_mesh(**{**P, **change})
