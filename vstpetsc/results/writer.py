"""Writes a result file (names: :mod:`vstpetsc.results.layout`), on rank 0.

Kept rows are buffered in memory and written in blocks: when the buffer is
full or ``interval`` seconds (wall time) after the previous block, and
always when the run ends, fails or is stopped.  With every block go the
snapshots (the running right-hand side, the state a restart needs, taken
at the block's last row) and an HDF5 flush, so a file whose writer was
killed holds every row up to its last block, and ``--restart`` continues
it bit for bit.

Disk space for a block is reserved before HDF5 writes it
(:class:`~vstpetsc.results.files.DiskReserve`); a full disk is then an
:class:`OutputFailed` while the file is intact (status "failed", every
earlier block kept).  An HDF5 error despite that (another process filled
the disk meanwhile) leaves the file unclosed: HDF5 1.10 crashes when such
a file is closed (see :func:`unclosable`).
"""

import math
import os
import re
import time

import h5py
import numpy as np

from vstpetsc.version import __version__
from vstpetsc.errors import InputError, SolveFailed
from vstpetsc.results import layout
from vstpetsc.results.blocks import BlockThread
from vstpetsc.results.files import DiskFull, DiskReserve, OutputLock
from vstpetsc.results.hdf5 import Grown, Growing, count_attr, open_to_write, set_attrs, start_swmr
from vstpetsc.results.layout import COMPLETE_GAUGE_ROWS, COMPLETE_ROWS

BUFFER_VALUES = 1 << 20          # doubles per series buffer (8 MB; two of them with a thread)
BUFFER_ROWS = 1 << 13            # rows a block holds at most (a block costs ~3 ms)
THREAD_ROWS = 16                 # fewer rows a block: no second set, no thread
EVENT_CHUNK = 256                # rows of an events dataset's chunk
CHUNK_FLOOR = 64                 # fewest rows of a series' chunk (chunk_rows)
MARGIN = 1 << 18                 # bytes reserved beyond a block's estimate
_UNCLOSABLE = []                 # files HDF5 failed to write: never closed


class OutputFailed(SolveFailed):
    """The result file could not be written (disk full, I/O error)."""


def unclosable():
    """Whether a result file of this process hit an HDF5 write error; such
    a file must not be closed, so the process should end with os._exit."""
    return bool(_UNCLOSABLE)


class GaugeStream:
    """The series written every slab (the gauges, :mod:`vstpetsc.line.gauges`):
    one buffer of rows, a column per dataset, written with the kept rows'
    blocks (or alone when it is full)."""

    def __init__(self, growing, names, rows=BUFFER_ROWS):
        self.names = names
        self.ids = [growing[name].id for name in names]
        self.n = growing[names[0]].rows
        # a series of rows of several values (a 2-D gauge's (x, y)) takes
        # as many columns, in order
        self.tails = [tuple(dsid.shape[1:]) for dsid in self.ids]
        ends = np.cumsum([math.prod(tail) for tail in self.tails])
        self.columns = [slice(int(b - w), int(b)) for b, w in
                        zip(ends, [math.prod(tail) for tail in self.tails])]
        self.width = int(ends[-1])
        rows = max(1, min(BUFFER_ROWS, rows))
        self.buffer = _touched((rows, self.width), np.float64)
        self.spare = _touched((rows, self.width), np.float64)   # in flight
        self.pending = 0

    @classmethod
    def of(cls, growing, rows=BUFFER_ROWS):
        """The stream of the gauge series among ``growing`` ({name: Grown}),
        a buffer of at most ``rows`` rows (None when there are none)."""
        names = [name for name in growing if layout.every_slab(name)]
        return cls(growing, names, rows) if names else None

    def slot(self):
        """The next row to fill (a view of the buffer)."""
        i = self.pending
        self.pending = i + 1
        return self.buffer[i]

    def full(self):
        return self.pending == self.buffer.shape[0]

    def need(self):
        """Bytes the next write may take, whole chunks included."""
        return (self.pending + 4096) * 8 * self.width

    def take(self):
        """(rows, count) of the filled buffer for :meth:`write`; the next
        rows go to the other buffer."""
        rows, k = self.buffer, self.pending
        self.buffer, self.spare, self.pending = self.spare, rows, 0
        return rows, k

    def write(self, block):
        """Append a block of :meth:`take` to the datasets."""
        rows, k = block
        for dsid, cols, tail in zip(self.ids if k else (), self.columns, self.tails):
            _append(dsid, self.n, rows[:k, cols].reshape((k,) + tail))
        self.n += k

    def truncate(self, rows):
        """Drop rows after the first ``rows`` (a restart from an earlier slab)."""
        for dsid, tail in zip(self.ids, self.tails):
            dsid.set_extent((min(rows, self.n),) + tail)
        self.n = min(rows, self.n)


class EventRows:
    """The pairs' contact events (``/contact/<k>/events``, (m, 2)): the
    rows the recorder hands over with the kept rows (the events of every
    slab up to that row), appended with the same block, so the file holds
    the events up to its last row whether the run ends, stops or is killed.
    Each dataset's attribute ``complete_rows`` counts the rows on disk (set
    after the block's flush, as :class:`Completed`) for readers of a running
    file."""

    def __init__(self, growing):
        self.ids = {name: ds.id for name, ds in growing.items() if layout.is_events(name)}
        self.n = {name: growing[name].rows for name in self.ids}
        self.pending = {}
        self.counts = {name: count_attr(dsid, COMPLETE_ROWS, self.n[name])
                       for name, dsid in self.ids.items()}

    def add(self, name, rows):
        self.pending.setdefault(name, []).append(rows)

    def need(self):
        """Bytes the next write may take, a new chunk each included."""
        return sum(16 * (sum(map(len, parts)) + EVENT_CHUNK) for parts in self.pending.values())

    def take(self):
        block, self.pending = self.pending, {}
        return block

    def write(self, block):
        for name, parts in block.items():
            rows = np.concatenate(parts)
            _append(self.ids[name], self.n[name], rows)
            self.n[name] += rows.shape[0]

    def truncate(self, counts):
        """Keep the first ``counts[name]`` events of each set (a restart
        from the last row, which counts the events up to its slab)."""
        for name, count in counts.items():
            self.n[name] = min(int(count), self.n[name])
            self.ids[name].set_extent((self.n[name], 2))

    def complete(self):
        """The counts of rows on disk (after an HDF5 flush)."""
        for name, attr in self.counts.items():
            attr.write(np.array(self.n[name], dtype=np.int64))


class Snapshots:
    """The datasets rewritten with every block (restart state, envelopes),
    each with its attribute ``slab``, through low-level handles kept from
    the first write (h5py's high level costs ~0.2 ms an array, a block
    writes several).  Every one of them is made before the file goes into
    SWMR mode (:meth:`reserve`): the blocks only write their data."""

    def __init__(self, f):
        self.f, self.handles = f, {}
        self.maker = Growing(f)

    def write(self, snapshots, slab):
        stamp = np.array(-1 if slab is None else slab, dtype=np.int64)
        for name, data in snapshots.items():
            data = np.ascontiguousarray(data, dtype=np.float64)
            handles = self.handles.get(name)
            if handles is None or handles[2] != data.shape:
                handles = self.handles[name] = self._dataset(name, data.shape)
            dsid, attr, _ = handles
            dsid.write(h5py.h5s.ALL, h5py.h5s.ALL, data)
            attr.write(stamp)

    def reserve(self, state, last=None):
        """Make the datasets of ``state`` ({name: array}: the restart state
        the blocks write) before SWMR starts.  A SWMR writer may write
        data, not make objects: a block that made /solver/rhs_state,
        newton_state and energy_sums turned /solver's links into a fractal
        heap, which a reader met half written ("wrong fractal heap header
        signature").  One absent or of another shape (a restart on another
        number of ranks) is written now with ``state``, stamped -1 (no
        state yet: a restart does not take it), or ``last`` when the one it
        replaces was the state of slab ``last``, which this run continues
        from."""
        for name, data in (state or {}).items():
            data = np.asarray(data)
            old = self.f.get(name)
            if old is not None and old.shape == data.shape:
                continue
            valid = old is not None and int(old.attrs.get("slab", -1)) == last
            self.write({name: data}, last if valid else None)

    def _dataset(self, name, shape):
        """(dataset id, id of its attribute ``slab``, shape) of snapshot
        ``name``, (re)created when absent or of another shape (through the
        low level: a tiny run makes several, ~0.4 ms each through h5py's
        high level)."""
        dsid = None
        if name in self.f:
            dsid = self.f[name].id
            if dsid.shape != shape:
                del self.f[name]
                dsid = None
        if dsid is None:
            dsid = self.maker.fixed(name, shape, "f8")
        return dsid, count_attr(dsid, "slab", 0), shape


class Completed:
    """The root attributes that tell readers how many rows (and gauge rows)
    every dataset holds in full (:data:`~vstpetsc.results.layout.COMPLETE_ROWS`).
    A dataset grows before its rows are written and HDF5 may put metadata
    on disk in any order, so these are written only after the block's HDF5
    flush, in place (h5py's ``attrs[...] =`` deletes and re-creates an
    attribute), and flushed again: a reader of a running file sees a count
    whose rows are all on disk."""

    def __init__(self, f):
        self.ids = [count_attr(f.id, name, 0) for name in (COMPLETE_ROWS, COMPLETE_GAUGE_ROWS)]

    def write(self, rows, gauge_rows, flush=None):
        """The gauge count first, and on disk (``flush``, an HDF5 flush,
        when there are gauge rows) before the kept-row count is written:
        HDF5 writes the file's metadata in the order of their addresses,
        not of the writes, and the two counts may lie in two blocks of the
        root's attribute heap.  A reader reads the kept-row count first,
        and with both counts only growing it then never meets a kept row
        whose gauge rows are not counted yet (a CI run read kept rows to
        slab 11680 and gauge rows to 11641)."""
        kept, gauges = self.ids
        gauges.write(np.array(gauge_rows, dtype=np.int64))
        if flush is not None and gauge_rows:
            flush()
        kept.write(np.array(rows, dtype=np.int64))


class ResultWriter:
    """Buffered appends to an HDF5 result file, under an :class:`OutputLock`.

    Use :meth:`create` (a new file) or :meth:`reopen` (a restart).
    """

    def __init__(self, f, lock, interval, fd, growing=None, expected=None):
        self.f, self.lock, self.interval = f, lock, interval
        self.reserve = DiskReserve(fd)
        self.series, self.buffers = {}, {}
        self.spare = {}                          # the buffers of the block in flight
        self.thread = BlockThread()
        self.snapshots = Snapshots(f)
        self.capacity = None
        self.n = self.f[layout.TIME].shape[0]   # rows in the file
        self.pending = 0                         # rows in the buffers
        self.flushed_slab = None
        self.last_flush = time.monotonic()
        self.broken = False
        # the file's growing datasets {name: Grown}: those a new file
        # was made with, or the walk of a reopened file (a walk costs ~3 ms)
        self.growing = _series_of(f) if growing is None else growing
        # buffers no longer than the run needs (``expected``: its kept rows
        # and gauge rows at most): a tiny run's blocks are written at once,
        # without the thread and the buffers' ~1 ms of memory (issue 29)
        self.expected = expected or (BUFFER_ROWS, BUFFER_ROWS)
        self.gauges = GaugeStream.of(self.growing, self.expected[1])
        self.events = EventRows(self.growing)
        self.completed = Completed(f)

    @classmethod
    def create(cls, path, series, statics, groups, attrs, first_row, interval=0.5,
               snapshots=None, events=(), expected=None, state=None):
        """A new file: written under a temporary name with ``first_row``
        (its gauge values included, and the ``snapshots`` of t = 0) and the
        empty ``events`` datasets, then renamed to ``path``; InputError if
        it cannot be.  ``expected``: (kept rows, gauge rows) the run writes
        at most (the first row included), if known.  ``state``: the restart
        state the blocks will write ({name: array}), whose datasets are made
        now (:meth:`Snapshots.reserve`)."""
        return _create(cls, path, series, statics, groups, attrs, first_row, interval,
                       snapshots, events, expected, state)

    @classmethod
    def reopen(cls, lock, attrs, interval=0.5, expected=None, state=None, events=None):
        """Append to an existing result file (a restart) whose
        :class:`OutputLock` the caller holds (and hands over); ``expected``
        and ``state`` as for :meth:`create`; ``events``: {events dataset:
        rows to keep} (:meth:`EventRows.truncate`), cut before the file
        goes into SWMR mode."""
        return _reopen(cls, lock, attrs, interval, expected, state, events)

    def append(self, row):
        """Buffer one kept row; ``row`` maps every series name to its value."""
        buffers, i = self.slot()
        for name, buf in buffers.items():
            buf[i] = row[name]

    def slot(self):
        """(buffers {series name: array}, i): the caller fills row i of every
        buffer (the next kept row)."""
        if not self.series:
            self.series, self.buffers, self.spare, self.capacity = \
                _track(self.growing, self.expected[0])
        i = self.pending
        self.pending = i + 1
        return self.buffers, i

    def due(self):
        """Whether a block is due: the buffer is full or the wall-time
        interval since the last block has passed (the caller then flushes,
        with the snapshots of this row)."""
        return self.pending > 0 and (self.pending == self.capacity or
                                     time.monotonic() - self.last_flush >= self.interval)

    def flush(self, snapshots=None, slab=None, gauges_only=False):
        """Write the buffered rows and ``snapshots`` ({name: array}, state
        at the last row, slab number ``slab``; arrays given away: the
        thread writes them while the run goes on), then flush HDF5: on a
        thread (:mod:`~vstpetsc.results.blocks`) when there are two sets
        of buffers, after the block before it, whose failure is raised
        here; with ``gauges_only`` the gauge rows alone, at once (a full
        gauge buffer between kept rows)."""
        self.settle()
        snapshots = snapshots or {}
        try:
            need = _block_bytes(self.series, self.n, self.pending) + MARGIN
            need += sum(np.asarray(a).nbytes for a in snapshots.values())
            need += self.gauges.need() if self.gauges else 0
            need += 0 if gauges_only else self.events.need()
            self.reserve.ensure(self.f.id.get_filesize(), need + need // 20)
        except DiskFull as exc:
            raise OutputFailed(self._failure(exc)) from None
        if gauges_only:
            self._write(self.gauges.write, self.gauges.take())
        elif self.spare is None:
            self._write(self._write_block, self._take(), snapshots, slab)
        else:
            block = self._take()
            self.thread.start(lambda: self._write(self._write_block, block, snapshots, slab))
        self.last_flush = time.monotonic()

    def settle(self):
        """Until the block in flight is in the file; its OutputFailed."""
        self.thread.wait()

    def _write(self, action, *args):
        """``action(*args)``, an HDF5 flush, the counts of complete rows
        (:class:`Completed`, with a flush between them) and a flush; an
        HDF5 error breaks the file."""
        try:
            action(*args)
            self.f.flush()
            self.completed.write(self.n, self._gauge_rows(), self.f.flush)
            self.events.complete()
            self.f.flush()
        except (OSError, RuntimeError, ValueError) as exc:
            self.broken = True
            raise OutputFailed(self._failure(exc)) from None

    def _gauge_rows(self):
        return self.gauges.n if self.gauges else 0

    def _failure(self, exc):
        kept = ("nothing written yet" if self.flushed_slab is None else
                f"the file keeps every slab up to slab {self.flushed_slab}")
        return f"cannot write {self.lock.path}: {_reason(exc)}; {kept}"

    def _take(self):
        """The buffered block (buffers, rows, gauge block); the next rows
        go to the other buffers."""
        block = (self.buffers, self.pending, self.gauges.take() if self.gauges else None,
                 self.events.take())
        if self.spare is not None:
            self.buffers, self.spare = self.spare, self.buffers
        self.pending = 0
        return block

    def _write_block(self, block, snapshots, slab):
        buffers, k, gauges, events = block
        if gauges:
            self.gauges.write(gauges)
        self.events.write(events)
        if k:
            n = self.n
            for name, (dsid, _, _) in self.series.items():
                _append(dsid, n, buffers[name][:k])
            self.flushed_slab = int(buffers["solver/slab"][k - 1])
            self.n = n + k
        self.snapshots.write(snapshots, slab)

    def close(self, status, snapshots=None, slab=None, groups=None, **attrs):
        """Write what is buffered, set the status and attributes (``groups``:
        {group: attributes} too), close the file, cut off the reserved tail
        and release the lock.  If the last block cannot be written the
        status becomes "failed" and the error is raised after the file is
        closed.  The status is written after the last block's rows are on
        disk, once the file has left SWMR mode (:meth:`_end_swmr`)."""
        error = None
        if not self.broken:
            try:
                self.flush(snapshots, slab)
                self.settle()
            except OutputFailed as exc:
                error, status, attrs = exc, "failed", {"message": str(exc)}
        if not self.broken:
            try:
                self._end_swmr()
                set_attrs(self.f, {"status": status, **attrs})
                for group, values in (groups or {}).items():
                    set_attrs(self.f[group], values)
                self.f.flush()
            except (OSError, RuntimeError, ValueError) as exc:
                self.broken = True
                error = error or OutputFailed(self._failure(exc))
        self.thread.stop()
        _abandon(self.f, self.broken, self.lock.fd)
        self.lock.release()
        if error is not None:
            raise error

    def _end_swmr(self):
        """Close a file in SWMR mode and open it again plainly: SWMR lets a
        writer write its datasets' data, not make or change attributes,
        which the closing status and summaries are.  Its space is reserved
        again (HDF5 cut the reserved tail off when it closed the file)."""
        if not self.f.swmr_mode:
            return
        self.f.close()
        self.f = open_to_write(self.lock.path, "a")
        self.reserve.ensure(self.f.id.get_filesize(), MARGIN)


def _create(cls, path, series, statics, groups, attrs, first_row, interval, snapshots,
            events, expected, state):
    """:meth:`ResultWriter.create` (``cls`` the writer's class)."""
    lock = OutputLock(path)
    temp, f, fd, writer = lock.new(), None, None, None
    try:
        f = open_to_write(temp, "w")
        fd = os.open(temp, os.O_RDWR)
        header = sum(np.asarray(a).nbytes for a in statics.values())
        DiskReserve(fd).ensure(f.id.get_filesize(), header + MARGIN)
        growing = _header(f, series, statics, groups, attrs, events, expected)
        writer = cls(f, lock, interval, fd, growing, expected)
        writer.append(first_row)
        if writer.gauges:
            writer.gauges.slot()[:] = np.concatenate([np.ravel(first_row[n])
                                                      for n in writer.gauges.names])
        writer.flush(snapshots, 0)
        writer.settle()
        _make_state(writer, state)
        start_swmr(f)          # every object is made: readers may come
        lock.publish(fd)
    except (OSError, RuntimeError, ValueError, OutputFailed) as exc:
        hdf5_failed = (writer.broken if writer is not None else
                       not isinstance(exc, (DiskFull, InputError)))
        if writer is not None:           # its block thread ends with the file
            writer.thread.stop()
        _abandon(f, hdf5_failed)
        if fd is not None and lock.fd is None:
            os.close(fd)
        lock.release()
        if isinstance(exc, InputError):        # another run took the name
            raise
        raise InputError(f"output: cannot create {path}: {_reason(exc)}") from None
    return writer


def _make_state(writer, state, last=None):
    """Make the datasets of the restart state the blocks write
    (:meth:`Snapshots.reserve`) before the file goes into SWMR mode; disk
    space for them is reserved first (DiskFull), and an HDF5 error breaks
    the file."""
    need = sum(np.asarray(a).nbytes for a in (state or {}).values()) + MARGIN
    writer.reserve.ensure(writer.f.id.get_filesize(), need)
    try:
        writer.snapshots.reserve(state, last)
    except (OSError, RuntimeError, ValueError):
        writer.broken = True
        raise


def _reopen(cls, lock, attrs, interval, expected, state, events):
    """:meth:`ResultWriter.reopen` (``cls`` the writer's class)."""
    path = lock.path
    try:
        f = open_to_write(path, "a")
        DiskReserve(lock.fd).ensure(f.id.get_filesize(), MARGIN)
        for k, v in attrs.items():
            f.attrs[k] = v
        f.attrs["status"] = "running"
        f.attrs["restarts"] = int(f.attrs.get("restarts", 0)) + 1
        writer = cls(f, lock, interval, lock.fd, expected=expected)
        last = int(f["solver/slab"][-1])      # the run continues from its last kept slab
        if writer.gauges:
            writer.completed.write(writer.n, min(last + 1, writer.gauges.n))    # before the cut
            f.flush()
            writer.gauges.truncate(last + 1)
        writer.completed.write(writer.n, writer._gauge_rows())
        # events of slabs after the last row (a block killed midway) cut and
        # the restart state's datasets made while SWMR has not started
        writer.events.truncate(events or {})
        writer.events.complete()
        _make_state(writer, state, last)
        f.flush()
        start_swmr(f)          # a file of the older format goes on without
    except (OSError, RuntimeError, ValueError) as exc:
        lock.release()
        raise InputError(f"--restart: cannot append to {path}: {_reason(exc)}") from None
    return writer


def _track(growing, most=BUFFER_ROWS):
    """(series {name: (low-level handle, row shape, (chunk rows, chunk
    bytes))}, two sets of buffers {name: array}, rows a buffer holds) of
    the series kept with the rows among ``growing`` ({name:
    Grown}), buffers of at most ``most`` rows (h5py's high-level resize
    and item assignment cost ~200 us a call); the second set is None when a
    buffer holds fewer than THREAD_ROWS rows (huge rows: memory first, and
    a tiny run: blocks are written at once)."""
    series, buffers, capacity = {}, {}, None
    for name, ds in growing.items():
        if layout.every_slab(name) or layout.is_events(name):
            continue
        tail, dtype = ds.tail, ds.dtype
        rows = max(1, min(BUFFER_ROWS, BUFFER_VALUES // max(1, math.prod(tail)), most))
        chunk = (ds.chunks[0], math.prod(ds.chunks) * dtype.itemsize)
        series[name] = (ds.id, tail, chunk)
        buffers[name] = _touched((rows,) + tail, dtype)
        capacity = min(rows, capacity or rows)
    spare = None if capacity is not None and capacity < THREAD_ROWS else \
        {name: _touched(b.shape, b.dtype) for name, b in buffers.items()}
    return series, buffers, spare, capacity


def _block_bytes(series, n, k):
    """Bytes HDF5 may add to write rows n..n+k-1 of ``series`` (it allocates
    whole chunks, each when its first row is written)."""
    return sum(nbytes * (-(-(n + k) // rows) - (-(-n // rows)))
               for _, _, (rows, nbytes) in series.values())


def _append(dsid, n, rows):
    """Write ``rows`` (k rows of a series) after the first n rows of the
    dataset ``dsid``, growing it (h5py's low level: its high-level resize
    and item assignment cost ~200 us a call)."""
    rows = np.ascontiguousarray(rows)
    k, tail = rows.shape[0], rows.shape[1:]
    dsid.set_extent((n + k,) + tail)
    fspace = dsid.get_space()
    fspace.select_hyperslab((n,) + (0,) * len(tail), (k,) + tail)
    dsid.write(h5py.h5s.create_simple(rows.shape), fspace, rows)


def _series_of(f):
    """{name: :class:`~vstpetsc.results.hdf5.Grown`} of every growing
    dataset of an open file."""
    found = {}
    f.visititems(lambda name, obj: found.update({name: Grown.of(obj)})
                 if isinstance(obj, h5py.Dataset) and layout.grows(obj) else None)
    return found


def _header(f, series, statics, groups, attrs, events=(), expected=None):
    """Write a new file's attributes, static datasets and groups and create
    its growing datasets, chunks of :func:`chunk_rows` (``expected``: the
    kept rows and gauge rows the run writes, if known); returns {name:
    Grown} of those."""
    set_attrs(f, {"status": "running", "version": __version__, **attrs})
    for name, data in statics.items():
        f.create_dataset(name, data=data)
    for group, group_attrs in groups.items():
        # a static dataset may carry attributes too (/mesh/region's names)
        set_attrs(f[group] if group in statics else f.require_group(group), group_attrs)
    growing = Growing(f)
    for name, tail in series:
        rows = expected and expected[1 if layout.every_slab(name) else 0]
        growing.add(name, tail, chunk_rows(tail, rows),
                    "i8" if name in layout.INTEGER_SERIES else "f8")
    for name in events:
        growing.add(name, (2,), EVENT_CHUNK, "f8")
    f.require_group(layout.CONTACT)
    return growing.ids


def chunk_rows(tail, rows=None):
    """Rows of a chunk of a growing dataset of rows ``tail``: 512 kB at
    most, 4096 rows at most, and for a run known to keep ``rows`` rows no
    more than those rounded up to a power of two (at least CHUNK_FLOOR):
    HDF5 writes whole chunks, and a tiny run's file was 2.5 MB of zeros.
    A restart that continues a short run far keeps its small chunks."""
    most = max(1, min(4096, 65536 // max(1, math.prod(tail))))
    if rows is None:
        return most
    return min(most, max(CHUNK_FLOOR, 1 << max(0, int(rows) - 1).bit_length()))


def _abandon(f, broken, fd=None):
    """Close ``f`` and cut the reserved tail off (through ``fd``) unless
    HDF5 failed a write on it: then keep it open for good (see module)."""
    if f is None:
        return
    if broken:
        _UNCLOSABLE.append(f)
        return
    try:
        end = f.id.get_filesize()
        f.close()
        if fd is not None:
            os.ftruncate(fd, end)
    except (OSError, RuntimeError, ValueError):
        pass


def _reason(exc):
    """The short reason of an OS or HDF5 error (HDF5 puts the system's
    message inside its own)."""
    text = str(exc)
    found = re.search(r"error message = '([^']+)'", text)
    if found:
        return found.group(1)
    if isinstance(exc, DiskFull):
        return f"disk full: {exc.strerror}"
    text = getattr(exc, "strerror", None) or text
    return text.split("(")[0].strip() or type(exc).__name__


def _touched(shape, dtype, most=1 << 22):
    """An array whose memory is mapped and written once (np.zeros alone maps
    pages lazily, at first write), when it takes at most ``most`` bytes: a
    bigger buffer is left lazy (its pages fault as rows arrive, 3.6-10 us a
    4 kB page on the bench's VM: paid once either way, and untouched rows
    cost no memory)."""
    out = np.empty(shape, dtype=dtype)
    if out.nbytes <= most:
        out.fill(0)
    return out
