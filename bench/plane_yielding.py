"""Yielding regions in 2-D (issue 46): what an MKZ zone costs per slab
against the same section linear.

An embankment-like section (the generated dam mesh: a 40 m dam on a 40 m
foundation, cells of about H_CELL) shaken through its absorbing base,
gravity with a static start; the dam region linear, or yielding (MKZ,
gamma_ref GAMMA_REF) under a tenth of the shaking ("gentle") and under all
of it ("strong"); with its base an interface that slides (friction FRICTION)
beside the strong yielding.  One rank, the run's own slab loop after WARM
slabs (bench/plane_interfaces.py's harness); min / median of REPEATS
batches of BATCH slabs, the variants interleaved in one process; the
ratio to the linear section's, and the largest strain reached.  A variant
whose Newton fails (SolveFailed) is reported with its message and left out
of the timing (the base sliding under strong yielding at 1e4 cells stalls:
docs/nonlinear-soil.md section 8, "Limits").

    .venv/bin/python bench/plane_yielding.py [--quick]
"""

import sys

import numpy as np

import plane_interfaces as harness
import vstpetsc

H_CELL, REPEATS, WARM = 1.0, 5, 250
GAMMA_REF = 3.0e-4
FRICTION = 0.3         # the base: the soft dam spreads under its weight, 0.05 would not hold it at rest


def dam_section(scale, law, friction=None, h=H_CELL):
    doc = harness.dam_case(friction, h, scale).doc
    doc = {**doc, "region": [dict(r) for r in doc["region"]]}
    dam = doc["region"][0]
    dam.update({"E": 2.0e8, "nu": 0.3, "rho": 2100.0})      # rockfill, not concrete
    if law:
        dam["shear_law"] = {"model": "mkz", "gamma_ref": GAMMA_REF, "beta": 1.0, "s": 0.919}
    return vstpetsc.Case.from_dict(doc)


def built(case):
    """The harness's warmed-up run, or the message of its SolveFailed."""
    from vstpetsc.errors import SolveFailed

    try:
        return harness.build(case)
    except SolveFailed as exc:
        return str(exc)


def measure(h, repeats):
    variants = {"linear": built(dam_section(1.0, False, h=h)),
                "yielding, gentle": built(dam_section(harness.GENTLE, True, h=h)),
                "yielding, strong": built(dam_section(1.0, True, h=h)),
                "yielding, strong, base sliding": built(dam_section(1.0, True, FRICTION, h))}
    out = {name: {"failed": part} for name, part in variants.items() if isinstance(part, str)}
    variants = {name: part for name, part in variants.items() if name not in out}
    out["cells"] = variants["linear"][3].ncells
    for name, row in harness.interleaved(variants, repeats, "linear").items():
        zone = variants[name][3].zone
        out[name] = {**row, "strain_max_over_gamma_ref": 0.0 if zone is None else
                     float(np.max(zone.strain_max)) / GAMMA_REF}
    return out


def main(argv):
    quick = "--quick" in argv
    # after WARM slabs (0.5 s) the strong shaking has driven the dam far
    # beyond gamma_ref (the table's last column)
    harness.WARM = WARM
    if quick:
        harness.BATCH = 3
    out = measure(4.0 if quick else H_CELL, 2 if quick else REPEATS)
    print(f"{out['cells']} cells; ms per slab (min / median), ratio of medians to linear:")
    for name, row in out.items():
        if isinstance(row, dict) and "failed" in row:
            print(f"  {name:32s} failed: {row['failed']}")
        elif isinstance(row, dict):
            print(f"  {name:32s} {row['min_ms']:8.2f} / {row['median_ms']:8.2f}  "
                  f"x {row['ratio_median']:.2f}  strain_max {row['strain_max_over_gamma_ref']:.3g}"
                  " gamma_ref")
    if not quick:
        harness.keep("plane_yielding", out, section)


def section(out):
    """The README's section of the measured ``out``."""
    lines = ["## Yielding zones in 2-D (issue 46)", "",
             f"bench/plane_yielding.py: a 40 m rockfill dam (E = 200 MPa) on its "
             f"foundation, {out['cells']} cells, static start, shaken through its absorbing "
             f"base; MKZ dam (gamma_ref {GAMMA_REF:g}) after {WARM} slabs of 2 ms, then "
             f"{REPEATS} batches of {harness.BATCH} slabs each, the variants interleaved "
             "(one rank; ms per slab; the goal: yielding at most 3 times the linear dam, "
             "with its interfaces sliding at most 4 times).", "",
             "| variant | min ms | median ms | median / linear | largest strain / gamma_ref |",
             "|---|---|---|---|---|"]
    for name, row in out.items():
        if isinstance(row, dict) and "failed" in row:
            failed = row['failed'].replace('|', '\\|')          # a table cell
            lines.append(f"| {name} | failed: {failed} | | | |")
        elif isinstance(row, dict):
            lines.append(f"| {name} | {row['min_ms']:.1f} | {row['median_ms']:.1f} | "
                         f"{row['ratio_median']:.2f} | "
                         f"{row['strain_max_over_gamma_ref']:.3g} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main(sys.argv[1:])
