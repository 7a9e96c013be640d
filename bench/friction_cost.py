"""The cost per slab of friction (issues 27, 36): a 10 m soil column on a
shaking wall, (a) axial only, (b) with its shear component (not driven:
the pair has no friction), (c) with its shear component welded to the
wall's motion, (d) with Coulomb friction at its base instead, (e) yielding
(MKZ) and welded, (f) yielding on friction (the soil's Newton hosts the
pair).
In-process runs interleaved, min and median of several, milliseconds per
slab; ratios against (b) and (c), the linear column without friction.

    .venv/bin/python bench/friction_cost.py [elements] [repeats]
"""

import io
import statistics
import sys
import tempfile
import time

import numpy as np

import vstpetsc

H, RHO, VS, MU, G = 10.0, 2000.0, 100.0, 0.2, 9.81
# yields to 20 gamma_ref and slides (0.3 m) under the wall's ramp
MKZ = {"model": "mkz", "gamma_ref": 2.0e-3, "beta": 1.0, "s": 0.919}
VARIANTS = ("axial", "shear", "welded", "friction", "yielding welded", "yielding+friction")
GROUND = [[0.0, 0.0], [0.3, 1.5], [1.2, 1.5]]        # the wall's shear velocity


def column(elements, variant):
    """The column case of ``variant`` (one of VARIANTS): on the wall across
    a pair; the shear component driven by the wall's motion, through
    friction ("...friction") or held to it (welded: a shear bc)."""
    body = {"name": "col", "x": [0.0, H], "elements": elements, "E": 1e10, "rho": RHO}
    contact = {"pair": ["wall", "col"], "wall": 0.0}
    bcs = []
    if variant != "axial":
        body["Vs"] = VS
    if variant.startswith("yielding"):
        body["shear_law"] = MKZ
    if variant.endswith("friction"):
        contact.update(friction=MU, wall_shear_velocity=GROUND)
    elif variant.endswith("welded"):
        bcs = [{"body": "col", "end": "left", "type": "velocity", "component": "shear",
                "value": GROUND}]
    return vstpetsc.Case.from_dict({
        "time": {"dt": 0.5 * H / elements / VS, "end": 1.2}, "output": {"every": 10},
        "gravity": {"g": -G, "initial": "static"}, "body": [body], "contact": [contact],
        "bc": bcs})


def per_slab(case, folder):
    start = time.perf_counter()
    vstpetsc.run(case, output=f"{folder}/r.h5", quiet=True, out=io.StringIO())
    return 1e3 * (time.perf_counter() - start) / case.nslabs


def main(elements=64, repeats=5):
    variants = VARIANTS
    cases = {v: column(elements, v) for v in variants}
    times = {v: [] for v in variants}
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(repeats):
            for v in variants:
                times[v].append(per_slab(cases[v], folder))
    ratio = lambda t, b: f"{min(t) / min(b):.2f} / {statistics.median(t) / statistics.median(b):.2f}"
    print(f"| column ({elements} elements, {cases['axial'].nslabs} slabs) | ms per slab, min "
          "| median | against shear (not driven), min / median | against welded |")
    print("|---|---|---|---|---|")
    for v in variants:
        t = times[v]
        print(f"| {v} | {min(t):.4f} | {statistics.median(t):.4f} | "
              f"{ratio(t, times['shear'])} | {ratio(t, times['welded'])} |")

if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
