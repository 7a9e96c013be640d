"""Benchmarks of vstpetsc: `make bench` (full, writes bench/results.json and
bench/README.md) and `make bench-quick` (small sizes, under a minute).

    python bench/run.py [--quick] [--out FOLDER] [--readme-only]

README.md: the head and this script's sections, then the sections the
benchmarks after it write (bench/readme.py), kept as they are;
--readme-only rewrites this script's part from results.json alone.

Every ratio is measured in one run on one machine; repeated timings report
min and median.  Speed is reported, never asserted.
"""

import argparse
import json
import math
import os
import platform
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import limit  # noqa: E402
import overhead  # noqa: E402
import peer   # noqa: E402
import pile_blow  # noqa: E402
from readme import with_other_sections  # noqa: E402

TARGETS = (1e-4, 1e-6, 1e-8)


def slabs_for(elements):
    """Slabs per run of the limit table: the difference of runs of n and 2n
    slabs must dwarf the noise of one run (~20 ms here)."""
    return int(min(20_000, max(50, 3e7 / elements)))


OVERHEAD_GOALS = {("free", 100): 15, ("free", 10_000): 1.5, ("held", 100): 25,
                  ("held", 1000): 5, ("held", 10_000): 2, ("impact", 100): 25,
                  ("impact", 1000): 5, ("impact", 10_000): 2}


def measure_overhead(quick):
    """The small-size table: per-slab cost with output every slab against
    one PCApply of the same case, and the whole bar-wall example."""
    sizes = [100, 1000] if quick else [100, 1000, 10_000]
    reps = 1 if quick else 5          # (quick: the fields, once; `make bench` repeats)
    rows = []
    for n in sizes:
        for kind in overhead.CASES:
            row = overhead.overhead(kind, n, overhead.slabs_for(kind, n, quick), reps)
            row["goal"] = OVERHEAD_GOALS.get((kind, n))
            rows.append(row)
            print(f"overhead {kind} {n}: {row['ratio']:.1f} x floor", flush=True)
    # the Python path, for comparison (quick: the small size only)
    python = [(kind, 100) for kind in ("free", "held", "impact")] + \
        ([] if quick else [("free", sizes[-1])])
    for kind, n in python:
        rows.append(overhead.overhead(kind, n, overhead.slabs_for(kind, n, quick), reps,
                                      options=("-vst_native", "0")))
        rows[-1]["goal"] = None
    lo, mid = overhead.example_wall(reps=reps)
    return {"rows": rows, "bar_wall_min_s": lo, "bar_wall_median_s": mid}


def measure(quick):
    sizes = [1000, 10_000] if quick else [1000, 10_000, 100_000, 1_000_000]
    reps = 1 if quick else 3
    res = {"quick": quick, "machine": f"{platform.node()} {os.cpu_count()} cores",
           "date": time.strftime("%Y-%m-%d"), "limit": [], "contact": {}, "peer": {}}
    for n in sizes:
        slabs = slabs_for(n)
        smin, smed, amin, amed = limit.solve_time(n, reps=reps)
        rmin, rmed, mem = limit.run_time(n, slabs, reps=reps)
        res["limit"].append({"elements": n, "slabs": slabs, "solve_min_ms": 1e3 * smin,
                             "solve_median_ms": 1e3 * smed, "apply_min_ms": 1e3 * amin,
                             "apply_median_ms": 1e3 * amed, "slab_min_ms": 1e3 * rmin,
                             "slab_median_ms": 1e3 * rmed, "ratio": rmin / smin,
                             "ratio_median": rmed / smed, "ratio_apply": rmin / amin,
                             "peak_memory_MB": mem})
        print(f"limit {n}: {res['limit'][-1]}", flush=True)
    ne = sizes[-1] if quick else 100_000
    # quick: enough slabs to beat the noise, while the bar stays on the wall (2L/c: 4 ne slabs)
    slabs = 1500 if quick else max(20, slabs_for(ne) // 4)
    free = limit.run_time(ne, slabs, contact=False, reps=reps)   # the contact case's dt
    touch = limit.run_time(ne, slabs, contact=True, reps=reps)
    res["contact"] = {"elements": ne, "slabs": slabs, "no_contact_ms": 1e3 * free[0],
                      "contact_ms": 1e3 * touch[0], "ratio": touch[0] / free[0]}
    print(f"contact: {res['contact']}", flush=True)
    res["overhead"] = measure_overhead(quick)
    from vstpetsc import Case, bundled
    pile = Case.from_toml(bundled.path("pile"))
    res["pile"] = pile_blow.compare(pile, (25, 50) if quick else (25, 50, 100),
                                (50, 100, 200) if quick else (50, 100, 200, 400))
    x = np.log([r["elements"] for r in res["limit"]])
    y = np.log([r["slab_min_ms"] for r in res["limit"]])
    res["growth_exponent"] = float(np.polyfit(x[-3:], y[-3:], 1)[0])
    sm = peer.smooth(elements=50 if quick else 200,
                     counts=(16, 32, 64) if quick else tuple(2 ** np.arange(4, 14)),
                     alpha_counts=None if quick else tuple(2 ** np.arange(4, 16)))
    res["peer"]["smooth"] = sm
    res["peer"]["wall_for_error"] = {
        key: {f"{t:g}": peer.wall_for_error(sm[key], t) for t in TARGETS}
        for key in sm if isinstance(sm[key], list)}
    res["peer"]["impact"] = peer.impact(elements=20 if quick else 50)
    res["peer"]["impact_accuracy"] = peer.impact_accuracy(quick=quick)
    print(f"peer: {res['peer']['wall_for_error']}", flush=True)
    return res


def readme(res):
    lim = res["limit"]
    lines = ["# Benchmarks", "",
             f"Generated by `bench/run.py` (`make bench`) on {res['machine']}, "
             f"{res['date']}; do not edit. One rank.", "",
             "## Against the physical limit", "",
             "Time per slab of a whole `vstpetsc run` (clamped steel bar, no contact, "
             "c dt/h = 0.5, output every 10^5 slabs; the difference of runs of n and 2n "
             "slabs, so fixed costs cancel) over the time of one KSPSolve with PETSc's "
             "LU factors (natural ordering) of the slab matrix A = HM (x) M + dt^2 HK (x) "
             "K; min and median of repetitions; the ratio uses the minima, the median "
             "ratio the medians. KSPSolve of KSPPREONLY zeroes the solution before it "
             "applies the factors; `vstpetsc run` applies them directly, so the table "
             "also gives one PCApply and the ratio to it, the stricter limit. Goals: ratio "
             "<= 1.5 at 1e5 and 1e6 elements, contact slab <= 2.5 times a slab without "
             "contact, memory < 1 GB at 1e6.", "",
             "| elements | slabs | one KSPSolve [ms] min / median | one PCApply [ms] min "
             "| slab [ms] min / median | ratio | median ratio | ratio to PCApply "
             "| peak memory [MB] |", "|---|---|---|---|---|---|---|---|---|"]
    for r in lim:
        lines.append(f"| {r['elements']} | {r['slabs']} | {r['solve_min_ms']:.3f} / "
                     f"{r['solve_median_ms']:.3f} | {r['apply_min_ms']:.3f} | "
                     f"{r['slab_min_ms']:.3f} / {r['slab_median_ms']:.3f} | "
                     f"{r['ratio']:.2f} | {r['ratio_median']:.2f} | {r['ratio_apply']:.2f} | "
                     f"{r['peak_memory_MB']:.0f} |")
    c = res["contact"]
    lines += ["", f"Growth: time per slab ~ elements^{res['growth_exponent']:.2f} over the "
              "three largest sizes.", "",
              f"A slab with an active contact pair (bar pressed on a wall, {c['elements']} "
              f"elements): {c['contact_ms']:.3f} ms against {c['no_contact_ms']:.3f} ms "
              f"without contact, ratio {c['ratio']:.2f}."]
    return "\n".join(lines + peer_section(res) + accuracy_section(res)
                     + overhead_section(res) + pile_section(res) + reading(res)) + "\n"


def table_head(title, intro, columns):
    """A README section's title, its paragraph and a table's head."""
    return ["", f"## {title}", "", intro, "", "| " + " | ".join(columns) + " |",
            "|" + "---|" * len(columns)]


def pile_section(res):
    """The bundled pile blow against the lumped-mass Smith algorithm."""
    pile = res.get("pile")
    if not pile:
        return []
    lines = table_head(
        "Pile driving: against the lumped-mass Smith algorithm",
        "The bundled `pile` blow (20 m steel pipe pile, 3 t ram at 4.43 m/s, cushion, "
        "Smith soil of 1.5 MN) with vstpetsc (the whole run, file included) and with the "
        "classical explicit lumped-mass algorithm of Smith (1960) written in numpy "
        "(tests/references/smith.py, dt = dx / 2c, best of 3).",
        ("method", "resolution", "steps", "set [mm]", "compression [MPa]", "tension [MPa]",
         "transferred [kJ]", "wall [s]"))
    for key, label in (("vstpetsc", "elements"), ("smith", "segments")):
        for r in pile[key]:
            lines.append(f"| {key} | {r[label]} {label} | {r['steps']} | {1e3 * r['set']:.4f} | "
                         f"{-1e-6 * r['stress_min']:.2f} | {1e-6 * r['stress_max']:.2f} | "
                         f"{1e-3 * r['transferred']:.3f} | {r['wall']:.3f} |")
    return lines


def peer_section(res):
    """Tables (a) and (b) against TSALPHA2."""
    lines = ["", "## Against PETSc's TSALPHA2 (generalized-alpha Newmark)", "",
              f"(a) Smooth vibration of a clamped bar ({res['peer']['smooth']['elements']} "
              "elements, modes 1 and 2) to 1.3 periods of mode 1: relative max error of u "
              "and v (the larger) against the semi-discrete modal solution, and wall time "
              "of the whole integration (vstpetsc: a whole `run` in-process, file "
              "included; TSALPHA2: set-up and solve).", "",
              "| method | steps | error | wall [s] |", "|---|---|---|---|"]
    sm = res["peer"]["smooth"]
    for key in [k for k in sm if isinstance(sm[k], list)]:
        for p in sm[key]:
            lines.append(f"| {key} | {p['steps']} | {p['error']:.2e} | {p['wall']:.3f} |")
    lines += ["", "Wall time needed for a relative error of:", "",
              "| method | " + " | ".join(f"{t:g}" for t in TARGETS) + " |",
              "|---|" + "---|" * len(TARGETS)]
    for key, row in res["peer"]["wall_for_error"].items():
        cells = ["not reached" if row[f"{t:g}"] is None else f"{row[f'{t:g}']:.3f} s"
                 for t in TARGETS]
        lines.append(f"| {key} | " + " | ".join(cells) + " |")
    im = res["peer"]["impact"]
    lines += ["", f"(b) Two identical bars, {im['elements_per_bar']} elements each, "
              f"dt = {im['dt']:g} (c dt/h = 0.5), the same penalty force law "
              f"f = k max(0, -g), k = {im['penalty']:g} (vstpetsc: power formulation). "
              "Force oscillation = standard deviation over mean on the middle 80 % of "
              "the contact phase (exact force 0.5).", "",
              "| method | plateau force | oscillation | contact duration (exact 2) | "
              "energy after | wall [s] |", "|---|---|---|---|---|---|"]
    for key in [k for k in im if isinstance(im[k], dict)]:
        m = im[key]
        lines.append(f"| {key} | {m['plateau_mean']:.4f} | {m['oscillation']:.4f} | "
                     f"{m['duration']:.3f} | {100 * m['energy_after']:+.2f} % | "
                     f"{m['wall']:.3f} |")
    return lines


def accuracy_section(res):
    """(c) the impact at equal accuracy of the contact force (issue 15)."""
    acc = res["peer"].get("impact_accuracy")
    if not acc:
        return []
    methods = [k for k in acc if isinstance(acc[k], list)]
    lines = ["", f"(c) The same impact at equal accuracy of the contact force: "
             f"{acc['elements_per_bar']} elements a bar, penalty k = {acc['penalty']:g} "
             f"(beta = {acc['beta']:g}) fixed for every dt. Error: relative L2 norm of the "
             f"force over the run against {acc['reference']} (the time-integration error "
             "alone; vstpetsc's slab means against the reference's means, TSALPHA2's "
             "step-end values against the reference there). beta = 1, not the default "
             "50: at 50 the semi-discrete contact chatters and no reference converges "
             "(see bench/peer.py). Wall: best of "
             f"{acc['repeats']} whole runs (vstpetsc: file included).", "",
             "| dt | " + " | ".join(f"{m} error / wall [ms]" for m in methods) + " |",
             "|---|" + "---|" * len(methods)]
    for i, row in enumerate(acc[methods[0]]):
        lines.append(f"| {row['dt']:.4g} | " + " | ".join(
            f"{acc[m][i]['error']:.2e} / {1e3 * acc[m][i]['wall']:.1f}" for m in methods) + " |")
    targets = list(acc["wall_for_error"][methods[0]])
    lines += ["", "Wall time to stay below an error (TSALPHA2 over vstpetsc in brackets):", "",
              "| method | " + " | ".join(targets) + " |", "|---|" + "---|" * len(targets)]
    for m in methods:
        cells = []
        for e in targets:
            w = acc["wall_for_error"][m][e]
            ratio = acc["ratio_to_vstfem"].get(m, {}).get(e) if m != "vstfem" else None
            cells.append("not reached" if w is None else f"{1e3 * w:.1f} ms"
                         + (f" ({ratio:.2f} x)" if ratio else ""))
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    orders = ", ".join(f"{m} {o:.2f}" for m, o in acc["order_fine"].items() if o)
    lines += ["", f"Fitted orders over the three finest dt: {orders}."]
    return lines


def overhead_section(res):
    """The table of per-slab costs at small sizes (issue 15)."""
    ov = res.get("overhead")
    if not ov:
        return []
    lines = table_head(
        "At the sizes people run: per-slab cost against the floor",
        "A whole `vstpetsc run` in a subprocess with output every slab; time per slab "
        "from the result file's wall-time series over the middle 80 % of the run "
        "(start-up and the last block excluded); the floor is one PCApply with the "
        "factored slab matrix of the same case, timed in the same process run as "
        "the table. Cases (bench/overhead.py): free = clamped bar vibrating, c dt/h "
        "= 0.5; held = bar between two walls at zero gap, pressing on one or the "
        "other in every slab, c dt/h = 0.5; impact = the same at c dt/h = 1 (the "
        "contact node chatters, the gap opens and closes inside slabs); soil = the bar "
        "driven at 1 m/s into Smith soil on its last ten elements and its toe (the soil "
        "acts in every slab; at most 2000 slabs). A goal is met when both the minimum "
        "and the median ratio meet it. Rows marked (-vst_native 0) ran the Python path "
        "instead of the compiled kernels (the penalty pairs' slab, the end of a slab).",
        ("case", "elements", "slabs", "slab [us] min / median", "floor [us] min / median",
         "ratio min / median", "goal", "Newton its / slab"))
    for r in ov["rows"]:
        met = r["goal"] is not None and max(r["ratio"], r["ratio_median"]) <= r["goal"]
        goal = "" if r["goal"] is None else f"<= {r['goal']:g} ({'met' if met else 'not met'})"
        lines.append(f"| {r['case']} | {r['elements']} | {r['slabs']} | "
                     f"{r['slab_min_us']:.1f} / {r['slab_median_us']:.1f} | "
                     f"{r['floor_min_us']:.2f} / {r['floor_median_us']:.2f} | "
                     f"{r['ratio']:.1f} / {r['ratio_median']:.1f} | {goal} | "
                     f"{r['newton_mean']:.2f} |")
    lines += ["", f"The whole `vstpetsc run examples/bar-wall.toml` (start-up included): "
              f"{ov['bar_wall_min_s']:.2f} s min, {ov['bar_wall_median_s']:.2f} s median "
              "(goal < 1 s)."]
    return lines


def reading(res):
    """Where v-ST/FEM wins and where it does not, from the numbers above."""
    lim = {r["elements"]: r for r in res["limit"]}
    out = ["", "## Reading", ""]
    big = [n for n in (100_000, 1_000_000) if n in lim]
    if big:
        met = all(lim[n]["ratio"] <= 1.5 for n in big)
        out.append("- Limit ratio: " + ", ".join(f"{lim[n]['ratio']:.2f} at {n}" for n in big)
                   + (" (goal 1.5: met)" if met else " (goal 1.5: not met)")
                   + "; to one PCApply: " + ", ".join(f"{lim[n]['ratio_apply']:.2f}"
                                                      for n in big)
                   + ". Besides the solve, a slab costs one product with a matrix of three "
                   "entries a row (the right-hand side is a running sum) and one vector sum "
                   "for the displacement: see docs/solver.md.")
    c = res["contact"]
    out.append(f"- A contact slab costs {c['ratio']:.2f} slabs without contact (goal 2.5: "
               f"{'met' if c['ratio'] <= 2.5 else 'not met'}): one solve, then Newton on "
               "the pair dofs only.")
    sm, wfe = res["peer"]["smooth"], res["peer"]["wall_for_error"]
    top = {k: max(p["steps"] for p in sm[k]) for k in sm if isinstance(sm[k], list)}
    for t in TARGETS:
        v, a = wfe["vstfem"][f"{t:g}"], wfe["alpha2_r1"][f"{t:g}"]
        if v is not None and a is not None:
            out.append(f"- Smooth, error {t:g}: v-ST/FEM {a / v:.1f} times faster than "
                       "trapezoidal Newmark (third order against second).")
        elif v is not None:
            out.append(f"- Smooth, error {t:g}: v-ST/FEM in {v:.3f} s; TSALPHA2 did not reach "
                       f"it within {top['alpha2_r1']} steps.")
    e = [p["error"] for p in sm["alpha2_r0.5"]]
    if len(e) > 2:
        order = np.log(e[-2] / e[-1]) / np.log(2)
        out.append(f"- TSALPHA2 with radius 0.5 converged at order {order:.2f} on the smooth "
                   "problem" + (" (its error halves with dt), so it reached no target; we did "
                                "not find why (its start-up step is a suspect)." if order < 1.5
                                else "."))
    im = res["peer"]["impact"]
    vs, r1, r5 = im["vstfem"], im["alpha2_r1"], im["alpha2_r0.5"]
    out += [f"- Impact, same dt and penalty: trapezoidal Newmark (radius 1) has no "
            f"high-frequency damping, and the stiff penalty spring rings: force oscillation "
            f"{r1['oscillation']:.2f}, energy after separation {100 * r1['energy_after']:+.1f} %; "
            f"v-ST/FEM: {vs['oscillation']:.3f} and {100 * vs['energy_after']:+.2f} %.",
            f"- Where v-ST/FEM does not win: generalized-alpha with radius 0.5 gives a "
            f"smoother contact force ({r5['oscillation']:.4f} against {vs['oscillation']:.3f}) "
            f"with a similar energy loss ({100 * r5['energy_after']:+.2f} %), and on these "
            "small meshes it is faster per run (wall times above): a slab solves a system "
            "twice the size of a Newmark step, and vstpetsc writes its result file as it goes."]
    return out + accuracy_reading(res) + [""]


def accuracy_reading(res):
    """What table (c) says, from its numbers."""
    acc = res["peer"].get("impact_accuracy")
    if not acc:
        return []
    out = []
    for m, ratios in acc["ratio_to_vstfem"].items():
        got = {e: r for e, r in ratios.items() if r}
        if got:
            out.append(f"- Impact at equal force accuracy, {m}: TSALPHA2 takes "
                       + ", ".join(f"{r:.2f} x vstpetsc's wall time for error {e}"
                                   for e, r in got.items())
                       + (" (vstpetsc faster)" if min(got.values()) > 1 else
                          " (vstpetsc not faster everywhere)") + ".")
    v = acc["vstfem"][-1]
    a = acc[[m for m in acc["ratio_to_vstfem"]][0]][-1]
    per_a, per_v = 1e6 * a["wall"] / a["steps"], 1e6 * v["wall"] / v["steps"]
    cheaper = "TSALPHA2 is cheaper" if per_a < per_v else "vstpetsc is as cheap or cheaper"
    out.append(f"- Per step {cheaper} ({per_a:.1f} us a TSALPHA2 step against {per_v:.1f} us "
               f"a slab at dt = {v['dt']:.3g}); vstpetsc wins mostly "
               "by needing fewer steps (third order against second). Against the exact "
               "continuum force no method converges with dt at a fixed mesh (mesh and penalty "
               "error); there the closest runs are: " + ", ".join(
                   f"{m} {p['error_exact']:.3f} at dt = {p['dt']:.3g} in {1e3 * p['wall']:.1f} ms"
                   for m, p in acc["best_exact"].items()) + ".")
    return out


def finite(obj):
    """True if every number in a nested structure is finite (None allowed
    only for 'not reached' errors)."""
    if isinstance(obj, dict):
        return all(finite(v) for v in obj.values())
    if isinstance(obj, list):
        return all(finite(v) for v in obj)
    if isinstance(obj, (int, float)) and not isinstance(obj, bool):
        return math.isfinite(obj)
    return True


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default=HERE)
    ap.add_argument("--readme-only", action="store_true",
                    help="rewrite README.md from the existing results.json")
    args = ap.parse_args(argv)
    json_path, readme_path = (os.path.join(args.out, name) for name in ("results.json",
                                                                       "README.md"))
    if args.readme_only:
        with open(json_path) as f:
            res = json.load(f)
    else:
        res = measure(args.quick)
        os.makedirs(args.out, exist_ok=True)
        with open(json_path, "w") as f:
            json.dump(res, f, indent=1)
    # the other benchmarks' sections stay: `make bench` replaces them after
    # this, --readme-only not at all
    text = with_other_sections(readme_path, readme(res))
    with open(readme_path, "w") as f:
        f.write(text)
    print(f"wrote {readme_path}" + ("" if args.readme_only else f" and {json_path}"))
    return 0 if finite(res) else 1


if __name__ == "__main__":
    sys.exit(main())
