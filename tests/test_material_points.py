"""The strain points of a plane-strain mesh (vstpetsc.plane.material_points,
issue 46), against what the element matrices and the physics fix:

1. S^T (w D) S over every cell is the assembled stiffness K (the points
   are the stiffness's own quadrature), and over some cells the sum of
   those cells' element matrices;
2. a linear displacement field strains every point by its constant
   gradient, exactly (the patch test);
3. the nodal forces of point stresses are the work conjugate of the
   strains: u . S^T (w sigma) = sum w sigma . eps(u).
"""

import numpy as np
import pytest
import scipy.sparse as sp

from test_plane_matrices import KINDS, LAM, MU, RHO, distorted
from vstpetsc.plane import assembly, elements
from vstpetsc.plane.material_points import material_points


def mixed_mesh():
    """A distorted quadrilateral mesh with two cells turned into triangles'
    worth of points: the quadrilaterals' mesh and the triangles' mesh
    side by side are checked separately, so here both kinds at once come
    from one mesh of each."""
    return distorted(False), distorted(True)


@pytest.mark.parametrize("kind", KINDS)
def test_the_points_integrate_the_stiffness(kind):
    m = distorted(KINDS[kind])
    points = material_points(m)
    D = elements.elasticity(np.full(points.count, LAM), np.full(points.count, MU))
    _, K = assembly.matrices(m, LAM, MU, RHO)
    scale = abs(K).max()
    assert abs(points.stiffness(D) - K).max() <= 1e-13 * scale
    some = np.arange(0, m.ncells, 3)
    part = material_points(m, some)
    parts = assembly.element_matrices(m, LAM, MU, RHO)
    blocks = [(cells[np.isin(cells, some)], Ke[np.isin(cells, some)])
              for cells, Ke, _ in parts.values()]
    expected = assembly.assemble(m, blocks)
    D = elements.elasticity(np.full(part.count, LAM), np.full(part.count, MU))
    assert abs(part.stiffness(D) - expected).max() <= 1e-13 * scale
    assert set(part.cell) == set(some)


@pytest.mark.parametrize("kind", KINDS)
def test_a_linear_field_strains_every_point_by_its_gradient(kind):
    m = distorted(KINDS[kind])
    grad = np.array([[1.0e-3, -4.0e-4], [2.5e-4, 7.0e-4]])        # du_i / dx_j
    u = (m.coordinates @ grad.T).ravel()
    eps = material_points(m).strains(u)
    exact = np.array([grad[0, 0], grad[1, 1], grad[0, 1] + grad[1, 0]])
    assert np.abs(eps - exact).max() <= 1e-15 * np.abs(grad).max() * 10


@pytest.mark.parametrize("kind", KINDS)
def test_forces_are_the_work_conjugate_of_strains(kind):
    m = distorted(KINDS[kind])
    points = material_points(m)
    rng = np.random.default_rng(5)
    u, sigma = rng.normal(size=2 * m.nnodes), rng.normal(size=(points.count, 3))
    work = float(np.sum(points.weight[:, None] * sigma * points.strains(u)))
    assert abs(u @ points.forces(sigma) - work) <= 1e-13 * np.abs(u).sum() * \
        np.abs(sigma).max() * np.abs(points.strain).max()
    assert points.weight.sum() == pytest.approx(m.areas().sum(), rel=1e-14)
    assert isinstance(points.stiffness(np.zeros((points.count, 3, 3))), sp.csr_matrix)
