"""The three problems of the comparison with OpenSees (bench/opensees.py)
and of docs/wave-accuracy.md, with their exact solutions and error
measures; numpy only, it imports nothing of vstpetsc.

1. wave: the bundled `wave` example's standing wave (steel bar 1 m,
   clamped left, free right, u0 = 1e-4 sin(pi x / 2L) at rest); the free
   end moves as 1e-4 cos(pi c t / 2L) (docs/examples.md). Error: relative
   L2 norm of the tip displacement over two periods (4L/c each).
2. impact: the steel bar at v0 = 1 m/s against a rigid wall at zero gap.
   It leaves after 2L/c with the uniform velocity -v0 (formulation.md
   section 7). Error: |mean velocity + v0| / v0 at 4L/c (mean velocity =
   momentum / mass); the peak contact force over Z v0 is reported too.
3. site: linear site response (see ``site_surface_exact``). Error:
   relative L2 norm of the surface velocity over [0, 1.2 s].  Also: the
   same layer on rigid rock (the base's velocity prescribed), and the
   layer's transfer function, of the continuum and of a semi-discrete
   model (its assembled M, C, K).

A job is one run of a problem: its mesh, step and method fields
(:func:`job_for`); :func:`case_doc` is the job as a vstpetsc case (a
dict), :func:`metrics` its error from the run's result.

Checked in tests/test_waves_reference.py; used by tests/test_wave_accuracy.py,
bench/opensees.py and studies/wave_study.py.
"""

import math
import os

import numpy as np

E, RHO, AREA, LENGTH = 2.0e11, 7850.0, 1.0, 1.0
C = math.sqrt(E / RHO)
Z = RHO * C * AREA
AMP = 1.0e-4                      # the wave example's amplitude
V0 = 1.0                          # impact velocity
SITE = {"H": 20.0, "c": 200.0, "rho": 1800.0, "c_rock": 1000.0, "rho_rock": 2200.0,
        "f": 10.0, "t0": 0.2, "end": 1.2, "table_dt": 1.0e-4}
Z_SOIL = SITE["rho"] * SITE["c"] * AREA
Z_ROCK = SITE["rho_rock"] * SITE["c_rock"] * AREA


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


def rigid_surface_exact(t):
    """The site layer's surface velocity with the base's velocity
    prescribed to the incident v_in: infinitely stiff rock (T = 2, R = -1)
    moves the base with 2 v_in, so half of that closed form."""
    s = SITE
    return 0.5 * site_surface_exact(t, site_incident()[2], s["H"], s["c"], Z_SOIL, 1e300)


def exact_transfer(omega):
    """Surface velocity per unit incident velocity of the continuum at
    angular frequency omega: 2 T e^{-ikH} / (1 - R e^{-2ikH}), the sum of
    site_surface_exact's multiple reflections."""
    kh = omega * SITE["H"] / SITE["c"]
    trans, refl = 2.0 * Z_ROCK / (Z_SOIL + Z_ROCK), (Z_SOIL - Z_ROCK) / (Z_SOIL + Z_ROCK)
    return 2.0 * trans * np.exp(-1j * kh) / (1.0 - refl * np.exp(-2j * kh))


def semi_discrete_transfer(m, c, k, omega, scale=1.0):
    """The same for the semi-discrete site model of the dense matrices
    ``m``, ``c``, ``k`` (base = node 0, surface = the last node):
    (-omega^2 M + i omega C + K) U = 2 Z_rock e_0; ``scale`` multiplies the
    base's dashpot and incident force."""
    c = c.astype(complex)
    c[0, 0] *= scale
    force = np.zeros(m.shape[0], dtype=complex)
    force[0] = 2.0 * Z_ROCK * scale
    u = np.linalg.solve(-omega ** 2 * m + 1j * omega * c + k, force)
    return 1j * omega * u[-1]


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


# ---------------------------------------------------------------- problems and jobs

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


def metrics(job, result):
    """:func:`evaluate` of a vstpetsc result of ``job`` (a Result or
    anything indexed by its dataset names)."""
    t = result["time"][1:]
    if job["problem"] == "impact":
        return evaluate("impact", t, None, result["body/bar/v"][-1],
                        result["contact/0/force"][1:])
    key = "body/bar/u" if job["problem"] == "wave" else "body/bar/v"
    return evaluate(job["problem"], t, result[key][1:, -1])


def steps_for(end, elements, courant, length, c):
    """Whole steps over [0, end] with c dt / h at most ``courant``."""
    return max(1, math.ceil(end * c * elements / (courant * length) - 1e-9))


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


def case_doc(job, folder):
    """The vstpetsc case of a job, as Python data (the site's incident
    record a CSV file in ``folder``)."""
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


def rigid_base(doc):
    """The site case ``doc`` with the base's velocity prescribed to the
    incident record instead of the absorbing base."""
    doc["bc"] = [{"body": "bar", "end": "left", "type": "velocity",
                  "value": doc["bc"][0]["incident"]}]
    return doc
