"""The laws' terms back into the slab's unknowns, x -= sum_j f_j Zred_j,
only where the columns Zred_j = A^-1 (the law's rows) are not zero.

A slab couples nodes weakly over a few dozen elements (docs/parallel.md),
so a column of A^-1 decays away from its law's nodes and is exactly zero
beyond a few hundred elements (below the smallest double).  PETSc's
VecMAXPY over the whole vector would add those zeros at every contact
slab: at 10 000 elements 35 us for two pairs against 2 us here.

The laws are grouped by the span of their columns (laws whose spans
overlap share a group, in law order), the groups and spans decided on the
whole vector and so the same on any number of ranks; each group is one
VecMAXPY on its span, where the other groups' columns are zero, so the
sum at every entry is the same whatever the number of ranks.
"""

import numpy as np
from petsc4py import PETSc


def nonzero_span(columns, offset):
    """[lo, hi) in global numbers of the entries where any of ``columns``
    (local arrays, the first at global entry ``offset``) is not zero;
    (huge, -1) when none is."""
    nz = np.flatnonzero(np.any([c != 0.0 for c in columns], axis=0)) if columns[0].size \
        else np.zeros(0, dtype=int)
    if nz.size == 0:
        return np.iinfo(np.int64).max, -1
    return offset + int(nz[0]), offset + int(nz[-1]) + 1


def groups_of(spans):
    """Lists of law numbers whose spans overlap (chains of overlaps merge),
    each in law order, the lists ordered by their first law."""
    order = sorted((lo, hi, j) for j, (lo, hi) in enumerate(spans) if hi > lo)
    merged = []               # [lo, hi, [laws]]
    for lo, hi, j in order:
        if merged and lo < merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], hi)
            merged[-1][2].append(j)
        else:
            merged.append([lo, hi, [j]])
    return sorted(((lo, hi, sorted(laws)) for lo, hi, laws in merged), key=lambda g: g[2][0])


class LawInfluence:
    """x -= sum_j f_j Zred_j on the columns' spans (``x`` the solver's
    array behind its unknowns, ``Zred`` two columns a law)."""

    def __init__(self, Zred, x, space):
        n0, n1 = space.nodes
        first = 2 * n0
        arrays = [z.getArray() for z in Zred]
        spans = [nonzero_span(arrays[c:c + 2], first) for c in range(0, len(Zred), 2)]
        starts, ends = (np.array(s, dtype=np.int64) for s in zip(*spans))
        if space.comm.getSize() > 1:          # the spans over the whole vector
            from mpi4py import MPI
            mpi = space.comm.tompi4py()
            mpi.Allreduce(MPI.IN_PLACE, starts, op=MPI.MIN)
            mpi.Allreduce(MPI.IN_PLACE, ends, op=MPI.MAX)
        self.groups, self.spans = [], []      # spans: each group's [a, b) in x
        for lo, hi, members in groups_of(list(zip(starts.tolist(), ends.tolist()))):
            a, b = max(lo, first) - first, min(hi, 2 * n1) - first
            if b <= a:
                continue
            cols = np.array([c for j in members for c in (2 * j, 2 * j + 1)])
            views = [PETSc.Vec().createWithArray(arrays[c][a:b], comm=PETSc.COMM_SELF)
                     for c in cols]
            target = PETSc.Vec().createWithArray(x[a:b], comm=PETSc.COMM_SELF)
            self.groups.append((target, views, cols))
            self.spans.append((a, b))
        self.columns, self._keep = arrays, x        # the arrays the views point into

    def subtract(self, f):
        """x -= sum_j f_j Zred_j (f: the laws' terms, two a law)."""
        for target, views, cols in self.groups:
            target.maxpy(-f[cols], views)
