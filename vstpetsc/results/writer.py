"""Writes a result file (names: :mod:`vstpetsc.results.layout`).  Rank 0
only; every kept slab is appended and flushed as it is computed."""

import h5py
import numpy as np

from vstpetsc import __version__
from vstpetsc.results import layout


class ResultWriter:
    """Appends kept slabs to an HDF5 file.

    Parameters
    ----------
    path : str
    series : list of (dataset name, row shape), from layout.series
    statics : dict of datasets written once (node coordinates)
    groups : dict of group attributes
    attrs : dict of root attributes (status is set here)
    """

    def __init__(self, path, series, statics, groups, attrs):
        self.f = h5py.File(path, "w")
        self.n = 0
        f = self.f
        f.attrs["status"] = "running"
        f.attrs["version"] = __version__
        for k, v in attrs.items():
            f.attrs[k] = v
        for name, data in statics.items():
            f.create_dataset(name, data=data)
        for group, group_attrs in groups.items():
            g = f.require_group(group)
            for k, v in group_attrs.items():
                g.attrs[k] = v
        self.series = {}
        for name, tail in series:
            self._create(name, tail)
        f.require_group(layout.CONTACT)
        f.flush()

    def _create(self, name, tail):
        width = int(np.prod(tail)) if tail else 1
        rows = max(1, min(4096, 65536 // width))
        dtype = "i8" if name in layout.INTEGER_SERIES else "f8"
        ds = self.f.create_dataset(
            name, shape=(0,) + tail, maxshape=(None,) + tail, chunks=(rows,) + tail,
            dtype=dtype)
        self._track(name, ds)

    def _track(self, name, ds):
        # h5py's high-level resize and item assignment cost ~200 us per call;
        # the low-level calls below, with a cached memory space, a tenth.
        tail = ds.shape[1:]
        self.series[name] = (ds.id, tail, ds.dtype, h5py.h5s.create_simple((1,) + tail))

    @classmethod
    def reopen(cls, path, attrs):
        """Append to an existing result file (a restart)."""
        self = cls.__new__(cls)
        self.f = h5py.File(path, "a")
        self.series = {}
        self.f.visititems(lambda name, obj: self._track(name, obj)
                          if isinstance(obj, h5py.Dataset) and obj.maxshape[0] is None
                          else None)
        self.n = self.f[layout.TIME].shape[0]
        for k, v in attrs.items():
            self.f.attrs[k] = v
        self.f.attrs["status"] = "running"
        self.f.attrs["restarts"] = int(self.f.attrs.get("restarts", 0)) + 1
        self.f.flush()
        return self

    def append(self, row):
        """Append one kept time; ``row`` maps every series name to its value."""
        n = self.n + 1
        for name, (dsid, tail, dtype, mspace) in self.series.items():
            dsid.set_extent((n,) + tail)
            fspace = dsid.get_space()
            fspace.select_hyperslab((n - 1,) + (0,) * len(tail), (1,) + tail)
            data = np.ascontiguousarray(row[name], dtype=dtype).reshape((1,) + tail)
            dsid.write(mspace, fspace, data)
        self.n = n
        self.f.flush()

    def save_rhs_state(self, b, slab):
        """Keep the running right-hand side after ``slab`` (for a bit-for-bit
        restart); replaces the one kept before."""
        if layout.RHS_STATE in self.f:
            del self.f[layout.RHS_STATE]
        ds = self.f.create_dataset(layout.RHS_STATE, data=b)
        ds.attrs["slab"] = slab

    def close(self, status, **attrs):
        self.f.attrs["status"] = status
        for k, v in attrs.items():
            self.f.attrs[k] = v
        self.f.flush()
        self.f.close()
