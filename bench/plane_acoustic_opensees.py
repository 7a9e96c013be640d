"""The acoustic reservoir against OpenSees, both against Chopra's closed
form: the cost at equal error (issue 47).

    python bench/plane_acoustic_opensees.py [--quick] [--readme-only]

The problem
-----------
tests/test_water_acoustic_chopra.py's: a rigid vertical face (x = 0)
accelerating along x, A0 cos(omega t) after a half-cosine ramp over RAMP
periods, against a reservoir H deep and L = 3H long (c = 1500 m/s: bulk
2.25e9, rho 1000), free surface (p = 0) at y = H, rigid bottom, the
plane-wave dashpot dp/dn = -p_t / c at x = L. The quantity: the heel's
(x = y = 0) steady dynamic pressure, its complex amplitude fitted by least
squares over the last 4 of PERIODS periods after the ramp, against
tests/references/chopra_reservoir.pressure_truncated (the same truncated
reservoir's closed form); error = |P - P_exact| / |P_exact|. At omega =
0.5 and 1.5 times the first cut-off pi c / (2H) (every mode evanescent;
the first mode travelling to the far end, whose reflections die slowly:
20 periods). Both codes are given the face's motion as the same table,
TABLE points a period (vstpetsc its velocity, OpenSees its acceleration,
linear between points), and both read the heel every step / SAMPLES of
a period.

The codes
---------
vstpetsc: tests/acoustic_cases.reservoir_case (the water a region of
3n x n quadrilaterals, the face a one-cell rigid dam column moved by a
velocity boundary, far = the dashpot), the heel's total pressure less
rho g H from /water/reservoir/pressure; its slab dt varied (SLABS a period).

OpenSees (openseespy, in a child process: openseespy and petsc4py crash
in one process): one layer of AC3D8 bricks (thickness 1) on the same
3n x n grid. Read in OpenSees' sources (SRC/element/XMUelements/,
commit 2890cb3): AC3D8HexWithSensitivity has one dof a node, the
pressure p, a stiffness int grad N . grad N / rho and a mass int N N /
bulk lumped by rows (getTangentStiff, getMass; 2 x 2 x 2 Gauss), i.e. the
weak form of p_tt / bulk = div(grad p / rho) whose boundary term is
int N (1/rho) dp/dn. The front and back faces carry nothing (dp/dz = 0)
and the field is the same on both: exactly the plane problem, as a 2 x 2
Gauss quadrilateral with a row-lumped mass (vstpetsc's is averaged).
The face: rho a_n = -dp/dn (Euler's equation, a_n the wall's
acceleration into the water), so the boundary term is int N a_n dS, a
nodal load a(t) times the node's tributary area (h / 2 x 1/2 at a brick's
face node; no rho: the stiffness holds 1/rho). It is what
ASI3D8QuadWithSensitivity puts on the fluid's rows for a prescribed
wall (getResistingForceIncInertia: -Q^T a, Q = int N_s n N_f dS, n toward
the fluid) without a solid to move. The far end: AV3D4 on the x = L faces
(AV3D4QuadWithSensitivity::getDamp: C = int N N / sqrt(bulk rho) dS, the
dashpot dp/dn = -p_t / c). The free surface: p fixed at y = H. Newmark
average acceleration, Linear -factorOnce (the matrices are constant), the
fastest of OS_SYSTEMS. AV3D4 printf()s its Jacobians when built: the
child's C stdout goes to /dev/null, its answers through a copy of it.

Timing
------
Every (code, ratio, mesh, steps) run REPEATS times, interleaved, min and
median; each code in its own process, the whole solve: vstpetsc.run from
the Case (read before) to the closed result file (every SAMPLES-th of a
period written); OpenSees from wipe through the model, the analysis and
the heel's readings. The fit and the error are outside.

Equal error: each code's runs as (error, min time); its frontier (the
runs no other run beats in both); the time at a target error interpolated
log-log between the two frontier runs about it (None outside them).
Caveat: below the cut-off vstpetsc's time error and its space error have
opposite signs, so a coarse mesh with coarse slabs can land near zero by
cancellation; the table shows every run.

Writes bench/plane_acoustic_opensees.json and the section "Acoustic
reservoir against OpenSees (issue 47)" of bench/README.md.
"""

import io
import math
import os
import pathlib
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.append(HERE)
sys.path.append(os.path.join(os.path.dirname(HERE), "tests"))

import opensees_common as common  # noqa: E402
from acoustic_cases import BULK, RHO_W, reservoir_case  # noqa: E402
from readme import bench_arguments  # noqa: E402
from references import chopra_reservoir as chopra  # noqa: E402

H, L, A0, RAMP = 10.0, 30.0, 1.0, 4
C = math.sqrt(BULK / RHO_W)
FIRST = math.pi * C / (2.0 * H)                 # the first cut-off, rad/s
RATIOS = (0.5, 1.5)
PERIODS = {0.5: 8, 1.5: 20}                     # after the ramp; the fit takes the last 4
TABLE, SAMPLES = 960, 20                        # the motion's points, the heel's readings a period
MESHES, QUICK_MESHES = (5, 10, 20), (5, 10)     # cells over H (h = H / n)
STEPS = (20, 40, 80, 160)                       # slabs / steps a period, both codes
TARGETS = {0.5: (1e-2, 3e-3, 1e-3), 1.5: (3e-2, 1e-2)}
OS_SYSTEMS = ("BandSPD", "ProfileSPD", "SparseSYM", "UmfPack")
REPEATS, QUICK_REPEATS, SLOW_TOTAL = 3, 1, 120.0


# ---------------------------------------------------------------- the problem

def period(ratio):
    return 2.0 * math.pi / (ratio * FIRST)


def end_time(ratio):
    return (RAMP + PERIODS[ratio]) * period(ratio)


def ramp(ratio, t):
    """The half-cosine ramp over RAMP periods and its derivative."""
    rise = RAMP * period(ratio)
    inside = t < rise
    r = np.where(inside, 0.5 - 0.5 * np.cos(np.pi * t / rise), 1.0)
    return r, np.where(inside, 0.5 * np.pi / rise * np.sin(np.pi * t / rise), 0.0)


def face_velocity(ratio, t):
    """v(t) = ramp A0 sin(omega t) / omega (tests/test_water_acoustic_chopra's):
    its acceleration A0 cos(omega t) once the ramp is done."""
    omega = ratio * FIRST
    return ramp(ratio, t)[0] * A0 * np.sin(omega * t) / omega


def face_acceleration(ratio, t):
    """dv/dt of face_velocity, exactly (the ramp's derivative included):
    the same motion given to OpenSees."""
    omega = ratio * FIRST
    r, dr = ramp(ratio, t)
    return A0 * (r * np.cos(omega * t) + dr * np.sin(omega * t) / omega)


def table_times(ratio):
    return np.arange(0.0, end_time(ratio) + 2 * period(ratio), period(ratio) / TABLE)


def exact(ratio):
    return complex(chopra.pressure_truncated(0.0, 0.0, H, L, RHO_W, C, ratio * FIRST, A0))


def fit_error(ratio, t, p):
    """|P - P_exact| / |P_exact|, P the least-squares amplitude over the
    last 4 periods of the heel's dynamic pressure p(t)."""
    omega = ratio * FIRST
    last = t >= end_time(ratio) - 4 * period(ratio) - 1e-9 * period(ratio)
    X = np.column_stack([np.cos(omega * t[last]), np.sin(omega * t[last])])
    (a, b), *_ = np.linalg.lstsq(X, p[last], rcond=None)
    ref = exact(ratio)
    return float(abs(a - 1j * b - ref) / abs(ref))


# ---------------------------------------------------------------- OpenSees (child)

def node_tag(cells, i, j, k):
    """Node (x_i, y_j, z_k) of the 3n + 1 x n + 1 x 2 grid, from 1."""
    nx, ny = 3 * cells, cells
    return 1 + i + (nx + 1) * (j + (ny + 1) * k)


def opensees_mesh(ops, cells):
    """The nodes (p held at y = H), the AC3D8 bricks (OpenSees' brick
    order: the z = 0 face counter-clockwise, then z = 1) and the AV3D4
    faces at x = L."""
    nx, ny = 3 * cells, cells
    xs, ys = np.linspace(0.0, L, nx + 1).tolist(), np.linspace(0.0, H, ny + 1).tolist()
    for k in (0, 1):
        for j in range(ny + 1):
            for i in range(nx + 1):
                ops.node(node_tag(cells, i, j, k), xs[i], ys[j], float(k))
                if j == ny:
                    ops.fix(node_tag(cells, i, j, k), 1)
    ops.nDMaterial("AcousticMedium", 1, BULK, RHO_W)
    tag = 0
    for j in range(ny):
        for i in range(nx):
            tag += 1
            quad = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
            ops.element("AC3D8", tag, *[node_tag(cells, a, b, k) for k in (0, 1) for a, b in quad], 1)
    for j in range(ny):
        tag += 1
        ops.element("AV3D4", tag, node_tag(cells, nx, j, 0), node_tag(cells, nx, j + 1, 0),
                    node_tag(cells, nx, j + 1, 1), node_tag(cells, nx, j, 1), 1)


def opensees_face(ops, ratio, cells):
    """The face's flux: a(t) (a Path series, TABLE points a period) times
    each face node's tributary area (h/2 at the bottom, h between, the
    thickness halved between z = 0 and 1; the surface node is held)."""
    a = face_acceleration(ratio, table_times(ratio))
    ops.timeSeries("Path", 1, "-dt", period(ratio) / TABLE, "-values", *a.tolist())
    ops.pattern("Plain", 1, 1)
    h = H / cells
    for j in range(cells):
        for k in (0, 1):
            ops.load(node_tag(cells, 0, j, k), 0.5 * h * (0.5 if j == 0 else 1.0))


def opensees_run(job):
    """(seconds, the heel's times and pressures at SAMPLES a period over
    the fit's last 4 periods) of one run in this (child) process."""
    import openseespy.opensees as ops

    ratio, cells, steps = job["ratio"], job["cells"], job["steps"]
    start = time.perf_counter()
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 1)
    opensees_mesh(ops, cells)
    opensees_face(ops, ratio, cells)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system(job["system"])
    ops.algorithm("Linear", "-factorOnce")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    dt, every = period(ratio) / steps, max(1, steps // SAMPLES)
    total = int(round(end_time(ratio) / dt))
    early = total - 4 * steps
    t, p = [], []
    if ops.analyze(early, dt) != 0:
        raise RuntimeError(f"OpenSees failed on {job}")
    for _ in range(early, total, every):
        ops.analyze(every, dt)
        t.append(ops.getTime())
        p.append(ops.nodeDisp(node_tag(cells, 0, 0, 0), 1))
    seconds = time.perf_counter() - start
    ops.wipe()
    return seconds, t, p


def opensees_answer(job):
    import openseespy.opensees as ops

    if "probe" in job:
        answer = {"systems": {s: opensees_run({**job["probe"], "system": s})[0]
                              for s in OS_SYSTEMS}}
    else:
        seconds, t, p = opensees_run(job)
        answer = {"seconds": seconds, "t": t, "p": p}
    answer["version"] = ops.version()
    return answer


def worker():
    """The child's loop, its answers through a copy of stdout: AV3D4's
    printf()s go to fd 1, which is sent to /dev/null."""
    channel = os.fdopen(os.dup(1), "w")
    os.dup2(os.open(os.devnull, os.O_WRONLY), 1)
    sys.stdout = channel
    return common.serve(opensees_answer)


class OpenSeesChild(common.SystemChild):
    """The child running OpenSees jobs with the system ``probe`` found
    fastest; a call answers (seconds, error)."""

    def __init__(self):
        super().__init__(__file__, OS_SYSTEMS)

    def __call__(self, job):
        got = self.ask({**job, "system": self.system})
        return got["seconds"], fit_error(job["ratio"], np.asarray(got["t"]), np.asarray(got["p"]))


# ---------------------------------------------------------------- vstpetsc

def velocity_text(ratio):
    t = table_times(ratio)
    v = face_velocity(ratio, t)
    return "[" + ", ".join(f"[{a!r}, {b!r}]" for a, b in zip(t.tolist(), v.tolist())) + "]"


class VstRunner:
    """vstpetsc's runs in this process: the case written and read once per
    job (outside the timing), run to a result file in a temporary folder."""

    def __init__(self):
        self.folder = tempfile.TemporaryDirectory()
        self.cases = {}

    def case(self, job):
        import vstpetsc

        key = (job["ratio"], job["cells"], job["steps"])
        if key not in self.cases:
            ratio, cells, steps = key
            name = f"r{ratio:g}_n{cells}_s{steps}".replace(".", "p")
            path = reservoir_case(pathlib.Path(self.folder.name), H, L, 3 * cells, cells,
                                  period(ratio) / steps, end_time(ratio), velocity_text(ratio),
                                  name=name, every=max(1, steps // SAMPLES))
            self.cases[key] = vstpetsc.Case.from_toml(path)
        return self.cases[key]

    def __call__(self, job):
        import h5py
        import vstpetsc

        case = self.case(job)
        out = os.path.join(self.folder.name, "run.h5")
        start = time.perf_counter()
        vstpetsc.run(case, output=out, quiet=True, out=io.StringIO())
        seconds = time.perf_counter() - start
        with h5py.File(out) as f:
            t = f["time"][:]
            p = f["water/reservoir/pressure"][:, 0] - RHO_W * 9.81 * H
        return seconds, fit_error(job["ratio"], t, p)

    def close(self):
        self.folder.cleanup()



# ---------------------------------------------------------------- measuring

def jobs(quick):
    """Every (code, ratio, mesh, steps): a list of (key, (code, job))."""
    out = []
    for ratio in RATIOS:
        for cells in QUICK_MESHES if quick else MESHES:
            for steps in STEPS:
                job = {"ratio": ratio, "cells": cells, "steps": steps}
                out += [((code, ratio, cells, steps), (code, job))
                        for code in ("vstpetsc", "opensees")]
    return out


def time_all(chosen, runners, reps, log):
    """Every job ``reps`` times, interleaved: rows with the error (of the
    first run: both codes are deterministic) and min / median seconds; a
    job past SLOW_TOTAL seconds stops after one run."""
    times, errors = {key: [] for key in chosen}, {}
    for rep in range(reps):
        for key, (code, job) in chosen.items():
            if times[key] and sum(times[key]) > SLOW_TOTAL:
                continue
            seconds, error = runners[code](job)
            times[key].append(seconds)
            errors.setdefault(key, error)
            if rep == 0:
                log(f"{code} ratio {job['ratio']:g} h = H/{job['cells']} "
                    f"{job['steps']} a period: error {error:.3e} in {seconds:.2f} s")
    return [{"code": k[0], "ratio": k[1], "cells": k[2], "steps": k[3], "error": errors[k],
             "time_min": min(v), "time_median": float(np.median(v)), "runs": len(v)}
            for k, v in times.items()]


def frontier(rows):
    """The runs that no other run beats in both error and min time, by
    error."""
    keep = [r for r in rows if not any(o["error"] < r["error"] and o["time_min"] < r["time_min"]
                                       for o in rows)]
    return sorted(keep, key=lambda r: r["error"])


def time_at(rows, target):
    """The min time at error ``target``, log-log between the frontier's
    two runs about it (the cheapest run within it if the frontier's
    coarsest run is; None if no run reaches it)."""
    front = frontier(rows)
    within = [r for r in front if r["error"] <= target]
    if not within:
        return None
    best = within[-1]                             # the cheapest run within the target
    above = [r for r in front if r["error"] > target]
    if not above:
        return best["time_min"]
    worse = above[0]
    s = math.log(target / best["error"]) / math.log(worse["error"] / best["error"])
    return math.exp(math.log(best["time_min"]) + s * math.log(worse["time_min"] / best["time_min"]))


def equal_error(rows):
    """Per ratio and target: each code's time there and vstpetsc / OpenSees."""
    out = []
    for ratio in RATIOS:
        for target in TARGETS[ratio]:
            t = {code: time_at([r for r in rows if r["code"] == code and r["ratio"] == ratio],
                               target) for code in ("vstpetsc", "opensees")}
            ratio_ = (t["vstpetsc"] / t["opensees"]) if None not in t.values() else None
            out.append({"ratio": ratio, "target": target, **t, "vstpetsc_over_opensees": ratio_})
    return out


def measure(quick, log=print):
    child = OpenSeesChild()                      # before PETSc starts Open MPI
    vst = VstRunner()
    probe = child.probe({"ratio": 0.5, "cells": 10, "steps": 40})
    log(f"OpenSees systems (s, ratio 0.5, h = H/10, 40 steps a period): {probe}")
    rows = time_all(dict(jobs(quick)), {"vstpetsc": vst, "opensees": child},
                    QUICK_REPEATS if quick else REPEATS, log)
    res = {**common.results_head(quick), "system_probe": probe, "system": child.system,
           "opensees_version": child.version, "exact": {str(r): [exact(r).real, exact(r).imag]
                                                        for r in RATIOS},
           "rows": rows, "equal_error": equal_error(rows)}
    child.close()
    vst.close()
    return res


# ---------------------------------------------------------------- README

SECTION = "## Acoustic reservoir against OpenSees (issue 47)"


def section(res):
    """The README section: the problem, every run, the times at equal error."""
    reps = QUICK_REPEATS if res["quick"] else REPEATS
    lines = [SECTION, "",
             common.generated_by("plane_acoustic_opensees.py", res)
             + f"Problem: a rigid vertical face shaken along x at {A0:g} cos(omega t) (after a "
             f"half-cosine ramp over {RAMP} periods) against a reservoir {H:g} m deep and "
             f"{L:g} m long (c = {C:g} m/s), free surface, rigid bottom, the plane-wave "
             "dashpot at the far end; error: the heel's steady pressure amplitude (least "
             "squares over the last 4 periods) against the truncated reservoir's closed form "
             "(tests/references/chopra_reservoir.py), at omega = 0.5 and 1.5 times the first "
             f"cut-off pi c / 2H ({PERIODS[0.5]} and {PERIODS[1.5]} periods after the ramp). "
             "vstpetsc: the water region of 3n x n quadrilaterals beside a rigid dam column "
             "moved by a velocity table (its averaged mass), slabs of T / m. OpenSees: one "
             "layer of AC3D8 bricks (AcousticMedium; the plane problem exactly; a row-lumped "
             "mass) on the same grid, AV3D4 at the far end, p held at the surface, the face "
             "as nodal loads a(t) x tributary area (the boundary term int N (1/rho) dp/dn of "
             "AC3D8's pressure formulation; ASI3D8's load on a fluid for a prescribed wall), "
             "Newmark average acceleration, Linear -factorOnce, system "
             f"{res['system']} (fastest of {len(OS_SYSTEMS)}), steps of T / m. Both get the "
             f"motion as a table of {TABLE} points a period. Every run {reps} times "
             "interleaved, min / median of the whole solve, each code in its own process.", "",
             "| omega / cut-off | code | h | steps a period | error | time [s] min / median |",
             "|---|---|---|---|---|---|"]
    lines += [f"| {r['ratio']:g} | {r['code']} | H/{r['cells']} | {r['steps']} | "
              f"{r['error']:.2e} | {r['time_min']:.2f} / {r['time_median']:.2f} |"
              for r in sorted(res["rows"], key=lambda r: (r["ratio"], r["code"] != "vstpetsc",
                                                           r["cells"], r["steps"]))]
    lines += ["", "At equal error: each code's min time at the target, log-log between the "
              "two runs of its frontier (the runs no other beats in both error and time) "
              "about it:", "",
              "| omega / cut-off | target | vstpetsc [s] | OpenSees [s] | vstpetsc / OpenSees |",
              "|---|---|---|---|---|"]
    fmt = lambda x, f: "not reached" if x is None else format(x, f)
    lines += [f"| {e['ratio']:g} | {e['target']:g} | {fmt(e['vstpetsc'], '.3f')} | "
              f"{fmt(e['opensees'], '.3f')} | {fmt(e['vstpetsc_over_opensees'], '.3f')} |"
              for e in res["equal_error"]]
    lines += ["", "Below the cut-off vstpetsc's time and space errors have opposite signs: "
              "a coarse mesh with coarse slabs can land near zero by cancellation (its H/5 "
              "runs), which the frontier then uses. OpenSees' error at a mesh stops falling "
              "with its steps at its lumped mass's space error."]
    return "\n".join(lines) + "\n"


def main(argv=None):
    args = bench_arguments("plane_acoustic_opensees", HERE).parse_args(argv)
    return common.bench_main("plane_acoustic_opensees", args, worker, measure, section, SECTION)


if __name__ == "__main__":
    sys.exit(main())
