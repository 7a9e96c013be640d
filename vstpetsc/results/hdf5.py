"""h5py's low level for what a run makes many of (issue 29): a new
file's growing datasets and attributes.  h5py's high level costs ~0.1 ms a
dataset and ~0.13 ms an attribute in Python around HDF5 (it checks,
converts and names each through several calls); a tiny run makes dozens of
each, so the run's fixed cost was mostly these.  The objects are the same
as the high level makes (types, chunks, property lists)."""

from typing import NamedTuple

import h5py
import numpy as np

STRING = h5py.string_dtype()      # what h5py stores a str attribute as
# HDF5's newest file format: what its single-writer/multiple-reader mode
# (SWMR) needs; HDF5 older than 1.10 cannot read such files
LIBVER = "latest"


def open_to_read(path):
    """Result file ``path`` open for reading, in HDF5's SWMR read mode where
    it can be: a file a run writes in SWMR mode is then read consistently
    (HDF5 orders the writer's metadata flushes so that a reader never
    meets an address not yet written), and a file whose SWMR writer was
    killed opens at all (it keeps HDF5's "open for writing" mark, which a
    plain open refuses).  A file that a run writes without SWMR (a restart
    of a file of the older format) opens plainly: ``f.swmr_mode`` tells."""
    try:
        return h5py.File(path, "r", locking=False, swmr=True)
    except OSError as exc:
        if "not already open for SWMR writing" not in str(exc):
            raise
    return h5py.File(path, "r", locking=False)


def swmr_format(path):
    """Whether file ``path`` is of the format HDF5's SWMR mode needs (its
    superblock of version 3, at the start of the file: vstpetsc writes no
    user block).  A file of an older format read in SWMR mode is read
    without SWMR's guarantees."""
    with open(path, "rb") as f:
        head = f.read(9)
    return head[:8] == b"\x89HDF\r\n\x1a\n" and head[8] >= 3


def swmr_writing(path):
    """Whether a writer has file ``path`` open in SWMR mode now: the flag
    0x04 of the file consistency flags (byte 11 of a superblock of version
    3) that HDF5 sets when SWMR writing starts and clears when the file is
    closed (a plain open for writing sets 0x01 alone)."""
    try:
        with open(path, "rb") as f:
            head = f.read(12)
    except OSError:
        return False
    return len(head) == 12 and head[:8] == b"\x89HDF\r\n\x1a\n" and head[8] >= 3 \
        and bool(head[11] & 0x04)


def open_to_write(path, mode):
    """Result file ``path`` open to write (``mode`` "w" or "a") in the newest
    format; a file whose SWMR writer was killed is first cleared of HDF5's
    "open for writing" mark (:func:`clear_writer_mark`)."""
    try:
        return h5py.File(path, mode, locking=False, libver=LIBVER)
    except OSError as exc:
        if mode == "w" or "h5clear" not in str(exc):
            raise
    clear_writer_mark(path)
    return h5py.File(path, mode, locking=False, libver=LIBVER)


def clear_writer_mark(path):
    """Clear the mark HDF5 leaves in the superblock of a file whose SWMR
    writer did not close it, with HDF5's own tool (h5clear -s, Debian's
    hdf5-tools); OSError naming what is missing if it cannot."""
    import os
    import shutil
    import subprocess
    tool = shutil.which("h5clear")
    if tool is None:
        raise OSError(f"{path} was left open for writing by a killed run; HDF5's h5clear "
                      "(Debian package hdf5-tools) clears that mark, and is not installed")
    # HDF5's own file lock off: the restart holds vstpetsc's lock on the file
    env = dict(os.environ, HDF5_USE_FILE_LOCKING="FALSE")
    p = subprocess.run([tool, "-s", path], capture_output=True, text=True, env=env)
    if p.returncode != 0:
        raise OSError(f"h5clear -s {path}: {(p.stderr or p.stdout).strip()}")


def start_swmr(f):
    """Put file ``f`` (open to write) in SWMR mode: from here on readers in
    other processes see a consistent prefix of it.  False when its format
    has no SWMR (a file written before vstpetsc used the newest format)."""
    try:
        f.swmr_mode = True
    except (ValueError, RuntimeError, OSError):
        return False
    return True


def set_attrs(obj, values):
    """``obj.attrs.update(values)`` (``obj`` a File or Group): a new str,
    int or float attribute through the low level, anything else (an
    existing name, an array of strings, ...) through h5py's high level."""
    for key, value in values.items():
        data = _plain(value)
        name = key.encode()
        if data is None or h5py.h5a.exists(obj.id, name):
            obj.attrs[key] = value
            continue
        attr = h5py.h5a.create(obj.id, name, h5py.h5t.py_create(data.dtype, logical=True),
                               h5py.h5s.create_simple(data.shape))
        try:
            attr.write(data, mtype=h5py.h5t.py_create(data.dtype))
        finally:
            attr.close()


def _plain(value):
    """``value`` as the array h5py would store for it, when it is a str or
    numbers (None otherwise: left to the high level)."""
    if isinstance(value, str):
        return np.array(value, dtype=STRING)
    if isinstance(value, (bool, np.bool_)):
        return None
    data = np.asarray(value)
    return data if data.dtype.kind in "iuf" else None


class Grown(NamedTuple):
    """A growing dataset as the writer needs it: its low-level id, rows,
    row shape, chunk shape and dtype (read from HDF5, each costs ~10-25
    us; a new file's are known)."""

    id: object
    rows: int
    tail: tuple
    chunks: tuple
    dtype: np.dtype

    @classmethod
    def of(cls, ds):
        """The Grown of an open h5py Dataset."""
        return cls(ds.id, ds.shape[0], ds.shape[1:], ds.chunks, ds.dtype)


class Growing:
    """The growing datasets of a new file (and the writer's snapshots),
    made through h5py's low level with one creation property list per
    chunk shape: what h5py's ``create_dataset`` makes (chunked or
    contiguous, no time stamps, intermediate groups created), at a third of
    its cost (~0.1 ms a dataset there, and a run makes dozens); {name:
    :class:`Grown`} of the growing ones in ``ids``, in the order made."""

    def __init__(self, f):
        self.f, self.ids, self.plists = f, {}, {}
        self.lcpl = h5py.h5p.create(h5py.h5p.LINK_CREATE)
        self.lcpl.set_create_intermediate_group(True)
        self.lcpl.set_char_encoding(h5py.h5t.CSET_UTF8)
        self.types = {}

    def add(self, name, tail, rows, dtype):
        """An empty dataset ``name`` of rows ``tail`` growing along its first
        axis, chunks of ``rows`` rows."""
        tail, chunks = tuple(tail), (rows,) + tuple(tail)
        space = h5py.h5s.create_simple((0,) + tail, (h5py.h5s.UNLIMITED,) + tail)
        self.ids[name] = Grown(self._make(name, space, dtype, chunks), 0, tail, chunks,
                               np.dtype(dtype))

    def fixed(self, name, shape, dtype):
        """The id of a new dataset ``name`` of fixed ``shape`` (contiguous)."""
        return self._make(name, h5py.h5s.create_simple(tuple(shape)), dtype, None)

    def _make(self, name, space, dtype, chunks):
        dcpl = self.plists.get(chunks)
        if dcpl is None:
            dcpl = self.plists[chunks] = h5py.h5p.create(h5py.h5p.DATASET_CREATE)
            if chunks is not None:
                dcpl.set_chunk(chunks)
            dcpl.set_obj_track_times(False)
        tid = self.types.get(dtype)
        if tid is None:
            tid = self.types[dtype] = h5py.h5t.py_create(np.dtype(dtype), logical=True)
        return h5py.h5d.create(self.f.id, name.encode(), tid, space, dcpl=dcpl, lcpl=self.lcpl)


def count_attr(oid, name, value):
    """The int64 attribute ``name`` of object ``oid`` (a count of rows on
    disk, a slab number) as a :class:`CountAttr`, created with ``value``
    if absent."""
    key = name.encode()
    if not h5py.h5a.exists(oid, key):
        attr = h5py.h5a.create(oid, key, h5py.h5t.py_create(np.dtype(np.int64)),
                               h5py.h5s.create(h5py.h5s.SCALAR))
        attr.write(np.array(value, dtype=np.int64))
        attr.close()
    return CountAttr(oid, key)


class CountAttr(NamedTuple):
    """An int64 attribute written in place, opened for each write (~10 us):
    HDF5 starts SWMR writing only while no attribute of the file is open."""

    oid: object
    key: bytes

    def write(self, value):
        attr = h5py.h5a.open(self.oid, self.key)
        try:
            attr.write(np.asarray(value, dtype=np.int64))
        finally:
            attr.close()
