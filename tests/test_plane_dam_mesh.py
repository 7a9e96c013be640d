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
