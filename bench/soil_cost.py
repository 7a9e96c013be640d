"""The cost per slab of a hysteretic soil (issue 28): a 30 m column of
100 elements on elastic rock under an 8000-slab outcrop record, (a) linear,
(b) MKZ with the default plain Newton and the compiled kernel, (c) the
same with the Python kernel, (d) the SNES (GMRES preconditioned by the
tangent's factors), (e) the SNES as modified Newton.
In-process runs interleaved, min and median of several, milliseconds per
slab, and the ratio of the minima to the linear column's.

    .venv/bin/python bench/soil_cost.py [elements] [slabs] [repeats]
"""

import io
import statistics
import sys
import tempfile
import time

import numpy as np

import vstpetsc

H, RHO, VS, DT = 30.0, 2000.0, 250.0, 0.005
VARIANTS = {"linear": [], "mkz (default: the compiled Newton)": [],
            "mkz, Python path (-vst_native 0)": ["-vst_native", "0"],
            "mkz, SNES (GMRES on the factors)": ["-snes_type", "newtonls"],
            "mkz, SNES modified Newton": ["-newton_ksp_type", "preonly"]}


def record(slabs):
    """An outcrop acceleration (m/s^2): a 1.5 Hz burst, peak about 3 m/s^2."""
    t = np.arange(slabs + 1) * DT
    mid = 0.3 * t[-1]
    return np.column_stack([t, 3.0 * np.sin(3.0 * np.pi * t) * np.exp(-((t - mid) / (0.2 * t[-1])) ** 2)])


def column(elements, slabs, nonlinear):
    body = {"name": "soil", "x": [0.0, H], "elements": elements, "E": 1e8, "rho": RHO, "Vs": VS}
    if nonlinear:
        body["shear_law"] = {"model": "mkz", "gamma_ref": 5e-4, "beta": 1.0, "s": 0.92}
    return vstpetsc.Case.from_dict({
        "time": {"dt": DT, "end": slabs * DT}, "output": {"every": 10}, "body": [body],
        "bc": [{"body": "soil", "end": "left", "type": "absorbing", "component": "shear",
                "rock": {"rho": 2400.0, "Vs": 1000.0}, "motion": "outcrop",
                "incident": {"table": record(slabs).tolist(), "integrate": True}},
               {"body": "soil", "end": "left", "type": "fixed"}],
        "gauge": [{"name": "surface", "body": "soil", "x": H}]})


def per_slab(case, options, folder):
    start = time.process_time()
    vstpetsc.run(case, output=f"{folder}/r.h5", options=options, quiet=True, out=io.StringIO())
    seconds = time.process_time() - start
    result = vstpetsc.Result(f"{folder}/r.h5")
    peak = float(result.body("soil")["shear"]["strain_max"].max())
    return 1e3 * seconds / case.nslabs, peak, float(np.mean(result.solver["newton_iterations"]))


def main(elements=100, slabs=8000, repeats=3):
    cases = {True: column(elements, slabs, True), False: column(elements, slabs, False)}
    times = {v: [] for v in VARIANTS}
    facts = {}
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(repeats):
            for v, options in VARIANTS.items():
                ms, peak, newton = per_slab(cases[v != "linear"], options, folder)
                times[v].append(ms)
                facts[v] = (peak, newton)
    base, middle = min(times["linear"]), statistics.median(times["linear"])
    print(f"| column ({elements} elements, {slabs} slabs; CPU time) | ms per slab, min | median "
          "| min / linear's min | median / linear's median | largest strain "
          "| Newton its per kept slab |")
    print("|---|---|---|---|---|---|---|")
    for v, t in times.items():
        print(f"| {v} | {min(t):.3f} | {statistics.median(t):.3f} | {min(t) / base:.1f} "
              f"| {statistics.median(t) / middle:.1f} | {facts[v][0]:.3g} | {facts[v][1]:.2f} |")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:4]))
