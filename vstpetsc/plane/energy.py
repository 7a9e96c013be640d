"""Energy terms of plane-strain slabs (the 1-D names and meanings,
docs/loads.md section 4), each exact for the slab's linear velocity:

- kinetic 1/2 v^T M v and strain 1/2 u^T K u at the slab ends (v^{(n+1)-});
- damping: int v^T C v dt = dt (v1 C v1 + (v1 C v2 + v2 C v1) / 2 + v2 C v2) / 3
  (C's symmetric part: an acoustic water's skew coupling does no work);
- external: the forces' work, sum_a (int T_a f dt) . v_a;
- numerical: what the balance leaves (initial + external = kinetic +
  strain + damping + numerical): the energy of the velocity jumps at the
  slab starts, >= 0.

Stresses at the cells' centres, sigma_xx, sigma_yy, sigma_xy.  Pure numpy."""

import numpy as np

from vstpetsc.runner import energy as shared
from vstpetsc.plane import elements


def centre_stress(mesh, u, lam, mu):
    """(ne, 3) sigma_xx, sigma_yy, sigma_xy at each cell's centre (exact for
    a linear displacement; a quadrilateral's at its reference centre)."""
    out = np.zeros((mesh.ncells, 3))
    D = elements.elasticity(np.broadcast_to(lam, (mesh.ncells,)),
                            np.broadcast_to(mu, (mesh.ncells,)))
    for cells, corners, gradients in ((mesh.triangles, 3, elements.triangle_gradients),
                                      (mesh.quadrilaterals, 4, elements.centre_gradients)):
        if not cells.size:
            continue
        nodes = mesh.cells[cells, :corners]
        B = elements.strain_operator(gradients(mesh.coordinates[nodes]))
        uc = u.reshape(-1, 2)[nodes].reshape(cells.size, -1)
        out[cells] = np.einsum("nab,nb->na", D[cells], np.einsum("nbj,nj->nb", B, uc))
    return out



class RunEnergyBook(shared.EnergyBook):
    """The shared EnergyBook (the rows' terms, restarts, the guard) over a
    plane-strain solver: the state's kinetic and strain energy come with
    the solver's totals (summed over the ranks); no springs but the
    interfaces' (their energy is "contact")."""

    def __init__(self, model, solver):
        super().__init__(model)
        self.solver = solver
        self.first = (0.0, 0.0)

    def state(self, u, v, d=None, known=None):
        kinetic, strain = known if known is not None else self.first
        return {"kinetic": kinetic, "strain": strain, "spring": 0.0}

    def start(self, u, v):
        """t = 0: the state's energies and, with interfaces, their pairs'
        state from u (the gaps; a static start's stick springs) and the
        energy their springs store (vstpetsc.plane.pairs)."""
        self.first = self.solver.held_energies(u, v)         # collective
        self.held0 = self.initial = sum(self.first)
        pairs = self.model.pairs
        if pairs is not None:
            gravity = self.model.case.gravity
            pairs.start(np.asarray(u).reshape(-1, 2),
                        static=gravity is not None and gravity.initial == "static")
            self.offset["contact"] = pairs.stored_energy()
            self.initial += self.offset["contact"]
        self.largest = abs(self.initial)

    def row(self, u, v, totals, d=None, known=None):
        if "kinetic" in totals:
            known = (totals["kinetic"], totals["strain"])
        return super().row(u, v, totals, d, known)
