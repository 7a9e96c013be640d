"""Slabs of a plane-strain model in the plain algebra of formulation.md:
A x = R (u^n, v^{n-}) with A = HM (x) M + dt HC (x) C + dt^2 HK (x) K
(vstpetsc.slab.sparse_slab_matrix: the 1-D time algebra, any geometry),
factored once by PETSc's LU; held dofs keep zero velocity (identity rows).

The first 2-D solver: what the mesh, the element matrices and the time
algebra give together, checked against the semi-discrete solution
(tests/test_plane_time.py).  The running right-hand side, loads,
boundaries and the time loop of the 1-D room come next."""

import numpy as np
import scipy.sparse as sp

from vstpetsc import slab
from vstpetsc.plane.assembly import petsc_matrix


class PlaneSlabs:
    """Slabs of dt for the spatial matrices M, C (or None), K (CSR, 2 dofs a
    node); ``held`` the spatial dofs whose velocity is zero."""

    def __init__(self, M, C, K, dt, held=()):
        from petsc4py import PETSc

        self.M, self.K, self.dt = M, K, dt
        self.held = np.asarray(held, dtype=int)
        rows = (2 * self.held[:, None] + np.arange(2)).ravel()
        A = slab.sparse_slab_matrix(M, C, K, dt).tolil()
        A[rows, :] = 0.0
        A[rows, rows] = 1.0
        self.rows = rows
        self.A = petsc_matrix(sp.csr_matrix(A))
        self.ksp = PETSc.KSP().create(comm=PETSc.COMM_SELF)
        self.ksp.setOperators(self.A)
        self.ksp.setType("preonly")
        self.ksp.getPC().setType("lu")
        self.ksp.setUp()
        self.x, self.b = self.A.createVecs()

    def step(self, u, v, forces=None):
        """(u^{n+1}, v^{(n+1)-}) from (u^n, v^{n-}); ``forces`` the slab's
        nodal force integrals (2 per dof, interleaved), if any."""
        r = slab.sparse_rhs(self.M, self.K, self.dt, u, v)
        if forces is not None:
            r += forces
        r[self.rows] = 0.0
        self.b.setArray(r)
        self.ksp.solve(self.b, self.x)
        x = self.x.getArray()
        v1, v2 = x[0::2], x[1::2]
        return u + 0.5 * self.dt * (v1 + v2), v2.copy()
