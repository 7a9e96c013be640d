"""The result file (HDF5, layout of docs/result-file.md).  Written by rank 0
only; every kept slab is appended and flushed as it is computed."""

import h5py
import numpy as np

from vstpetsc import __version__


INTEGER_SERIES = ("solver/newton_iterations", "solver/linear_iterations", "solver/slab")
# Extensions: running totals over every slab (exact whatever `every` is).
CONTACT_TOTALS = ("impulse_total", "contact_time", "episodes", "force_peak",
                  "first_contact")


class ResultWriter:
    """Appends kept slabs to an HDF5 file.

    Parameters
    ----------
    path : str
    bodies : list of (name, x_nodes, n_elements)
    contacts : list of dict of attributes per pair
    attrs : dict of root attributes (status is set here)
    """

    def __init__(self, path, bodies, contacts, attrs):
        self.f = h5py.File(path, "w")
        self.n = 0
        f = self.f
        f.attrs["status"] = "running"
        f.attrs["version"] = __version__
        for k, v in attrs.items():
            f.attrs[k] = v
        self.series = {}
        self._series("time", ())
        for name, x, ne in bodies:
            g = f.create_group(f"body/{name}")
            g.create_dataset("x", data=x)
            for key, width in (("u", x.size), ("v", x.size), ("stress", ne)):
                self._series(f"body/{name}/{key}", (width,))
        for k, meta in enumerate(contacts):
            g = f.require_group(f"contact/{k}")
            for key, val in meta.items():
                g.attrs[key] = val
            for key in ("gap", "force", "impulse") + CONTACT_TOTALS:
                self._series(f"contact/{k}/{key}", ())
        for key in ("energy/kinetic", "energy/strain", "solver/newton_iterations",
                    "solver/linear_iterations", "solver/wall_time", "solver/slab"):
            self._series(key, ())
        f.require_group("contact")
        f.flush()

    def _series(self, name, tail):
        width = int(np.prod(tail)) if tail else 1
        rows = max(1, min(4096, 65536 // width))
        dtype = "i8" if name in INTEGER_SERIES else "f8"
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
        self.n = self.f["time"].shape[0]
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
        if "solver/rhs_state" in self.f:
            del self.f["solver/rhs_state"]
        ds = self.f.create_dataset("solver/rhs_state", data=b)
        ds.attrs["slab"] = slab

    def close(self, status, **attrs):
        self.f.attrs["status"] = status
        for k, v in attrs.items():
            self.f.attrs[k] = v
        self.f.flush()
        self.f.close()
