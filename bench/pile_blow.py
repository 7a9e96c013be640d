"""The bundled pile blow by vstpetsc and by the Smith (1960) peer
(tests/references/smith.py) at several resolutions, timed: the pile
section of bench/README.md (bench/run.py) and bench/pile_speed.py.
"""

import io
import os
import sys
import tempfile
import time

import numpy as np

sys.path.append(os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                             "tests"))
from references import smith  # noqa: E402


def vstpetsc_blow(case, elements):
    """The same blow with vstpetsc: ``elements`` on the pile (dt at c dt/h
    = 0.5 of the pile, the ram in proportion); set, stresses, transferred
    energy, wall time of the whole run (file included)."""
    import vstpetsc

    ram, pile = case.bodies
    c = float(np.sqrt(pile.E(pile.x[0]) / pile.rho(pile.x[0])))
    dt = 0.5 * (pile.x[1] - pile.x[0]) / elements / c
    share = (ram.x[1] - ram.x[0]) / (pile.x[1] - pile.x[0])
    changed = (case.with_value("body.pile.elements", elements)
               .with_value("body.ram.elements", max(3, round(elements * share)))
               .with_value("time.dt", dt).with_value("time.end", case.nslabs * case.dt))
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        r = vstpetsc.run(changed, output=os.path.join(folder, "r.h5"), quiet=True,
                         out=io.StringIO())
        wall = time.perf_counter() - start
        s = r.summary()
    body = [b for b in s["bodies"] if b["name"] == pile.name][0]
    return {"set": s["soils"][0]["set"], "stress_min": body["compression"][0],
            "stress_max": body["tension"][0], "transferred": s["energy"]["transferred"],
            "wall": wall, "dt": dt, "steps": changed.nslabs}


def compare(case, vst_sizes=(25, 50, 100), smith_sizes=(50, 100, 200, 400)):
    """Both methods on the bundled pile at several resolutions (best wall
    time of 3 runs for the peer, which is fast)."""
    end = case.nslabs * case.dt
    out = {"vstpetsc": [], "smith": []}
    for n in vst_sizes:
        out["vstpetsc"].append({"elements": n, **vstpetsc_blow(case, n)})
    for n in smith_sizes:
        runs = [smith.run(case, n, end) for _ in range(3)]
        out["smith"].append({"segments": n, **min(runs, key=lambda r: r["wall"])})
    return out
