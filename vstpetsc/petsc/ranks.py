"""Sums, maxima and gathers over the ranks of a communicator: what the
shared time loop, recorder and energy book ask of either geometry's
solver (``solver.space``)."""

import numpy as np


class Ranks:
    """The collective helpers on ``comm`` (a PETSc communicator)."""

    def __init__(self, comm):
        self.comm = comm

    def max_over_ranks(self, value):
        """The largest of every rank's ``value`` (a number), on every rank."""
        if self.comm.getSize() == 1:
            return value
        from mpi4py import MPI
        return self.comm.tompi4py().allreduce(value, op=MPI.MAX)

    def sum_over_ranks(self, value):
        """The sum of every rank's ``value`` (a number), on every rank."""
        if self.comm.getSize() == 1:
            return value
        return self.comm.tompi4py().allreduce(value)

    def gather_on_rank0(self, value):
        """Every rank's ``value`` (a number) in rank order, on rank 0 (None
        elsewhere)."""
        if self.comm.getSize() == 1:
            return [value]
        return self.comm.tompi4py().gather(value, root=0)

    def assemble_on_rank0(self, size, index, *arrays):
        """Arrays of length ``size`` on rank 0 (None elsewhere), each rank
        contributing ``arrays`` at the global positions ``index``."""
        if self.comm.getSize() == 1:
            parts = [(index, arrays)]
        else:
            parts = self.comm.tompi4py().gather((index, arrays), root=0)
            if parts is None:
                return None
        out = [np.zeros(size) for _ in arrays]
        for idx, values in parts:
            for full, part in zip(out, values):
                full[idx] = part
        return out

    def from_rank0(self, obj):
        """Rank 0's ``obj`` on every rank."""
        if self.comm.getSize() == 1:
            return obj
        return self.comm.tompi4py().bcast(obj, root=0)
