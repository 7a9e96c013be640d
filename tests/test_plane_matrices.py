"""The plane-strain element matrices and their assembly (issue 37, the
first step of the 2-D room), against what the physics fixes exactly:

1. rigid motions (two translations, a rotation) strain nothing: K's null
   space on a free, distorted mesh of triangles and of quadrilaterals is
   exactly those three;
2. the mass matrix carries the mass rho x area in each direction, the
   consistent one the exact integral of a linear field's kinetic energy;
3. the patch test: a linear displacement field gives the exact constant
   stress, and interior nodes feel no force;
4. a column one cell wide, its side nodes tied, is the 1-D bar of the same
   mesh: v_x gives the shear bar (G = mu), v_y the axial bar
   (E = lambda + 2 mu), for both cell kinds and every mass.
"""

import numpy as np
import pytest

from conftest import bar, make_case
from vstpetsc.line.model import build_model
from vstpetsc.plane import assembly, elements, mesh as plane_mesh

E, NU, RHO = 2.0e8, 0.3, 1800.0
LAM, MU = elements.lame(E, NU)
KINDS = {"quadrilaterals": False, "triangles": True}


def distorted(triangles, seed=3):
    """A 4 x 3 rectangle mesh whose interior nodes are moved randomly (by a
    fifth of a cell): no symmetry helps any check."""
    m = plane_mesh.rectangle((0.0, 4.0), (-3.0, 0.0), 4, 3, triangles)
    rng = np.random.default_rng(seed)
    edge = np.unique(np.concatenate([c.ravel() for c in m.curves.values()]))
    inner = np.setdiff1d(np.arange(m.nnodes), edge)
    m.coordinates[inner] += rng.uniform(-0.2, 0.2, (inner.size, 2))
    return m


def rigid_modes(xy):
    """(2 nn, 3): translations along x and y, a rotation about the origin."""
    n = xy.shape[0]
    R = np.zeros((2 * n, 3))
    R[0::2, 0] = R[1::2, 1] = 1.0
    R[0::2, 2], R[1::2, 2] = -xy[:, 1], xy[:, 0]
    return R


@pytest.mark.parametrize("kind", KINDS)
def test_rigid_motions_are_the_null_space_of_k(kind):
    m = distorted(KINDS[kind])
    assert np.all(m.areas() > 0)
    _, K = assembly.matrices(m, LAM, MU, RHO)
    K = K.toarray()
    scale = np.abs(K).max()
    assert np.abs(K - K.T).max() <= 1e-14 * scale
    assert np.abs(K @ rigid_modes(m.coordinates)).max() <= 1e-12 * scale
    w = np.linalg.eigvalsh(K)
    assert w[0] >= -1e-12 * w[-1] and np.all(w[:3] < 1e-12 * w[-1]) and w[3] > 1e-6 * w[-1]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("mass", ["consistent", "lumped", "averaged"])
def test_mass_is_rho_times_area(kind, mass):
    m = distorted(KINDS[kind])
    M, _ = assembly.matrices(m, LAM, MU, RHO, mass)
    ones = rigid_modes(m.coordinates)[:, :2]
    total = ones.T @ M @ ones
    assert np.allclose(total, RHO * 12.0 * np.eye(2), rtol=1e-14, atol=1e-9)


@pytest.mark.parametrize("kind", KINDS)
def test_consistent_mass_integrates_a_linear_field_exactly(kind):
    """v = (a + b x + c y) e_x: 1/2 v^T M v = 1/2 rho int v^2 over the
    domain, which the mesh fills exactly (distorted inside, a rectangle)."""
    m = distorted(KINDS[kind])
    M, _ = assembly.matrices(m, LAM, MU, RHO, "consistent")
    x, y = m.coordinates.T
    v = np.zeros(2 * m.nnodes)
    v[0::2] = 1.0 + 0.5 * x - 0.25 * y
    # int over [0, 4] x [-3, 0] of (1 + x/2 - y/4)^2, by the exact polynomial integral
    X0, X1, Y0, Y1 = 0.0, 4.0, -3.0, 0.0
    px = np.polynomial.Polynomial([1.0, 0.5])
    py = np.polynomial.Polynomial([0.0, -0.25])
    ix = lambda p: (p.integ()(X1) - p.integ()(X0))
    iy = lambda p: (p.integ()(Y1) - p.integ()(Y0))
    exact = ix(px ** 2) * (Y1 - Y0) + 2 * ix(px) * iy(py) + (X1 - X0) * iy(py ** 2)
    assert v @ (M @ v) == pytest.approx(RHO * exact, rel=1e-13)


@pytest.mark.parametrize("kind", KINDS)
def test_patch_test(kind):
    """u = A (x, y) + c: every cell's stress D eps(A), the interior nodes'
    forces zero, the boundary's the traction of that stress."""
    m = distorted(KINDS[kind])
    _, K = assembly.matrices(m, LAM, MU, RHO)
    A = np.array([[1e-3, -2e-4], [5e-4, -3e-4]])
    u = (m.coordinates @ A.T + [0.1, -0.2]).ravel()
    f = K @ u
    edge = np.unique(np.concatenate([c.ravel() for c in m.curves.values()]))
    inner = np.setdiff1d(np.arange(m.nnodes), edge)
    force_scale = np.abs(f).max()
    assert np.abs(f.reshape(-1, 2)[inner]).max() <= 1e-12 * force_scale
    # the boundary forces sum to zero (equilibrium)
    assert np.abs(f.reshape(-1, 2).sum(axis=0)).max() <= 1e-12 * force_scale * m.nnodes
    eps = np.array([A[0, 0], A[1, 1], A[0, 1] + A[1, 0]])
    sigma = elements.elasticity(LAM, MU) @ eps
    # the right side (x = 4, its nodes a cell height apart): each node between
    # its corners carries the traction (sigma_xx, sigma_xy) over its length
    right = m.curve_nodes("right")
    between = np.setdiff1d(right, np.concatenate([m.curve_nodes("top"),
                                                  m.curve_nodes("bottom")]))
    assert between.size == 2
    assert np.allclose(f.reshape(-1, 2)[between], [sigma[0], sigma[2]], rtol=1e-10)


def one_cell_column(triangles, ny=6, width=0.5, height=3.0):
    return plane_mesh.rectangle((0.0, width), (0.0, height), 1, ny, triangles)


def tie(m):
    """(2 nn, ny + 1) P: the side nodes at each height move together in x
    (columns: the 1-D nodes); and the same in y."""
    y = m.coordinates[:, 1]
    levels = np.unique(y)
    P = np.zeros((m.nnodes, levels.size))
    P[np.arange(m.nnodes), np.searchsorted(levels, y)] = 1.0
    Px, Py = np.zeros((2 * m.nnodes, levels.size)), np.zeros((2 * m.nnodes, levels.size))
    Px[0::2], Py[1::2] = P, P
    return Px, Py


def one_d_operators(E1, mass, ny=6, width=0.5, height=3.0):
    """(M, K) of the 1-D bar of the same nodes, area = the column's width."""
    case = make_case(0.01, 0.02, [bar("b", (0.0, height), ny, E=E1, rho=RHO, area=width,
                                      mass=mass)])
    ops = build_model(case).ops
    n = ny + 1
    tri = lambda d, o: np.diag(d) + np.diag(o, 1) + np.diag(o, -1)
    return tri(ops.m_diag, ops.m_off), tri(ops.k_diag, ops.k_off)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("mass", ["consistent", "lumped", "averaged"])
def test_a_tied_column_one_cell_wide_is_the_1d_bar(kind, mass):
    m = one_cell_column(KINDS[kind])
    M, K = (A.toarray() for A in assembly.matrices(m, LAM, MU, RHO, mass))
    Px, Py = tie(m)
    for P, E1 in ((Px, MU), (Py, LAM + 2 * MU)):
        M1, K1 = one_d_operators(E1, mass)
        assert np.allclose(P.T @ K @ P, K1, rtol=1e-12, atol=1e-12 * np.abs(K1).max())
        assert np.allclose(P.T @ M @ P, M1, rtol=1e-12, atol=1e-12 * np.abs(M1).max())
