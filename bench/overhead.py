"""Per-slab cost at the sizes people run (100 to 10 000 elements, output
every slab) against the floor: one PCApply with the factored slab matrix of
the same case, timed in the same process right after the run.

Cases (a steel bar of 1 m, a `vstpetsc run` in a subprocess, output every
slab; the time per slab is read from the result file's wall-time series
over the middle of the run, so start-up and the last block do not count):

- free: clamped at its left end, vibrating (c dt/h = 0.5);
- held: between two rigid walls at zero gap, v0 = 1 m/s (c dt/h = 0.5):
  it presses on one wall, then on the other, so every slab has an active
  pair, closed over the whole slab (one Newton iteration);
- impact: the same at c dt/h = 1 (the bundled examples' ratio): the
  contact node chatters, the gap opens and closes inside slabs (three to
  four Newton iterations);
- soil: the bar driven into Smith soil (v0 = 1 m/s, c dt/h = 0.5; R_u =
  20 MN, 30 % at its right end's toe, the shaft on its last ten elements
  whatever their size, so the soil's nodes are as many at every size): the
  soil acts in every slab.

Used by bench/run.py.
"""

import os
import statistics
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

import limit   # the floor: one solve with the factored slab matrix, timed
from cases import steel_bar

VSTPETSC = os.path.join(os.path.dirname(sys.executable), "vstpetsc")
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = {"free": 0.5, "held": 0.5, "impact": 1.0, "soil": 0.5}       # name: c dt / h
SOIL_ELEMENTS = 10          # the soil's shaft: the bar's last elements
SOIL_SLABS = 2000           # at most (its Newton runs in Python: ~1-3 ms a slab)


def case_text(kind, elements, slabs):
    """The case file of ``kind`` (see the module) with ``elements`` elements."""
    text = steel_bar(elements, slabs, CASES[kind], every=1)
    if kind == "free":
        return text + ("v0 = [[0.0, 0.0], [1.0, 1.0]]\n"
                       "[[bc]]\nbody = \"bar\"\nend = \"left\"\ntype = \"fixed\"\n")
    if kind == "soil":
        top = 1.0 - SOIL_ELEMENTS / elements
        return text + ("v0 = 1.0\n[[soil]]\nbody = \"bar\"\ncapacity = 2.0e7\ntoe_share = 0.3\n"
                       f"shaft = {{ quake = 2.5e-3, damping = 0.16, from = {top!r}, to = 1.0 }}\n"
                       "toe = { quake = 2.5e-3, damping = 0.5, end = \"right\" }\n")
    return text + ("v0 = 1.0\n[[contact]]\npair = [\"bar\", \"wall\"]\nwall = 1.0\n"
                   "[[contact]]\npair = [\"wall\", \"bar\"]\nwall = 0.0\n")


def floor(text, solves=200, reps=5):
    """(min, median) seconds of one PCApply with the factored slab matrix of
    the case ``text`` (vstpetsc's own solver of it)."""
    linear, b, x = limit.factored_slab(text)
    return limit.seconds_per_call(linear.pc.apply, b, x, solves, reps)


def per_slab(path, contact, law=False):
    """(seconds per slab, mean Newton iterations, share of slabs with an
    active law) over the middle 80 % of a result file's slabs; for a
    contact case over its slabs where a pair carries a force only (a
    pair may let go for a while as the waves pass; a steady contact may
    need no Newton step: its guess from the slab before already holds);
    ``law``: a law must act (Newton) in most slabs."""
    with h5py.File(path, "r", locking=False) as f:
        wall = f["solver/wall_time"][...]
        newton = f["solver/newton_iterations"][...]
        acting = np.any([g["impulse"][...] > 0 for g in f["contact"].values()], axis=0) \
            if contact else newton > 0
    n = wall.size - 1
    a, b = max(1, n // 10), n - n // 10
    step = np.diff(wall)[a - 1:b - 1]          # slab i's time: wall[i] - wall[i - 1]
    its, on = newton[a:b], acting[a:b]
    active = float(np.mean(on))
    if law and active < 0.5:
        raise RuntimeError(f"{path}: a law acts in only {100 * active:.0f} % of slabs")
    if not contact:
        return float(step.mean()), float(its.mean()), active
    if active < 0.5:
        raise RuntimeError(f"{path}: a contact pair acts in only {100 * active:.0f} % of slabs")
    return float(step[on].mean()), float(its[on].mean()), active


def run_once(folder, text, options=()):
    """Seconds of a whole `vstpetsc run` of ``text`` (start-up included)."""
    path = os.path.join(folder, "case.toml")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(folder, "r.h5")
    t0 = time.perf_counter()
    p = subprocess.run([VSTPETSC, "run", path, "-o", out, "--quiet", *options],
                       capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(p.stderr)
    return time.perf_counter() - t0, out


def overhead(kind, elements, slabs, reps=5, options=()):
    """One row of the table: per-slab time (min, median over ``reps`` runs),
    the floor (min, median) and their ratios; ``options`` for the runs."""
    text = case_text(kind, elements, slabs)
    times, newton, active = [], 0.0, 1.0
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(reps):
            _, out = run_once(folder, text, options)
            t, newton, active = per_slab(out, kind in ("held", "impact"), kind == "soil")
            times.append(t)
    lo, mid = floor(text)
    name = kind + (f" ({' '.join(options)})" if options else "")
    return {"case": name, "elements": elements, "slabs": slabs,
            "slab_min_us": 1e6 * min(times), "slab_median_us": 1e6 * statistics.median(times),
            "floor_min_us": 1e6 * lo, "floor_median_us": 1e6 * mid,
            "ratio": min(times) / lo, "ratio_median": statistics.median(times) / mid,
            "newton_mean": newton, "active_share": active}


def example_wall(name="bar-wall", reps=5):
    """(min, median) seconds of a whole `vstpetsc run` of a bundled example,
    start-up included."""
    text = open(os.path.join(ROOT, "examples", f"{name}.toml")).read()
    with tempfile.TemporaryDirectory() as folder:
        times = [run_once(folder, text)[0] for _ in range(reps)]
    return min(times), statistics.median(times)


def slabs_for(kind, elements, quick):
    """Slabs enough for ~0.3 s of running and the first blocks' fresh
    buffers (a page fault costs 3.6-10 us on the bench's VM) a small part of
    the middle of the run (fewer when quick); output every slab makes 24
    bytes a node a slab, so at 10 000 elements 3000 slabs write 720 MB."""
    if quick:
        slabs = 800 if elements <= 100 else 300     # (the suite runs it: fields, not speed)
    else:
        slabs = int(min(30_000, max(3000, 3e6 / elements)))
    return min(slabs, SOIL_SLABS) if kind == "soil" else slabs
