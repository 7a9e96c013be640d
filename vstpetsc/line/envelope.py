"""Stress envelopes: the smallest and largest stress E du/dx of every
element over every slab end (t = 0 included).  Each rank keeps the elements
whose left node it owns; the right node of its last one may be the next
rank's (a ghost value the solver keeps).

E / h > 0 does not change in time, so the envelopes of the elongation
u_{i+1} - u_i times E / h are those of the stress, bit for bit (rounding is
monotonic): three vector passes a slab, with buffers allocated once, and
the factor applied when the envelopes are read.  Pure numpy."""

import numpy as np


class StressEnvelope:
    """Envelopes of the elements starting at nodes n0..n1-1 of ``mesh``.

    Works on node pairs (i, i+1) of the local range; pairs that join two
    bodies are no element and carry a zero factor.
    """

    def __init__(self, mesh, nodes):
        n0, n1 = nodes
        self.n0, self.n1 = n0, n1
        self.ghost = n1 < mesh.nnodes
        npairs = n1 - n0 - (0 if self.ghost else 1)
        el = np.nonzero((mesh.elem_node >= n0) & (mesh.elem_node < n1))[0]
        self.elements = el                               # global element numbers
        self.pair = mesh.elem_node[el] - n0              # their local pair index
        self.factor = np.zeros(max(npairs, 0))
        self.factor[self.pair] = (mesh.E / mesh.h)[el]
        self.buf = np.empty(max(npairs, 0))
        self.ext = np.empty(n1 - n0 + 1) if self.ghost else None
        # filled in place, so that compiled code may hold them
        self.lo, self.hi = np.empty_like(self.buf), np.empty_like(self.buf)
        self._u = None

    def elongation(self, u, ghost=0.0):
        """u_{i+1} - u_i of the local node pairs for the owned u."""
        if self.ghost:
            self.ext[:-1] = u
            self.ext[-1] = ghost
            u = self.ext
        if u is not self._u:             # the solver passes the same array every slab
            self._u, self._right, self._left = u, u[1:], u[:-1]
        np.subtract(self._right, self._left, out=self.buf)
        return self.buf

    def start(self, u, ghost=0.0, restored=None):
        """Begin with u (or continue ``restored`` elongation envelopes
        (lo, hi) of the local elements, from a result file)."""
        d = self.elongation(u, ghost)
        self.lo[:] = d
        self.hi[:] = d
        if restored is not None:
            self.lo[self.pair], self.hi[self.pair] = restored

    def update(self, u, ghost=0.0):
        d = self.elongation(u, ghost)
        np.minimum(self.lo, d, out=self.lo)
        np.maximum(self.hi, d, out=self.hi)

    def local(self):
        """(global element numbers, elongation lo, hi) of the local elements;
        times E / h they are the stress envelopes."""
        return self.elements, self.lo[self.pair], self.hi[self.pair]
