"""How closely two arithmetic paths agree, and why: the tolerance each
pair of paths guarantees on any x86-64 CPU.

Bit equality is asserted only between paths built to give the same bits:
the same operations, in the same order, on the same numbers (a restart
against the uninterrupted run, a file against its copy or its export, a C
kernel compiled with -ffp-contract=off against a Python twin made of the
same elementwise operations).  IEEE 754 rounds +, -, *, / and sqrt
exactly, so those agree on every CPU whatever vector width does them.

Two paths that differ in the order of a sum, in BLAS (OpenBLAS picks its
kernel per CPU, with fused multiply-adds or without), in a reduction that
the C compiler vectorises (its width set by -march) or in a
transcendental (numpy picks its pow, exp and log kernels per CPU: AVX2,
AVX-512 SVML or the C library's) agree to rounding only:

- every dataset within ``rtol`` of its own largest value (an envelope,
  ``*_min`` or ``*_max``: of the larger of the pair);
- an energy term within ``rtol`` of the largest energy of the run: the
  numerical energy and the transferred work are small differences of
  large energies, so their own size says nothing of their rounding.

``make test-portable`` runs the suite with numpy's dispatch narrowed, the
BLAS kernel of an older CPU and the C kernels built for the baseline
x86-64 and for this CPU, so that a test that leans on one CPU's rounding
shows up on this machine.
"""

import h5py
import numpy as np

EPS = np.finfo(np.float64).eps
# One pow, exp or log and the few exact roundings after it: glibc's libm
# and numpy's SIMD kernels each round within a few ulp of the exact value
# (numpy's own accuracy tests, core/tests/test_umath_accuracy.py, hold its
# float64 SIMD kernels to at most 4).
TRANSCENDENTAL_RTOL = 8 * EPS
SKIPPED = ("solver/wall_time",)          # a clock, not a result


def datasets(result):
    """{name: array} of every dataset of a result file (a path or a Result)."""
    out = {}
    with h5py.File(str(getattr(result, "path", result)), "r") as f:
        f.visititems(lambda name, obj: out.__setitem__(name, obj[()])
                     if isinstance(obj, h5py.Dataset) else None)
    return out


def is_energy(key):
    """Whether a dataset holds energy terms (the series, or the running sums
    a restart reads)."""
    return key.startswith("energy/") or key == "solver/energy_sums"


def energy_scale(data):
    """The largest energy of a run ({name: array} of its datasets): what an
    energy term's rounding is measured against."""
    terms = [np.nanmax(np.abs(x), initial=0.0) for k, x in data.items()
             if k.startswith("energy/") and x.size]
    return max(terms, default=0.0) or 1.0


def field_scale(data, key):
    """The largest |value| of the field a dataset holds: its own, or, for
    one envelope of a pair (``stress_min``, ``stress_max``), of both (an
    envelope that stays small beside the other is rounding of the field,
    not of itself); for a 2-D interface's ``slip``, ``gap`` or ``stretch``,
    of all three: each is a relative displacement of the same node pairs,
    and a joint that sticks has a slip of the displacements' rounding
    (rockfill-dam-mkz at 0.3 s: 4e-11 m of slip beside 2.7 mm of opening;
    gravity-dam-reservoir's stick springs' stretch on two ranks 1.3e-10 of
    its own largest, with the redundant LU)."""
    own = np.nanmax(np.abs(data[key]))
    relative = ("/slip", "/gap", "/stretch")
    pairs = [("_min", "_max"), ("_max", "_min")] + \
        [(end, other) for end in relative for other in relative if other != end]
    for end, other in pairs:
        if key.endswith(end) and key[:-len(end)] + other in data and \
                (end[0] == "_" or key.startswith("interface/")):
            own = max(own, np.nanmax(np.abs(data[key[:-len(end)] + other])))
    return own or 1.0


def differences(da, db, skip=SKIPPED):
    """{name: largest |a - b| over the scale it is measured against} for
    every dataset of two runs (NaN where one is NaN and the other not)."""
    assert da.keys() == db.keys(), set(da) ^ set(db)
    energy = max(energy_scale(da), energy_scale(db))
    out = {}
    for key, x in da.items():
        y = db[key]
        if key in skip or key.endswith("iterations"):
            continue
        assert x.shape == y.shape, key
        if not x.size:
            continue
        if x.dtype.kind not in "fc":          # counts, indices, names: exact
            out[key] = 0.0 if np.array_equal(x, y) else np.inf
            continue
        if not np.array_equal(np.isnan(x), np.isnan(y)):
            out[key] = np.nan
            continue
        scale = energy if is_energy(key) else field_scale(da, key)
        out[key] = np.nanmax(np.abs(x - y), initial=0.0) / scale
    return out


def unequal(da, db, skip=SKIPPED):
    """{name: first row that differs} of the datasets of two runs that must
    agree bit for bit ("shape" where the shapes differ).  Every one is
    named: the first in name order that carries data, energy/damping,
    differs whatever diverged, and the rows tell a state that drifted from
    the start from one that parted at a restart."""
    out = {}
    for key in sorted(set(da) | set(db)):
        x, y = da.get(key), db.get(key)
        if key in skip:
            continue
        if x is None or y is None or x.shape != y.shape:
            out[key] = "shape"
        elif not np.array_equal(x, y):
            rows = (x != y).reshape(x.shape[0], -1).any(axis=1) if x.ndim else [True]
            out[key] = int(np.argmax(rows))
    return out


def assert_runs_agree(a, b, rtol, iterations=0, skip=SKIPPED):
    """Two result files (or their datasets) of one case by two paths agree
    to ``rtol`` (module docstring); their Newton iteration counts differ by
    at most ``iterations`` in every slab (None: not compared)."""
    da = a if isinstance(a, dict) else datasets(a)
    db = b if isinstance(b, dict) else datasets(b)
    off = {k: d for k, d in differences(da, db, skip).items() if not d <= rtol}
    assert not off, off
    if iterations is not None:
        for key in da:
            if key.endswith("iterations") and key not in skip:
                assert np.abs(da[key] - db[key]).max(initial=0) <= iterations, key
