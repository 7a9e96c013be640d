"""Spatial accuracy of waves by mass matrix (issue 26 item 4;
docs/wave-accuracy.md). The problems, closed forms and error norms are
tests/references/waves.py's (bench/opensees.py's problems too):

wave  the `wave` example's standing wave (u0 exact at the nodes): tip
      displacement, relative L2 error over two periods;
site  20 m soil layer on elastic rock, absorbing base with a 10 Hz Ricker
      incident pulse: surface velocity, relative L2 error over 1.2 s;
rigid the site layer with the base's velocity prescribed (v_in) instead:
      the same against the closed form for rigid rock (R = -1);
semi  the site problem's semi-discrete solution (no time stepping: the
      assembled M, C, K per frequency, FFT), as assembled and with the
      base's impedance scaled by 1 - (kh)^2 / 12 (a test of the cause of
      its second-order error; not realisable in the time domain).

    .venv/bin/python studies/wave_study.py [wave|site|rigid|semi]
"""

import io
import math
import os
import sys
import tempfile

import numpy as np

# the problems' exact solutions live beside the tests that check them
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.append(os.path.join(ROOT, "tests"))
from references import waves  # noqa: E402

SITE = waves.SITE
ELEMENTS = {"wave": (5, 10, 20, 40), "site": (10, 20, 40, 80, 160)}
COURANTS = {"wave": (2.0, 1.0, 0.5, 0.25, 0.125, 0.0625),
            "site": (2.0, 1.25, 1.0, 0.5, 0.25, 0.125)}


def site_matrices(elements, mass, folder):
    """Dense M, C, K of the site problem's model."""
    import vstpetsc
    from vstpetsc.line import model as model_mod

    doc = waves.case_doc(waves.job_for("site", {"mass": mass}, elements, 1.0), folder)
    return model_mod.dense(model_mod.build_model(vstpetsc.Case.from_dict(doc)).ops, "mck")


def semi_discrete_error(elements, mass, corrected, folder, span=8.0, dt=1e-4):
    """Relative L2 error over [0, 1.2 s] of the semi-discrete surface
    velocity (the incident table's spectrum times the transfer function,
    frequencies below 200 Hz; ``corrected``: base impedance scaled by
    1 - (kh)^2 / 12)."""
    m, c, k = site_matrices(elements, mass, folder)
    t = np.arange(int(span / dt)) * dt
    v_in = waves.site_incident()[2]
    freq = np.fft.rfftfreq(t.size, dt)
    h = SITE["H"] / elements
    response = np.zeros(freq.size, dtype=complex)
    for i, f in enumerate(freq):
        if 0.0 < f < 200.0:
            omega = 2.0 * math.pi * f
            scale = 1.0 - (omega * h / SITE["c"]) ** 2 / 12.0 if corrected else 1.0
            response[i] = waves.semi_discrete_transfer(m, c, k, omega, scale)
    v = np.fft.irfft(np.fft.rfft(v_in(t)) * response, t.size)
    keep = t <= SITE["end"]
    exact = waves.site_surface_exact(t[keep], v_in, SITE["H"], SITE["c"], waves.Z_SOIL,
                                     waves.Z_ROCK)
    return waves.rel_l2(v[keep], exact)


def run_doc(doc, folder, name):
    """vstpetsc.run of the case ``doc``, quietly, into FOLDER/NAME."""
    import vstpetsc

    return vstpetsc.run(vstpetsc.Case.from_dict(doc), os.path.join(folder, name),
                        quiet=True, out=io.StringIO())


def job_error(job, folder):
    """The relative error of one run of a waves job (its metrics' "error")."""
    return waves.metrics(job, run_doc(waves.case_doc(job, folder), folder, "run.h5"))["error"]


def rigid_error(elements, courant, mass, folder):
    """The site layer with the base's velocity prescribed to v_in."""
    job = waves.job_for("site", {"mass": mass}, elements, courant)
    r = run_doc(waves.rigid_base(waves.case_doc(job, folder)), folder, "rigid.h5")
    return waves.rel_l2(r["body/bar/v"][1:, -1], waves.rigid_surface_exact(r["time"][1:]))


def table(name, folder):
    """Error against elements (rows) and c dt/h (columns), both masses."""
    print(f"{name}: c dt/h = " + ", ".join(f"{c:g}" for c in COURANTS[name]))
    for mass in ("averaged", "consistent"):
        for n in ELEMENTS[name]:
            errors = [job_error(waves.job_for(name, {"mass": mass}, n, c), folder)
                      for c in COURANTS[name]]
            print(f"| {mass} | {n} | " + " | ".join(f"{e:.2e}" for e in errors) + " |",
                  flush=True)


def main(part):
    with tempfile.TemporaryDirectory() as folder:
        if part in ("wave", "site"):
            table(part, folder)
        elif part == "rigid":
            for n in (10, 20, 40, 80):
                errors = [rigid_error(n, c, "averaged", folder) for c in (1.0, 0.25, 0.0625)]
                print(f"rigid averaged {n}: c dt/h = 1, 0.25, 0.0625: "
                      + " ".join(f"{e:.2e}" for e in errors), flush=True)
        else:
            for n in (10, 20, 40, 80):
                got = [semi_discrete_error(n, "averaged", fix, folder) for fix in (False, True)]
                print(f"semi-discrete averaged {n}: as assembled {got[0]:.2e}, "
                      f"base impedance scaled {got[1]:.2e}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "wave")
