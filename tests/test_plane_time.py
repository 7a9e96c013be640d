"""v-ST/FEM slabs with plane-strain M and K (vstpetsc.plane.solver.stepper, the
1-D time algebra in sparse form): third order in time on a genuinely 2-D
problem, triangles and quadrilaterals, against the semi-discrete solution
of the same M, K computed here from their eigenvectors; energy is
conserved up to the scheme's dissipation (>= 0), without damping."""

import numpy as np
import pytest
import scipy.linalg

from vstpetsc.plane import assembly, elements, mesh as plane_mesh
from vstpetsc.plane.solver.stepper import PlaneSlabs

E, NU, RHO = 2.0e8, 0.3, 1800.0
LAM, MU = elements.lame(E, NU)


def plate(triangles):
    """A 4 x 3 plate fixed along its bottom, distorted inside."""
    m = plane_mesh.rectangle((0.0, 4.0), (0.0, 3.0), 4, 3, triangles)
    rng = np.random.default_rng(7)
    edge = np.unique(np.concatenate([c.ravel() for c in m.curves.values()]))
    inner = np.setdiff1d(np.arange(m.nnodes), edge)
    m.coordinates[inner] += rng.uniform(-0.2, 0.2, (inner.size, 2))
    held = (2 * m.curve_nodes("bottom")[:, None] + np.arange(2)).ravel()
    return m, held


def modal(M, K, held, u0, t):
    """u(t), v(t) of M u'' + K u = 0 from u0 at rest, held dofs at 0."""
    free = np.setdiff1d(np.arange(M.shape[0]), held)
    w2, phi = scipy.linalg.eigh(K[np.ix_(free, free)], M[np.ix_(free, free)])
    w = np.sqrt(w2)
    a = phi.T @ M[np.ix_(free, free)] @ u0[free]
    u, v = np.zeros_like(u0), np.zeros_like(u0)
    u[free] = phi @ (a * np.cos(w * t))
    v[free] = phi @ (-a * w * np.sin(w * t))
    return u, v, w


@pytest.mark.parametrize("triangles", [False, True], ids=["quadrilaterals", "triangles"])
def test_third_order_in_time_against_the_semi_discrete_solution(triangles):
    m, held = plate(triangles)
    M, K = assembly.matrices(m, LAM, MU, RHO, "consistent")
    Md, Kd = M.toarray(), K.toarray()
    free = np.setdiff1d(np.arange(Md.shape[0]), held)
    w2, phi = scipy.linalg.eigh(Kd[np.ix_(free, free)], Md[np.ix_(free, free)])
    u0 = np.zeros(Md.shape[0])
    u0[free] = phi[:, 0] / np.abs(phi[:, 0]).max() + 0.3 * phi[:, 2] / np.abs(phi[:, 2]).max()
    T = 2 * np.pi / np.sqrt(w2[0])               # the first mode's period
    u_ex, v_ex, _ = modal(Md, Kd, held, u0, T)
    errors = []
    for n in (20, 40, 80, 160):
        dt = T / n
        stepper = PlaneSlabs(M, None, K, dt, held=held)
        u, v = u0.copy(), np.zeros_like(u0)
        energy = [0.5 * (v @ Md @ v + u @ Kd @ u)]
        for _ in range(n):
            u, v = stepper.step(u, v)
            energy.append(0.5 * (v @ Md @ v + u @ Kd @ u))
        errors.append((np.abs(u - u_ex).max() / np.abs(u_ex).max(),
                       np.abs(v - v_ex).max() / np.abs(v_ex).max()))
        # no energy from nowhere: the jumps only dissipate
        assert np.diff(energy).max() <= 1e-12 * energy[0]
    # the local orders of each halving of dt (measured: u 2.99, 3.00, 3.01;
    # v 2.52, 2.82, 2.92 on quadrilaterals, 2.28, 2.74, 2.89 on triangles: the
    # third mode is resolved last)
    orders = np.log2(np.array(errors)[:-1] / np.array(errors)[1:])
    print("plane slabs, errors", errors, "local orders", orders)
    assert orders.min() >= 2.2 and orders[-1].min() >= 2.8, (errors, orders)
