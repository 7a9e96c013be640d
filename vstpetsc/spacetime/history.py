"""Piecewise-linear histories ``f(t)`` (or profiles ``f(x)``): a number, a
``[[t, value], ...]`` table, or samples read from a CSV or PEER ``.AT2``
file, optionally scaled and integrated; and their exact integrals against
the linear time shape functions of a slab.

An integrated record (an acceleration, linear between its samples) is the
exact integral of that acceleration: piecewise quadratic, so its value
between samples and its slab integrals are exact too (issue 28: the
trapezoidal values joined linearly filtered the record like
1 - (2/3) (pi f dt)^2 and kinked it at every sample).

Every form ends as the same (t, f) table, so the same data inline or from a
file give identical results.
"""

import csv
import io
import re

import numpy as np

# 3-point Gauss-Legendre rule on [0, 1]: exact for polynomials of degree <= 5.
GAUSS_X = 0.5 + 0.5 * np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
GAUSS_W = np.array([5.0, 8.0, 5.0]) / 18.0


class History:
    """A constant, a piecewise-linear or (an integrated record) a piecewise
    quadratic function of one variable.

    Outside the table the end values are held (like :func:`numpy.interp`).

    Parameters
    ----------
    points : array_like, shape (n, 2), optional
        Increasing abscissae and values.  ``None`` for a constant.
    value : float
        The constant value when ``points`` is ``None``.
    slopes : array_like, shape (n,), optional
        df/dt at the points, linear in between (an integrated record's
        acceleration samples): f is then quadratic between points, the
        exact integral of its slopes.  ``None``: f is linear between points.
    """

    def __init__(self, points=None, value=0.0, slopes=None):
        if points is None:
            self.t = np.array([0.0])
            self.f = np.array([float(value)])
        else:
            pts = np.asarray(points, dtype=float)
            self.t, self.f = pts[:, 0].copy(), pts[:, 1].copy()
        self.slopes = None if slopes is None else np.array(slopes, dtype=float)
        if self.slopes is not None:
            # f = f_i + s (c1_i + c2_i s) on [t_i, t_i+1], s = t - t_i: once per history
            self._c1 = self.slopes[:-1]
            self._c2 = np.diff(self.slopes) / (2.0 * np.diff(self.t))

    @property
    def finite(self):
        """Whether its values, slopes and quadratic terms are all finite
        doubles (samples near overflow, scaled or integrated, may not be)."""
        parts = (self.t, self.f) if self.slopes is None else \
            (self.t, self.f, self.slopes, self._c2)
        return all(np.all(np.isfinite(p)) for p in parts)

    @property
    def is_zero(self):
        return not np.any(self.f) and (self.slopes is None or not np.any(self.slopes))

    @property
    def is_constant(self):
        return bool(np.all(self.f == self.f[0])) and \
            (self.slopes is None or not np.any(self.slopes))

    def __eq__(self, other):
        return (isinstance(other, History) and np.array_equal(self.t, other.t)
                and np.array_equal(self.f, other.f)
                and (self.slopes is None) == (other.slopes is None)
                and (self.slopes is None or np.array_equal(self.slopes, other.slopes)))

    def __repr__(self):
        if self.t.size == 1:
            return f"History({self.f[0]!r})"
        kind = "points" if self.slopes is None else "points, quadratic"
        return f"History({self.t.size} {kind}, {self.t[0]:g} .. {self.t[-1]:g})"

    def __call__(self, t):
        if self.slopes is None:
            return np.interp(t, self.t, self.f)
        return self._quadratic(np.asarray(t, dtype=float))

    def _quadratic(self, t):
        """The piecewise quadratic at t; the end values held outside."""
        i = np.clip(np.searchsorted(self.t, t, side="right") - 1, 0, self.t.size - 2)
        s = np.maximum(t - self.t[i], 0.0)
        inside = self.f[i] + s * (self._c1[i] + self._c2[i] * s)
        return np.where(t >= self.t[-1], self.f[-1], inside)[()]

    def scaled(self, factor):
        """This history times ``factor`` (slopes too)."""
        slopes = None if self.slopes is None else factor * self.slopes
        return History(np.column_stack([self.t, factor * self.f]), slopes=slopes)

    def hat_integrals(self, t0, t1):
        """Exact ``(int T1 f dt, int T2 f dt)`` over ``[t0, t1]``.

        ``T1 = 1 - theta`` and ``T2 = theta`` with ``theta = (t - t0)/(t1 - t0)``;
        the interval is split at the table's break points, so a Gauss rule on
        each piece integrates the product of T_a and a linear or quadratic
        f exactly (degree 3 <= 5).
        """
        lo, hi = np.searchsorted(self.t, [t0, t1], side="right")
        inner = self.t[lo:hi]
        inner = inner[(inner > t0) & (inner < t1)]
        edges = np.concatenate(([t0], inner, [t1]))
        lo, length = edges[:-1], np.diff(edges)
        t = lo[:, None] + length[:, None] * GAUSS_X[None, :]
        w = length[:, None] * GAUSS_W[None, :]
        f = self(t) * w
        theta = (t - t0) / (t1 - t0)
        return np.array([np.sum(f * (1.0 - theta)), np.sum(f * theta)])


    def slab_integrals(self, dt, k0, k1):
        """``hat_integrals`` of the slabs k0+1 .. k1 ((k - 1) dt, k dt], as
        an array (k1 - k0, 2), vectorized over the slabs: every piece between
        slab edges and table break points gets the 3-point Gauss rule (exact:
        f is at most quadratic on a piece)."""
        edges = dt * np.arange(k0, k1 + 1)
        inner = self.t[(self.t > edges[0]) & (self.t < edges[-1])]
        points = np.union1d(edges, inner)
        lo, length = points[:-1], np.diff(points)
        slab = np.searchsorted(edges, lo, side="right") - 1
        t = lo[:, None] + length[:, None] * GAUSS_X[None, :]
        f = (self(t) * length[:, None] * GAUSS_W[None, :]).ravel()
        span = np.diff(edges)[slab][:, None]           # t1 - t0 as hat_integrals has it
        theta = ((t - edges[slab][:, None]) / span).ravel()
        which = np.repeat(slab, GAUSS_X.size)
        out = np.empty((k1 - k0, 2))
        out[:, 0] = np.bincount(which, f * (1.0 - theta), minlength=k1 - k0)
        out[:, 1] = np.bincount(which, f * theta, minlength=k1 - k0)
        return out


def from_samples(t, f, scale=1.0, integrate=False):
    """The history of samples (t, f): times scale, then (``integrate``)
    integrated once, exactly, from 0 at the first sample: f linear between
    samples gives a piecewise quadratic whose values at the samples are
    the trapezoidal sums."""
    t = np.asarray(t, dtype=float)
    # samples near overflow give inf, not warnings: History.finite tells
    with np.errstate(over="ignore", invalid="ignore"):
        f = np.asarray(f, dtype=float) * scale
        if not integrate:
            return History(np.column_stack([t, f]))
        v = np.concatenate(([0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(t))))
        return History(np.column_stack([t, v]), slopes=f)


class RecordError(ValueError):
    """A history file that cannot be read; the message says where."""


def read_csv(path, column=2, magnitude=None):
    """(t, values) of a CSV file: time in column 1, one optional header
    line, ``column`` a header name or a 1-based index; with ``magnitude``
    (lo, hi), a time or value beyond hi in magnitude is refused (see
    :func:`_within`).

    A plain file (no quotes) is read by numpy's loadtxt (measured: 0.4 us
    a row, 1.6 row by row); anything it does not take (a bad row, a quoted
    cell, a number only Python reads) is read again row by row
    (:func:`read_csv_rows`), which gives the same samples and says what is
    wrong where."""
    text = _csv_text(path)
    samples = _plain_csv(path, text, column)
    if samples is None:
        samples = _csv_rows(path, text, column)
    t, v, first = samples
    return _within(path, *_checked(path, t, v), magnitude, "row", first)


def read_csv_rows(path, column=2, magnitude=None):
    """:func:`read_csv` read row by row only (csv.reader): the reference
    that the loadtxt path is tested against."""
    t, v, first = _csv_rows(path, _csv_text(path), column)
    return _within(path, *_checked(path, t, v), magnitude, "row", first)


def _csv_text(path):
    """The text of a CSV file, line ends as they are (csv.reader's own)."""
    try:
        with open(path, newline="") as f:
            return f.read()
    except OSError as exc:
        raise RecordError(f"cannot read {path} ({exc.strerror})") from None
    except UnicodeDecodeError as exc:
        raise RecordError(f"{path}: not a CSV text file ({exc})") from None


def _csv_rows(path, text, column):
    """(t, values, row number of the first sample) read row by row: the
    messages name the row (counting rows that hold a cell) and its cells."""
    try:
        rows = [r for r in csv.reader(io.StringIO(text, newline=""))
                if r and any(c.strip() for c in r)]
    except csv.Error as exc:
        raise RecordError(f"{path}: not a CSV text file ({exc})") from None
    header = None
    if rows and not _numeric(rows[0][0]):
        header, rows = [c.strip() for c in rows[0]], rows[1:]
    index = _column_index(path, header, column)
    first = 2 if header else 1
    t, v = [], []
    for line, row in enumerate(rows, start=first):
        if len(row) <= index:
            raise RecordError(f"{path}, row {line}: no column {index + 1}")
        if not (_numeric(row[0]) and _numeric(row[index])):
            raise RecordError(f"{path}, row {line}: not a number: {row[0]!r}, {row[index]!r}")
        t.append(float(row[0]))
        v.append(float(row[index]))
    return np.array(t), np.array(v), first


def _plain_csv(path, text, column):
    """(t, values, row number of the first sample) of a CSV text by numpy's
    loadtxt, or None for a text it may read differently from csv.reader
    (quotes, NUL, blank rows of commas, cells float() reads and numpy does
    not): the caller reads those row by row."""
    if '"' in text or "\0" in text:
        return None
    text = text.replace("\r\n", "\n").replace("\r", "\n")   # csv.reader's line ends
    head = _first_row(text)
    if head is None:
        return None
    start, end = head
    cells = text[start:end].split(",")
    header = None if _numeric(cells[0]) else [c.strip() for c in cells]
    index = _column_index(path, header, column)
    body = text[end + 1:] if header else text[start:]
    if not body.strip():
        return None
    try:
        data = np.loadtxt(io.StringIO(body), delimiter=",", usecols=(0, index), comments=None,
                          dtype=float, ndmin=2)
    except ValueError:
        return None
    return data[:, 0].copy(), data[:, 1].copy(), 2 if header else 1


def _first_row(text):
    """(start, end) of the first line that holds a cell (csv.reader skips
    the others), or None."""
    start = 0
    while start <= len(text):
        end = text.find("\n", start)
        end = len(text) if end < 0 else end
        if text[start:end].replace(",", "").strip():
            return start, end
        start = end + 1
    return None


def _within(path, t, v, magnitude, unit, first):
    """(t, v) if no time or value exceeds ``magnitude[1]`` in magnitude (the
    limit of an inline table's numbers: doubles of that size square without
    overflow); RecordError naming the sample otherwise (``unit`` "row" or
    "sample", numbered from ``first``)."""
    if magnitude is None:
        return t, v
    beyond = np.nonzero((np.abs(t) > magnitude[1]) | (np.abs(v) > magnitude[1]))[0]
    if beyond.size:
        k = beyond[0]
        bad = t[k] if abs(t[k]) > magnitude[1] else v[k]
        raise RecordError(f"{path}, {unit} {k + first}: must lie in {magnitude[0]:g} .. "
                          f"{magnitude[1]:g} in magnitude (or be 0), got {bad:g}")
    return t, v


# The fourth header line of a PEER record: NGA-West2's "NPTS= n, DT= dt SEC"
# or the older "n dt NPTS, DT" (numbers first).
AT2_HEADS = (re.compile(r"NPTS\s*=\s*(\S+?)\s*,?\s*DT\s*=\s*([^\s,]+?)\s*(?:SECS?)?(?:[\s,]|$)",
                        re.I),
             re.compile(r"^\s*(\S+?)\s*,?\s+(\S+?)\s*,?\s+NPTS\s*,\s*DT\b", re.I))
# What the third header line may say the values are in; g is what vstpetsc
# reads, anything else is refused rather than guessed (a factor of 981 or
# 9.81 off otherwise).
AT2_UNITS = re.compile(r"\bUNITS?\b\s*(?:OF|:|=|IN)?\s*([A-Z0-9/*^.\-]+)", re.I)


def read_at2(path, magnitude=None):
    """(t, values) of a PEER record: four header lines, the third naming
    the units (g), the fourth ``NPTS= n, DT= dt SEC`` or ``n dt NPTS, DT``;
    sample k at t = k dt; ``magnitude`` as for :func:`read_csv` (samples
    numbered from 1)."""
    try:
        with open(path) as f:
            lines = f.read().splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise RecordError(f"cannot read {path} ({getattr(exc, 'strerror', exc)})") from None
    lines += [""] * (4 - len(lines))
    _at2_units(path, lines[2])
    n, dt = _at2_header(path, lines[3])
    try:
        values = np.array(" ".join(lines[4:]).split(), dtype=float)
    except ValueError as exc:
        raise RecordError(f"{path}: not a number after the header ({exc})") from None
    if values.size < n:
        raise RecordError(f"{path}: header says {n} samples at DT = {dt:g}, "
                          f"found {values.size}")
    return _within(path, *_checked(path, dt * np.arange(n), values[:n]), magnitude,
                   "sample", 1)


def _at2_header(path, head):
    """(n, dt) of the fourth header line."""
    match = AT2_HEADS[0].search(head) or AT2_HEADS[1].search(head)
    if not match:
        raise RecordError(f"{path}: line 4 is neither 'NPTS= n, DT= dt SEC' nor "
                          f"'n dt NPTS, DT': {head.strip()!r}")
    text_n, text_dt = (g.rstrip(",") for g in match.groups())
    if not text_n.isdigit():
        raise RecordError(f"{path}: line 4: NPTS is not a whole number: {text_n!r}")
    if not _numeric(text_dt) or not 0 < float(text_dt) < float("inf"):
        raise RecordError(f"{path}: line 4: DT is not a positive number: {text_dt!r}")
    return int(text_n), float(text_dt)


def _at2_units(path, line):
    """Nothing if line 3 names no units or names g; RecordError otherwise."""
    match = AT2_UNITS.search(line)
    if match and match.group(1).rstrip(".,;").upper() != "G":
        raise RecordError(f"{path}: line 3: values in {match.group(1)}; vstpetsc reads PEER "
                          "records in g only (convert the file, or give it as a CSV with "
                          "its scale)")


def _checked(path, t, v):
    if t.size < 2:
        raise RecordError(f"{path}: needs at least two samples, got {t.size}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
        raise RecordError(f"{path}: samples must be finite")
    bad = np.nonzero(np.diff(t) <= 0)[0]
    if bad.size:
        raise RecordError(f"{path}: times must increase (sample {bad[0] + 2} at "
                          f"{t[bad[0] + 1]:g} after {t[bad[0]]:g})")
    return t, v


def _column_index(path, header, column):
    if isinstance(column, str) and not column.isdigit():
        if header is None or column not in header:
            known = ", ".join(header) if header else "none (no header line)"
            raise RecordError(f"{path}: no column named {column!r} (columns: {known})")
        index = header.index(column)
        if index == 0:
            raise RecordError(f"{path}: column {column!r} is the time column; name a column "
                              "of values")
        return index
    index = int(column) - 1
    if index < 1:
        raise RecordError(f"{path}: column {column} is time; give 2 or more")
    return index


def _numeric(text):
    try:
        float(text)
        return True
    except ValueError:
        return False
