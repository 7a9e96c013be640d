"""The cost per slab of friction (issue 27): a 10 m soil column on a
shaking wall, (a) axial only, (b) with its shear component, (c) with
Coulomb friction at its base.  In-process runs interleaved, min and median
of several, milliseconds per slab.

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


def column(elements, variant):
    """The column case of ``variant``: "axial", "shear" or "friction"."""
    body = {"name": "col", "x": [0.0, H], "elements": elements, "E": 1e10, "rho": RHO}
    contact = {"pair": ["wall", "col"], "wall": 0.0}
    if variant != "axial":
        body["Vs"] = VS
    if variant == "friction":
        contact.update(friction=MU, wall_shear_velocity=[[0.0, 0.0], [0.3, 1.5], [1.2, 1.5]])
    return vstpetsc.Case.from_dict({
        "time": {"dt": 0.5 * H / elements / VS, "end": 1.2}, "output": {"every": 10},
        "gravity": {"g": -G, "initial": "static"}, "body": [body], "contact": [contact]})


def per_slab(case, folder):
    start = time.perf_counter()
    vstpetsc.run(case, output=f"{folder}/r.h5", quiet=True, out=io.StringIO())
    return 1e3 * (time.perf_counter() - start) / case.nslabs


def main(elements=64, repeats=5):
    variants = ("axial", "shear", "friction")
    cases = {v: column(elements, v) for v in variants}
    times = {v: [] for v in variants}
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(repeats):
            for v in variants:
                times[v].append(per_slab(cases[v], folder))
    base = min(times["axial"])
    print(f"| column ({elements} elements, {cases['axial'].nslabs} slabs) | ms per slab, min "
          "| median | min / axial |")
    print("|---|---|---|---|")
    for v in variants:
        t = times[v]
        print(f"| {v} | {min(t):.4f} | {statistics.median(t):.4f} | {min(t) / base:.2f} |")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
