"""The first natural frequencies of a triangular dam on rigid ground
(vstpetsc.plane: the generated dam section's dam region, its base held)
from the generalized eigenvalues of its M and K: converged in h, and the
first horizontal mode against the shear-beam formula
f_1 = 2.404 Vs / (2 pi H) (issue 37; 2.404 the first zero of J_0), within
that formula's own approximation: it keeps only the horizontal shear of
the wedge, where plane strain also has vertical motion and normal
strains (measured 9.1 % below it at slopes 2 : 1, nu = 0.3; asserted
within 5-15 %); and v-ST/FEM slabs started in that mode return after one
period to third order in time."""

import numpy as np
import pytest
import scipy.sparse.linalg as sla

from vstpetsc.plane import assembly, elements
from vstpetsc.plane.dam_mesh import dam_mesh
from vstpetsc.plane.solver.stepper import PlaneSlabs

H, VS, RHO, NU = 40.0, 300.0, 2000.0, 0.3
G = RHO * VS ** 2
LAM, MU = elements.lame(2.0 * G * (1.0 + NU), NU)
SHEAR_BEAM = 2.404 * VS / (2 * np.pi * H)


def dam_on_rock(h, slope=2.0):
    """(M, K, held dofs, mesh) of a triangular dam (crest 0) on rigid ground."""
    m = dam_mesh(H, 0.0, slope, slope, 10.0, 1000.0, h).region_mesh("dam")
    M, K = assembly.matrices(m, LAM, MU, RHO, "consistent")
    base = m.curve_nodes("contact")
    return M, K, (2 * base[:, None] + np.arange(2)).ravel(), m


def horizontal_modes(M, K, held, count=8):
    """The frequencies and shapes of the lowest modes, ordered, and each
    one's horizontal participation (phi^T M e_x)^2 / (phi^T M phi)."""
    free = np.setdiff1d(np.arange(M.shape[0]), held)
    Mf, Kf = M[free][:, free], K[free][:, free]
    w2, phi = sla.eigsh(Kf, k=count, M=Mf, sigma=0, which="LM")
    order = np.argsort(w2)
    w2, phi = w2[order], phi[:, order]
    ex = np.zeros(M.shape[0])
    ex[0::2] = 1.0
    part = (phi.T @ (Mf @ ex[free])) ** 2 / np.einsum("ik,ik->k", phi, Mf @ phi)
    return np.sqrt(w2) / (2 * np.pi), phi, part, free


def test_the_first_mode_against_the_shear_beam():
    f = {}
    for h in (4.0, 2.0, 1.0):
        freq, _, part, _ = horizontal_modes(*dam_on_rock(h)[:3])
        f[h] = freq[np.argmax(part)]                 # the mode that carries most mass along x
    # converged in h (measured 2.6133, 2.6084, 2.6071 Hz at h = 4, 2, 1)
    assert abs(f[1.0] / f[2.0] - 1) < 1e-3 and abs(f[2.0] / f[4.0] - 1) < 1e-2, f
    ratio = f[1.0] / SHEAR_BEAM
    print("dam f1", f, "shear beam", SHEAR_BEAM, "ratio", ratio)
    assert 0.85 < ratio < 0.95, ratio


def test_slabs_in_the_first_mode_keep_its_frequency():
    M, K, held, m = dam_on_rock(2.0)
    freq, phi, part, free = horizontal_modes(M, K, held)
    k = int(np.argmax(part))
    T = 1.0 / freq[k]
    u0 = np.zeros(M.shape[0])
    u0[free] = phi[:, k] / np.abs(phi[:, k]).max()
    crest = int(np.argmax(m.coordinates[:, 1]))
    errors = []
    for n in (16, 32, 64):
        slabs = PlaneSlabs(M, None, K, T / n, held=held)
        u, v = u0.copy(), np.zeros_like(u0)
        for _ in range(n):
            u, v = slabs.step(u, v)
        errors.append(abs(u[2 * crest] - u0[2 * crest]) / abs(u0[2 * crest]))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    print("dam mode after one period:", errors, orders)
    assert errors[-1] < 1e-4 and orders.min() > 2.7, (errors, orders)
