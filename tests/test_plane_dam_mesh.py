"""The generated dam mesh (vstpetsc.plane.dam_mesh): its geometry exact,
conforming (every inner edge in two cells, the boundary exactly its named
curves, the contact inside), cells of about h, and a mixed mesh the
assembly takes (rigid motions strain nothing); without polylines or a
reservoir the same mesh to the bit as before them; polyline faces exact
through every break; the reservoir's water conforming with the dam and
the foundation, its curves exact and where they should be; bad profiles
refused naming the key."""

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


# -- polyline faces and the reservoir's water ---------------------------------

# a Koyna-like section (a slight batter at the upstream heel, the downstream
# face's slope break at 66.5 m, the vertical neck above) and its reservoir
KOYNA = dict(height=103.0, crest=None, upstream=[[-2.0, 0.0], [0.0, 20.0], [0.0, 103.0]],
             downstream=[[70.0, 0.0], [14.8, 66.5], [14.8, 103.0]], foundation_depth=40.0,
             foundation_width=300.0, h=5.0, reservoir={"level": 91.7, "length": 60.0})
# straight slopes: the water's face slants all the way (triangles); full to the crest and
# out to the foundation's left end (x_far = -W/2)
RESERVOIRS = {"koyna": KOYNA,
              "sloped": {**DAM, "reservoir": {"level": 30.0, "length": 50.0}},
              "full": {**DAM, "crest": 0.0, "h": 4.0,
                       "reservoir": {"level": 40.0, "length": 150.0 - 2.0 * 40.0}}}


def old_dam_mesh(height, crest, upstream, downstream, foundation_depth, foundation_width, h):
    """dam_mesh before polylines and reservoirs (commit 1e13a4c), its
    foundation and curves inlined: without the new keys the mesh must be
    the same to the bit."""
    from vstpetsc.plane.dam_mesh import _zip_rows, divisions

    H, W, D = height, foundation_width, foundation_depth
    xa, xb = -(crest / 2 + upstream * H), crest / 2 + downstream * H
    xs = np.concatenate([divisions(-W / 2, xa, h)[:-1], divisions(xa, xb, h)[:-1],
                         divisions(xb, W / 2, h)])
    ys = divisions(-D, 0.0, h)
    X, Y = np.meshgrid(xs, ys)
    fnode = np.arange(xs.size * ys.size).reshape(ys.size, xs.size)
    quads = np.column_stack([fnode[:-1, :-1].ravel(), fnode[:-1, 1:].ravel(),
                             fnode[1:, 1:].ravel(), fnode[1:, :-1].ravel()])
    in_base = (xs >= xa - 1e-12 * W) & (xs <= xb + 1e-12 * W)
    rows, points = [fnode[-1][in_base]], [np.column_stack([X.ravel(), Y.ravel()])]
    count = points[0].shape[0]
    for y in divisions(0.0, H, h)[1:]:
        left, right = xa + upstream * y, xb - downstream * y
        x = divisions(left, right, h) if right - left > 1e-9 * h else np.array([left])
        rows.append(count + np.arange(x.size))
        points.append(np.column_stack([x, np.full(x.size, y)]))
        count += x.size
    coords = np.concatenate(points)
    tris = np.concatenate([_zip_rows(lo, up, coords[lo, 0], coords[up, 0])
                           for lo, up in zip(rows[:-1], rows[1:])])
    cells = np.concatenate([quads, np.column_stack([tris, -np.ones(len(tris), int)])])
    region = np.concatenate([np.ones(len(quads), int), np.zeros(len(tris), int)])
    edges = lambda n: np.column_stack([n[:-1], n[1:]])
    top, (first, last) = fnode[-1], np.flatnonzero(in_base)[[0, -1]]
    parts = {"top_left": edges(top[:first + 1]), "upstream": edges(np.array([r[0] for r in rows])),
             "crest": edges(rows[-1]), "downstream": edges(np.array([r[-1] for r in rows])),
             "top_right": edges(top[last:])}
    curves = {"base": edges(fnode[0]), "left": edges(fnode[:, 0]), "right": edges(fnode[:, -1]),
              "faces": np.concatenate(list(parts.values())), "contact": edges(top[first:last + 1]),
              **parts}
    return coords, cells, region, curves


@pytest.mark.parametrize("params", [DAM, {**DAM, "crest": 0.0, "h": 3.3},
                                    dict(height=7.3, crest=3.7, upstream=0.05, downstream=0.8,
                                         foundation_depth=9.0, foundation_width=40.0, h=1.3)])
def test_without_the_new_keys_the_mesh_is_the_old_one(params):
    new = dam_mesh(**params)
    coords, cells, region, curves = old_dam_mesh(**params)
    assert np.array_equal(new.coordinates, coords) and np.array_equal(new.cells, cells)
    assert np.array_equal(new.region, region) and new.region_names == ("dam", "foundation")
    assert list(new.curves) == list(curves)
    assert all(np.array_equal(new.curves[k], v) for k, v in curves.items())


def profile(p):
    """(upstream points, downstream points, x_heel, x_far, level) of a
    case, the slopes' points by the closed form."""
    H, c = p["height"], p["crest"]
    up, down = p["upstream"], p["downstream"]
    if not isinstance(up, list):
        up = [[-(c / 2 + up * H), 0.0], [-c / 2, H]]
        down = [[c / 2 + down * H, 0.0], [c / 2, H]]
    up, down = np.array(up), np.array(down)
    r = p["reservoir"]
    return up, down, up[0, 0], up[0, 0] - r["length"], r["level"]


def shoelace(xy):
    x, y = np.asarray(xy).T
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def polyline_length(points):
    return float(np.linalg.norm(np.diff(points, axis=0), axis=1).sum())


def below(points, level):
    """The polyline cut at y = level (its points below, then the cut)."""
    keep = points[points[:, 1] < level]
    return np.vstack([keep, [np.interp(level, points[:, 1], points[:, 0]), level]])


def edge_uses(m):
    """(edge keys, how many cells use each, the regions of the cells
    beside each (the lowest and the highest))."""
    cells, a, b = m.edges()
    keys = m.edge_keys(a, b)
    unique, at, uses = np.unique(keys, return_inverse=True, return_counts=True)
    low = np.full(unique.size, 9)
    high = np.full(unique.size, -1)
    np.minimum.at(low, at, m.region[cells])
    np.maximum.at(high, at, m.region[cells])
    return unique, uses, low, high


def keys_of(m, *names):
    return np.unique(np.concatenate([m.edge_keys(*m.curves[n].T) for n in names]))


@pytest.fixture(scope="module", params=list(RESERVOIRS))
def reservoir_mesh(request):
    p = RESERVOIRS[request.param]
    return p, dam_mesh(**p)


def test_the_regions_fill_their_polygons(reservoir_mesh):
    """Every cell counter-clockwise; the dam's cells fill the polygon of
    its faces, the water's the polygon from x_far along the floor, up the
    face and back along the surface, the foundation W x D."""
    p, m = reservoir_mesh
    up, down, heel, x_far, level = profile(p)
    a = m.areas()
    assert m.region_names == ("dam", "foundation", "water") and a.min() > 0
    dam = shoelace(np.vstack([down, up[::-1]]))
    water = shoelace(np.vstack([[[x_far, 0.0]], below(up, level), [[x_far, level]]]))
    rock = p["foundation_width"] * p["foundation_depth"]
    for r, area in enumerate((dam, rock, water)):
        assert a[m.region == r].sum() == pytest.approx(area, rel=1e-12), r


def test_the_water_conforms_and_the_boundary_is_the_named_curves(reservoir_mesh):
    """Every inner edge in exactly two cells; the outer boundary exactly
    the foundation's base and sides, its top beyond the water, the water's
    far end and surface, the face above the water, the crest, the
    downstream face and the top beyond the toe: its length the closed
    form; the whole passes the mesh checks a run makes."""
    from vstpetsc.plane import mesh_checks

    p, m = reservoir_mesh
    up, down, heel, x_far, level = profile(p)
    W, D, H = p["foundation_width"], p["foundation_depth"], p["height"]
    keys, uses, _, _ = edge_uses(m)
    assert set(uses) <= {1, 2}
    outer = np.setdiff1d(keys_of(m, "base", "left", "right", "top_left", "far", "surface",
                                 "upstream", "crest", "downstream", "top_right"),
                         keys_of(m, "wet", "floor"))
    assert np.array_equal(keys[uses == 1], outer)
    face_above = polyline_length(up) - polyline_length(below(up, level))
    x_face = np.interp(level, up[:, 1], up[:, 0])
    expected = (W + 2 * D + (x_far + W / 2) + level + (x_face - x_far) + face_above +
                (down[-1, 0] - up[-1, 0]) + polyline_length(down) + (W / 2 - down[0, 0]))
    _, a, b = m.edges()                 # a boundary edge is one cell's side
    once = np.isin(m.edge_keys(a, b), outer)
    perimeter = np.linalg.norm(m.coordinates[a[once]] - m.coordinates[b[once]], axis=1).sum()
    assert perimeter == pytest.approx(expected, rel=1e-12)
    mesh_checks.check(m)


def test_the_water_curves_have_their_lengths_and_sides(reservoir_mesh):
    """"wet" is the face below the level, "floor" the reservoir's length,
    "far" the level (at x = x_far), "surface" the length and the face's
    offset at the level (at y = level); "wet" lies between water and dam
    cells, "floor" between water and foundation cells."""
    p, m = reservoir_mesh
    up, down, heel, x_far, level = profile(p)
    x_face = np.interp(level, up[:, 1], up[:, 0])
    expected = {"wet": polyline_length(below(up, level)), "floor": p["reservoir"]["length"],
                "far": level, "surface": x_face - x_far}
    for name, value in expected.items():
        assert length(m, m.curves[name]) == pytest.approx(value, rel=1e-12), name
    assert (m.coordinates[m.curves["far"], 0] == x_far).all()
    assert (m.coordinates[m.curves["surface"], 1] == level).all()
    keys, uses, low, high = edge_uses(m)
    for name, solid in (("wet", 0), ("floor", 1)):
        at = np.searchsorted(keys, keys_of(m, name))
        assert (uses[at] == 2).all() and (low[at] == solid).all() and (high[at] == 2).all()


def test_polyline_faces_pass_through_every_break():
    """Koyna's faces: a node at every point of both polylines, every node
    of "upstream" and "downstream" on its polyline (to rounding), the
    crest the polylines' 14.8 m; beside the vertical face the water is
    quadrilaterals, beside the batter triangles."""
    m = dam_mesh(**KOYNA)
    xy = m.coordinates
    for name in ("upstream", "downstream"):
        points = np.array(KOYNA[name])
        on = xy[m.curve_nodes(name)]
        for point in points:
            assert (on == point).all(axis=1).any(), (name, point)
        assert np.allclose(np.interp(on[:, 1], points[:, 1], points[:, 0]), on[:, 0],
                           rtol=0, atol=1e-12)
    assert length(m, m.curves["crest"]) == pytest.approx(14.8, rel=1e-12)
    water = m.region == 2
    low = xy[np.where(m.cells < 0, m.cells[:, :1], m.cells), 1].min(axis=1)
    quads = m.cells[:, 3] >= 0
    assert quads[water & (low >= 20.0)].all() and not quads[water & (low < 20.0)].any()


def test_a_polyline_beside_a_slope_hangs_it_from_the_crest():
    """One polyline: the slope's crest corner lies ``crest`` beyond the
    polyline's."""
    m = dam_mesh(**{**KOYNA, "crest": 10.0, "downstream": 0.7, "reservoir": None})
    xy = m.coordinates[m.curve_nodes("downstream")]
    assert np.allclose(xy[:, 0], 10.0 + 0.7 * (103.0 - xy[:, 1]), rtol=0, atol=1e-12)
    assert "water" not in m.region_names and "wet" not in m.curves


@pytest.mark.parametrize("change, words", [
    ({"upstream": [[-2.0, 1.0], [0.0, 103.0]]},
     "upstream: points must rise from y = 0 to y = height (103)"),
    ({"downstream": [[70.0, 0.0], [14.8, 66.5], [14.8, 66.5], [14.8, 103.0]]},
     "downstream: points must rise from y = 0 to y = height"),
    ({"crest": 10.0}, "crest: the polylines' crest is 14.8 wide, not 10"),
    ({"downstream": 0.7}, "crest: missing"),
    ({"downstream": [[70.0, 0.0], [-5.0, 66.5], [14.8, 103.0]]},
     "downstream: the faces cross at y = 66.5"),
    ({"foundation_width": 120.0}, "foundation_width: the dam's base [-2, 70] is wider than its "
                                  "foundation [-60, 60]"),
    ({"reservoir": {"level": 110.0, "length": 60.0}}, "reservoir.level: must lie in (0, height"),
    ({"reservoir": {"level": 50.0, "length": 150.0}},
     "reservoir.length: the water's far end x = -152 lies beyond the foundation's left end"),
    ({"upstream": [[-2.0, 0.0], [-80.0, 20.0], [0.0, 103.0]]},
     "reservoir.length: the upstream face reaches x = -80 at y = 20"),
])
def test_bad_profiles_are_refused_naming_the_key(change, words):
    """The mesh's ValueError, and the reader's one line (mesh.dam.<key>)."""
    from vstpetsc.input.checker import Checker
    from vstpetsc.plane import schema

    params = {**KOYNA, **change}
    with pytest.raises(ValueError) as error:
        dam_mesh(**params)
    assert str(error.value).startswith(words)
    chk = Checker()
    given = {k: v for k, v in params.items() if v is not None}
    assert schema.read_mesh(chk, {"dam": given}) is None
    assert len(chk.problems) == 1 and chk.problems[0].startswith(f"mesh.dam.{words}"), \
        chk.problems


def test_the_reader_takes_the_new_keys_and_counts_the_water():
    """The reader's spec builds the mesh; its size estimate counts the
    water's cells (a reservoir can make a mesh too big); bad reservoir
    tables are one line per key."""
    from vstpetsc.input.checker import Checker
    from vstpetsc.plane import schema

    read = lambda **p: (schema.read_mesh(chk := Checker(), {"dam": p}), chk.problems)
    given = {k: v for k, v in KOYNA.items() if v is not None}
    spec, problems = read(**given)
    assert not problems and spec.params["crest"] is None
    assert dam_mesh(**spec.params).region_names == ("dam", "foundation", "water")
    wide = dict(height=10.0, crest=2.0, upstream=0.5, downstream=0.5, foundation_depth=1.0,
                foundation_width=20000.0, h=0.1)
    assert read(**wide)[1] == []
    _, problems = read(**wide, reservoir={"level": 10.0, "length": 9000.0})
    assert len(problems) == 1 and problems[0].startswith("mesh.dam.h: 2e+07 cells")
    _, problems = read(**{**given, "reservoir": {"level": -1.0, "length": "far", "x": 1}})
    assert problems == ["mesh.dam.reservoir.x: unknown key (allowed: level, length)",
                        "mesh.dam.reservoir.level: must be positive, got -1",
                        "mesh.dam.reservoir.length: must be a number, got a string 'far'"]
    _, problems = read(**{**given, "upstream": [[0.0, 0.0], [0.0]]})
    assert problems == ["mesh.dam.upstream: must be a slope (a number) or a list of at least "
                        "two [x, y] points, got an array [[0.0, 0.0], [0.0]]"]
