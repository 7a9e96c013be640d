"""Plane-strain element matrices of every cell at once (per unit
thickness): stiffness K_e = int B^T D B and consistent mass
M_e = int rho N^T N, unknowns interleaved per node (v_x, v_y).

Linear triangles: B constant, M_e = rho A / 12 (1 + delta_ij) per
component (both exact).  Bilinear quadrilaterals: 2 x 2 Gauss points,
exact for both on a parallelogram (the integrands are then polynomials of
degree <= 2 in each reference coordinate: for the mass N_i N_j times a
constant Jacobian, for the stiffness B's entries are linear).  Lumped
mass: the consistent mass's row sums on the diagonal; averaged: the mean
of the two (interface.md "Plane strain (2-D)").  Pure numpy.
"""

import numpy as np

GAUSS = np.array([-1.0, 1.0]) / np.sqrt(3.0)
# the quadrilateral's reference corners (counter-clockwise) and Gauss points
CORNERS = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
POINTS = np.array([[xi, eta] for eta in GAUSS for xi in GAUSS])


def lame(E, nu):
    """(lambda, mu) of Young's modulus and Poisson's ratio."""
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))


def elasticity(lam, mu):
    """(n, 3, 3) plane-strain D for strains (eps_xx, eps_yy, gamma_xy)."""
    lam, mu = np.broadcast_arrays(np.asarray(lam, float), np.asarray(mu, float))
    D = np.zeros(lam.shape + (3, 3))
    D[..., 0, 0] = D[..., 1, 1] = lam + 2.0 * mu
    D[..., 0, 1] = D[..., 1, 0] = lam
    D[..., 2, 2] = mu
    return D


def strain_operator(dN):
    """(n, 3, 2k) B from the shape functions' gradients dN (n, k, 2)."""
    n, k = dN.shape[:2]
    B = np.zeros((n, 3, 2 * k))
    B[:, 0, 0::2] = dN[:, :, 0]
    B[:, 1, 1::2] = dN[:, :, 1]
    B[:, 2, 0::2] = dN[:, :, 1]
    B[:, 2, 1::2] = dN[:, :, 0]
    return B


def interleave(m):
    """(n, k, k) scalar matrices to (n, 2k, 2k), the same for both components."""
    n, k = m.shape[:2]
    out = np.zeros((n, 2 * k, 2 * k))
    out[:, 0::2, 0::2] = m
    out[:, 1::2, 1::2] = m
    return out


def triangle_gradients(xy, area=False):
    """(n, 3, 2) the shape functions' gradients of linear triangles with
    corners xy (n, 3, 2) (and their areas when ``area``)."""
    x, y = xy[..., 0], xy[..., 1]
    b = np.roll(y, -1, axis=1) - np.roll(y, -2, axis=1)         # y_j - y_k
    c = np.roll(x, -2, axis=1) - np.roll(x, -1, axis=1)         # x_k - x_j
    a = 0.5 * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])
    dN = np.stack([b, c], axis=-1) / (2.0 * a)[:, None, None]
    return (dN, a) if area else dN


def triangle_matrices(xy, D, rho):
    """(K_e, M_e) of linear triangles with corners xy (n, 3, 2)."""
    dN, area = triangle_gradients(xy, area=True)
    B = strain_operator(dN)
    K = area[:, None, None] * (B.transpose(0, 2, 1) @ (D @ B))
    m = (rho * area / 12.0)[:, None, None] * (np.ones((3, 3)) + np.eye(3))
    return K, interleave(m)


def quadrilateral_gradients(xy, xi, eta):
    """(N (4,), dN (n, 4, 2), det J (n,)) of bilinear quadrilaterals with
    corners xy (n, 4, 2) at the reference point (xi, eta)."""
    N = 0.25 * (1.0 + CORNERS[:, 0] * xi) * (1.0 + CORNERS[:, 1] * eta)
    dN_ref = 0.25 * np.column_stack([CORNERS[:, 0] * (1.0 + CORNERS[:, 1] * eta),
                                     CORNERS[:, 1] * (1.0 + CORNERS[:, 0] * xi)])
    J = np.einsum("ka,nkb->nab", dN_ref, xy)               # d(x, y) / d(xi, eta)
    det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
    # J^{-1} written out (a batched LAPACK call costs ten times more)
    inv = np.stack([np.stack([J[:, 1, 1], -J[:, 0, 1]], -1),
                    np.stack([-J[:, 1, 0], J[:, 0, 0]], -1)], -2) / det[:, None, None]
    return N, np.einsum("ka,nba->nkb", dN_ref, inv), det


def centre_gradients(xy):
    """A quadrilateral's gradients at its reference centre."""
    return quadrilateral_gradients(xy, 0.0, 0.0)[1]


def quadrilateral_matrices(xy, D, rho):
    """(K_e, M_e) of bilinear quadrilaterals with corners xy (n, 4, 2),
    2 x 2 Gauss points."""
    n = xy.shape[0]
    K, m = np.zeros((n, 8, 8)), np.zeros((n, 4, 4))
    for xi, eta in POINTS:
        N, dN, det = quadrilateral_gradients(xy, xi, eta)
        B = strain_operator(dN)
        K += det[:, None, None] * (B.transpose(0, 2, 1) @ (D @ B))
        m += (rho * det)[:, None, None] * np.outer(N, N)[None]
    return K, interleave(m)


def lumped(M):
    """The row sums of element masses on their diagonals."""
    out = np.zeros_like(M)
    idx = np.arange(M.shape[1])
    out[:, idx, idx] = M.sum(axis=2)
    return out


MASSES = {"consistent": lambda M: M, "lumped": lumped,
          "averaged": lambda M: 0.5 * (M + lumped(M))}
