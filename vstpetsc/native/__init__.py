"""Compiled kernels: one library of C sources for both geometries, its
loader (:func:`library`) and :func:`bind`, which points a ctypes struct at
numpy arrays.  The Python side of each kernel lives with what it serves:
the penalty pairs' Newton (penalty_newton.c) in
:mod:`vstpetsc.line.native.penalty`, the end of a slab (slab_close.c, on each rank's nodes)
is in :mod:`vstpetsc.line.native.closing`, the copies of a kept row
(row_copier.c) in :mod:`vstpetsc.native.rows`.

`make install` builds ``libvstnative.so`` next to this file with the
system's C compiler; without it (a plain ``pip install``) :func:`library`
returns None and the Python path runs.  ``-vst_native 0`` turns it off.
The environment variable ``VSTPETSC_NATIVE_LIB`` names another build of
the library to load (``make test-portable`` builds it for other CPUs).
"""

import ctypes
import os


HERE = os.path.dirname(os.path.abspath(__file__))
LIBRARY = os.environ.get("VSTPETSC_NATIVE_LIB") or os.path.join(HERE, "libvstnative.so")
_loaded = []

_P = ctypes.c_void_p


def library():
    """The compiled kernels (None when not built)."""
    if not _loaded:
        lib = None
        if os.path.exists(LIBRARY) or "VSTPETSC_NATIVE_LIB" in os.environ:
            lib = ctypes.CDLL(LIBRARY)      # a library asked for by name must load
            lib.vst_penalty_newton.argtypes = [_P, ctypes.c_int]
            lib.vst_penalty_newton.restype = ctypes.c_int
            lib.vst_penalty_slab.argtypes = [_P, _P]
            lib.vst_penalty_slab.restype = ctypes.c_int
            lib.vst_penalty_advance.argtypes = [_P, _P, ctypes.c_int]
            lib.vst_penalty_advance.restype = None
            for name, args in (("vst_close", [_P]),
                               ("vst_rows_copy", [_P, ctypes.c_int, ctypes.c_long]),
                               ("vst_column_sweep", [ctypes.c_long, ctypes.c_int] + [_P] * 5),
                               ("vst_column_sweep_many",
                                [ctypes.c_long, ctypes.c_int] + [_P] * 5 + [ctypes.c_long]),
                               ("vst_block_columns",
                                [ctypes.c_long, ctypes.c_long, ctypes.c_int] + [_P] * 8),
                               ("vst_rows_axpy",
                                [ctypes.c_long, _P, _P, _P, ctypes.c_long, _P])):
                getattr(lib, name).argtypes = args
                getattr(lib, name).restype = None
        _loaded.append(lib)
    return _loaded[0]


def bind(struct, arrays):
    """Point every pointer field of the ctypes ``struct`` that ``arrays``
    ({field: numpy array}) names at that array's data; returns ``struct``.
    The caller keeps the arrays alive."""
    for name, kind in struct._fields_:
        if kind is _P and name in arrays:
            setattr(struct, name, arrays[name].ctypes.data)
    return struct


# METIS 5.1's NodeND (Debian's libmetis5, whose idx_t is 32 bits wide: its
# metis.h, IDXTYPEWIDTH 32) with its default options (METIS_NOPTIONS of them)
METIS = "libmetis.so.5"
METIS_NOPTIONS = 40
METIS_OK = 1
_metis = []


def metis_library():
    """Debian's libmetis5 (None when it is not installed)."""
    if not _metis:
        try:
            _metis.append(ctypes.CDLL(METIS))
        except OSError:
            _metis.append(None)
    return _metis[0]


def metis_defaults(lib):
    """METIS's default options (int32, METIS_NOPTIONS of them) from ``lib``."""
    import numpy as np

    options = np.zeros(METIS_NOPTIONS, dtype=np.int32)
    lib.METIS_SetDefaultOptions(options.ctypes.data_as(_P))
    return options


def metis_order(graph):
    """METIS's nested dissection order (new position i takes node
    order[i]) of the symmetric graph ``graph`` (CSR without its diagonal,
    indices sorted), or None without the library.  METIS seeds its own
    generator: the same graph, the same order, on any machine."""
    import numpy as np

    lib = metis_library()
    if lib is None:
        return None
    n = graph.shape[0]
    xadj, adjncy = graph.indptr.astype(np.int32), graph.indices.astype(np.int32)
    options = metis_defaults(lib)
    perm, iperm = np.empty(n, dtype=np.int32), np.empty(n, dtype=np.int32)
    status = lib.METIS_NodeND(ctypes.byref(ctypes.c_int32(n)), xadj.ctypes.data_as(_P),
                              adjncy.ctypes.data_as(_P), None, options.ctypes.data_as(_P),
                              perm.ctypes.data_as(_P), iperm.ctypes.data_as(_P))
    if status != METIS_OK:
        raise RuntimeError(f"METIS_NodeND failed ({status})")
    return perm.astype(np.int64)
