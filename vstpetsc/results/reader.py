"""Reading a result file: :class:`Result`, lazy (each value is read from
the file when it is asked for, so a big file costs nothing to open).

A file being written by a run is read safely: the run writes it in HDF5's
single-writer/multiple-reader (SWMR) mode and a Result reads it in SWMR
read mode, so every read sees a consistent file without retries
(:func:`~vstpetsc.results.hdf5.open_to_read`).  A run writes its file
without SWMR for a moment at its start (a restart) and at its end (the
status and summaries, after the last block): HDF5 then refuses to open it
("file is already open for write") and a read may meet a write half done;
such an error, while a run holds the file and is not in SWMR mode, is
retried (:meth:`FileReads._with_file`).  The run grows its datasets
before it writes their rows, so a Result reads, when it is opened, how
many rows are complete in every dataset (the attributes
:data:`~vstpetsc.results.layout.COMPLETE_ROWS` and ``COMPLETE_GAUGE_ROWS``
that the writer sets after each block is on disk; the shortest dataset in
a file without them) and shows every series cut to those many rows.  A
file of the older format continued by a restart is written without SWMR
all along: its reads are retried so too.
"""

import contextlib
import os
import time

import numpy as np

from vstpetsc.errors import InputError
from vstpetsc.results import layout, plane_layout
from vstpetsc.results.files import held
from vstpetsc.results.layout import text
from vstpetsc.results.summary import summarize

RETRY_SECONDS = 5.0      # how long reads of a file being written are retried
STEADY_READS = 20        # most outline reads of a file being written
# what h5py raises for metadata read half written (retried while a run
# holds the file); a damaged file raises these too, after no retry
HDF5_ERRORS = (OSError, RuntimeError, KeyError)


class FileReads:
    """The reads of a result file that a run may be writing: each opens it
    (or uses the session's open file) and reads what the Result's outline
    names, cut to the rows complete (module docstring)."""

    def _steady_outline(self):
        """The file's outline; while a run holds a file it writes without
        SWMR (:func:`~vstpetsc.results.hdf5.open_to_read`), read until two
        reads in a row name the same groups and datasets (a read that met
        the run rewriting the root's header may miss a name silently)."""
        from vstpetsc.results.hdf5 import swmr_format
        outline, swmr = self._with_file(lambda f: (_outline(f), f.swmr_mode))
        self._swmr = swmr and swmr_format(self.path)
        for _ in range(0 if swmr else STEADY_READS):
            if not held(self.path):
                break
            again = self._with_file(_outline)
            if again[-1] == outline[-1]:
                return again
            outline = again
        return outline

    def _open(self):
        # h5py here, not at the top: `import vstpetsc` leaves it (~0.1 s) to
        # what reads or writes a file.  A run may be writing the file: read
        # it without HDF5's file lock
        from vstpetsc.results.hdf5 import open_to_read
        return open_to_read(self.path)

    @contextlib.contextmanager
    def session(self):
        """Keep the file open for the reads inside (a summary makes some 30
        reads: one open instead of one each, 30 ms a run of a sweep)."""
        if self._file is not None:
            yield self
            return
        self._file = self._retried(self._open)
        try:
            yield self
        finally:
            if self._file is not None:          # (None: given up, _with_file)
                self._file.close()
            self._file = None

    def _with_file(self, action):
        """``action(f)`` on the open file (the session's, or one opened for
        it), retried as :meth:`_retried` says.  A session's file that met
        an error is closed, and the session's reads open the file each:
        HDF5 shares a file opened twice in a process, so reads retried
        beside it would meet its stale metadata again."""
        if self._file is not None:
            try:
                return action(self._file)
            except HDF5_ERRORS:
                if _in_swmr(self.path):
                    raise
                self._file.close()
                self._file = None

        def read():
            with self._open() as f:
                return action(f)
        return self._retried(read)

    def _retried(self, read):
        """``read()``; an HDF5 error is raised at once while a run holds the
        file in SWMR mode (none is expected there: HDF5 orders the writer's
        metadata for SWMR readers).  While a run holds it without SWMR (a
        file of the older format; a restart before SWMR starts; the end of
        a run, its status written after the file left SWMR mode) it is read
        again every 10 ms for up to RETRY_SECONDS.  On a file that no run
        holds it is read once more at once (the run may have let go of it
        since the error), then raised."""
        from vstpetsc.results.hdf5 import swmr_writing
        deadline, again = time.monotonic() + RETRY_SECONDS, True
        while True:
            try:
                return read()
            except HDF5_ERRORS:
                free = not held(self.path)
                if (free and not again) or time.monotonic() > deadline or \
                        (not free and swmr_writing(self.path)):
                    raise
                again = not free
            if again:
                time.sleep(0.01)

    def _rows_of(self, name, ds=None):
        """The rows of dataset ``name`` (open as ``ds``) a reader sees
        (None: all of it, a dataset that does not grow with the run)."""
        name = name.strip("/")
        if layout.is_events(name):                 # its own count of rows on disk
            count = ds.attrs.get(layout.COMPLETE_ROWS)
            return None if count is None else int(count)
        if self._names.get(name) not in ("series", "table"):
            return None
        return self._gauge_rows if layout.every_slab(name) else self._rows


class PlaneParts:
    """What a plane-strain Result has beyond the shared parts: its mesh,
    fields and interfaces (a 1-D result raises KeyError)."""

    @property
    def mesh(self):
        """A plane-strain result's mesh: ``.coordinates`` (nn, 2), ``.cells``
        (ne, 4; -1 pads a triangle), ``.region`` (ne,) and ``.region_names``."""
        self._plane_only("mesh")
        group = Group(self, plane_layout.MESH)
        group.region_names = [text(n) for n in self.group_attrs(
            f"{plane_layout.MESH}/region").get("names", [])]
        return group

    @property
    def field(self):
        """A plane-strain result's fields at the kept times: ``.u``, ``.v``
        (nt, nn, 2), ``.stress`` (nt, ne, 3: sigma_xx, sigma_yy, sigma_xy);
        the envelopes over the run (ne,): ``.principal_max``,
        ``.principal_min`` and their ``_time`` (a yielding run's
        ``.strain_max``)."""
        self._plane_only("field")
        return Group(self, plane_layout.FIELD)

    def _plane_only(self, what):
        if self.dimension != 2:
            raise KeyError(f"{self.path} is a 1-D result: it has no {what} (see .body)")

    @property
    def interfaces(self):
        """The names of a plane-strain result's interfaces (empty without)."""
        return self.keys("interface") if "interface" in self else []

    def interface(self, name):
        """Datasets of a plane-strain interface: ``.nodes`` (m, 2), ``.normal``,
        ``.tangent`` (m, 2), ``.length`` (m,), and at the kept times ``.gap``,
        ``.normal_force``, ``.shear_force``, ``.slip``, ``.stretch`` (nt, m);
        ``.attrs`` (formulation, penalty, friction, permanent_slip)."""
        self._plane_only("interface")
        if name not in self.interfaces:
            raise KeyError(f"no interface {name!r} (interfaces: "
                           f"{', '.join(self.interfaces) or 'none'})")
        return Group(self, f"interface/{name}")

    @property
    def waters(self):
        """The names of a plane-strain result's [[water]] tables (empty without)."""
        return self.keys(plane_layout.WATER) if plane_layout.WATER in self else []

    def water(self, name):
        """Datasets of a [[water]] table: ``.nodes`` (m,) the wetted nodes in
        order along its faces, at the kept times ``.pressure`` (nt, m) and
        ``.force`` (nt, 2) its resultant on the solid per unit thickness."""
        self._plane_only("water")
        if name not in self.waters:
            raise KeyError(f"no water {name!r} (water tables: "
                           f"{', '.join(self.waters) or 'none'})")
        return Group(self, f"{plane_layout.WATER}/{name}")


class Result(PlaneParts, FileReads):
    """A result file of `vstpetsc run`.

    Examples
    --------
    >>> r = Result("bar-wall.h5")                         # doctest: +SKIP
    >>> r.time, r.body("bar").u, r.contact(0).force       # doctest: +SKIP
    >>> r.energy["kinetic"], r.status, r.summary()        # doctest: +SKIP

    Parameters
    ----------
    path : str
        A file written by :func:`vstpetsc.run`; :class:`vstpetsc.InputError`
        if it is missing or not a vstpetsc result.

    A file that a run is writing shows the rows complete in every dataset
    when the Result was made (every series as long as ``time``, the gauge
    series as long as each other); a new Result shows the rows since.
    """

    def __init__(self, path):
        self.path = str(path)
        self._file = None                  # open for a session's reads
        self._swmr = False                 # read in HDF5's SWMR mode (no retries)
        if not os.path.isfile(self.path):
            raise InputError(f"{self.path}: no such file")
        try:
            missing, self.bodies, self.ncontacts, self._rows, self._gauge_rows, self._names = \
                self._steady_outline()
        except HDF5_ERRORS + (ValueError, IndexError):
            raise InputError(f"{self.path}: not an HDF5 file, or a damaged one") from None
        if missing:
            raise InputError(f"{self.path}: not a vstpetsc result (no {', '.join(missing)})")

    def __getitem__(self, name):
        """The whole dataset ``name`` (e.g. "contact/0/gap") as an array."""
        return self.read(name)

    def read(self, name, selection=()):
        """Dataset ``name``, or the part of it that ``selection`` (an index
        expression, e.g. ``np.s_[rows, :]``) picks, as an array."""
        import h5py
        def part(f):
            if name.strip("/") not in self._names:
                return None
            if name not in f:                   # named in the outline: a racing read
                raise KeyError(name)
            if not isinstance(f[name], h5py.Dataset):
                return None
            ds = f[name]
            rows = self._rows_of(name, ds)
            return ds[selection] if rows is None else _rows(ds, rows, selection)

        found = self._with_file(part)
        if found is None:
            raise KeyError(f"{self.path} has no dataset {name!r}")
        return found

    def __contains__(self, name):
        return name.strip("/") in self._names

    def keys(self, group=""):
        """Names of the datasets and groups under ``group`` (as the file
        had them when the Result was made), in the file's order."""
        group = group.strip("/")
        if group and group not in self._names:
            raise KeyError(f"{self.path} has no group {group!r}")
        prefix = group + "/" if group else ""
        return [n[len(prefix):] for n in self._names
                if n.startswith(prefix) and "/" not in n[len(prefix):]]

    def series(self, group):
        """{name: array} of the 1-D series of ``group`` (datasets that grow
        with the run), in the file's order."""
        top = group.strip("/")
        names = [k for k in self.keys(top) if self._names[f"{top}/{k}"] == "series"]

        def read(f):
            return {k: _rows(f[f"{group}/{k}"], self._rows_of(f"{group}/{k}"), ()) for k in names}
        return self._with_file(read)

    def group_attrs(self, group=""):
        """The attributes of ``group`` (strings decoded)."""
        return self._with_file(lambda f: {k: text(v) if isinstance(v, (bytes, str)) else v
                                          for k, v in f[group or "/"].attrs.items()})

    @property
    def attrs(self):
        """The root attributes (status, case, dt, ...)."""
        return self.group_attrs()

    @property
    def status(self):
        """"running", "completed", "failed" or "interrupted"; "killed" for a
        file left "running" that no process writes any more (the run was
        killed: it holds every block written before; --restart continues
        it)."""
        status = self.attrs.get("status", "?")
        if status == "running" and not held(self.path):
            return "killed"
        return status

    @property
    def time(self):
        """The kept times (t = 0 and the kept slab ends)."""
        return self[layout.TIME]

    @property
    def dimension(self):
        """2 for a plane-strain result, 1 for bodies on a line."""
        return int(self.attrs.get(plane_layout.DIMENSION, 1))

    def body(self, name):
        """Datasets of body ``name``: ``.x``, ``.u``, ``.v``, ``.stress``."""
        if name not in self.bodies:
            raise KeyError(f"no body {name!r} (bodies: {', '.join(self.bodies)})")
        return Group(self, layout.body_path(name))

    def contact(self, k):
        """Datasets of contact pair ``k``: ``.gap``, ``.force``, ``.impulse``,
        running totals, ``.events`` ((m, 2): time, +1 close / -1 open) and
        ``.attrs``."""
        if not 0 <= int(k) < self.ncontacts:
            raise KeyError(f"no contact {k} (there are {self.ncontacts})")
        return Group(self, f"{layout.CONTACT}/{int(k)}")

    @property
    def gauges(self):
        """The gauge names (empty if the case has none)."""
        return self.keys("gauge") if "gauge" in self else []

    def gauge(self, name):
        """Datasets of gauge ``name``: ``.u``, ``.v``, ``.stress``,
        ``.strain`` after every slab (t = 0 first; ``.time`` the slab
        ends), ``.attrs`` (body, x)."""
        if name not in self.gauges:
            raise KeyError(f"no gauge {name!r} (gauges: {', '.join(self.gauges) or 'none'})")
        return GaugeGroup(self, f"gauge/{name}")

    @property
    def energy(self):
        """{name: array} of the energy datasets, read when asked for."""
        return Group(self, "energy")

    @property
    def solver(self):
        """{name: array} of the solver datasets (iterations, wall time, slab)."""
        return Group(self, "solver")

    def case(self):
        """The Case that produced the file (its text; relative file names
        refer to the folder the case was read from)."""
        from vstpetsc.input.case import Case
        a = self.attrs
        return Case.from_text(a["case"], source=f"{self.path}:case", folder=a.get("case_folder"))

    def to_csv(self, folder):
        """Write the time series as CSV files in ``folder``
        (:func:`vstpetsc.results.export.to_csv`); returns their paths."""
        from vstpetsc.results.export import to_csv
        return to_csv(self, folder)

    def to_xdmf(self, path=None):
        """Write an XDMF index of u, v, stress over time for ParaView
        (default RESULT.xdmf beside the file); returns its path."""
        from vstpetsc.results.export import to_xdmf
        return to_xdmf(self, path)

    def summary(self):
        """The dict that `vstpetsc info` prints."""
        with self.session():
            return summarize(self)


def _in_swmr(path):
    """Whether a run holds file ``path`` and writes it in SWMR mode now."""
    from vstpetsc.results.hdf5 import swmr_writing
    return held(path) and swmr_writing(path)


def _outline(f):
    """(missing required names, body names left to right, number of
    contact pairs, complete rows, complete gauge rows, {name: kind} of every
    group and dataset (:func:`_walk`)) of an open file.  The counts of
    complete rows are read first, the kept rows' before the gauge rows'
    (the writer puts them on disk in the other order, ``Completed``), and
    the datasets' lengths after them: a running file's datasets only grow,
    so each is then at least as long as its count (lengths read before
    could be older than the counts: a walk that met a block's flush half
    done saw the kept rows grown and the gauge rows not yet)."""
    limits = [int(f.attrs.get(attr, np.iinfo(np.int64).max))
              for attr in (layout.COMPLETE_ROWS, layout.COMPLETE_GAUGE_ROWS)]
    plane = int(f.attrs.get(plane_layout.DIMENSION, 1)) == 2
    missing = [k for k in (plane_layout.REQUIRED if plane else layout.REQUIRED) if k not in f]
    bodies = [name for _, name in sorted((f[layout.body_path(n, "x")][0], n)
                                         for n in f[layout.BODY])] \
        if not (missing or plane) else []
    ncontacts = len(f[layout.CONTACT]) if layout.CONTACT in f else 0
    names, kept, every_slab = {}, [], []
    for name, kind, length in _walk(f):
        names[name] = kind
        if kind in ("series", "table") and not layout.is_events(name):
            (every_slab if layout.every_slab(name) else kept).append(length)
    counts = [min(lengths + [limit]) if lengths else 0
              for lengths, limit in zip((kept, every_slab), limits)]
    return missing, bodies, ncontacts, *counts, names


def _walk(f):
    """[(name, kind, rows)] of every group and dataset of an
    open file, in the file's order, through h5py's low level (its
    ``visititems`` makes a Dataset or Group per name: ~10 ms for a small
    result file, the most of opening it)."""
    import h5py
    found = []

    def note(name, info):
        if info.type != h5py.h5o.TYPE_DATASET:
            found.append((name.decode(), "group", None))
            return
        space = h5py.h5d.open(f.id, name).get_space()
        dims, most = space.get_simple_extent_dims(), space.get_simple_extent_dims(True)
        found.append((name.decode(), _kind_of(dims, most), dims[0] if dims else None))
    h5py.h5o.visit(f.id, note, info=True)
    return found


def _kind_of(dims, most):
    """What a dataset of shape ``dims`` and largest shape ``most`` is:
    "series" (1-D, growing with the run), "table" (growing along its first
    axis) or "dataset"."""
    import h5py
    if not most or most[0] != h5py.h5s.UNLIMITED:
        return "dataset"
    return "series" if len(dims) == 1 else "table"


def _rows(ds, rows, selection):
    """``ds[selection]`` of a dataset seen with its first ``rows`` rows only
    (the selection's first index counts within those)."""
    if rows is None or rows >= ds.shape[0]:
        return ds[selection]
    index = selection if isinstance(selection, tuple) else (selection,)
    if any(i is Ellipsis for i in index):
        return ds[:rows][selection]          # rare: read the rows, then pick
    first, rest = (index[0], index[1:]) if index else (slice(None), ())
    if isinstance(first, slice):
        first = slice(*first.indices(rows))
    elif np.ndim(first) == 0:
        if not -rows <= int(first) < rows:
            raise IndexError(f"row {first} out of range for {rows} rows")
        first = int(first) % rows
    else:
        first = np.asarray(first)
        if first.size and (first.max() >= rows or first.min() < -rows):
            raise IndexError(f"rows out of range for {rows} rows")
        first = np.where(first < 0, first + rows, first)
    return ds[(first,) + tuple(rest)]


class Group:
    """A group of a result file; its datasets read on attribute or item
    access (``g.u`` or ``g["u"]``), a subgroup as a Group (``body.shear``),
    ``g.attrs`` its attributes."""

    def __init__(self, result, path):
        self._result, self._path = result, path

    def __getattr__(self, key):
        if key.startswith("_"):
            raise AttributeError(key)
        try:
            return self[key]
        except KeyError:
            raise AttributeError(f"{self._path} has no dataset {key!r}") from None

    def __getitem__(self, key):
        path = f"{self._path}/{key}"
        if self._result._names.get(path.strip("/")) == "group":
            return Group(self._result, path)
        return self._result[path]

    def keys(self):
        return self._result.keys(self._path)

    def __iter__(self):
        return iter(self.keys())

    def items(self):
        return [(k, self[k]) for k in self.keys()]

    @property
    def attrs(self):
        return self._result.group_attrs(self._path)

    def __repr__(self):
        return f"<{self._path} of {self._result.path}: {', '.join(self.keys())}>"


class GaugeGroup(Group):
    """A gauge's group; ``.time`` the slab ends its rows belong to;
    ``.acceleration`` and ``.shear_acceleration`` the derivatives of its
    ``v`` and ``shear_v`` (:func:`vstpetsc.results.spectrum.acceleration`)."""

    @property
    def name(self):
        return self._path.split("/", 1)[1]

    @property
    def dt(self):
        return float(self._result.attrs["dt"])

    @property
    def time(self):
        return np.arange(len(self.u)) * self.dt

    @property
    def acceleration(self):
        """The axial acceleration at the slab ends: central differences of
        ``v`` (one-sided at the first and last); on a plane-strain gauge
        (``v`` (n, 2)) the (n, 2) accelerations a_x, a_y, each column
        from its own velocity component."""
        from vstpetsc.results.spectrum import acceleration
        return acceleration(self.v, self.dt)

    @property
    def shear_acceleration(self):
        """The shear acceleration at the slab ends, from ``shear_v`` as
        :attr:`acceleration` (AttributeError without a shear component)."""
        from vstpetsc.results.spectrum import acceleration
        return acceleration(self.shear_v, self.dt)
