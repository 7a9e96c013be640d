"""Freed memory handed back to the system between a run's set-up steps:
glibc keeps a freed array's pages for its own reuse, and the slab
matrix's factors, allocated whole, cannot take them; malloc_trim(0)
returns them (measured at 2e5 cells: 0.25 GB of the CSR copies' pages
once they are freed; bench/plane_memory.py).  A no-op where the C
library has no malloc_trim."""

import ctypes
import ctypes.util

_LIBC = None


def _libc():
    global _LIBC
    if _LIBC is None:
        try:
            _LIBC = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
            _LIBC.malloc_trim
        except (OSError, AttributeError):
            _LIBC = False
    return _LIBC


def give_back():
    """Return the freed heap's pages to the system (glibc), or nothing."""
    libc = _libc()
    if libc:
        libc.malloc_trim(0)
