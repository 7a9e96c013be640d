"""The gauges' row of a slab on one rank in one compiled call
(gauge_row.c): numpy's dozen calls on a few numbers become one.  The
Python path (:meth:`vstpetsc.line.gauges.Gauges.fill` on
:class:`vstpetsc.line.solver.probe.NodeValues`) runs on several ranks, with
``-vst_native 0`` and for channels that read a hysteretic soil's stress."""

import ctypes

import numpy as np

from vstpetsc.native import bind, library

_P = ctypes.c_void_p


class _Row(ctypes.Structure):
    """The C struct GaugeRow of gauge_row.c, field for field."""

    _fields_ = [("channels", ctypes.c_long)] + [(name, _P) for name in (
        "left", "right", "w", "factor", "inv_h", "u", "z", "V1", "order", "values")]


class GaugeRow:
    """Fills the writer's gauge slot from the solver's arrays."""

    def __init__(self, lib, gauges, solver, order):
        lib.vst_gauge_row.argtypes = [_P, _P]
        lib.vst_gauge_row.restype = None
        self.lib = lib
        nodes = gauges.nodes
        self.a = {"left": np.ascontiguousarray(nodes[gauges.lpos], dtype=np.int64),
                  "right": np.ascontiguousarray(nodes[gauges.rpos], dtype=np.int64),
                  "w": np.ascontiguousarray(gauges.w, dtype=float),
                  "factor": np.ascontiguousarray(gauges.factor, dtype=float),
                  "inv_h": np.ascontiguousarray(gauges.inv_h, dtype=float),
                  "u": solver.u, "z": solver.x, "V1": np.ascontiguousarray(solver.V[1]),
                  "order": np.ascontiguousarray(order, dtype=np.int64),
                  "values": np.zeros(4 * len(gauges))}
        self.row = bind(_Row(channels=len(gauges)), self.a)
        self.ref = ctypes.addressof(self.row)

    @classmethod
    def of(cls, gauges, solver, order):
        """The compiled row, or None where the Python path must run."""
        lib = library()
        if lib is None or not (solver.serial and solver.native) or gauges.soil_channels.size:
            return None
        return cls(lib, gauges, solver, order)

    def __call__(self, slot):
        """Fill ``slot`` (a C-ordered float64 row of the writer's buffer)."""
        self.lib.vst_gauge_row(self.ref, slot.ctypes.data)
