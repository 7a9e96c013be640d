"""The bars' element stiffnesses as K is assembled from them: rounded so
that K's rows sum to zero exactly (shared by the axial model and the
hysteretic shear soil, which both assemble from E A / h)."""

import numpy as np


def exact_row_sums(mesh, ke):
    """The element stiffnesses E A / h rounded, each to a multiple of the
    unit in the last place of twice the node sums ke_{e-1} + ke_e it
    enters (a change of at most about 2e-16 of that sum), so that every
    such sum is exact and K's rows sum to zero exactly, as the bars' own
    stiffness does: with the plain sums a body moving as a whole felt
    springs to the ground of that rounding (k_ii + k_ij != 0), whose
    energy no term of the balance holds (docs/loads.md section 4).  An
    element never rounds to zero stiffness (at least one unit)."""
    shared = mesh.elem_body[1:] == mesh.elem_body[:-1]       # elements e, e+1 share a node
    unit = np.where(shared, np.spacing(2.0 * (ke[:-1] + ke[1:])), 0.0)
    q = np.zeros_like(ke)                 # the coarser grid of the two sums of each element
    q[:-1] = unit
    q[1:] = np.maximum(q[1:], unit)
    # q is a power of 2: ke / q and the product below are exact
    rounded = np.maximum(np.round(ke / np.where(q > 0, q, 1.0)), 1.0) * q
    return np.where(q > 0, rounded, ke)
