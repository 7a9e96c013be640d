"""PETSc's matrices of the plane-strain room's CSR matrices."""

from petsc4py import PETSc


def petsc_matrix(A, comm=None):
    """PETSc's AIJ of a CSR matrix: the whole matrix on one rank, or on
    ``comm`` the rows a rank owns (global columns; local rows = columns)."""
    A = A.tocsr()
    A.sort_indices()
    n, N = A.shape
    return PETSc.Mat().createAIJ(((n, N), (n, N)), comm=comm or PETSc.COMM_SELF, csr=(
        A.indptr.astype(PETSc.IntType), A.indices.astype(PETSc.IntType), A.data))
