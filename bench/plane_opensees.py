"""Plane strain against OpenSees: time to solution at equal accuracy on a
2-D standing wave with a closed form (issue 37).

    python bench/plane_opensees.py [--quick] [--readme-only]

The problem
-----------
The square [0, L]^2 of an isotropic elastic solid in plane strain
(Lame lambda, mu, density rho; Vp^2 = (lambda + 2 mu) / rho, Vs^2 = mu / rho)
on rollers: on x = 0 and x = L, u_x = 0 and the shear traction is free; on
y = 0 and y = L, u_y = 0 and the shear traction is free. With
a = m pi / L, b = n pi / L, k^2 = a^2 + b^2, the fields

    u_x = A sin(a x) cos(b y) sin(w t),   u_y = B cos(a x) sin(b y) sin(w t)

are exact solutions (Graff, Wave Motion in Elastic Solids, 1975, sec. 5.1:
the Lame potentials of a rectangle's separable modes; Achenbach, Wave
Propagation in Elastic Solids, 1973, sec. 2.5, the displacement equation
of motion). The check, from Navier's equation
rho u_tt = (lambda + mu) grad div u + mu lap u:

    div u = (a A + b B) cos(a x) cos(b y) sin(w t),
    grad div u = -(a A + b B) (a sin(a x) cos(b y), b cos(a x) sin(b y)) sin(w t),
    lap u = -k^2 u,  rho u_tt = -rho w^2 u,

so the x and y components ask, of the amplitudes alone,

    rho w^2 A = (lambda + mu) (a A + b B) a + mu k^2 A,
    rho w^2 B = (lambda + mu) (a A + b B) b + mu k^2 B.

Dilatational family (A, B) = (a, b) / k: a A + b B = k, and both lines
read rho w^2 = (lambda + 2 mu) k^2, w = Vp k. Rotational family
(A, B) = (b, -a) / k: a A + b B = 0, div u = 0, and rho w^2 = mu k^2,
w = Vs k. The boundaries: u_x has sin(a x), zero at x = 0, L (a L = m pi);
u_y has sin(b y), zero at y = 0, L; the shear stress
sigma_xy = mu (du_x/dy + du_y/dx) = -mu (b A + a B) sin(a x) sin(b y) sin(w t)
vanishes on all four sides. tests/test_bench_plane_opensees.py checks
both families against Navier's equation and the rollers by finite
differences.

The run: one P mode (m, n) = (1, 1) and one S mode (2, 1) of the same
displacement amplitude U, started at rest in the undeformed state with the
velocity of u at t = 0 (OpenSees' Newmark then needs no initial
acceleration: M a0 = -K u0 = 0; the sine, not the cosine, in time):

    u(x, t) = U sum_modes phi_mode(x) sin(w_mode t),  v(x, 0) = U sum w phi.

Error measure (the same for both codes): the relative L2 norm over the
mesh's nodes and the 16 times t_j = j T_S / 8 (j = 1..16, two periods of
the slower S mode, T_S = 2 pi / w_S) of the nodal displacement against the
closed form at the nodes,

    e = sqrt(sum_j sum_nodes |u_h - u|^2) / sqrt(sum_j sum_nodes |u|^2).

The codes
---------
vstpetsc: PlaneModel, plane_loads and PlaneSolver in-process (set up as
bench/plane_slab.py does, no result file), set_state(0, v0), slabs stepped
and u copied at the 16 times; bilinear quadrilaterals, its defaults
(averaged mass, PETSc's LU; the consistent mass's error is 3.6 times the
averaged one's here, at n = 8 to 32). OpenSees (openseespy, a child process:
openseespy and petsc4py crash in one process): nDMaterial
ElasticIsotropic, the same nodes, plane-strain four-node elements, rollers
by `fix`, v0 by `setNodeVel` (committed); Newmark average acceleration
(gamma 1/2, beta 1/4), constraints Plain, algorithm Linear -factorOnce
(the problem is linear), the fastest of SYSTEMS on this machine for
each element (set-up and PROBE_STEPS steps at n = PROBE_N), the
displacements read by nodeDisp at the 16 times. OpenSees' `quad`
(FourNodeQuad, the same 2 x 2 Gauss stiffness as vstpetsc's) has only a
lumped mass; its consistent-mass four-node elements are `bbarQuad`
(mixed B-bar volumetric strain) and `enhancedQuad` (enhanced assumed
strain): all three are compared.

Search and timing as bench/opensees.py: for each method and target, the
cheapest run (elements x steps) reaching it, n up the LADDER (h shrinking
by sqrt(2) a rung, not 2, so that no method overshoots a target by much)
at each of the method's Courant numbers Vp dt / h until the smallest
target is met or the work cap is passed; then all chosen runs timed
again, interleaved, min and median. A target not met within the cap gets
an estimate: the mesh the last two runs' order predicts and its time at
the last run's cost per element x step (a lower bound). Time = the whole
solve: set-up (vstpetsc: mesh, distribution, assembly, factorisation;
OpenSees: model building through openseespy's calls, analysis set-up) and
time stepping with the 16 copies of the field; the error's evaluation is
outside the timed part in both.

Writes bench/plane_opensees.json and the section "Plane strain against
OpenSees" of bench/README.md.
"""

import json
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.append(HERE)

import opensees_common as common  # noqa: E402
from readme import bench_arguments  # noqa: E402

# the material (nu = 1/4: Vp = sqrt(3) Vs) and the square
LENGTH, E, NU, RHO = 10.0, 2.0e8, 0.25, 2000.0
LAM, MU = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
VP, VS = math.sqrt((LAM + 2 * MU) / RHO), math.sqrt(MU / RHO)
AMPLITUDE = 1e-3
MODES = (("P", 1, 1), ("S", 2, 1))
SAMPLES = 16                      # times j T_S / 8, j = 1..16: two periods of the S mode
TARGETS = (1e-3, 1e-4, 1e-5)
# meshes n x n, h shrinking by sqrt(2) a rung (halving h would let a run
# overshoot a target by up to 4 times in error, and the work with it)
LADDER = tuple(int(round(4 * 2 ** (k / 2))) for k in range(17))    # 4, 6, 8, 11, 16, ... 1024
WORK_CAP = 2.0e7                  # elements x steps of the largest run of the search
QUICK_CAP = 1.0e6
SLOW_TOTAL = 30.0                 # seconds of timing runs after which a job stops at three
# OpenSees' linear systems tried on each element (the fastest is used)
SYSTEMS = ("SuperLU", "Mumps", "UmfPack", "BandGen", "BandSPD", "ProfileSPD", "SparseSYM")
PROBE_N, PROBE_STEPS = 64, 40


# ---------------------------------------------------------------- the closed form

def mode(kind, m, n):
    """(A, B, a, b, w) of a roller-square mode: the dilatational ("P",
    (A, B) = (a, b) / k, w = Vp k) or rotational ("S", (b, -a) / k, Vs k)."""
    a, b = m * math.pi / LENGTH, n * math.pi / LENGTH
    k = math.hypot(a, b)
    if kind == "P":
        return a / k, b / k, a, b, VP * k
    return b / k, -a / k, a, b, VS * k


def shapes(xy):
    """[(phi (nn, 2), w)] of MODES at the points xy (nn, 2)."""
    out = []
    for kind, m, n in MODES:
        A, B, a, b, w = mode(kind, m, n)
        x, y = xy[:, 0], xy[:, 1]
        phi = np.column_stack([A * np.sin(a * x) * np.cos(b * y),
                               B * np.cos(a * x) * np.sin(b * y)])
        out.append((phi, w))
    return out


def slow_period():
    return 2.0 * math.pi / min(mode(*m)[4] for m in MODES)


def sample_times():
    return slow_period() / 8.0 * np.arange(1, SAMPLES + 1)


def exact(xy, times):
    """u (nt, nn, 2) of the closed form at the points xy and ``times``."""
    return AMPLITUDE * sum(np.sin(w * times)[:, None, None] * phi[None] for phi, w in shapes(xy))


def initial_velocity(xy):
    """v(x, 0) (nn, 2); exact zeros on the rollers' held components."""
    v = AMPLITUDE * sum(w * phi for phi, w in shapes(xy))
    v[np.isclose(xy[:, 0], 0.0) | np.isclose(xy[:, 0], LENGTH), 0] = 0.0
    v[np.isclose(xy[:, 1], 0.0) | np.isclose(xy[:, 1], LENGTH), 1] = 0.0
    return v


def relative_error(xy, u):
    """The relative L2 error over nodes and sample times of u (nt, nn, 2)."""
    ref = exact(xy, sample_times())
    return float(np.linalg.norm(u - ref) / np.linalg.norm(ref))


def grid(n):
    """The nodes of the n x n square, node (i, j) = j (n + 1) + i (mesh.rectangle's order)."""
    s = np.linspace(0.0, LENGTH, n + 1)
    X, Y = np.meshgrid(s, s)
    return np.column_stack([X.ravel(), Y.ravel()])


def job_for(method, n, courant):
    """A run of ``method`` on the n x n mesh with Vp dt / h <= courant, dt
    dividing T_S / 8 (the sample times fall on steps)."""
    per_sample = max(1, math.ceil(VP * slow_period() / 8.0 * n / (LENGTH * courant)))
    dt = slow_period() / 8.0 / per_sample
    return {"method": method, "n": n, "per_sample": per_sample, "dt": dt,
            "steps": SAMPLES * per_sample, "courant": VP * dt * n / LENGTH,
            "target_courant": courant}


# ---------------------------------------------------------------- OpenSees (child)

# method -> (OpenSees element, the arguments after its nodes, its mass)
OPENSEES_ELEMENTS = {
    "opensees quad": ("quad", (1.0, "PlaneStrain", 1), "lumped"),
    "opensees bbarQuad": ("bbarQuad", (1.0, 1), "consistent"),
    "opensees enhancedQuad": ("enhancedQuad", (1.0, "PlaneStrain", 1), "consistent"),
}


def opensees_model(ops, n, method):
    """Nodes, material (rho in the material: every element takes it from
    there), elements and rollers of the n x n square."""
    kind, args, _ = OPENSEES_ELEMENTS[method]
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 2)
    xy = grid(n)
    for tag, (x, y) in enumerate(xy.tolist(), start=1):
        ops.node(tag, x, y)
    ops.nDMaterial("ElasticIsotropic", 1, E, NU, RHO)
    node = np.arange(1, (n + 1) ** 2 + 1).reshape(n + 1, n + 1)
    corners = np.column_stack([node[:-1, :-1].ravel(), node[:-1, 1:].ravel(),
                               node[1:, 1:].ravel(), node[1:, :-1].ravel()])
    for tag, quad in enumerate(corners.tolist(), start=1):
        ops.element(kind, tag, *quad, *args)
    hold_x = np.isclose(xy[:, 0], 0.0) | np.isclose(xy[:, 0], LENGTH)
    hold_y = np.isclose(xy[:, 1], 0.0) | np.isclose(xy[:, 1], LENGTH)
    for i in np.flatnonzero(hold_x | hold_y).tolist():
        ops.fix(i + 1, int(hold_x[i]), int(hold_y[i]))
    return xy


def opensees_analysis(ops, system):
    """Newmark average acceleration, linear: the system factored once."""
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system(system)
    ops.algorithm("Linear", "-factorOnce")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")


def opensees_run(job):
    """One OpenSees run in this (child) process: (seconds, u (nt, nn, 2) or
    None if the analysis failed, xy)."""
    import openseespy.opensees as ops

    start = time.perf_counter()
    xy = opensees_model(ops, job["n"], job["method"])
    for tag, (vx, vy) in enumerate(initial_velocity(xy).tolist(), start=1):
        ops.setNodeVel(tag, 1, vx, "-commit")
        ops.setNodeVel(tag, 2, vy, "-commit")
    opensees_analysis(ops, job["system"])
    tags = range(1, xy.shape[0] + 1)
    u = np.empty((SAMPLES, xy.shape[0], 2))
    for j in range(SAMPLES):
        if ops.analyze(job["per_sample"], job["dt"]) != 0:
            u = None
            break
        u[j] = [ops.nodeDisp(tag) for tag in tags]
    seconds = time.perf_counter() - start
    ops.wipe()
    return seconds, u, xy


def opensees_probe(method):
    """{system: seconds} of set-up, factorisation and PROBE_STEPS steps of
    ``method`` on the PROBE_N mesh with each of SYSTEMS."""
    import openseespy.opensees as ops

    out = {}
    for system in SYSTEMS:
        start = time.perf_counter()
        opensees_model(ops, PROBE_N, method)
        opensees_analysis(ops, system)
        ok = ops.analyze(PROBE_STEPS, 1e-4) == 0
        out[system] = time.perf_counter() - start if ok else None
        ops.wipe()
    return out


def worker():
    """Child loop: one JSON job a line on stdin, one JSON answer a line."""
    return common.serve(opensees_answer)


def opensees_answer(job):
    """The child's answer to a probe (the systems' seconds) or to a run
    (its seconds and error), with OpenSees' version."""
    import openseespy.opensees as ops

    if "probe" in job:
        answer = {"systems": opensees_probe(job["probe"])}
    else:
        seconds, u, xy = opensees_run(job)
        answer = {"seconds": seconds, "error": None if u is None else relative_error(xy, u)}
    answer["version"] = ops.version()
    return answer


class OpenSeesChild(common.WorkerChild):
    """The child process that runs OpenSees jobs; each job's method gets
    the system that ``probe`` found fastest."""

    def __init__(self):
        super().__init__(__file__, quiet=True, close_timeout=60)    # quiet: OpenSees' banners
        self.systems, self.version = {}, None

    def ask(self, job):
        got = super().ask(job)
        self.version = got.pop("version")
        return got

    def probe(self, method):
        """{system: seconds}; the fastest is kept for ``method``'s runs."""
        times = self.ask({"probe": method})["systems"]
        self.systems[method] = min((t, s) for s, t in times.items() if t is not None)[1]
        return times

    def __call__(self, job):
        got = self.ask({**job, "system": self.systems.get(job["method"], SYSTEMS[0])})
        return got["seconds"], got["error"]


# ---------------------------------------------------------------- vstpetsc

VST_MASSES = {"vstpetsc": "averaged"}


def vst_case(job):
    """The vstpetsc Case of a job: the square, rollers as held velocities."""
    import vstpetsc

    n, dt = job["n"], job["dt"]
    side = [0.0, LENGTH]
    roll = lambda name, axis: {"name": name, "type": "velocity", "value": {axis: 0.0}}
    return vstpetsc.Case.from_dict({
        "time": {"dt": dt, "end": dt * job["steps"]},
        "mesh": {"rectangle": {"x": side, "y": side, "nx": n, "ny": n}},
        "region": [{"name": "domain", "E": E, "nu": NU, "rho": RHO,
                    "mass": VST_MASSES[job["method"]]}],
        "boundary": [roll("left", "x"), roll("right", "x"), roll("bottom", "y"),
                     roll("top", "y")]})


def vst_run(job):
    """One vstpetsc run in this process: (seconds, u (nt, nn, 2), xy), u in
    the solver's (owned) order and xy the same nodes' coordinates."""
    from petsc4py import PETSc

    from vstpetsc.plane.loads import plane_loads
    from vstpetsc.plane.model import PlaneModel
    from vstpetsc.plane.solver.slab_solver import PlaneSolver

    case = vst_case(job)
    start = time.perf_counter()
    comm = PETSc.COMM_SELF
    model = PlaneModel(case, comm)
    loads = plane_loads(model, case.dt)
    solver = PlaneSolver(model, case.dt, comm, loads)
    xy_read = model.mesh.coordinates
    solver.set_state(np.zeros_like(xy_read), initial_velocity(xy_read))
    u = np.empty((SAMPLES, model.nnodes, 2))
    k = 0
    for j in range(SAMPLES):
        for _ in range(job["per_sample"]):
            k += 1
            solver.rhs(*loads.slab(k)[:2])
            solver.solve(k)
            solver.advance()
        u[j] = solver.u.reshape(-1, 2)
    seconds = time.perf_counter() - start
    return seconds, u, xy_read[model.owned_original]


def vst_runner(job):
    seconds, u, xy = vst_run(job)
    return seconds, relative_error(xy, u)


# ---------------------------------------------------------------- methods and search

def methods(quick=False):
    """{method: (runner kind, Courant numbers Vp dt / h)}: vstpetsc's time
    error is small up to 4 (third order); Newmark's period error adds to
    the lumped mass's (smaller is better, at a price) and partly cancels
    the consistent mass's (best near 0.5-1; 2 was 3 times worse at n = 32)."""
    if quick:
        return {"vstpetsc": ("vst", (2.0,)), "opensees quad": ("os", (0.5,)),
                "opensees bbarQuad": ("os", (1.0,))}
    return {"vstpetsc": ("vst", (1.0, 2.0, 4.0)),
            "opensees quad": ("os", (0.25, 0.5, 1.0)),
            "opensees bbarQuad": ("os", (0.5, 1.0)),
            "opensees enhancedQuad": ("os", (1.0,))}


def work(run):
    return run["n"] ** 2 * run["steps"]


def cheapest(rows, target):
    """The row of least work (elements x steps) whose error is <= target."""
    return common.cheapest(rows, target, work)


def search(runners, quick, log):
    """Every method's runs up the LADDER per Courant number until the
    smallest target is met, the error stops falling, or the next run would
    pass the cap on elements x steps (a cap on work, not on time: the same
    runs whatever the machine's load)."""
    cap = QUICK_CAP if quick else WORK_CAP
    rows = {}
    for method, (kind, courants) in methods(quick).items():
        rows[method] = []
        for courant in courants:
            last = None
            for n, n_next in zip(LADDER, LADDER[1:]):
                job = job_for(method, n, courant)
                seconds, error = runners[kind](job)
                rows[method].append({**job, "seconds": seconds, "error": error})
                log(f"{method} n={n} Vp dt/h={job['courant']:.3g} steps={job['steps']}: "
                    f"error {error} in {seconds:.3f} s")
                if error is None or error <= min(TARGETS) or \
                        work(job_for(method, n_next, courant)) > cap or \
                        (last is not None and error > 0.9 * last):
                    break
                last = error
    return rows


def extrapolate(rows, target):
    """For a target no run met: per Courant number, the mesh that the last
    two runs' convergence rate (error ~ n^-p) predicts, and its time at
    the last run's cost per element x step (a lower bound: the solves cost
    more per unknown as n grows); the cheapest of them, or None."""
    best = None
    for courant in sorted({r["target_courant"] for r in rows}):
        done = [r for r in rows if r["target_courant"] == courant and r["error"] is not None]
        if len(done) < 2 or not done[-1]["error"] < done[-2]["error"]:
            continue
        a, b = done[-2], done[-1]
        p = math.log(a["error"] / b["error"]) / math.log(b["n"] / a["n"])
        n = b["n"] * (b["error"] / target) ** (1.0 / p)
        steps = b["steps"] * n / b["n"]
        seconds = b["seconds"] * n * n * steps / work(b)
        if best is None or seconds < best["seconds"]:
            best = {"n": n, "steps": steps, "order": p, "seconds": seconds,
                    "target_courant": courant}
    return best


def measure(quick, log=print):
    child = OpenSeesChild()                      # before PETSc starts Open MPI
    runners = {"vst": vst_runner, "os": child}
    plan = methods(quick)
    systems = {m: child.probe(m) for m, (kind, _) in plan.items() if kind == "os"}
    log(f"OpenSees systems (s for {PROBE_STEPS} steps at n = {PROBE_N}): {systems}")
    res = {**common.results_head(quick), "work_cap": QUICK_CAP if quick else WORK_CAP, "system_probe": systems,
           "systems": dict(child.systems), "runs": search(runners, quick, log), "table": []}
    chosen = {}
    for method, (kind, _) in plan.items():
        for target in TARGETS:
            best = cheapest(res["runs"][method], target)
            row = {"target": target, "method": method, "run": best}
            if best is None:
                row["estimate"] = extrapolate(res["runs"][method], target)
            else:
                chosen[(method, best["n"], best["per_sample"])] = (kind, job_fields(best))
            res["table"].append(row)
    timed = common.time_chosen(chosen, runners, 2 if quick else 5, SLOW_TOTAL)
    for row in res["table"]:
        if row["run"] is not None:
            key = (row["method"], row["run"]["n"], row["run"]["per_sample"])
            row["time_min"], row["time_median"] = timed[key]
    res["opensees_version"] = child.version
    child.close()
    return res


def job_fields(run):
    return {k: run[k] for k in ("method", "n", "per_sample", "dt", "steps", "courant",
                                "target_courant")}


# ---------------------------------------------------------------- README

SECTION = "## Plane strain against OpenSees"


def section(res):
    """The README section: the cheapest run of each method and target."""
    sys_note = ", ".join(f"{m.split()[-1]} {s}" for m, s in res["systems"].items())
    lines = [SECTION, "",
             "Generated by `bench/plane_opensees.py` (`make bench`, `make bench-opensees`) on "
             f"{res['machine']}, {res['date']}; openseespy {res['opensees_version']} from "
             "PyPI. Problem: the standing wave of a roller-supported square (plane strain, "
             "10 m, nu = 1/4, Vs = 200 m/s), a P mode (1, 1) and an S mode (2, 1) of equal "
             "amplitude, started at rest undeformed with their velocity (closed form and its "
             "check in the script's docstring). Error: relative L2 of the nodal displacement "
             "over all nodes and 16 times (every eighth of the S period, two periods). Both "
             "codes on the same n x n grid of four-node quadrilaterals: vstpetsc with its "
             "defaults (averaged mass, PETSc's LU); OpenSees with Newmark average "
             "acceleration (Linear, factored once), rollers by `fix`, v0 by `setNodeVel`, "
             f"the fastest linear system of {len(SYSTEMS)} tried ({sys_note}); `quad` "
             "has a lumped mass only, `bbarQuad` and `enhancedQuad` a consistent one. "
             "For each method and target the cheapest run (elements x steps) reaching it: "
             "n up a ladder of ratio sqrt(2) at each Courant number Vp dt / h until the "
             f"smallest target or elements x steps of {res['work_cap']:.2g}; then the chosen "
             "runs timed again interleaved (5 times; 3 past 30 s): min / median of the whole "
             "solve (set-up, factorisation, steps, the 16 copies of the field; vstpetsc in-"
             "process without a result file, OpenSees in a child process). \"needs n ~\": "
             "for a target not reached, the mesh that the order of the last two runs "
             "predicts, and its time at the largest run's cost per element x step (a lower "
             "bound: the solves cost more per unknown on finer meshes).", "",
             "| target | method | mesh | steps | Vp dt / h | error | time [s] min / median "
             "| OpenSees / vstpetsc |", "|---|---|---|---|---|---|---|---|"]
    vst = {r["target"]: r for r in res["table"] if r["method"] == "vstpetsc"}
    for row in res["table"]:
        lines.append(table_row(row, vst[row["target"]], res["runs"][row["method"]]))
    return common.section_text(lines, fastest_lines(res))


def table_row(row, vst_row, runs):
    run, head = row["run"], f"| {row['target']:g} | {row['method']} |"
    if run is None:
        best = common.most_accurate(runs)
        note = "not reached" + (f" (best {best['error']:.2e} at {best['n']} x {best['n']})"
                                if best else "")
        est = row.get("estimate")
        if est:
            note += (f"; needs n ~ {est['n']:.0f} (order {est['order']:.2f}), "
                     f">= {est['seconds']:.3g} s")
        return head + f" {note} | | | | | |"
    ratio = ""
    if row["method"].startswith("opensees") and vst_row["run"] is not None:
        ratio = f"{row['time_min'] / vst_row['time_min']:.1f}"
    return (head + f" {run['n']} x {run['n']} | {run['steps']} | {run['courant']:.2f} | "
            f"{run['error']:.2e} | {row['time_min']:.2f} / {row['time_median']:.2f} | "
            f"{ratio} |")


def fastest_lines(res):
    """One line a target: the fastest method, the others' ratios."""
    return [common.fastest_line(f"{target:g}", res["table"], target,
                                lambda seconds: f"{seconds:.2f} s")
            or f"- {target:g}: no method within the cap." for target in TARGETS]


def single_run(method, n, courant):
    """One job of ``method`` (OpenSees' system probed first), printed."""
    job = job_for(method, n, courant)
    if method in VST_MASSES:
        seconds, error = vst_runner(job)
    else:
        child = OpenSeesChild()
        child.probe(method)
        seconds, error = child(job)
        child.close()
    print(json.dumps({**job, "seconds": seconds, "error": error}))
    return 0


def main(argv=None):
    ap = bench_arguments("plane_opensees", HERE)
    ap.add_argument("--run", nargs=3, metavar=("METHOD", "N", "COURANT"),
                    help="one run beyond the cap, e.g. --run 'opensees bbarQuad' 362 1: "
                         "its error and time, nothing written")
    args = ap.parse_args(argv)
    if args.run and not args.worker:
        return single_run(args.run[0], int(args.run[1]), float(args.run[2]))
    return common.bench_main("plane_opensees", args, worker, measure, section, SECTION)


if __name__ == "__main__":
    sys.exit(main())
