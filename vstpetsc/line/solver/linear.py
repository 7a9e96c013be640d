"""The linear slab solve: a KSP (prefix ``vst_``) on the slab matrix A,
factored once per run."""

import math

import numpy as np
from petsc4py import PETSc

from vstpetsc.errors import InputError, SolveFailed
from vstpetsc.petsc.options import PREFIX, default
from vstpetsc.line.solver.overlap import OverlapLU


def reason_name(cls, code):
    """The name of a PETSc converged/diverged reason code."""
    for name in dir(cls):
        if not name.startswith("_") and getattr(cls, name) == code:
            return name
    return str(code)


class LinearSolver:
    """Solves A x = b with the factors of A (or any KSP the options choose).

    Defaults, which the options database overrides: ``preonly`` with PETSc's
    LU in natural ordering on one rank (the block band is already optimal);
    on several ranks one application of restricted additive Schwarz, each
    rank's LU of its part of the band grown by ``overlap`` nodes on either
    side (:class:`OverlapLU`; ``-pc_asm_overlap`` sets another): a slab
    couples nodes so weakly across a few dozen elements that one
    application gives the solution to rounding (docs/parallel.md gives the
    measured errors and speed).  Any ``-ksp_type`` or ``-pc_type`` option
    puts a PETSc KSP in its place (``-pc_type asm`` with the same defaults).
    """

    def __init__(self, A, space, overlap=32):
        comm = space.comm
        self.count = 0             # linear solves (applications of the factors)
        self.schwarz = None
        opts = PETSc.Options()
        overlap = opts.getInt(PREFIX + "pc_asm_overlap", overlap)
        if overlap < 0:
            raise InputError(f"-pc_asm_overlap: must be 0 or more nodes, got {overlap}")
        if comm.getSize() > 1 and not any(opts.hasName(PREFIX + k)
                                          for k in ("ksp_type", "pc_type")):
            self.schwarz = OverlapLU(A, space, overlap)
            self.ksp = self.pc = None
            self.direct, self.serial_direct = True, False
            return
        self.ksp, self.pc = ksp, _ = self._petsc_ksp(A, comm, overlap)
        self.direct = ksp.getType() == "preonly"
        self.serial_direct = self.direct and comm.getSize() == 1
        ksp.viewFromOptions("-ksp_view")

    def vectors(self, space):
        """((b, its array), (x, its array)): the solver's right-hand side
        and solution, global vectors stored in numpy arrays of ours (for
        the restricted Schwarz solve: views of its grown arrays, so that
        their solve copies nothing)."""
        if self.schwarz is not None:
            return self.schwarz.owned_vectors(space.comm)
        return space.array_vector(), space.array_vector()

    @staticmethod
    def _petsc_ksp(A, comm, overlap):
        """(ksp, pc): PETSc's KSP with vstpetsc's defaults, set up."""
        ksp = PETSc.KSP().create(comm=comm)
        ksp.setOptionsPrefix(PREFIX)
        ksp.setOperators(A, A)
        ksp.setType("preonly")
        ksp.setTolerances(rtol=1e-12, atol=1e-50, max_it=1000)
        pc = ksp.getPC()
        if comm.getSize() > 1:
            pc.setType("asm")
            for key, val in (("pc_asm_overlap", str(overlap)), ("sub_pc_type", "lu"),
                             ("sub_pc_factor_mat_solver_type", "petsc"),
                             ("sub_pc_factor_mat_ordering_type", "natural"),
                             # the redundant LU, still one option away
                             ("redundant_pc_type", "lu"),
                             ("redundant_pc_factor_mat_solver_type", "petsc"),
                             ("redundant_pc_factor_mat_ordering_type", "natural")):
                default(PREFIX + key, val)
        else:
            pc.setType("lu")
            pc.setFactorSolverType("petsc")
            pc.setFactorOrdering("natural")
        ksp.setFromOptions()       # the options database wins over the defaults above
        ksp.setUp()                # factors A, once per run
        return ksp, pc

    def solve(self, b, x, slab_index=None):
        if self.schwarz is not None:
            self.schwarz.apply(b, x)
            self.count += 1
            return
        if self.direct:
            # KSPSolve of KSPPREONLY would first zero x (measured: 7 % of
            # a solve at 1e6 elements) and then apply the PC: do the latter.
            self.pc.apply(b, x)
            self.count += 1
            return
        self.ksp.solve(b, x)
        reason = self.ksp.getConvergedReason()
        if reason < 0:
            where = f"slab {slab_index}: " if slab_index is not None else \
                "solving for the laws' dofs (Z = A^-1 E): "
            raise SolveFailed(f"{where}linear solve did not converge "
                              f"({reason_name(PETSc.KSP.ConvergedReason, reason)})")
        self.count += max(1, self.ksp.getIterationNumber())

    def finite(self, x, array):
        """Whether x (stored in ``array``) is finite.  On one rank its first
        entry says it: an LU solve carries a NaN or Inf anywhere in b or the
        factors into every entry of the backward sweep (0 * NaN is NaN), so
        no pass over x (on several ranks each rank's part, by the same
        argument for its grown block, then a logical and)."""
        if self.schwarz is not None:
            return self.schwarz.finite(array)
        if not self.serial_direct:
            return np.isfinite(x.norm())
        return array.size == 0 or math.isfinite(array[0])

    def describe(self):
        """One line naming the linear solver actually in use."""
        if self.schwarz is not None:
            return self.schwarz.describe()
        what = self.pc.getType()
        if what in ("lu", "cholesky", "ilu", "icc"):
            what = f"{what} ({self.pc.getFactorSolverType()})"
        elif what == "redundant":
            inner = PETSc.Options().getString(PREFIX + "redundant_pc_type", "lu")
            what = f"redundant ({inner} of the whole matrix on every rank)"
        elif what == "asm":
            overlap = PETSc.Options().getInt(PREFIX + "pc_asm_overlap", 1)
            inner = PETSc.Options().getString(PREFIX + "sub_pc_type", "ilu")
            what = f"asm (overlap {overlap} nodes, {inner} of each rank's part)"
        return f"KSP {self.ksp.getType()}, PC {what}"
