"""Pile driving at equal accuracy: the bundled `pile` blow with vstpetsc
against the explicit lumped-mass Smith method (tests/references/smith.py),
and the cost of a soil slab against the floor.

- The converged set: Smith's sequence converges at first order in dx
  (dt = dx / 2c: its sets at 200, 400, 800 segments differ by 6.9 and 3.3
  um), so 2 s(800) - s(400) extrapolates it (400 and 200 with --quick);
  vstpetsc's sets on the way are reported beside it.
- Each method at the coarsest resolution (from its list) whose set is
  within 0.1 % of the converged one; vstpetsc at c dt/h = 0.5 as Smith.
- Time to solution, interleaved in this one process: vstpetsc a whole run
  through the API (PETSc started, its result file written), Smith its loop
  in numpy; min and median of ``reps`` runs each.
- The soil slab: the bundled example as shipped (50 elements, output every
  5 slabs), seconds per slab from its result's wall-time series over the
  middle 80 % of the blow, against one PCApply with its factored slab
  matrix (bench/overhead.py ``floor``); both with the compiled slab and
  with ``-vst_native 0``.

`make bench` runs it after bench/run.py and writes its section of
bench/README.md and bench/pile_speed.json.
"""

import argparse
import io
import json
import os
import statistics
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.append(os.path.join(os.path.dirname(HERE), "tests"))

import overhead  # noqa: E402
import pile_blow  # noqa: E402
import readme  # noqa: E402
from references import smith  # noqa: E402

SECTION = "## Pile driving at equal accuracy: against the explicit Smith method"
TOL = 1e-3


def converged_set(case, end, finest):
    """(the set extrapolated from Smith at finest / 2 and finest segments,
    Smith's sets {segments: set})."""
    sets = {n: smith.run(case, n, end)["set"] for n in (finest // 2, finest)}
    return 2.0 * sets[finest] - sets[finest // 2], sets


def coarsest(sizes, set_of, reference):
    """The first size whose set is within TOL of ``reference`` and the
    sets seen on the way {size: set}."""
    seen = {}
    for n in sizes:
        seen[n] = set_of(n)
        if abs(seen[n] - reference) <= TOL * reference:
            return n, seen
    return n, seen                       # not reached: the finest (its error shows it)


def interleaved(runs, reps):
    """{name: [seconds]} of the callables ``runs`` {name: f}, one of each
    in turn, ``reps`` times."""
    times = {name: [] for name in runs}
    for _ in range(reps):
        for name, f in runs.items():
            times[name].append(f())
    return times


def soil_slab(case, reps, options=()):
    """(min, median) seconds a slab of the bundled pile, and the share of
    its slabs in which the soil acted (Newton ran)."""
    import h5py
    import vstpetsc

    per, active = [], 0.0
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "pile.h5")
        for _ in range(reps):
            vstpetsc.run(case, output=path, options=list(options), quiet=True,
                         out=io.StringIO())
            with h5py.File(path, "r") as f:
                wall, slab = f["solver/wall_time"][()], f["solver/slab"][()]
                newton = f["solver/newton_iterations"][()]
            lo, hi = int(0.1 * wall.size), int(0.9 * wall.size)
            per.append((wall[hi] - wall[lo]) / (slab[hi] - slab[lo]))
            active = float(np.mean(newton[lo:hi] > 0))
    return min(per), statistics.median(per), active


def measure(quick):
    from vstpetsc import Case, bundled

    case = Case.from_toml(bundled.path("pile"))
    end = case.nslabs * case.dt
    reference, smith_sets = converged_set(case, end, 400 if quick else 800)
    vst_sizes = (8, 16, 25, 50) if quick else (8, 10, 12, 14, 16, 20, 25, 50, 100)
    nv, vst_sets = coarsest(vst_sizes, lambda n: pile_blow.vstpetsc_blow(case, n)["set"], reference)
    ns, peer_sets = coarsest((50, 100, 200, 400, 800), lambda n: smith_sets.get(n) or
                             smith.run(case, n, end)["set"], reference)
    reps = 3 if quick else 7
    times = interleaved({"vstpetsc": lambda: pile_blow.vstpetsc_blow(case, nv)["wall"],
                         "smith": lambda: smith.run(case, ns, end)["wall"]}, reps)
    text = open(bundled.path("pile")).read()
    floor = overhead.floor(text, reps=3 if quick else 5)
    slabs = {"compiled": soil_slab(case, reps=2 if quick else 5),
             "python": soil_slab(case, reps=1 if quick else 3, options=["-vst_native", "0"])}
    return {"reference": reference, "smith_sets": smith_sets, "tol": TOL,
            "vstpetsc": {"size": nv, "sets": vst_sets, "min": min(times["vstpetsc"]),
                         "median": statistics.median(times["vstpetsc"])},
            "smith": {"size": ns, "sets": peer_sets, "min": min(times["smith"]),
                      "median": statistics.median(times["smith"])},
            "floor": {"min": floor[0], "median": floor[1]},
            "slab": {k: {"min": v[0], "median": v[1], "active": v[2]} for k, v in slabs.items()}}


def section(res):
    v, s, fl = res["vstpetsc"], res["smith"], res["floor"]
    ref = res["reference"]
    rows = [f"| vstpetsc | {v['size']} elements | {1e3 * v['sets'][v['size']]:.4f} | "
            f"{100 * (v['sets'][v['size']] / ref - 1):+.3f} | {1e3 * v['min']:.1f} | "
            f"{1e3 * v['median']:.1f} |",
            f"| Smith (explicit) | {s['size']} segments | {1e3 * s['sets'][s['size']]:.4f} | "
            f"{100 * (s['sets'][s['size']] / ref - 1):+.3f} | {1e3 * s['min']:.1f} | "
            f"{1e3 * s['median']:.1f} |"]
    slab_rows = [f"| {name} | {1e6 * r['min']:.1f} / {1e6 * r['median']:.1f} | "
                 f"{1e6 * fl['min']:.2f} / {1e6 * fl['median']:.2f} | "
                 f"{r['min'] / fl['min']:.1f} / {r['median'] / fl['median']:.1f} | "
                 f"{100 * r['active']:.0f} % |" for name, r in res["slab"].items()]
    coarser = ", ".join(f"{n}: {1e3 * x:.4f}" for n, x in v["sets"].items())
    return "\n".join([
        SECTION, "",
        f"Converged set {1e3 * ref:.4f} mm (Smith at {min(res['smith_sets'])} and "
        f"{max(res['smith_sets'])} segments extrapolated at first order; vstpetsc's sets "
        f"on the way [mm]: {coarser}). Each method at the "
        f"coarsest resolution within {100 * res['tol']:g} % of it (c dt/h = 0.5 for both); "
        "time to solution interleaved in one process (vstpetsc: a whole run through the API, "
        "result file written).", "",
        "| method | resolution | set [mm] | error [%] | time min [ms] | time median [ms] |",
        "|---|---|---|---|---|---|", *rows, "",
        f"Smith's time over vstpetsc's: {s['min'] / v['min']:.2f} (min), "
        f"{s['median'] / v['median']:.2f} (median); goal >= 1.", "",
        "A slab of the bundled `pile` (50 elements, output every 5 slabs) against one PCApply "
        "of its slab matrix (goal: the compiled slab within 50 times):", "",
        "| path | slab [us] min / median | floor [us] min / median | ratio min / median | "
        "kept slabs with a Newton step |", "|---|---|---|---|---|", *slab_rows, ""])


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default=HERE)
    args = ap.parse_args(argv)
    res = measure(args.quick)
    with open(os.path.join(args.out, "pile_speed.json"), "w") as f:
        json.dump(res, f, indent=1)
    text = section(res)
    readme.write_readme(os.path.join(args.out, "README.md"), text)
    print(text)


if __name__ == "__main__":
    sys.exit(main())
