"""Energy terms of plane-strain slabs (the 1-D names and meanings,
docs/loads.md section 4), each exact for the slab's linear velocity:

- kinetic 1/2 v^T M v and strain 1/2 u^T K u at the slab ends (v^{(n+1)-});
- damping: int v^T C v dt = dt (v1 C v1 + v1 C v2 + v2 C v2) / 3;
- external: the forces' work, sum_a (int T_a f dt) . v_a;
- numerical: what the balance leaves (initial + external = kinetic +
  strain + damping + numerical): the energy of the velocity jumps at the
  slab starts, >= 0.

Stresses at the cells' centres, sigma_xx, sigma_yy, sigma_xy.  Pure numpy."""

import numpy as np

from vstpetsc import energy as shared

from vstpetsc.plane import elements


class EnergyBook:
    """The running energy terms of a serial plane-strain run."""

    def __init__(self, M, C, K, dt, u, v):
        self.M, self.C, self.K, self.dt = M, C, K, dt
        self.initial = self._held(u, v)
        self.damping = self.external = 0.0

    def _held(self, u, v):
        return 0.5 * float(v @ (self.M @ v)) + 0.5 * float(u @ (self.K @ u))

    def add_slab(self, v1, v2, forces=None):
        """The slab of start and end velocities v1, v2 (forces: its int T_a f
        dt interleaved per dof, or None)."""
        if self.C is not None:
            c1, c2 = self.C @ v1, self.C @ v2
            self.damping += self.dt * float(v1 @ c1 + v1 @ c2 + v2 @ c2) / 3.0
        if forces is not None:
            self.external += float(forces[0::2] @ v1 + forces[1::2] @ v2)

    def terms(self, u, v):
        kinetic, strain = 0.5 * float(v @ (self.M @ v)), 0.5 * float(u @ (self.K @ u))
        numerical = self.initial + self.external - kinetic - strain - self.damping
        return {"kinetic": kinetic, "strain": strain, "damping": self.damping,
                "external": self.external, "numerical": numerical}


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
    """The shared EnergyBook (the rows' terms, restarts, the peak) over a
    plane-strain solver: the state's kinetic and strain energy come with
    the solver's totals (summed over the ranks); no springs."""

    def __init__(self, model, solver):
        self.model, self.solver = model, solver
        self.initial = self.held0 = self.peak = self.beyond0 = 0.0
        self.offset = dict.fromkeys(shared.SUMMED, 0.0)
        self.first = (0.0, 0.0)

    def state(self, u, v, d=None, known=None):
        kinetic, strain = known if known is not None else self.first
        return {"kinetic": kinetic, "strain": strain, "spring": 0.0}

    def start(self, u, v):
        self.first = self.solver.held_energies(u, v)         # collective
        self.held0 = self.initial = sum(self.first)
        self.peak = abs(self.initial)

    def row(self, u, v, totals, d=None, known=None):
        if "kinetic" in totals:
            known = (totals["kinetic"], totals["strain"])
        return super().row(u, v, totals, d, known)
