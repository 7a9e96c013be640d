"""Spatial accuracy of waves by mass matrix (issue 26 item 4,
docs/wave-accuracy.md): the standing wave of the `wave` example and the
site response of a soil layer on elastic rock, both against their closed
forms (tests/references/waves.py: the problems of bench/opensees.py and
studies/wave_study.py, their exact solutions and error norms, and the
semi-discrete transfer function)."""

import io
import math
import os

import vstpetsc
from references import waves
from vstpetsc.line import model as model_mod


def run(tmp_path, doc):
    """vstpetsc.run of the case ``doc``, quietly, into tmp_path/run.h5."""
    path = tmp_path / "run.h5"
    if path.exists():
        os.remove(path)
    return vstpetsc.run(vstpetsc.Case.from_dict(doc), str(path), quiet=True, out=io.StringIO())


def error(tmp_path, problem, elements, courant, mass):
    """The benchmark's error of one run: the standing wave's tip L2 error
    over two periods (u0 exact at the nodes), or the site's surface
    velocity L2 error over 1.2 s; c dt/h = ``courant``."""
    job = waves.job_for(problem, {"mass": mass}, elements, courant)
    return waves.metrics(job, run(tmp_path, waves.case_doc(job, str(tmp_path))))["error"]


def rigid_error(tmp_path, elements, courant):
    """The site layer's error with the base's velocity prescribed to the
    incident v_in (averaged mass)."""
    job = waves.job_for("site", {"mass": "averaged"}, elements, courant)
    r = run(tmp_path, waves.rigid_base(waves.case_doc(job, str(tmp_path))))
    return waves.rel_l2(r["body/bar/v"][1:, -1], waves.rigid_surface_exact(r["time"][1:]))


def wave_error(tmp_path, elements, courant, mass):
    return error(tmp_path, "wave", elements, courant, mass)


def site_error(tmp_path, elements, courant, mass):
    return error(tmp_path, "site", elements, courant, mass)


def order(coarse, fine):
    """The fitted order of an error that halving h divides by 2^order."""
    return math.log2(coarse / fine)


# ---------------------------------------------------------------- standing wave

def test_standing_wave_goal_with_twenty_elements(tmp_path):
    """Issue 26's goal: 1e-5 with at most 20 elements, averaged mass, at
    c dt/h = 0.5 (the consistent mass stays at its space error, ~2e-3)."""
    assert wave_error(tmp_path, 20, 0.5, "averaged") <= 1e-5


def test_standing_wave_spatial_order(tmp_path):
    """At small dt (c dt/h = 0.125) the error is the space discretisation's:
    order 4 in h with the averaged mass, 2 with the consistent."""
    avg = [wave_error(tmp_path, n, 0.125, "averaged") for n in (10, 20)]
    con = [wave_error(tmp_path, n, 0.125, "consistent") for n in (10, 20)]
    assert abs(order(*avg) - 4.0) <= 0.15
    assert abs(order(*con) - 2.0) <= 0.05


# ---------------------------------------------------------------- site response

def test_site_response_with_forty_elements(tmp_path):
    """Issue 26's goal of 1e-4 with 40 elements is not reached: the best
    measured is 8e-4 (c dt/h = 0.9; 1.8e-3 at small dt). The floor is in
    space, second order, set by the absorbing base (the tests below); with a
    perfect base the averaged mass's dispersion alone still costs ~2e-4 at
    40 elements. The consistent mass is at 5e-2."""
    assert site_error(tmp_path, 40, 0.9, "averaged") <= 1e-3
    assert site_error(tmp_path, 40, 0.9, "consistent") >= 2e-2


def test_site_response_goal_reached_with_160_elements(tmp_path):
    """The goal's 1e-4 takes 160 elements (averaged mass, c dt/h = 1.25)."""
    assert site_error(tmp_path, 160, 1.25, "averaged") <= 1e-4


def test_site_error_is_second_order_in_space_with_the_absorbing_base(tmp_path):
    """At small dt, averaged mass: order 2 with the absorbing base, order 4
    when the base's velocity is prescribed instead (rigid rock: the closed
    form with R = -1; the same mesh and pulse)."""
    absorbing = [site_error(tmp_path, n, 0.125, "averaged") for n in (40, 80)]
    assert abs(order(*absorbing) - 2.0) <= 0.1
    rigid = [rigid_error(tmp_path, n, 0.0625) for n in (20, 40)]
    assert abs(order(*rigid) - 4.0) <= 0.15


def transfer_orders(tmp_path, hz, scaled):
    """Fitted order (20 to 40 elements, averaged mass) of the semi-discrete
    surface velocity's transfer function at ``hz``; ``scaled``: the base's
    dashpot and incident force times 1 - (kh)^2 / 12."""
    omega = 2.0 * math.pi * hz
    errors = []
    for n in (20, 40):
        kh = omega * waves.SITE["H"] / n / waves.SITE["c"]
        doc = waves.case_doc(waves.job_for("site", {"mass": "averaged"}, n, 1.0), str(tmp_path))
        m, c, k = model_mod.dense(model_mod.build_model(vstpetsc.Case.from_dict(doc)).ops, "mck")
        got = waves.semi_discrete_transfer(m, c, k, omega, 1.0 - kh ** 2 / 12.0 if scaled else 1.0)
        errors.append(abs(got / waves.exact_transfer(omega) - 1.0))
    return order(*errors)


def test_the_base_impedance_error_is_second_order(tmp_path):
    """Why the site error is second order: the mesh seen from the absorbing
    base has the impedance Z_soil (1 - (kh)^2 / 12). It shows at the layer's
    resonance (c / 4H = 2.5 Hz: sin kH = 1), where the error is of order 2,
    and not where sin kH = 0 (c / 2H = 5 Hz: the dispersion's order 4);
    the base's impedance scaled by the same factor restores order 4."""
    assert abs(transfer_orders(tmp_path, 2.5, False) - 2.0) <= 0.1
    assert abs(transfer_orders(tmp_path, 5.0, False) - 4.0) <= 0.1
    assert abs(transfer_orders(tmp_path, 2.5, True) - 4.0) <= 0.2
