"""The static start of a plane-strain run under gravity ([gravity]
initial = "static", as in 1-D: docs/loads.md): K u = f_g with every held
dof and every node of an absorbing curve held, solved once; the run then
starts from rest in u with the absorbing nodes' reactions K u - f_g kept
as constant forces, so that (u, 0) is an exact equilibrium of the slab
equations (with v = 0 their right-hand side is dt/2 (f - K u) on both
time rows, zero everywhere)."""

from dataclasses import dataclass

import numpy as np
from petsc4py import PETSc

from vstpetsc.history import History
from vstpetsc.plane.assembly import petsc_matrix
from vstpetsc.plane.solver import gather_to_rank0, identity_rows

PREFIX = "vst_static_"


@dataclass
class PlaneStatic:
    u: np.ndarray           # (nn, 2) of every node, the mesh's numbering as read (every rank)
    reactions: tuple        # (pattern over the owned dofs, History 1): the kept forces


def static_state(model, gravity_pattern):
    """The PlaneStatic of ``model`` under the load pattern of g(0) (collective)."""
    comm, bounds = model.comm, model.boundaries
    M, _, K = model.matrices()
    f = gravity_pattern * float(model.case.gravity.g(np.array([0.0]))[0])
    held = np.union1d(bounds.held_dofs()[0], bounds.absorbing_dofs())
    A = petsc_matrix(identity_rows(K, held, 2 * model.first), comm)
    ksp = PETSc.KSP().create(comm=comm)
    ksp.setOptionsPrefix(PREFIX)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    if comm.getSize() > 1:
        ksp.getPC().setFactorSolverType("mumps")
    ksp.setFromOptions()
    x, b = A.createVecs()
    rhs = f.copy()
    rhs[held] = 0.0
    b.setArray(rhs)
    ksp.solve(b, x)
    u = x.getArray(readonly=True).copy()
    Kmat = petsc_matrix(K, comm)
    ku = Kmat.createVecLeft()
    Kmat.mult(x, ku)
    reaction = np.zeros_like(u)
    free_absorbing = np.setdiff1d(bounds.absorbing_dofs(), bounds.held_dofs()[0])
    reaction[free_absorbing] = (ku.getArray(readonly=True) - f)[free_absorbing]
    whole = gather_to_rank0(model, comm)
    u_all = u if whole is None else whole(u)
    u_all = comm.tompi4py().bcast(u_all, root=0) if comm.getSize() > 1 else u_all
    return PlaneStatic(np.asarray(u_all).reshape(-1, 2), (reaction, History(value=1.0)))
