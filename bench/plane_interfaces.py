"""Interfaces in 2-D (issue 38): what a dam's interface costs per slab.

(1) A gravity dam on its foundation (the generated section, cells of
about H_CELL) shaken through its absorbing base, per slab: welded (no
[[interface]]), with its base an interface that stays closed and sticks
(friction 10: every pair in the linear regime, A_c's one solve), and
with one that slides (friction 0.05: every pair slides, Newton with the
dense coupling's steps, and with -vst_contact_steps krylov); "sticking"
under a tenth of the shaking (every pair closed and sticking), "sticking,
shaking, friction 10" under all of it (the dam rocks and lifts: every pair opens at times).  One rank,
the run's own slab loop (rhs, solve, advance) after WARM slabs of
shaking, every pair's coupling columns formed before (a run forms them
the first time a pair opens or slides; their time is the last column); min / median of REPEATS batches of BATCH slabs, the variants
interleaved in one process.

(2) The rockfill-dam example shortened to END_2 s: wall time of
`vstpetsc run` on one rank and under `mpirun -n 2`, interleaved,
REPEATS_2 times each.

(3) A strip sliding on a joint of 64, 256 and 1024 node pairs (every
pair sliding): ms per slab of Newton on the pairs and, up to 256 pairs,
of GMRES steps: how each grows with the pairs.

    .venv/bin/python bench/plane_interfaces.py [--quick] [--no-pairs] [--no-ranks]
"""

import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
from petsc4py import PETSc

import vstpetsc
from vstpetsc import bundled
from vstpetsc.plane.loads import plane_loads
from vstpetsc.plane.model import PlaneModel
from vstpetsc.plane.solver.slab_solver import PlaneSolver

H_CELL, REPEATS, BATCH, WARM = 1.0, 5, 10, 60
GENTLE = 0.1            # the shaking that leaves every pair closed and sticking
END_2, REPEATS_2 = 1.2, 3
PAIR_COUNTS, KRYLOV_PAIRS = (64, 256, 1024), 256
SHAKE = [[0.0, 0.0], [0.1, 2.0], [0.2, -2.0], [0.3, 2.0], [0.4, -2.0], [0.5, 2.0],
         [0.6, -2.0], [0.7, 2.0], [0.8, -2.0], [0.9, 2.0], [1.0, 0.0], [10.0, 0.0]]


def dam_case(friction, h, scale=1.0):
    shake = [[t, scale * v] for t, v in SHAKE]
    doc = {"time": {"dt": 2e-3, "end": 1.0},
           "mesh": {"dam": {"height": 40.0, "crest": 8.0, "upstream": 0.1, "downstream": 0.8,
                            "foundation_depth": 40.0, "foundation_width": 200.0, "h": h}},
           "region": [{"name": "dam", "E": 2.5e10, "nu": 0.2, "rho": 2400.0},
                      {"name": "foundation", "E": 4.0e10, "nu": 0.25, "rho": 2600.0}],
           "boundary": [{"name": "base", "type": "absorbing", "incident": {"x": shake}},
                        {"name": "left", "type": "absorbing"},
                        {"name": "right", "type": "absorbing"}],
           "gravity": {"g": -9.81, "initial": "static"}}
    if friction is not None:
        doc["interface"] = [{"name": "contact", "friction": friction}]
    return vstpetsc.Case.from_dict(doc)


def build(case, options=()):
    from vstpetsc.plane.loads import gravity_pattern
    from vstpetsc.plane.solver.static import static_state

    opts = PETSc.Options()
    for key, value in options:
        opts[key] = value
    comm = PETSc.COMM_SELF
    model = PlaneModel(case, comm)
    static = static_state(model, gravity_pattern(model))
    loads = plane_loads(model, case.dt, (static.reactions,))
    solver = PlaneSolver(model, case.dt, comm, loads)
    for key, _ in options:
        del opts[key]
    from vstpetsc.plane.energy import RunEnergyBook
    RunEnergyBook(model, solver).start(static.u, static.v)
    solver.set_state(static.u, static.v)
    coupling = getattr(solver.newton, "coupling", None)
    t0 = time.perf_counter()
    if coupling is not None:            # every pair's columns now, not inside a timed batch
        coupling.ensure(np.arange(model.pairs.m))
    columns = time.perf_counter() - t0
    for k in range(WARM):
        run_slab(solver, loads, k)
    return [solver, loads, WARM, model, columns]


def run_slab(solver, loads, k):
    solver.rhs(*loads.slab(k))
    solver.solve(k)
    solver.advance()


def batch(part):
    solver, loads, k = part[:3]
    t0 = time.perf_counter()
    for j in range(k, k + BATCH):
        run_slab(solver, loads, j)
    part[2] = k + BATCH
    return (time.perf_counter() - t0) / BATCH


def interleaved(variants, repeats, base):
    """{name: {min_ms, median_ms, ratio_median}} of the built ``variants``
    ({name: build()}) timed in turn, ``repeats`` batches each; the ratio
    of medians to variant ``base``'s."""
    times = {name: [] for name in variants}
    for _ in range(repeats):
        for name, part in variants.items():
            times[name].append(batch(part))
    reference = statistics.median(times[base])
    return {name: {"min_ms": 1e3 * min(t), "median_ms": 1e3 * statistics.median(t),
                   "ratio_median": statistics.median(t) / reference}
            for name, t in times.items()}


def keep(name, out, section):
    """bench/NAME.json of ``out`` and its README section ``section(out)``."""
    import json

    from readme import write_readme

    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, f"{name}.json"), "w") as f:
        json.dump(out, f, indent=1)
    write_readme(os.path.join(here, "README.md"), section(out))


def changed_share(part):
    """The share of the pairs not closed and sticking in the last slab
    (open somewhere in it, or sliding)."""
    from vstpetsc.plane import pair_kernels as pk

    pairs = part[3].pairs
    if pairs is None:
        return 0.0
    out = pairs.out
    changed = (out[:, pk.ACTED] == 0) | (out[:, pk.DISSIPATED] != 0) | (pairs.gap > 0)
    return float(changed.mean())


def per_slab(h, repeats):
    variants = {"welded": build(dam_case(None, h)),
                "sticking": build(dam_case(10.0, h, GENTLE)),
                "full shaking, friction 10": build(dam_case(10.0, h)),
                "sliding (dense)": build(dam_case(0.05, h)),
                "sliding (krylov)": build(dam_case(0.05, h),
                                          (("vst_contact_steps", "krylov"),))}
    times = {name: [] for name in variants}
    for _ in range(repeats):
        for name, part in variants.items():
            times[name].append(batch(part))
    out = {}
    for name, t in times.items():
        out[name] = {"min_ms": 1e3 * min(t), "median_ms": 1e3 * statistics.median(t),
                     "changed_pairs": changed_share(variants[name]),
                     "pairs": variants[name][3].pairs.m if variants[name][3].pairs else 0,
                     "columns_s": variants[name][4]}
    out["cells"] = variants["welded"][3].ncells
    return out


def strip_case(pairs):
    """A strip of blocks (cells of 0.25 m, four rows above a driven row)
    on a frictional joint of ``pairs`` node pairs, its base accelerated at
    0.5 g: every pair slides from the first slabs."""
    width = 0.25 * (pairs - 1)
    drive = [[0.0, 0.0], [0.2, 0.981], [10.0, 0.981]]
    return vstpetsc.Case.from_dict({
        "time": {"dt": 1e-3, "end": 1.0},
        "mesh": {"rectangle": {"x": [0.0, width], "y": [-0.25, 1.0], "nx": pairs - 1, "ny": 5,
                               "joints": {"base": 0.0}}},
        "region": [{"name": "domain", "E": 1e10, "nu": 0.2, "rho": 2000.0}],
        "boundary": [{"name": "bottom", "type": "velocity", "value": {"x": drive, "y": 0.0}}],
        "interface": [{"name": "base", "friction": 0.2}],
        "gravity": {"g": -9.81, "initial": "static"}})


def many_pairs(counts, repeats):
    """ms per slab of the sliding strip for each number of pairs, Newton on
    the pairs (dense) and with GMRES steps (krylov, up to KRYLOV_PAIRS)."""
    out = {}
    for m in counts:
        kinds = [("dense", ())] + ([("krylov", (("vst_contact_steps", "krylov"),))]
                                   if m <= KRYLOV_PAIRS else [])
        for kind, options in kinds:
            part = build(strip_case(m), options)
            times = [batch(part) for _ in range(repeats)]
            out[f"{m} {kind}"] = {"min_ms": 1e3 * min(times),
                                  "median_ms": 1e3 * statistics.median(times),
                                  "columns_s": part[4], "cells": part[3].ncells}
            print(f"| {m} | {kind} | {part[3].ncells} | {1e3 * min(times):.1f} / "
                  f"{1e3 * statistics.median(times):.1f} | {part[4]:.2f} |", flush=True)
    return out


def ranks(repeats):
    folder = tempfile.mkdtemp()
    case = vstpetsc.Case.from_toml(bundled.path("rockfill-dam")).with_value("time.end", END_2)
    path = os.path.join(folder, "rockfill.toml")
    with open(path, "w") as f:
        f.write(case.to_toml())
    for c in bundled.companions("rockfill-dam"):
        os.symlink(c, os.path.join(folder, os.path.basename(c)))
    times = one_and_two_ranks(path, folder, repeats)
    return {k: {"min_s": min(v), "median_s": statistics.median(v)} for k, v in times.items()}


def one_and_two_ranks(path, folder, repeats):
    """{"1 rank": [s], "2 ranks": [s]}: whole `vstpetsc run` processes of
    the case file ``path`` (results in ``folder``), interleaved."""
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    exe = [sys.executable, "-m", "vstpetsc", "run", path, "-q"]
    commands = {"1 rank": exe + ["-o", os.path.join(folder, "one.h5")],
                "2 ranks": ["mpirun", "-n", "2"] + exe + ["-o", os.path.join(folder, "two.h5")]}
    times = {k: [] for k in commands}
    for _ in range(repeats):
        for name, cmd in commands.items():
            t0 = time.perf_counter()
            subprocess.run(cmd, check=True, env=env, capture_output=True)
            times[name].append(time.perf_counter() - t0)
    return times


def main(argv):
    quick = "--quick" in argv
    res = per_slab(2.0 if quick else H_CELL, 2 if quick else REPEATS)
    welded = res["welded"]
    print(f"gravity dam, {res['cells']} cells, {res['sticking']['pairs']} pairs; per slab, "
          "min / median ms, and ratio to welded (min / median)")
    for name in ("welded", "sticking", "full shaking, friction 10", "sliding (dense)",
                 "sliding (krylov)"):
        r = res[name]
        print(f"| {name} | {r['min_ms']:.2f} / {r['median_ms']:.2f} | "
              f"{r['min_ms'] / welded['min_ms']:.2f} / "
              f"{r['median_ms'] / welded['median_ms']:.2f} | "
              f"{100 * r['changed_pairs']:.0f} % open or sliding | {r['columns_s']:.2f} |",
              flush=True)
    if "--no-pairs" not in argv:
        print("a sliding strip: pairs | steps | cells | ms per slab (min / median) | columns s")
        many_pairs(PAIR_COUNTS[:2] if quick else PAIR_COUNTS, 2 if quick else 3)
    if "--no-ranks" not in argv:
        two = ranks(1 if quick else REPEATS_2)
        one, pair = two["1 rank"], two["2 ranks"]
        print(f"rockfill-dam to {END_2} s: 1 rank {one['min_s']:.2f} / {one['median_s']:.2f} s, "
              f"2 ranks {pair['min_s']:.2f} / {pair['median_s']:.2f} s: speed-up "
              f"{one['min_s'] / pair['min_s']:.2f} / {one['median_s'] / pair['median_s']:.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
