"""Against OpenSees: time to solution at equal accuracy (issue 26).

    python bench/opensees.py [--quick] [--readme-only]

Three problems with exact solutions, each solved by vstpetsc (defaults,
and the averaged mass) and by OpenSees (openseespy: 1-D trusses, Newmark
average acceleration, consistent and lumped mass):

1. wave: the bundled `wave` example's standing wave (steel bar 1 m,
   clamped left, free right, u0 = 1e-4 sin(pi x / 2L) at rest); the free
   end moves as 1e-4 cos(pi c t / 2L) (docs/examples.md). Error: relative
   L2 norm of the tip displacement over two periods (4L/c each).
2. impact: the steel bar at v0 = 1 m/s against a rigid wall at zero gap.
   It leaves after 2L/c with the uniform velocity -v0 (formulation.md
   section 7). Error: |mean velocity + v0| / v0 at 4L/c (mean velocity =
   momentum / mass); the peak contact force over Z v0 is reported too.
3. site: linear site response (see ``site_surface_exact``). Error:
   relative L2 norm of the surface velocity over [0, 1.2 s].

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

import argparse
import io
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

from readme import write_readme

HERE = os.path.dirname(os.path.abspath(__file__))
E, RHO, AREA, LENGTH = 2.0e11, 7850.0, 1.0, 1.0
C = math.sqrt(E / RHO)
Z = RHO * C * AREA
AMP = 1.0e-4                      # the wave example's amplitude
V0 = 1.0                          # impact velocity
SITE = {"H": 20.0, "c": 200.0, "rho": 1800.0, "c_rock": 1000.0, "rho_rock": 2200.0,
        "f": 10.0, "t0": 0.2, "end": 1.2, "table_dt": 1.0e-4}
TARGETS = {"wave": (1e-3, 1e-4, 1e-5), "impact": (5e-3, 3e-3, 1e-3),
           "site": (1e-3, 1e-4, 1e-5)}
SQRT_HALF = math.sqrt(0.5)
WORK_CAP = 1.2e7                  # elements x steps of the largest run of the search
SLOW_TOTAL = 8.0                  # seconds of timing runs after which a job stops at three


# ---------------------------------------------------------------- exact solutions

def wave_period(length=LENGTH, c=C):
    """Period of the clamped-free bar's first mode, 4L/c."""
    return 4.0 * length / c


def tip_exact(t, amp=AMP, length=LENGTH, c=C):
    """Free-end displacement of the first mode started at rest."""
    return amp * np.cos(0.5 * math.pi * c * np.asarray(t) / length)


def ricker(t, f, t0):
    """Ricker wavelet of peak frequency f centred at t0, peak 1."""
    a = (math.pi * f * (np.asarray(t) - t0)) ** 2
    return (1.0 - 2.0 * a) * np.exp(-a)


def site_surface_exact(t, v_in, height, c, z_soil, z_rock, tol=1e-15):
    """Surface velocity of a uniform layer on elastic rock.

    Layer 0 < x < H (base at x = 0, free surface at x = H), speed c,
    impedance Z_s = rho c A; below, rock of impedance Z_r carrying an
    upgoing wave whose particle velocity at x = 0 is v_in(t) (zero for
    t < 0). In the layer v = f(t - x/c) + g(t + x/c) and the stress is
    sigma = Z_s (g - f) / A. The free surface reflects g(t + H/c) = f(t - H/c),
    so at the base g(t) = f(t - 2H/c). The rock acts on the base with
    Z_r (2 v_in - v) along +x (a Lysmer dashpot plus the incident wave's
    force), and that force is -sigma A:

        Z_s (f - g) = Z_r (2 v_in - f - g)
        f(t) = T v_in(t) + R f(t - 2H/c),  T = 2 Z_r / (Z_s + Z_r),
                                           R = (Z_s - Z_r) / (Z_s + Z_r)

    (T the rock-to-soil transmission, R the reflection of a downgoing
    wave at the base; R < 0 for soft soil on stiff rock). Unrolled, with
    v(H, t) = 2 f(t - H/c):

        v(H, t) = 2 T sum_{n >= 0} R^n v_in(t - (2n + 1) H / c)

    the multiple reflections; terms stop when |R|^n < tol. Its transfer
    function to the outcrop motion 2 v_in is T / |1 - R exp(-2 i k H)| =
    1 / sqrt(cos^2 kH + a^2 sin^2 kH), a = Z_s / Z_r (docs/examples.md).
    """
    t = np.asarray(t, dtype=float)
    trans, refl = 2.0 * z_rock / (z_soil + z_rock), (z_soil - z_rock) / (z_soil + z_rock)
    out, n = np.zeros_like(t), 0
    while abs(refl) ** n >= tol and n < 10_000:
        lag = t - (2 * n + 1) * height / c
        out += 2.0 * trans * refl ** n * np.where(lag >= 0.0, v_in(np.maximum(lag, 0.0)), 0.0)
        n += 1
        if (lag < 0.0).all():
            break
    return out


def site_incident():
    """The incident wave as both codes get it: a table of the Ricker pulse
    (linear between samples; zero after the pulse), and that table as a
    function (the exact solution uses it, so the table's own error of ~1e-7
    against the smooth pulse is in neither)."""
    s = SITE
    t = np.arange(0.0, 2.0 * s["t0"] + 0.5 * s["table_dt"], s["table_dt"])
    v = ricker(t, s["f"], s["t0"])
    v[-1] = 0.0
    return t, v, (lambda x: np.interp(x, t, v, left=0.0, right=0.0))


# ---------------------------------------------------------------- error norms

def rel_l2(values, exact):
    """Relative discrete L2 norm of the error over equally spaced samples."""
    values, exact = np.asarray(values, dtype=float), np.asarray(exact, dtype=float)
    return float(np.linalg.norm(values - exact) / np.linalg.norm(exact))


def node_masses(elements, rho=RHO, area=AREA, length=LENGTH):
    """Row sums of the mass matrix (the same for consistent, averaged and
    lumped): rho A h / 2 at the ends, rho A h inside."""
    m = np.full(elements + 1, rho * area * length / elements)
    m[[0, -1]] *= 0.5
    return m


def mean_velocity(v, masses):
    """Momentum over mass: the rigid-body velocity of the bar."""
    return float(np.dot(v, masses) / np.sum(masses))


def rebound_error(v_mean, v0=V0):
    """|v_mean - (-v0)| / v0: the exact bar leaves the wall with -v0."""
    return abs(v_mean + v0) / abs(v0)


def steps_for(end, elements, courant, length, c):
    """Whole steps over [0, end] with c dt / h at most ``courant``."""
    return max(1, math.ceil(end * c * elements / (courant * length) - 1e-9))


def cheapest(rows, target):
    """The row of least work (elements x steps) whose error is <= target."""
    ok = [r for r in rows if r["error"] is not None and r["error"] <= target]
    return min(ok, key=lambda r: r["elements"] * r["steps"]) if ok else None


# ---------------------------------------------------------------- problems

def problem(name):
    """(length, speed, end time, first element count) of a problem."""
    if name == "wave":
        return LENGTH, C, 2.0 * wave_period(), 8
    if name == "impact":
        return LENGTH, C, 4.0 * LENGTH / C, 25
    return SITE["H"], SITE["c"], SITE["end"], 10


def evaluate(name, t, series, final_v=None, force=None):
    """Error (and extras) of one run from its sampled output."""
    if name == "wave":
        return {"error": rel_l2(series, tip_exact(t))}
    if name == "site":
        s = SITE
        exact = site_surface_exact(t, site_incident()[2], s["H"], s["c"], s["rho"] * s["c"],
                                   s["rho_rock"] * s["c_rock"])
        return {"error": rel_l2(series, exact)}
    v_mean = mean_velocity(final_v, node_masses(len(final_v) - 1))
    return {"error": rebound_error(v_mean), "rebound": v_mean,
            "peak_force": float(np.max(np.abs(force)) / (Z * V0))}


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
        for line in sys.stdin:
            seconds, metrics = opensees_run(json.loads(line), folder)
            sys.stdout.write(json.dumps({"seconds": seconds, **metrics}) + "\n")
            sys.stdout.flush()
    return 0


class OpenSeesChild:
    """The child process that runs OpenSees jobs."""

    def __init__(self):
        self.proc = subprocess.Popen([sys.executable, os.path.abspath(__file__), "--worker"],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)

    def __call__(self, job):
        self.proc.stdin.write(json.dumps(job) + "\n")
        self.proc.stdin.flush()
        answer = self.proc.stdout.readline()
        if not answer:
            raise RuntimeError(f"the OpenSees child died on {job}")
        got = json.loads(answer)
        return got.pop("seconds"), got

    def close(self):
        self.proc.stdin.close()
        self.proc.wait(timeout=30)


# ---------------------------------------------------------------- vstpetsc

def vst_case(job, folder):
    """The case of a vstpetsc job, as Python data."""
    name, n, steps, dt = job["problem"], job["elements"], job["steps"], job["dt"]
    length = problem(name)[0]
    body = {"name": "bar", "x": [0.0, length], "elements": n, "E": E, "rho": RHO}
    if job["mass"] != "default":
        body["mass"] = job["mass"]
    doc = {"time": {"dt": dt, "end": steps * dt}, "output": {"every": 1}, "body": [body]}
    if name == "wave":
        x = np.linspace(0.0, LENGTH, n + 1)
        body["u0"] = np.column_stack([x, AMP * np.sin(0.5 * math.pi * x)]).tolist()
        doc["bc"] = [{"body": "bar", "end": "left", "type": "fixed"}]
    elif name == "impact":
        body["v0"] = V0
        pair = {"pair": ["bar", "wall"], "wall": LENGTH}
        if job.get("penalty"):
            pair.update(formulation="power", penalty=job["penalty"])
        if job.get("formulation"):
            pair["formulation"] = job["formulation"]
        doc["contact"] = [pair]
    else:
        s = SITE
        body.update(E=s["rho"] * s["c"] ** 2, rho=s["rho"])
        doc["bc"] = [{"body": "bar", "end": "left", "type": "absorbing",
                      "impedance": s["rho_rock"] * s["c_rock"] * AREA,
                      "incident": {"file": incident_csv(folder), "column": "v"}}]
    return doc


def incident_csv(folder):
    """The incident wave as a CSV record, the form users give (a TOML table
    of 20000 rows costs vstpetsc more to check than to solve)."""
    path = os.path.join(folder, "incident.csv")
    if not os.path.exists(path):
        t, v, _ = site_incident()
        np.savetxt(path, np.column_stack([t, v]), fmt="%.17g", delimiter=",",
                   header="t,v", comments="")
    return path


def vst_run(job, folder):
    """One vstpetsc run in this process: (seconds, metrics)."""
    import vstpetsc

    path = os.path.join(folder, "run.h5")
    if os.path.exists(path):
        os.remove(path)
    doc = vst_case(job, folder)
    start = time.perf_counter()
    result = vstpetsc.run(vstpetsc.Case.from_dict(doc), path, quiet=True, out=io.StringIO())
    seconds = time.perf_counter() - start
    t = result["time"][1:]
    if job["problem"] == "impact":
        v = result["body/bar/v"]
        return seconds, evaluate("impact", t, None, v[-1], result["contact/0/force"][1:])
    key = "body/bar/u" if job["problem"] == "wave" else "body/bar/v"
    return seconds, evaluate(job["problem"], t, result[key][1:, -1])


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


def job_for(name, fields, n, courant):
    """The job of a method (its fields) at n elements and c dt/h = courant;
    a penalty given per unit 1/h becomes 0.5 E A / h of this mesh."""
    length, c, end, _ = problem(name)
    steps = steps_for(end, n, courant, length, c)
    job = {"problem": name, "elements": n, "steps": steps, "dt": end / steps,
           "courant": courant, **fields}
    if job.get("penalty"):
        job["penalty"] = job["penalty"] * n / length
    return job


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


def time_chosen(chosen, runners, reps):
    """Run every chosen job ``reps`` times, interleaved: (min, median) each;
    a job that has taken SLOW_TOTAL seconds stops after three runs."""
    keys = list(chosen)
    times = {key: [] for key in keys}
    for _ in range(reps):
        for key in keys:
            if len(times[key]) >= 3 and sum(times[key]) > SLOW_TOTAL:
                continue
            kind, job = chosen[key]
            times[key].append(runners[kind](job)[0])
    return {key: (min(v), float(np.median(v))) for key, v in times.items()}


def measure(quick, log=print):
    child = OpenSeesChild()                      # before PETSc starts Open MPI
    with tempfile.TemporaryDirectory() as folder:
        runners = {"vst": lambda job: vst_run(job, folder), "os": child}
        res = {"quick": quick, "date": time.strftime("%Y-%m-%d"),
               "machine": f"{os.uname().nodename} {os.cpu_count()} cores", "problems": {}}
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
        timed = time_chosen(chosen, runners, 2 if quick else 5)
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
             "form of that record, docstring of `site_surface_exact`). vstpetsc = "
             "the defaults (averaged mass; power contact, penalty 0.5 E A / h); vstpetsc seed "
             "= the source document's method (`mass = \"consistent\"`, seed contact, its "
             "default penalty).", "",
             "| problem | target | method | elements | dt [s] | c dt/h | error | peak force / Z v0 "
             "| time [ms] min / median |", "|---|---|---|---|---|---|---|---|---|"]
    for name, prob in res["problems"].items():
        for row in prob["table"]:
            lines.append(table_row(name, row, prob["runs"][row["method"]]))
    return "\n".join(lines + ["", "Fastest per target (min times; the others as multiples "
                               "of it):", ""] + fastest_lines(res)) + "\n"


def fastest_lines(res):
    """One line a problem and target: the fastest method, the others' ratios."""
    out = []
    for name, prob in res["problems"].items():
        for target in TARGETS[name]:
            rows = [r for r in prob["table"] if r["target"] == target and r["run"]]
            if not rows:
                continue
            best = min(rows, key=lambda r: r["time_min"])
            others = ", ".join(f"{r['method']} {r['time_min'] / best['time_min']:.1f} x"
                               for r in rows if r is not best)
            missing = [r["method"] for r in prob["table"]
                       if r["target"] == target and not r["run"]]
            out.append(f"- {name} {target:g}: {best['method']} "
                       f"{1e3 * best['time_min']:.1f} ms" + (f"; {others}" if others else "")
                       + (f"; not reached: {', '.join(missing)}" if missing else "") + ".")
    return out


def table_row(name, row, runs):
    run = row["run"]
    head = f"| {name} | {row['target']:g} | {row['method']} |"
    if run is None:
        done = [r for r in runs if r["error"] is not None]
        best = min(done, key=lambda r: r["error"]) if done else None
        note = (f"not reached (best {best['error']:.2e} at {best['elements']} elements)"
                if best else "not reached")
        return head + f" {note} | | | | | |"
    peak = f"{run['peak_force']:.3f}" if "peak_force" in run else ""
    return (head + f" {run['elements']} | {run['dt']:.3g} | {run['courant']:.3g} | "
            f"{run['error']:.2e} | {peak} | {1e3 * row['time_min']:.1f} / "
            f"{1e3 * row['time_median']:.1f} |")


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--readme-only", action="store_true",
                    help="rewrite the README section from bench/opensees.json")
    ap.add_argument("--out", default=HERE)
    args = ap.parse_args(argv)
    if args.worker:
        return worker()
    json_path = os.path.join(args.out, "opensees.json")
    if args.readme_only:
        with open(json_path) as f:
            res = json.load(f)
    else:
        res = measure(args.quick, log=lambda s: print(s, flush=True))
        os.makedirs(args.out, exist_ok=True)
        with open(json_path, "w") as f:
            json.dump(res, f, indent=1)
    write_readme(os.path.join(args.out, "README.md"), section(res))
    print(f"wrote {json_path} and the section {SECTION!r} of README.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
