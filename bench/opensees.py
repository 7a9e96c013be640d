"""Against OpenSees: time to solution at equal accuracy (issue 26).

    python bench/opensees.py [--quick] [--readme-only]

Three problems with exact solutions (wave, impact, site: their
definitions, closed forms and error measures in tests/references/waves.py),
each solved by vstpetsc (defaults, and the averaged mass) and by OpenSees
(openseespy: 1-D trusses, Newmark average acceleration, consistent and
lumped mass).

For each method and target error, the cheapest run reaching it is found by
halving h at each of the method's Courant numbers c dt/h (cost measure:
elements x steps), then all chosen runs are timed again, interleaved,
several times: min and median. Time = the whole solve with its output
(vstpetsc: `vstpetsc.run` in-process, case set-up and result file
included; OpenSees: model set-up, analysis and its recorder file). OpenSees
runs in a child process (openseespy and petsc4py crash in one process),
started before PETSc is imported.

Writes bench/opensees.json and the section "Against OpenSees" of
bench/README.md (after bench/run.py, which writes the head and its own sections).
"""

import io
import math
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.append(os.path.join(os.path.dirname(HERE), "tests"))

import opensees_common as common  # noqa: E402
from readme import bench_arguments, write_readme  # noqa: E402,F401
from references.waves import (AMP, AREA, E, LENGTH, RHO, SITE, V0,  # noqa: E402
                              case_doc, evaluate, job_for, metrics, node_masses, problem,
                              site_incident)

TARGETS = {"wave": (1e-3, 1e-4, 1e-5), "impact": (5e-3, 3e-3, 1e-3),
           "site": (1e-3, 1e-4, 1e-5)}
SQRT_HALF = math.sqrt(0.5)
WORK_CAP = 1.2e7                  # elements x steps of the largest run of the search
SLOW_TOTAL = 8.0                  # seconds of timing runs after which a job stops at three


def work(run):
    """The search's cost measure: elements x steps."""
    return run["elements"] * run["steps"]


def cheapest(rows, target):
    """The row of least work (elements x steps) whose error is <= target."""
    return common.cheapest(rows, target, work)


# ---------------------------------------------------------------- OpenSees (child)

def opensees_run(job, folder):
    """One OpenSees run in this (child) process: (seconds, metrics)."""
    import openseespy.opensees as ops

    name, n, steps, dt = job["problem"], job["elements"], job["steps"], job["dt"]
    length, c = problem(name)[:2]
    rho = SITE["rho"] if name == "site" else RHO
    record = os.path.join(folder, "record.txt")
    start = time.perf_counter()
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    x = np.linspace(0.0, length, n + 1)
    for i, xi in enumerate(x):
        ops.node(i + 1, float(xi))
    ops.uniaxialMaterial("Elastic", 1, rho * c * c)
    mass = ("-cMass", 1) if job["mass"] == "consistent" else ()
    for e in range(n):
        ops.element("Truss", e + 1, e + 1, e + 2, AREA, 1, "-rho", rho * AREA, *mass)
    what = _opensees_setup(ops, name, job, x, record)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("BandSPD")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    status = ops.analyze(steps, dt)
    ops.remove("recorders")
    seconds = time.perf_counter() - start
    final_v = np.array([ops.nodeVel(i + 1, 1) for i in range(n + 1)])
    ops.wipe()
    if status != 0:
        return seconds, {"error": None, "failed": True}
    data = np.loadtxt(record, ndmin=2)
    if what == "force":
        return seconds, evaluate(name, data[:, 0], None, final_v, data[:, 1])
    return seconds, evaluate(name, data[:, 0], data[:, 1])


def _opensees_setup(ops, name, job, x, record):
    """Boundary conditions, initial state, loads, algorithm and recorder."""
    n = x.size - 1
    prec = ("-precision", 17)
    if name == "wave":
        ops.fix(1, 1)
        u0 = AMP * np.sin(0.5 * math.pi * x / LENGTH)
        a0 = initial_acceleration(u0, n, job["mass"])
        for i in range(1, n + 1):
            ops.setNodeDisp(i + 1, 1, float(u0[i]), "-commit")
            ops.setNodeAccel(i + 1, 1, float(a0[i]), "-commit")
        ops.algorithm("Linear", "-factorOnce")
        ops.recorder("Node", "-file", record, *prec, "-time", "-node", n + 1, "-dof", 1, "disp")
        return "tip"
    if name == "impact":
        ops.node(n + 2, LENGTH)
        ops.fix(n + 2, 1)
        ops.uniaxialMaterial("ENT", 2, job["penalty"])
        ops.element("zeroLength", n + 1, n + 1, n + 2, "-mat", 2, "-dir", 1)
        for i in range(n + 1):
            ops.setNodeVel(i + 1, 1, V0, "-commit")
        ops.test("NormDispIncr", 1e-14, 30)
        ops.algorithm("Newton")
        ops.recorder("Element", "-file", record, *prec, "-time", "-ele", n + 1, "force")
        return "force"
    s = SITE
    z_rock = s["rho_rock"] * s["c_rock"] * AREA
    ops.node(n + 2, 0.0)
    ops.fix(n + 2, 1)
    ops.uniaxialMaterial("Viscous", 3, z_rock, 1.0)
    ops.element("zeroLength", n + 1, n + 2, 1, "-mat", 3, "-dir", 1)
    t, v, _ = site_incident()
    ops.timeSeries("Path", 1, "-time", *t.tolist(), "-values", *(2.0 * z_rock * v).tolist())
    ops.pattern("Plain", 1, 1)
    ops.load(1, 1.0)
    ops.algorithm("Linear", "-factorOnce")
    ops.recorder("Node", "-file", record, *prec, "-time", "-node", n + 1, "-dof", 1, "vel")
    return "surface"


def initial_acceleration(u0, n, mass):
    """a0 = -M^-1 K u0 of the clamped bar (node 0 fixed): Newmark needs it,
    OpenSees starts from zero acceleration otherwise."""
    h = LENGTH / n
    k_diag, k_off = np.full(n + 1, 2 * E * AREA / h), np.full(n, -E * AREA / h)
    k_diag[[0, -1]] *= 0.5
    ku = k_diag * u0
    ku[:-1] += k_off * u0[1:]
    ku[1:] += k_off * u0[:-1]
    m_lump = node_masses(n)
    if mass == "lumped":
        a = -ku / m_lump
    else:
        diag, off = 2.0 / 3.0 * m_lump, np.full(n, RHO * AREA * h / 6.0)
        full = np.diag(diag[1:]) + np.diag(off[1:], 1) + np.diag(off[1:], -1)
        a = np.r_[0.0, np.linalg.solve(full, -ku[1:])]
    a[0] = 0.0
    return a


def worker():
    """Child loop: one JSON job a line on stdin, one JSON answer a line."""
    with tempfile.TemporaryDirectory() as folder:
        return common.serve(lambda job: opensees_answer(job, folder))


def opensees_answer(job, folder):
    """The child's answer to a job: its seconds and its metrics."""
    seconds, metrics = opensees_run(job, folder)
    return {"seconds": seconds, **metrics}


class OpenSeesChild(common.WorkerChild):
    """The child process that runs OpenSees jobs."""

    def __init__(self):
        super().__init__(__file__)

    def __call__(self, job):
        got = self.ask(job)
        return got.pop("seconds"), got


# ---------------------------------------------------------------- vstpetsc

def vst_run(job, folder):
    """One vstpetsc run in this process: (seconds, metrics)."""
    import vstpetsc

    path = os.path.join(folder, "run.h5")
    if os.path.exists(path):
        os.remove(path)
    doc = case_doc(job, folder)
    start = time.perf_counter()
    result = vstpetsc.run(vstpetsc.Case.from_dict(doc), path, quiet=True, out=io.StringIO())
    seconds = time.perf_counter() - start
    return seconds, metrics(job, result)


# ---------------------------------------------------------------- methods and search

def methods(name):
    """{method: (runner kind, job fields, Courant numbers)} of a problem."""
    k = 0.5 * E * AREA           # times 1/h: OpenSees' penalty 0.5 E A / h, vstpetsc's default
    impact = name == "impact"
    vst_cfl = (0.5, 1.0) if impact else (0.5, 1.0, 2.0)
    return {"vstpetsc": ("vst", {"mass": "default"}, vst_cfl),
           "vstpetsc seed": ("vst", {"mass": "consistent", "formulation": "seed"}, vst_cfl),
           "opensees consistent": ("os", {"mass": "consistent", "penalty": k}, (SQRT_HALF,)),
           "opensees lumped": ("os", {"mass": "lumped", "penalty": k}, (SQRT_HALF,))}


def search(name, runners, quick, log):
    """Every method's runs, h halved per Courant number until the smallest
    target is met or the next run would exceed the cap on elements x steps
    (a cap on work, not on time: the same runs whatever the machine's load;
    1.2e7 is about 1.5 s of vstpetsc and 7 s of OpenSees here)."""
    cap = 5e5 if quick else WORK_CAP
    goal = min(TARGETS[name])
    rows = {}
    for method, (kind, fields, courants) in methods(name).items():
        rows[method] = []
        for courant in courants:
            n = problem(name)[3]
            while True:
                job = job_for(name, fields, n, courant)
                seconds, got = runners[kind](job)
                rows[method].append({**job, "seconds": seconds, **got})
                log(f"{name} {method} n={n} cfl={courant:.3g}: error "
                    f"{got['error']} in {seconds:.3f} s")
                if got["error"] is None or got["error"] <= goal or 4 * n * job["steps"] > cap:
                    break
                n *= 2
    return rows


def measure(quick, log=print):
    child = OpenSeesChild()                      # before PETSc starts Open MPI
    with tempfile.TemporaryDirectory() as folder:
        runners = {"vst": lambda job: vst_run(job, folder), "os": child}
        res = {**common.results_head(quick), "problems": {}}
        chosen = {}
        for name in TARGETS:
            rows = search(name, runners, quick, log)
            res["problems"][name] = {"runs": rows, "table": []}
            for method, kind_fields in methods(name).items():
                for target in TARGETS[name]:
                    best = cheapest(rows[method], target)
                    res["problems"][name]["table"].append(
                        {"target": target, "method": method, "run": best})
                    if best is not None:
                        key = (name, method, best["elements"], best["courant"])
                        chosen[key] = (kind_fields[0], {k: best[k] for k in job_keys(best)})
        timed = common.time_chosen(chosen, runners, 2 if quick else 5, SLOW_TOTAL)
        for name, prob in res["problems"].items():
            for row in prob["table"]:
                run = row["run"]
                if run is not None:
                    lo, mid = timed[(name, row["method"], run["elements"], run["courant"])]
                    row.update(time_min=lo, time_median=mid)
    child.close()
    return res


def job_keys(run):
    return [k for k in ("problem", "elements", "steps", "dt", "courant", "mass", "penalty",
                        "formulation") if k in run]


# ---------------------------------------------------------------- README

SECTION = "## Against OpenSees"


def section(res):
    """The README section: one table of the cheapest runs per target."""
    lines = [SECTION, "",
             "Generated by `bench/opensees.py` (`make bench`, after bench/run.py) on "
             f"{res['machine']}, {res['date']}; openseespy from PyPI. Time to solution at "
             "equal accuracy: for each method and target the cheapest run (elements x steps) "
             "reaching it, h halved at fixed c dt/h until the smallest target or "
             f"elements x steps of {WORK_CAP:.2g} (\"not reached\": beyond that) "
             "(vstpetsc: 0.5, 1, 2; 0.5, 1 for the "
             "impact; OpenSees: 1/sqrt(2), Newmark average acceleration's dispersion-"
             "cancelling Courant number with consistent mass), then timed again "
             "interleaved (5 times; 3 for jobs past 8 s): min / median of the whole solve "
             "with its output (vstpetsc: "
             "`vstpetsc.run` in-process, result file included; OpenSees: model, analysis "
             "and recorder file, in a child process). Problems: wave = the `wave` example "
             "(tip displacement, relative L2 error over two periods); impact = steel bar "
             "1 m at 1 m/s against a rigid wall (error: rebound velocity |v + v0| / v0; "
             "OpenSees: zeroLength "
             "with an ENT material of 0.5 E A / h, Newton); site = 20 m soil layer "
             "(200 m/s, 1800 kg/m^3) on rock (1000 m/s, 2200 kg/m^3, absorbing base / "
             "Lysmer dashpot) under a 10 Hz Ricker incident pulse, given to both as a record "
             "sampled every 0.1 ms (vstpetsc: a CSV file, read within the timed run; surface "
             "velocity, relative L2 error over 1.2 s against the multiple-reflection closed "
             "form of that record, tests/references/waves.py `site_surface_exact`). vstpetsc = "
             "the defaults (averaged mass; power contact, penalty 0.5 E A / h); vstpetsc seed "
             "= the source document's method (`mass = \"consistent\"`, seed contact, its "
             "default penalty).", "",
             "| problem | target | method | elements | dt [s] | c dt/h | error | peak force / Z v0 "
             "| time [ms] min / median |", "|---|---|---|---|---|---|---|---|---|"]
    for name, prob in res["problems"].items():
        for row in prob["table"]:
            lines.append(table_row(name, row, prob["runs"][row["method"]]))
    return common.section_text(lines, fastest_lines(res))


def fastest_lines(res):
    """One line a problem and target: the fastest method, the others' ratios."""
    lines = (common.fastest_line(f"{name} {target:g}", prob["table"], target,
                                 lambda seconds: f"{1e3 * seconds:.1f} ms")
             for name, prob in res["problems"].items() for target in TARGETS[name])
    return [line for line in lines if line is not None]


def table_row(name, row, runs):
    run = row["run"]
    head = f"| {name} | {row['target']:g} | {row['method']} |"
    if run is None:
        best = common.most_accurate(runs)
        note = (f"not reached (best {best['error']:.2e} at {best['elements']} elements)"
                if best else "not reached")
        return head + f" {note} | | | | | |"
    peak = f"{run['peak_force']:.3f}" if "peak_force" in run else ""
    return (head + f" {run['elements']} | {run['dt']:.3g} | {run['courant']:.3g} | "
            f"{run['error']:.2e} | {peak} | {1e3 * row['time_min']:.1f} / "
            f"{1e3 * row['time_median']:.1f} |")


def main(argv=None):
    args = bench_arguments("opensees", HERE).parse_args(argv)
    return common.bench_main("opensees", args, worker, measure, section, SECTION)


if __name__ == "__main__":
    sys.exit(main())
