"""How a sweep's ranks share its runs and wait for each other (sweep.py).

Runs are dealt as the ranks ask for them, not in a fixed order: a rank
whose runs are cheap (a smaller mesh, a run already done, a core it has
to itself) takes more of them, so no rank sits idle while another still
has a queue of runs.  A rank that has finished waits for the others with
a sleeping test, not in an MPI wait: Open MPI's waits poll without
sleeping, and a rank spinning in one takes a core from the ranks still
running (measured: a rank with one run of a sweep's three used as much
CPU time as the rank with two).
"""

import time

import numpy as np

PAUSE = 0.002      # seconds between two tests of a wait: ~0.5 % of a core, 2 ms late at most


class RunQueue:
    """The indices 0 .. n-1 of a sweep's runs, each given to exactly one
    group of ranks.  Group g (ranks g K .. g K + K - 1) takes run g first,
    then whichever run is next when it asks: a counter held by rank 0 of
    ``comm`` that a group's first rank increments atomically (MPI one-sided
    fetch-and-add, which needs nothing of rank 0 while it runs a case).
    The group's ranks learn the index from their first rank.  Make and
    :meth:`free` it on every rank of ``comm`` (both are collective)."""

    def __init__(self, comm, group, count):
        self.count = count
        self.group = group
        self.first = comm.Get_rank() // group.Get_size()
        groups = comm.Get_size() // group.Get_size()
        self._window = _counter(comm, start=groups) if groups > 1 else None

    def __iter__(self):
        index = self.first
        while index < self.count:
            yield index
            index = self._next(index)

    def _next(self, index):
        """The next index no group has taken (the group's first rank takes
        it); with one group, the one after ``index``."""
        from mpi4py import MPI

        if self._window is None:
            return index + 1
        taken = None
        if self.group.Get_rank() == 0:
            one, before = np.ones(1, np.int64), np.zeros(1, np.int64)
            self._window.Lock(0, MPI.LOCK_SHARED)
            self._window.Fetch_and_op(one, before, 0, 0, MPI.SUM)
            self._window.Unlock(0)
            taken = int(before[0])
        return self.group.bcast(taken, root=0) if self.group.Get_size() > 1 else taken

    def free(self):
        if self._window is not None:
            self._window.Free()
            self._window = None


def _counter(comm, start):
    """A window of one int64 on rank 0 of ``comm`` set to ``start``, ready
    for every rank once this returns."""
    from mpi4py import MPI

    window = MPI.Win.Allocate(8 if comm.Get_rank() == 0 else 0, 8, comm=comm)
    if comm.Get_rank() == 0:
        window.Lock(0, MPI.LOCK_EXCLUSIVE)
        window.Put(np.array([start], np.int64), 0)
        window.Unlock(0)
    comm.Barrier()
    return window


def wait_for_all(comm, pause=PAUSE):
    """Return once every rank of ``comm`` has called this, sleeping
    between tests (a rank done with its runs then costs no core)."""
    if comm.Get_size() == 1:
        return
    request = comm.Ibarrier()
    while not request.Test():
        time.sleep(pause)
