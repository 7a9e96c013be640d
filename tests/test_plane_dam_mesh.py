"""The generated dam mesh (vstpetsc.plane.dam_mesh): its geometry exact,
conforming (every inner edge in two cells, the boundary exactly its named
curves, the contact inside), cells of about h, and a mixed mesh the
assembly takes (rigid motions strain nothing)."""

import math
from collections import Counter

import numpy as np
import pytest

from vstpetsc.plane import assembly, elements
from vstpetsc.plane.dam_mesh import dam_mesh

DAM = dict(height=40.0, crest=10.0, upstream=2.0, downstream=1.5, foundation_depth=30.0,
           foundation_width=300.0, h=2.0)


def cell_edges(m):
    """[(a, b) sorted, ...] of every cell's sides, with the cell's region."""
    out = []
    for cell, r in zip(m.cells, m.region):
        n = cell[cell >= 0]
        out += [(tuple(sorted((n[k], n[(k + 1) % n.size]))), r) for k in range(n.size)]
    return out


def length(m, edges):
    return float(np.linalg.norm(np.diff(m.coordinates[edges], axis=1)[:, 0], axis=1).sum())


@pytest.fixture(scope="module")
def dam():
    return dam_mesh(**DAM)


def test_areas_are_the_sections(dam):
    H, c, u, d = DAM["height"], DAM["crest"], DAM["upstream"], DAM["downstream"]
    base = c + (u + d) * H
    a = dam.areas()
    assert a.min() > 0
    assert a[dam.region == 0].sum() == pytest.approx((c + base) / 2 * H, rel=1e-13)
    assert a[dam.region == 1].sum() == pytest.approx(300.0 * 30.0, rel=1e-13)


def test_conforming_with_the_named_boundary(dam):
    uses = Counter(e for e, _ in cell_edges(dam))
    assert set(uses.values()) == {1, 2}
    boundary = {e for e, k in uses.items() if k == 1}
    named = {tuple(sorted(e)) for name in ("base", "left", "right", "faces")
             for e in dam.curves[name].tolist()}
    assert boundary == named
    contact = {tuple(sorted(e)) for e in dam.curves["contact"].tolist()}
    sides = {}
    for e, r in cell_edges(dam):
        sides.setdefault(e, set()).add(r)
    assert all(sides[e] == {0, 1} for e in contact)


def test_curves_have_their_lengths(dam):
    H, c, u, d = DAM["height"], DAM["crest"], DAM["upstream"], DAM["downstream"]
    base = c + (u + d) * H
    faces = c + H * (math.hypot(u, 1.0) + math.hypot(d, 1.0)) + 300.0 - base
    expected = {"base": 300.0, "left": 30.0, "right": 30.0, "contact": base, "faces": faces}
    for name, value in expected.items():
        assert length(dam, dam.curves[name]) == pytest.approx(value, rel=1e-12), name


def test_cells_are_about_h(dam):
    sides = np.array([np.linalg.norm(np.subtract(*dam.coordinates[list(e)]))
                      for e, _ in cell_edges(dam)])
    h = DAM["h"]
    diagonal = math.hypot(h, h * max(DAM["upstream"], DAM["downstream"]))
    assert sides.max() <= diagonal * 1.01 and sides.min() >= 0.5 * h


def test_the_assembly_takes_the_mixed_mesh():
    m = dam_mesh(**{**DAM, "h": 5.0})
    assert m.triangles.size and m.quadrilaterals.size
    lam, mu = elements.lame(2.5e10, 0.2)
    _, K = assembly.matrices(m, lam, mu, 2400.0)
    R = np.zeros((2 * m.nnodes, 3))
    R[0::2, 0] = R[1::2, 1] = 1.0
    R[0::2, 2], R[1::2, 2] = -m.coordinates[:, 1], m.coordinates[:, 0]
    assert np.abs(K @ R).max() <= 1e-12 * np.abs(K).max() * 100.0


def test_a_base_wider_than_the_foundation_is_refused():
    with pytest.raises(ValueError, match="wider than its foundation"):
        dam_mesh(**{**DAM, "foundation_width": 100.0})


def test_the_faces_parts_are_the_slopes_crest_and_ground(dam):
    """"upstream" and "downstream" hold exactly the slopes' edges (both
    ends on the slope's line y = (x - x_a) / u, y = (x_b - x) / d, 0 <= y
    <= H), "crest" the edges at y = H, "top_left" and "top_right" the
    foundation's top left of the heel and right of the toe; disjoint, and
    their union is "faces"."""
    H, c, u, d = DAM["height"], DAM["crest"], DAM["upstream"], DAM["downstream"]
    xa, xb = -(c / 2 + u * H), c / 2 + d * H
    xy = dam.coordinates
    on = {"upstream": lambda x, y: np.isclose(x, xa + u * y, atol=1e-9) & (y >= -1e-9) & (y <= H + 1e-9),
          "downstream": lambda x, y: np.isclose(x, xb - d * y, atol=1e-9) & (y >= -1e-9) & (y <= H + 1e-9),
          "crest": lambda x, y: np.isclose(y, H) & (abs(x) <= c / 2 + 1e-9),
          "top_left": lambda x, y: np.isclose(y, 0.0) & (x <= xa + 1e-9),
          "top_right": lambda x, y: np.isclose(y, 0.0) & (x >= xb - 1e-9)}
    faces = {tuple(sorted(e)) for e in dam.curves["faces"].tolist()}
    union = set()
    for name, line in on.items():
        mine = {tuple(sorted(e)) for e in dam.curves[name].tolist()}
        assert len(mine) == len(dam.curves[name]) and mine, name
        # exactly the faces' edges with both ends on the part's line
        expected = {e for e in faces if line(*xy[list(e)].T).all()}
        assert mine == expected, name
        assert not mine & union, name
        union |= mine
    assert union == faces
    assert length(dam, dam.curves["upstream"]) == pytest.approx(H * math.hypot(u, 1.0), rel=1e-12)
    assert length(dam, dam.curves["downstream"]) == pytest.approx(H * math.hypot(d, 1.0), rel=1e-12)
    assert length(dam, dam.curves["crest"]) == pytest.approx(c, rel=1e-12)
    assert length(dam, dam.curves["top_left"]) == pytest.approx(150.0 + xa, rel=1e-12)
    assert length(dam, dam.curves["top_right"]) == pytest.approx(150.0 - xb, rel=1e-12)


def test_water_refuses_faces_that_share_an_edge(dam):
    """"faces" holds "upstream": a [[water]] naming both would load the
    slope twice (vstpetsc.plane.water.check names the pair)."""
    from types import SimpleNamespace
    from vstpetsc.plane import water

    spec = lambda faces: SimpleNamespace(name="reservoir", level=30.0, faces=faces, acoustic=None)
    assert water.check([spec(("upstream",))], dam) is None
    assert water.check([spec(("upstream", "downstream", "top_left"))], dam) is None
    problem = water.check([spec(("faces", "upstream"))], dam)
    assert problem.startswith("water[0] (reservoir).faces: 'faces' and 'upstream' share the "
                              "edge at ("), problem
