"""A kept row's copies in one compiled call (row_copier.c): at 10 000
nodes the u, v and stress of a row are 240 kB, which numpy copies in
three calls through the cache; the C copy streams them past it."""

import ctypes

from vstpetsc.native import library

_P = ctypes.c_void_p


class _Job(ctypes.Structure):
    """The C struct Job of row_copier.c, field for field."""

    _fields_ = [("src", _P), ("factor", _P), ("dst", _P), ("n", ctypes.c_long),
                ("stride", ctypes.c_long)]


class RowCopier:
    """Copies ``sources`` ([(values, factor or None)], contiguous float64
    arrays) into row i of the bound buffers: ``dst[i] = values``, times
    ``factor`` where given (the same IEEE products as numpy's)."""

    def __init__(self, lib, sources):
        self.jobs = (_Job * len(sources))(*[
            _Job(src.ctypes.data, None if f is None else f.ctypes.data, None, src.size, 0)
            for src, f in sources])
        self.lib, self.sizes = lib, [src.size for src, _ in sources]
        self._keep = sources            # the jobs point into them
        self.targets, self.rows = None, 0

    @classmethod
    def of(cls, sources):
        """A copier of ``sources``, or None without the compiled library."""
        lib = library()
        return None if lib is None else cls(lib, sources)

    def bind(self, targets):
        """Write into ``targets`` (2-D, one a source, rows of the source's
        size, C order) from the next row on."""
        for job, t, n in zip(self.jobs, targets, self.sizes):
            if t.ndim != 2 or t.shape[1] != n or t.dtype.char != "d" or \
                    not t.flags.c_contiguous:
                raise ValueError(f"row copier: a target is not a C-ordered float64 "
                                 f"(rows, {n}) array")
            job.dst, job.stride = t.ctypes.data, n
        self.targets = targets          # alive while bound
        self.rows = min((t.shape[0] for t in targets), default=0)

    def post(self, i):
        """Copy the sources into row ``i`` of the targets."""
        if not 0 <= i < self.rows:
            raise IndexError(f"row copier: row {i} of {self.rows}")
        self.lib.vst_rows_copy(self.jobs, len(self.sizes), i)
