"""Westergaard's added masses ([[water]] hydrodynamic = "westergaard",
issue 47, docs/water.md "Westergaard"): each node's mass against
(7/8) rho sqrt(H (level - y)) L on a vertical face cut by the level and
its block m n n^T on an inclined face; the block dam of
tests/test_water_hydrostatic.py at rest (the added mass carries no
weight), the same dam made stiff and accelerated by its foundation (the
joint's shear rises by sum(m_i) a beyond the dry dam's M a, the energy
balance closes), two ranks against one and a restart bit for bit."""

import io

import numpy as np

import vstpetsc
from test_plane_run import mpirun_against_one_rank
from test_water_hydrostatic import B, D, H, RHO, RHO_W, THRUST, WEIGHT, block_case
from test_water_hydrostatic import restarted_as_whole

A, RISE, DT = 0.5, 0.2, 1e-3        # the foundation's acceleration, its rise time, the step
STIFF = 2.0e12                      # the stiff dam's E: its lowest period about 5e-3 s


def base_velocity(t):
    """The foundation base's v_x: its acceleration rises from 0 to A along
    a half cosine over RISE (a smooth start: the stiff dam's vibrations
    stay small), then stays A."""
    t = np.asarray(t, float)
    return np.where(t < RISE, A * (t / 2 - RISE / (2 * np.pi) * np.sin(np.pi * t / RISE)),
                    A * (t - RISE / 2))


def shaken_case(tmp_path, name, westergaard, end=0.3):
    """The block case (static start), E = STIFF, its foundation's bottom
    moving along x with base_velocity (a history of RISE / DT * 4 points,
    linear between them: an acceleration in steps of DT / 4)."""
    path = block_case(tmp_path, name, end=end, dt=DT)
    points = np.r_[np.arange(0.0, RISE, DT / 4), [RISE, 10.0]]
    history = ", ".join(f"[{t!r}, {float(base_velocity(t))!r}]" for t in points)
    text = path.read_text().replace('type = "fixed"', 'type = "velocity"\nvalue = { x = ['
                                    + history + "], y = 0.0 }")
    text = text.replace("E = 2.0e10", f"E = {STIFF}")
    if westergaard:
        text += 'hydrodynamic = "westergaard"\n'
    path.write_text(text)
    return path


def run(path, tmp_path, name="out"):
    return vstpetsc.run(vstpetsc.Case.from_toml(path), output=str(tmp_path / f"{name}.h5"),
                        quiet=True, out=io.StringIO())


def test_the_added_mass_of_each_node_on_a_vertical_face():
    """A vertical face (x = 0, y from 0 to 4 in four edges) wet to 2.5
    (the third edge cut in its middle): H = 2.5, and each node's mass is
    (7/8) rho sqrt(H (2.5 - y)) L with L = 1/2, 1, 1/2 + 1/4 (half of the
    cut edge's wet piece) for y = 0, 1, 2; none at y = 3, 4; n = (-1, 0)."""
    from vstpetsc.plane.mesh import rectangle
    from vstpetsc.plane.schema import WaterSpec
    from vstpetsc.plane.westergaard import added_masses, faces_bottom

    mesh = rectangle((0.0, 1.0), (0.0, 4.0), 1, 4)
    spec = WaterSpec("w", 2.5, RHO_W, ("left",), "westergaard")
    nodes, mass, n = added_masses(mesh, spec, faces_bottom(mesh, spec))
    y = mesh.coordinates[nodes, 1]
    exact = 7 / 8 * RHO_W * np.sqrt(2.5 * (2.5 - y)) * np.array([0.5, 1.0, 0.75])
    print("vertical face: largest error", np.abs(mass - exact).max() / exact.max())
    assert np.array_equal(y, [0.0, 1.0, 2.0]) and np.all(mesh.coordinates[nodes, 0] == 0)
    assert np.allclose(mass, exact, rtol=1e-15, atol=0)
    assert np.array_equal(n, np.tile([-1.0, 0.0], (3, 1)))


def test_the_nodal_masses_approach_westergaards_total():
    """A face of 200 edges wet to its top (level = H = 4): sum(m_i), the
    nodal sums of (7/8) rho sqrt(H (H - y)), tends to Westergaard's total
    (7/12) rho H^2; within 1e-3 (the sum's error near the surface, where
    sqrt has no derivative, falls as h^1.5: measured 1.1e-4)."""
    from vstpetsc.plane.mesh import rectangle
    from vstpetsc.plane.schema import WaterSpec
    from vstpetsc.plane.westergaard import added_masses

    mesh = rectangle((0.0, 1.0), (0.0, 4.0), 1, 200)
    _, mass, _ = added_masses(mesh, WaterSpec("w", 4.0, RHO_W, ("left",), "westergaard"), 0.0)
    total = 7 / 12 * RHO_W * 4.0 ** 2
    print("total against 7/12 rho H^2", mass.sum() / total - 1)
    assert abs(mass.sum() / total - 1) <= 1e-3


def test_an_inclined_face_takes_kuos_normal():
    """The triangle (0, 0), (4, 0), (1, 3): its slanted face wet to 2 has
    blocks m n n^T along the face's outward normal (1, 1) / sqrt(2), m at
    (4, 0) (7/8) rho sqrt(H (2 - 0)) L with H = 2 and L half the wet piece
    (2 sqrt(2) long)."""
    from vstpetsc.plane.mesh import PlaneMesh
    from vstpetsc.plane.schema import WaterSpec
    from vstpetsc.plane.westergaard import added_masses, owned_rows

    xy = np.array([[0.0, 0.0], [4.0, 0.0], [1.0, 3.0]])
    mesh = PlaneMesh(xy, np.array([[0, 1, 2, -1]]), np.zeros(1, int), ("domain",),
                     {"slope": np.array([[2, 1]])})
    spec = WaterSpec("w", 2.0, RHO_W, ("slope",), "westergaard")
    nodes, mass, n = added_masses(mesh, spec, 0.0)
    assert np.array_equal(nodes, [1]) and np.allclose(n, [[2 ** -0.5, 2 ** -0.5]], rtol=1e-15)
    assert np.isclose(mass[0], 7 / 8 * RHO_W * 2.0 * np.sqrt(2.0), rtol=1e-15)
    M = owned_rows(mesh, np.arange(3), 0, 3, [spec], [0.0]).toarray()
    assert np.allclose(M[2:4, 2:4], mass[0] / 2 * np.ones((2, 2)), rtol=1e-15)
    assert np.count_nonzero(M) == 4


def test_the_added_mass_carries_no_weight(tmp_path):
    """The block dam at rest from the static start with Westergaard's
    masses: its joint carries W and the thrust as without them (to 1e-9
    of W, measured 1e-14): the weight's pattern is the solid's M alone."""
    path = block_case(tmp_path)
    path.write_text(path.read_text() + 'hydrodynamic = "westergaard"\n')
    joint = run(path, tmp_path).interface("joint")
    normal = joint.normal_force[1:].sum(axis=1)
    shear = joint.shear_force[1:].sum(axis=1)
    print("normal against W", np.abs(normal - WEIGHT).max() / WEIGHT,
          "shear against the thrust", np.abs(shear + THRUST).max() / WEIGHT)
    assert np.abs(normal - WEIGHT).max() <= 1e-9 * WEIGHT
    assert np.abs(shear + THRUST).max() <= 1e-9 * WEIGHT


def block_added_mass(case):
    """sum(m_i) x-components over the nodes of the block above the joint
    (the split mesh of ``case``: the block's copies of the joint's nodes)."""
    from vstpetsc.plane.model import read_mesh, split_interfaces
    from vstpetsc.plane.westergaard import added_masses

    mesh, _ = split_interfaces(case, read_mesh(case.plane.mesh))
    nodes, mass, n = added_masses(mesh, case.plane.waters[0], -D)
    centres = np.where(mesh.cells >= 0, mesh.coordinates[mesh.cells, 1], np.nan)
    block = np.unique(mesh.cells[np.nanmean(centres, axis=1) > 0])
    assert np.allclose(n, [-1.0, 0.0])
    return mass[np.isin(nodes, block)].sum()


def test_a_stiff_dam_shaken_by_its_foundation_carries_the_added_mass(tmp_path):
    """The stiff block dam (E = 2e12) on its joint (sticking), the
    foundation's base accelerating along x (base_velocity: A after RISE):
    at every slab after RISE, the joint's sum(shear_force) with the
    Westergaard masses exceeds the hydrostatic-only run's by
    sum(m_i) A (the block's added masses; the foundation's own, below
    the joint, do not load it) within 2 % (measured 0.6 %: the stiff
    dam's undamped vibration left by the rise), their mean within 1e-3
    (measured 2.6e-5); the dry run's shear is -thrust + rho B H A within 1 %
    (measured 0.15 %).
    The energy balance closes: numerical >= 0 and below 1e-6 of the
    external work."""
    dry, wet = (run(shaken_case(tmp_path, f"c{w}", w), tmp_path, f"c{w}")
                for w in (False, True))
    added = block_added_mass(vstpetsc.Case.from_toml(shaken_case(tmp_path, "ct", True)))
    late = dry.time > RISE + 1e-9
    shear = lambda r: r.interface("joint").shear_force[:].sum(axis=1)[late]
    rise = (shear(wet) - shear(dry)) / (added * A)
    inertia = (shear(dry) + THRUST) / (RHO * B * H * A)
    energy = wet.energy
    numerical, external = energy["numerical"][:], energy["external"][-1]
    print("added mass", added, "largest error", np.abs(rise - 1).max(), "mean error",
          abs(rise.mean() - 1), "dry against M a", np.abs(inertia - 1).max(),
          "numerical", numerical.min(), numerical[-1] / external)
    assert np.abs(rise - 1).max() <= 0.02 and abs(rise.mean() - 1) <= 1e-3
    assert np.abs(inertia - 1).max() <= 0.01
    assert numerical.min() >= 0 and numerical[-1] <= 1e-6 * external


def test_westergaard_on_two_ranks_equals_one(tmp_path):
    two = mpirun_against_one_rank(tmp_path, shaken_case(tmp_path, "par", True, end=0.05))
    assert np.abs(vstpetsc.Result(two).interface("joint").shear_force[:]).max() > 0


def test_a_restart_with_westergaard_continues_bit_for_bit(tmp_path):
    restarted_as_whole(tmp_path, lambda end, name: shaken_case(tmp_path, name, True, end=end),
                       0.05)
