"""A yielding soil column against OpenSees: time to solution at equal
accuracy (issue 46).

    python bench/plane_yielding_opensees.py [--quick] [--readme-only]

The problem
-----------
A soil column HEIGHT high, one quadrilateral of WIDTH wide and CELLS high
(plane strain), rho, Vs, nu; every node holds v_y = 0 (a one-cell-wide
column then stays in simple shear: tests/test_plane_mkz_column.py), the
base is rigid and moves along x with the ground motion, the top is free;
no gravity. The soil is MKZ with extended Masing rules
(docs/nonlinear-soil.md sections 1, 7, 8): backbone tau = G gamma /
(1 + beta (|gamma| / gamma_ref)^s), GAMMA_REF, BETA, S_EXP. The ground
motion: the velocity pulse v_g(t) = V sin(2 pi f t) sin^2(pi t / T_d),
T_d = CYCLES / f, given to both codes as the same table of its
acceleration a_g = dv_g/dt sampled every TABLE_DT (linear between
samples); the run lasts END (the free vibration after the pulse, damped
by the loops alone).

The codes
---------
vstpetsc: the case (``case_doc``) run through vstpetsc.run: the bottom a
velocity boundary (x: the table with integrate = true, the exact integral
of the linear acceleration; y: 0), the sides holding v_y, the region
"lumped" mass (OpenSees' `quad` has only a lumped mass: with it the two
codes discretise the same semi-discrete system in space and differ only
in the law and in time), a gauge at the top; its slab dt varied.

OpenSees (openseespy in a child process; openseespy and petsc4py crash in
one process): the same nodes, `quad` elements (plane strain, 2 x 2 Gauss:
vstpetsc's quadrature) of nDMaterial PressureIndependMultiYield (PIMY;
OpenSees wiki "PressureIndependMultiYield Material": nd rho refShearModul
refBulkModul cohesi peakShearStra frictionAng refPress pressDependCoe
noYieldSurf, then for noYieldSurf < 0 its |noYieldSurf| pairs (strain,
G/Gmax) of a user-defined backbone; frictionAng 0 makes the yield
pressure-independent and the last pair's stress the strength, cohesi and
peakShearStra are then ignored: OpenSees' setUpSurfaces). The pairs are
sampled from the MKZ curve G/Gmax = 1 / (1 + beta (gamma / gamma_ref)^s),
SURFACES of them log-spaced from GAMMA_LO to GAMMA_HI: the parser takes
noYieldSurf > -40 only, so 39 at most. The strain of a pair is the
engineering shear strain gamma_xy in simple shear (setUpSurfaces: stress
G (G/Gmax) gamma, the surface of size sqrt(3) tau in sqrt(3/2 s:s), and the
plastic moduli against 2 G; tests/test_bench_plane_yielding_opensees.py
drives one element in simple shear and finds MKZ's tau(gamma) at the
pairs). openseespy 3.7.1 reads only 5 numbers before noYieldSurf (OpenSees
commit 6ba2fd0, Feb. 2025, "numdata = 5"; restored to 8 in 6f71a7d,
Oct. 2025): frictionAng, refPress and pressDependCoe keep their defaults
0, 100 and 0, which are the values wanted here; ``pimy_material`` tries
the documented list first. The material stage is set to plastic
(updateMaterialStage) before the first step: with no gravity the column
starts at rest and unstressed, so an elastic stage would change nothing.
The base: fixed along x, the ground motion as UniformExcitation of the
same acceleration table (Path time series, linear between samples): the
motion relative to the base, the absolute top velocity = relative +
v_g at the sample times (the table's trapezoidal sums: the exact integral
of the linear acceleration). Newmark average acceleration (gamma 1/2,
beta 1/4), Newton with the material's tangent, NormDispIncr to
OS_TOLERANCE, the fastest of OS_SYSTEMS.

Accuracy
--------
Error (both codes): the relative max error of the top's absolute
velocity v_x at the sample times t_j = j SAMPLE (j = 1 .. END / SAMPLE)
against the reference,

    e = max_j |v(t_j) - v_ref(t_j)| / max_j |v_ref(t_j)|.

Reference: vstpetsc at dt = SAMPLE / REF_PER_SAMPLE (its convergence in
dt is listed in the results: the reference's own error is at most the
difference to the run at twice its dt, far below every target). PIMY's
piecewise-linear backbone differs from MKZ: OpenSees' floor is its error
at OS_FLOOR_PER_SAMPLE steps a sample, where its time error has gone. The
targets are chosen above it (FLOOR_MARGIN times the floor and up); for
each code and target the largest dt (fewest steps) whose error is within
it, and the chosen runs timed again, interleaved, min and median of
REPEATS. Time = the whole solve in each code's own process (vstpetsc:
vstpetsc.run from the case to the closed result file, its gauge written
every slab; OpenSees: the model built through openseespy's calls, the
analysis, the top's velocity read at the samples); the error's
evaluation is outside the timed part.

Writes bench/plane_yielding_opensees.json and the section "Yielding column
against OpenSees (issue 46)" of bench/README.md.
"""

import io
import math
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.append(HERE)

import opensees_common as common  # noqa: E402
from readme import bench_arguments  # noqa: E402

# the column (SI)
HEIGHT, CELLS, WIDTH = 20.0, 20, 1.0
RHO, VS, NU = 2000.0, 200.0, 0.3
G = RHO * VS ** 2
BULK = 2.0 * G * (1.0 + NU) / (3.0 * (1.0 - 2.0 * NU))
GAMMA_REF, BETA, S_EXP = 3.0e-4, 1.0, 0.919
# the ground motion: three cycles of 2 Hz (below the column's linear
# resonance Vs / 4H = 2.5 Hz, where the softened column sits)
PULSE_V, PULSE_F, CYCLES = 0.2, 2.0, 3
TABLE_DT, END = 1.0e-3, 3.0
SAMPLE = 0.02                     # the error's sample interval; every dt divides it
# PIMY's backbone: SURFACES pairs log-spaced in [GAMMA_LO, GAMMA_HI]
SURFACES, GAMMA_LO, GAMMA_HI = 39, 1.0e-3 * GAMMA_REF, 100.0 * GAMMA_REF
# NormDispIncr's tolerance (m): the chosen runs again at OS_TIGHT change
# their errors by 2e-4 of themselves at most and take 1.5 to 1.9 times as
# long (one run each; "tolerance_check" in the results, a README line)
OS_TOLERANCE, OS_TIGHT, OS_ITERATIONS = 1.0e-6, 1.0e-10, 50
OS_SYSTEMS = ("BandGen", "ProfileSPD", "UmfPack", "SuperLU")
LADDER = (1, 2, 3, 4, 6, 8, 12, 16, 24, 32)            # steps per SAMPLE
QUICK_LADDER = (1, 2, 4, 8, 16)
REF_PER_SAMPLE, OS_FLOOR_PER_SAMPLE = 128, 64          # quick: QUICK_LADDER[-1] both
# relative max errors of the top's velocity; a target below FLOOR_MARGIN
# times OpenSees' floor is not compared (PIMY's backbone, not its time
# stepping, would decide it)
TARGETS = (1.5e-2, 3.0e-2, 6.0e-2)
FLOOR_MARGIN = 1.5
REPEATS, QUICK_REPEATS, SLOW_TOTAL = 5, 2, 60.0


# ---------------------------------------------------------------- the problem

def mkz_ratio(gamma):
    """MKZ's G/Gmax at the engineering shear strain gamma."""
    return 1.0 / (1.0 + BETA * (np.abs(gamma) / GAMMA_REF) ** S_EXP)


def backbone_pairs(n=SURFACES, lo=GAMMA_LO, hi=GAMMA_HI):
    """PIMY's user-defined backbone: n (strain, G/Gmax) pairs on MKZ's
    curve, log-spaced in [lo, hi] (the curve bends where it is log-
    uniform), flat as one list."""
    gamma = np.geomspace(lo, hi, n)
    return np.column_stack([gamma, mkz_ratio(gamma)]).ravel().tolist()


def pimy_backbone(gamma, n=SURFACES):
    """The backbone that PIMY builds from ``backbone_pairs(n)`` in simple
    shear (OpenSees' setUpSurfaces): elastic (G) up to the first pair's
    stress, linear between the pairs' (gamma_i, G r_i gamma_i), flat past
    the last (its strength)."""
    pairs = np.reshape(backbone_pairs(n), (-1, 2))
    tau = G * pairs[:, 0] * pairs[:, 1]
    knots = np.concatenate([[0.0, tau[0] / G], pairs[1:, 0]])
    a = np.abs(gamma)
    return np.sign(gamma) * np.interp(a, knots, np.concatenate([[0.0], tau]))


def acceleration_table():
    """a_g at t = k TABLE_DT, k = 0 .. END / TABLE_DT: the derivative of
    v_g(t) = V sin(2 pi f t) sin^2(pi t / T_d) on [0, T_d], 0 after."""
    t = TABLE_DT * np.arange(int(round(END / TABLE_DT)) + 1)
    w, duration = 2.0 * math.pi * PULSE_F, CYCLES / PULSE_F
    c = math.pi / duration
    a = PULSE_V * (w * np.cos(w * t) * np.sin(c * t) ** 2
                   + np.sin(w * t) * c * np.sin(2.0 * c * t))
    a[t >= duration] = 0.0
    return t, a


def base_velocity(times):
    """v_g at ``times`` (on the table's grid): the table's trapezoidal sums,
    the exact integral of the linear acceleration (what both codes get)."""
    t, a = acceleration_table()
    v = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * TABLE_DT)])
    return np.interp(times, t, v)


def sample_times():
    return SAMPLE * np.arange(1, int(round(END / SAMPLE)) + 1)


def relative_error(v, ref):
    """max_j |v - v_ref| / max_j |v_ref| (None if the run failed)."""
    if v is None:
        return None
    v, ref = np.asarray(v), np.asarray(ref)
    return float(np.abs(v - ref).max() / np.abs(ref).max())


def job_for(method, per_sample):
    dt = SAMPLE / per_sample
    return {"method": method, "per_sample": per_sample, "dt": dt,
            "steps": per_sample * sample_times().size, "courant": VS * dt * CELLS / HEIGHT}


# ---------------------------------------------------------------- OpenSees (child)

def pimy_material(ops, tag, pairs):
    """PIMY with the user-defined backbone ``pairs``, pressure-independent
    (frictionAng 0, refPress 100, pressDependCoe 0). The documented list
    first; openseespy 3.7.1's parser (5 numbers before noYieldSurf) refuses
    it (a float where it reads the int), then its own list."""
    n = len(pairs) // 2
    head = (2, RHO, G, BULK, 1.0, 0.1)          # cohesi, peakShearStra: ignored (user curve)
    try:
        ops.nDMaterial("PressureIndependMultiYield", tag, *head, 0.0, 100.0, 0.0, -n, *pairs)
        return "documented"
    except Exception:                            # openseespy.opensees.OpenSeesError
        ops.nDMaterial("PressureIndependMultiYield", tag, *head, -n, *pairs)
        return "3.7.1"


def opensees_model(ops, surfaces):
    """Nodes (row i: (0, y_i) and (WIDTH, y_i)), PIMY quads, v_y held
    everywhere, the base's v_x held (UniformExcitation moves it); the
    material set plastic. Returns the top's node tag and the parser used.
    ``surfaces`` 0: ElasticIsotropic instead (the harness's linear check)."""
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 2)
    ys = np.linspace(0.0, HEIGHT, CELLS + 1)
    for i, y in enumerate(ys.tolist()):
        ops.node(2 * i + 1, 0.0, y)
        ops.node(2 * i + 2, WIDTH, y)
        ops.fix(2 * i + 1, int(i == 0), 1)
        ops.fix(2 * i + 2, int(i == 0), 1)
    if surfaces:
        parser = pimy_material(ops, 1, backbone_pairs(surfaces))
    else:
        parser = None
        ops.nDMaterial("ElasticIsotropic", 1, 2.0 * G * (1.0 + NU), NU, RHO)
    for e in range(CELLS):
        a = 2 * e + 1
        ops.element("quad", e + 1, a, a + 1, a + 3, a + 2, 1.0, "PlaneStrain", 1)
    if surfaces:
        ops.updateMaterialStage("-material", 1, "-stage", 1)
    return 2 * CELLS + 1, parser


def opensees_analysis(ops, system, dt, tol=OS_TOLERANCE):
    t, a = acceleration_table()
    ops.timeSeries("Path", 1, "-dt", TABLE_DT, "-values", *a.tolist())
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system(system)
    ops.test("NormDispIncr", tol, OS_ITERATIONS)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")


def opensees_run(job):
    """One OpenSees run in this (child) process: (seconds, the top's
    relative v_x at the sample times or None if a step failed, parser)."""
    import openseespy.opensees as ops

    start = time.perf_counter()
    top, parser = opensees_model(ops, job.get("surfaces", SURFACES))
    opensees_analysis(ops, job["system"], job["dt"], job.get("tol", OS_TOLERANCE))
    n = sample_times().size
    v = np.empty(n)
    for j in range(n):
        if ops.analyze(job["per_sample"], job["dt"]) != 0:
            v = None
            break
        v[j] = ops.nodeVel(top, 1)
    seconds = time.perf_counter() - start
    ops.wipe()
    return seconds, v, parser


def opensees_simple_shear(path, surfaces=SURFACES):
    """One PIMY quad (1 x 1, the base held, v_y held) driven in simple
    shear through the engineering strains ``path`` (DisplacementControl of
    the top, its two nodes tied): [(gamma, tau_xy at the first Gauss
    point)] at every step."""
    import openseespy.opensees as ops

    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 2)
    for tag, (x, y) in enumerate(((0, 0), (1, 0), (1, 1), (0, 1)), start=1):
        ops.node(tag, float(x), float(y))
        ops.fix(tag, int(y == 0), 1)
    ops.equalDOF(3, 4, 1)
    pimy_material(ops, 1, backbone_pairs(surfaces))
    ops.element("quad", 1, 1, 2, 3, 4, 1.0, "PlaneStrain", 1)
    ops.updateMaterialStage("-material", 1, "-stage", 1)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(3, 1.0, 0.0)
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-14, 50)
    ops.algorithm("Newton")
    out, gamma = [], 0.0
    for target in path:
        ops.integrator("DisplacementControl", 3, 1, target - gamma)
        ops.analysis("Static")
        if ops.analyze(1) != 0:
            break
        gamma = ops.nodeDisp(3, 1)
        out.append((gamma, ops.eleResponse(1, "stresses")[2]))
    ops.wipe()
    return out


def opensees_answer(job):
    import openseespy.opensees as ops

    if "simple_shear" in job:
        answer = {"points": opensees_simple_shear(job["simple_shear"])}
    elif "probe" in job:
        answer = {"systems": {s: opensees_run({**job["probe"], "system": s})[0]
                              for s in OS_SYSTEMS}}
    else:
        seconds, v, parser = opensees_run(job)
        answer = {"seconds": seconds, "parser": parser,
                  "v": None if v is None else v.tolist()}
    answer["version"] = ops.version()
    return answer


def worker():
    return common.serve(opensees_answer)


class OpenSeesChild(common.SystemChild):
    """The child running OpenSees jobs, with the system ``probe`` found
    fastest; answers (seconds, the top's absolute v_x or None)."""

    def __init__(self):
        super().__init__(__file__, OS_SYSTEMS)
        self.parser = None

    def __call__(self, job):
        got = self.ask({**job, "system": self.system})
        self.parser = got["parser"]
        v = got["v"]
        return got["seconds"], None if v is None else np.asarray(v) + base_velocity(sample_times())


# ---------------------------------------------------------------- vstpetsc

def case_doc(dt, mass="lumped", linear=False):
    """The vstpetsc case of the column at slab ``dt`` (Case.from_dict);
    ``linear``: without its shear_law (the harness's linear check)."""
    t, a = acceleration_table()
    ground = {"table": np.column_stack([t, a]).tolist(), "integrate": True}
    held = {"type": "velocity", "value": {"y": 0.0}}
    steps = int(round(END / dt))
    law = {} if linear else {"shear_law": {"model": "mkz", "gamma_ref": GAMMA_REF,
                                            "beta": BETA, "s": S_EXP}}
    return {
        "time": {"dt": dt, "end": END}, "output": {"every": steps},
        "mesh": {"rectangle": {"x": [0.0, WIDTH], "y": [0.0, HEIGHT], "nx": 1, "ny": CELLS}},
        "region": [{"name": "domain", "Vs": VS, "nu": NU, "rho": RHO, "mass": mass, **law}],
        # the bottom first: the corners' v_x follow the ground (the first table wins)
        "boundary": [{"name": "bottom", "type": "velocity", "value": {"x": ground, "y": 0.0}},
                     {"name": "left", **held}, {"name": "right", **held}],
        "gauge": [{"name": "top", "x": [0.5 * WIDTH, HEIGHT]}]}


def vst_run(job):
    """(seconds, the top's v_x at the sample times, the largest strain /
    gamma_ref): vstpetsc.run in this process, to a result file in a
    temporary folder (removed after)."""
    import vstpetsc

    case = vstpetsc.Case.from_dict(case_doc(job["dt"], job.get("mass", "lumped"),
                                                job.get("linear", False)))
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        res = vstpetsc.run(case, output=os.path.join(folder, "column.h5"), quiet=True,
                           out=io.StringIO())
        seconds = time.perf_counter() - start
        gauge = res.gauge("top")
        t, v = gauge.time, np.asarray(gauge.v)[:, 0]
        rows = np.rint(sample_times() / job["dt"]).astype(int)
        assert np.allclose(t[rows], sample_times(), rtol=0, atol=1e-9)
        strain = None if job.get("linear") else float(np.max(res.field.strain_max)) / GAMMA_REF
    return seconds, v[rows], strain



# ---------------------------------------------------------------- search and timing

def vst_runner(job):
    seconds, v, _ = vst_run(job)
    return seconds, v


def search(kind, runner, ladder, ref, log):
    """The runs of one code up ``ladder`` (steps per SAMPLE) until the
    smallest target is met or the ladder ends: rows with their error
    against ``ref``."""
    rows = []
    for m in ladder:
        job = job_for(kind, m)
        seconds, v = runner(job)
        rows.append({**job, "seconds": seconds, "error": relative_error(v, ref)})
        log(f"{kind} dt={job['dt'] * 1e3:.4g} ms steps={job['steps']}: error "
            f"{rows[-1]['error']} in {seconds:.2f} s")
        if rows[-1]["error"] is not None and rows[-1]["error"] <= min(TARGETS):
            break
    return rows


def reference(quick, log):
    """(v_ref, facts): vstpetsc at the finest dt, and its change from the
    run at twice that dt (a bound on its own error)."""
    m = QUICK_LADDER[-1] if quick else REF_PER_SAMPLE
    seconds, ref, strain = vst_run(job_for("vst", m))
    _, half, _ = vst_run(job_for("vst", m // 2))
    facts = {"per_sample": m, "dt": SAMPLE / m, "seconds": seconds,
             "strain_max_over_gamma_ref": strain, "peak_top_velocity": float(np.abs(ref).max()),
             "change_from_twice_dt": relative_error(half, ref)}
    log(f"reference: dt {facts['dt'] * 1e3:.4g} ms, strain_max {strain:.2f} gamma_ref, "
        f"{facts['change_from_twice_dt']:.2e} from the run at twice its dt")
    return ref, facts


def floor(child, quick, ref, log):
    """OpenSees' floor: its error at its finest dt, where its time error
    has gone (the step before shows how far it has)."""
    m = QUICK_LADDER[-1] if quick else OS_FLOOR_PER_SAMPLE
    rows = []
    for k in (m // 2, m):
        seconds, v = child(job_for("opensees", k))
        rows.append({"per_sample": k, "dt": SAMPLE / k, "error": relative_error(v, ref),
                     "seconds": seconds})
    log(f"OpenSees floor: {rows[-1]['error']:.3e} at dt {rows[-1]['dt'] * 1e3:.4g} ms "
        f"({rows[0]['error']:.3e} at twice that)")
    return {"error": rows[-1]["error"], "runs": rows}


def linear_check(child, log):
    """The harness without the laws: vstpetsc (no shear_law) and OpenSees
    (ElasticIsotropic) linear at fine steps, the same column and motion:
    their difference shows that nodes, masses, base and velocities agree."""
    _, vv, _ = vst_run({**job_for("vst", 32), "linear": True})
    out = {}
    for m in (16, 32):
        _, vo = child({**job_for("opensees", m), "surfaces": 0})
        out[f"opensees dt {SAMPLE / m * 1e3:.4g} ms"] = relative_error(vo, vv)
    log(f"linear harness check against vstpetsc at dt {SAMPLE / 32 * 1e3:.4g} ms: {out}")
    return {"vstpetsc_dt": SAMPLE / 32, "differences": out}


def time_table(table, runners, repeats):
    """The chosen runs timed again, interleaved: min and median each."""
    chosen = {(r["method"], r["run"]["per_sample"]): (r["method"], job_for(r["method"], r["run"]["per_sample"]))
              for r in table if r["run"] is not None}
    timed = common.time_chosen(chosen, runners, repeats, SLOW_TOTAL)
    for row in table:
        if row["run"] is not None:
            row["time_min"], row["time_median"] = timed[(row["method"], row["run"]["per_sample"])]


def measure(quick, log=print):
    child = OpenSeesChild()                      # before PETSc starts Open MPI
    runners = {"vstpetsc": vst_runner, "opensees": child}
    ladder = QUICK_LADDER if quick else LADDER
    probe = child.probe(job_for("opensees", 4))
    log(f"OpenSees systems (s for a run at dt {SAMPLE / 4 * 1e3:.3g} ms): {probe}")
    ref, ref_facts = reference(quick, log)
    res = {**common.results_head(quick), "system_probe": probe, "system": child.system,
           "reference": ref_facts, "floor": floor(child, quick, ref, log),
           "runs": {kind: search(kind, runners[kind], ladder, ref, log) for kind in runners}}
    if not quick:
        res["linear_check"] = linear_check(child, log)
    res["table"] = [{"target": t, "method": kind, "below_floor": t < FLOOR_MARGIN * res["floor"]["error"],
                     "run": common.cheapest(res["runs"][kind], t, lambda r: r["steps"])}
                    for t in TARGETS for kind in runners]
    for row in res["table"]:
        if row["below_floor"]:
            row["run"] = None
    time_table(res["table"], runners, QUICK_REPEATS if quick else REPEATS)
    res["tolerance_check"] = tolerance_check(child, res["table"], ref)
    res.update(opensees_version=child.version, opensees_parser=child.parser,
               surfaces=SURFACES, backbone=[GAMMA_LO, GAMMA_HI])
    child.close()
    return res


def tolerance_check(child, table, ref):
    """OpenSees' chosen runs again at NormDispIncr OS_TIGHT: their errors."""
    out = {}
    for row in table:
        if row["method"] == "opensees" and row["run"] is not None:
            m = row["run"]["per_sample"]
            seconds, v = child({**job_for("opensees", m), "tol": OS_TIGHT})
            out[str(m)] = {"error": relative_error(v, ref), "seconds": seconds,
                           "error_at_default": row["run"]["error"]}
    return out


# ---------------------------------------------------------------- README

SECTION = "## Yielding column against OpenSees (issue 46)"


def section(res):
    """The README section: the problem, the reference and floor, then the
    cheapest run of each code per target."""
    ref, fl = res["reference"], res["floor"]
    lin = res.get("linear_check")
    lines = [SECTION, "",
             common.generated_by("plane_yielding_opensees.py", res)
             + f"Problem: a soil column {HEIGHT:g} m high, one {WIDTH:g} m quadrilateral wide "
             f"and {CELLS} high (plane strain, rho {RHO:g}, Vs {VS:g} m/s, nu {NU:g}), v_y held "
             "everywhere (simple shear), no gravity, MKZ soil (gamma_ref "
             f"{GAMMA_REF:g}, beta {BETA:g}, s {S_EXP:g}), its rigid base moved by the velocity "
             f"pulse {PULSE_V:g} sin(2 pi {PULSE_F:g} t) sin^2(pi t / {CYCLES / PULSE_F:g} s) "
             f"(an acceleration table every {TABLE_DT * 1e3:g} ms, the same in both), "
             f"{END:g} s; strains to {ref['strain_max_over_gamma_ref']:.1f} gamma_ref. "
             "vstpetsc: the case through vstpetsc.run, lumped mass (OpenSees' `quad` "
             "has no other: the same semi-discrete column), its slab dt varied. OpenSees: "
             "`quad` (plane strain) of PressureIndependMultiYield with a user-defined backbone "
             f"of {res['surfaces']} (gamma, G/Gmax) pairs of the MKZ curve, log-spaced from "
             f"{res['backbone'][0] / GAMMA_REF:g} to {res['backbone'][1] / GAMMA_REF:g} "
             "gamma_ref (39 is the parser's most), plastic from the start, the base "
             "motion as UniformExcitation, Newmark average acceleration, Newton "
             f"(NormDispIncr {OS_TOLERANCE:g}), system {res['system']} (fastest of "
             f"{len(OS_SYSTEMS)}). Error: the relative max error of the top's absolute "
             f"velocity at every {SAMPLE * 1e3:g} ms against the reference, vstpetsc at dt "
             f"{ref['dt'] * 1e3:.4g} ms ({ref['change_from_twice_dt']:.1e} from its run "
             "at twice that dt). OpenSees' floor (PIMY's piecewise-linear backbone "
             f"against MKZ): {fl['error']:.2e} at dt {fl['runs'][-1]['dt'] * 1e3:.4g} ms "
             f"({fl['runs'][0]['error']:.2e} at twice that); targets below "
             f"{FLOOR_MARGIN:g} x the floor are not compared."
             + (f" Linear harness check (both codes without their laws, fine dt): "
                + ", ".join(f"{k} {v:.1e}" for k, v in lin["differences"].items()) + "."
                if lin else "") + tolerance_line(res["tolerance_check"]),
             "", "Cheapest run (fewest steps) reaching each target, timed again interleaved "
             f"({QUICK_REPEATS if res['quick'] else REPEATS} times), min / median of the whole "
             "solve, each code in its own process:", "",
             "| target | code | dt [ms] | steps | error | time [s] min / median "
             "| vstpetsc / OpenSees (min, median) |", "|---|---|---|---|---|---|---|"]
    lines += [table_row(row, res["table"]) for row in res["table"]]
    failed = [f"{kind} at dt {r['dt'] * 1e3:.4g} ms" for kind, rows in res["runs"].items()
              for r in rows if r["error"] is None]
    lines += ["", f"The coarsest dt tried is {SAMPLE * 1e3:g} ms (Vs dt / h = "
              f"{VS * SAMPLE * CELLS / HEIGHT:g}, the error's sample interval): a code "
              "whose run there is well within a target might reach it with a coarser one."
              + (f" Failed (analyze returned an error): {', '.join(failed)}." if failed else "")]
    return "\n".join(lines) + "\n"


def tolerance_line(check):
    """How much OpenSees' chosen runs change at NormDispIncr OS_TIGHT."""
    if not check:
        return ""
    change = max(abs(c["error"] / c["error_at_default"] - 1) for c in check.values())
    seconds = ", ".join(f"{c['seconds']:.2f}" for c in check.values())
    return (f" OpenSees' chosen runs again at NormDispIncr {OS_TIGHT:g}: errors within "
            f"{change:.1e} of themselves, in {seconds} s (one run each).")


def table_row(row, table):
    head = f"| {row['target']:g} | {row['method']} |"
    if row["below_floor"]:
        return head + " below the floor | | | | |"
    run = row["run"]
    if run is None:
        return head + " not reached | | | | |"
    ratio = ""
    other = next(r for r in table if r["target"] == row["target"] and r is not row)
    if row["method"] == "vstpetsc" and other["run"] is not None:
        ratio = (f"{row['time_min'] / other['time_min']:.2f}, "
                 f"{row['time_median'] / other['time_median']:.2f}")
    return (head + f" {run['dt'] * 1e3:.4g} | {run['steps']} | {run['error']:.2e} | "
            f"{row['time_min']:.2f} / {row['time_median']:.2f} | {ratio} |")


def main(argv=None):
    args = bench_arguments("plane_yielding_opensees", HERE).parse_args(argv)
    return common.bench_main("plane_yielding_opensees", args, worker, measure, section, SECTION)


if __name__ == "__main__":
    sys.exit(main())
