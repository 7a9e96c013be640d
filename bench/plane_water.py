"""Water on a dam (issue 47): what a reservoir costs per slab against the
dry dam (the goal: Westergaard at most 1.05 times the dry dam per slab).

The gravity dam of bench/plane_interfaces.py (the generated section: a
40 m concrete dam on a 40 m foundation, cells of about H_CELL, its base
an interface "contact" with friction FRICTION that sticks) shaken through
its absorbing base, gravity with a static start; dry, with a [[water]]
on its curve "upstream" at LEVEL (hydrodynamic "none": the hydrostatic
pressure only), with Westergaard's added masses, and with those and the
uplift in "contact" (docs/water.md).  One rank, the run's own slab loop
after WARM slabs (bench/plane_interfaces.py's harness); min / median of
REPEATS batches of BATCH slabs, the variants interleaved in one process;
the ratio of medians to the dry dam's.

    .venv/bin/python bench/plane_water.py [--quick]
"""

import sys

import plane_interfaces as harness
import vstpetsc

H_CELL, REPEATS, WARM = 1.0, 5, 60
FRICTION = 10.0        # the base sticks (as plane_interfaces.py's "sticking")
LEVEL = 36.0           # the reservoir's surface (the dam is 40 m high)
LENGTH = 90.0          # the acoustic reservoir's, heel to far end (2.5 LEVEL; the foundation's edge)


def wet_dam(h, hydrodynamic=None, uplift=False):
    """The dam of harness.dam_case, dry (``hydrodynamic`` None) or with
    its reservoir on "upstream"."""
    doc = dict(harness.dam_case(FRICTION, h).doc)
    if hydrodynamic is not None:
        water = {"name": "reservoir", "level": LEVEL, "rho": 1000.0, "faces": ["upstream"],
                 "hydrodynamic": hydrodynamic}
        if uplift:
            water["uplift"] = "contact"
        doc["water"] = [water]
    return vstpetsc.Case.from_dict(doc)


def acoustic_dam(h):
    """The dam with an acoustic reservoir (docs/water.md): the mesh's
    region "water" LENGTH long upstream of the heel, up to LEVEL, wetting
    the dam's face and the foundation's top, its far end absorbing."""
    doc = dict(harness.dam_case(FRICTION, h).doc)
    mesh = dict(doc["mesh"]["dam"], reservoir={"level": LEVEL, "length": LENGTH})
    doc["mesh"] = {"dam": mesh}
    doc["water"] = [{"name": "reservoir", "level": LEVEL, "rho": 1000.0,
                     "faces": ["wet", "floor"], "hydrodynamic": "acoustic",
                     "region": "water", "far": "far"}]
    return vstpetsc.Case.from_dict(doc)


def measure(h, repeats):
    variants = {"dry": harness.build(wet_dam(h)),
                "hydrostatic": harness.build(wet_dam(h, "none")),
                "westergaard": harness.build(wet_dam(h, "westergaard")),
                "westergaard + uplift": harness.build(wet_dam(h, "westergaard", True)),
                "acoustic": harness.build(acoustic_dam(h))}
    out = {"cells": variants["dry"][3].ncells, "acoustic_cells": variants["acoustic"][3].ncells,
           **harness.interleaved(variants, repeats, "dry")}
    # the goal counts the water's cells as cells: a water cell no dearer than a solid's
    out["acoustic"]["per_cell"] = out["acoustic"]["ratio_median"] * out["cells"] / \
        out["acoustic_cells"]
    return out


def main(argv):
    quick = "--quick" in argv
    harness.WARM = WARM
    if quick:
        harness.BATCH = 3
    out = measure(4.0 if quick else H_CELL, 2 if quick else REPEATS)
    print(f"{out['cells']} cells ({out['acoustic_cells']} with the acoustic water); ms per "
          "slab (min / median), ratio of medians to dry (per cell):")
    for name, row in out.items():
        if isinstance(row, dict):
            print(f"  {name:24s} {row['min_ms']:8.2f} / {row['median_ms']:8.2f}  "
                  f"x {row['ratio_median']:.3f}" +
                  (f" ({row['per_cell']:.3f} per cell)" if "per_cell" in row else ""))
    if not quick:
        harness.keep("plane_water", out, section)


def section(out):
    """The README's section of the measured ``out``."""
    lines = ["## Water on a dam: cost per slab (issue 47)", "",
             f"bench/plane_water.py: the 40 m concrete gravity dam of bench/plane_interfaces.py "
             f"on its foundation, {out['cells']} cells, its base an interface that sticks "
             f"(friction {FRICTION:g}), static start, shaken through its absorbing base; "
             f"dry, or with a reservoir on its upstream face at {LEVEL:g} m (hydrostatic "
             "only, with Westergaard's added masses, and with those and the uplift in the "
             f"base interface), or an acoustic reservoir {LENGTH:g} m long meshed upstream "
             f"({out['acoustic_cells']} cells in all, its far end absorbing); after {WARM} "
             f"slabs of 2 ms, {REPEATS} batches of "
             f"{harness.BATCH} slabs each, the variants interleaved (one rank; ms per slab; "
             "the goals: Westergaard at most 1.05 times the dry dam, the acoustic reservoir "
             "at most 1.5 times per cell, its water's cells counted).", "",
             "| variant | min ms | median ms | median / dry | per cell / dry's |",
             "|---|---|---|---|---|"]
    for name, row in out.items():
        if isinstance(row, dict):
            per_cell = f"{row['per_cell']:.3f}" if "per_cell" in row else ""
            lines.append(f"| {name} | {row['min_ms']:.1f} | {row['median_ms']:.1f} | "
                         f"{row['ratio_median']:.3f} | {per_cell} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main(sys.argv[1:])
