"""The MKZ shear law (issue 28) in the solver, against the independent
reference tests/references/mkz.py (which imports nothing of vstpetsc):

1. two elements driven quasi-statically through growing cycles and an
   unload-reload inside a loop: the stress is masing_stress of the
   elements' own recorded strain; each loop's damping is Masing's closed form;
2. a two-layer column on a Lysmer base under a synthetic outcrop record:
   the 5 % surface spectrum against the converged explicit column;
3. the energy balance and the hysteretic dissipation against the reference;
4. -vst_fd_jacobian, modified Newton, a restart and two ranks give the same run;
5. bad shear_law input: one line, exit 2.
"""

import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import vstpetsc
from vstpetsc import petsc
from vstpetsc.input import toml_text
from conftest import ROOT, cli, solve, write_case
from faults import one_clean_line
from references import mkz as ref
from test_energy_restart import assert_same_files
from agreement import assert_runs_agree, datasets
from test_parallel import mpirun

MKZ = {"model": "mkz", "gamma_ref": 5.0e-4, "beta": 1.0, "s": 0.919}


def shear_strain(r, body):
    """Element strains (rows, ne) from the kept shear displacements."""
    return np.diff(r.body(body).shear.u, axis=1) / np.diff(r.body(body).x)


# ---- 1. one material, quasi-static cycles ----------------------------------

G, H = 1.0e6, 1.0
# strain targets of the legs, in gamma_ref: loops of 0.5, 2 and 8, then an
# unload from 8 to 2, a reload to 5 and an unload through 2 (rejoining the
# outer branch) down to -8
LEGS = (0.5, -0.5, 0.5, 2.0, -2.0, 2.0, 8.0, -8.0, 8.0, 2.0, 5.0, -8.0, 0.0)
LOOPS = {0.5: 1, 2.0: 4, 8.0: 7}          # amplitude: the leg its loop starts with
SLABS_PER_LEG, DT = 60, 0.01


def cyclic_velocity():
    """The top's shear velocity: a triangle per leg, zero at the slab where
    each leg ends (so every reversal is a kept row), area H x the leg's
    strain increment."""
    T, gref = SLABS_PER_LEG * DT, MKZ["gamma_ref"]
    points, before = [[0.0, 0.0]], 0.0
    for k, target in enumerate(LEGS):
        peak = 2.0 * H * gref * (target - before) / T
        points += [[(k + 0.5) * T, peak], [(k + 1) * T, 0.0]]
        before = target
    return points


def cyclic_case(modulus=G):
    """Two elements, base fixed, top driven; rho so small that inertia
    takes ~1e-15 of the stress (c dt / h is large: the implicit slabs do
    not mind)."""
    doc = {"time": {"dt": DT, "end": len(LEGS) * SLABS_PER_LEG * DT}, "output": {"every": 1},
           "body": [{"name": "e", "x": [0.0, H], "elements": 2, "E": 1.0e6, "G": modulus,
                     "rho": 1.0e-3, "shear_law": MKZ}],
           "bc": [{"body": "e", "end": "left", "type": "fixed"},
                  {"body": "e", "end": "left", "type": "fixed", "component": "shear"},
                  {"body": "e", "end": "right", "type": "velocity", "component": "shear",
                   "value": cyclic_velocity()}],
           "gauge": [{"name": "low", "body": "e", "x": 0.2}]}
    return vstpetsc.Case.from_dict(doc)


@pytest.fixture(scope="module")
def cyclic(tmp_path_factory):
    return solve(tmp_path_factory.mktemp("cyclic"), cyclic_case())


def reference_law():
    return ref.Mkz(G, MKZ["gamma_ref"], MKZ["beta"], MKZ["s"])


def test_cyclic_stress_is_masing_of_the_recorded_strain(cyclic):
    gamma, tau = shear_strain(cyclic, "e"), cyclic.body("e").shear.stress
    ends = gamma[SLABS_PER_LEG::SLABS_PER_LEG]
    # the legs reach their targets in both elements: uniform strain, no inertia
    assert np.abs(ends - MKZ["gamma_ref"] * np.array(LEGS)[:, None]).max() \
        <= 1e-6 * 8 * MKZ["gamma_ref"]
    for e in range(2):
        want = ref.masing_stress(gamma[:, e], G, MKZ["gamma_ref"], MKZ["beta"], MKZ["s"])
        assert np.abs(tau[:, e] - want).max() <= 1e-6 * np.abs(want).max()   # asked: 1 %
    # the largest stress is the backbone's at 8 gamma_ref
    assert tau[:, 0].max() == pytest.approx(reference_law().backbone(8 * MKZ["gamma_ref"]))
    gauge = cyclic.gauge("low")
    assert np.array_equal(gauge.shear_stress, tau[:, 0])
    assert np.allclose(gauge.shear_strain, gamma[:, 0], rtol=0, atol=1e-12 * np.abs(gamma).max())


@pytest.mark.parametrize("amplitude", sorted(LOOPS))
def test_loop_damping_is_masings_closed_form(cyclic, amplitude):
    """D = loop area / (2 pi tau_a gamma_a) from the recorded loop
    (trapezoids over the rows) and from /energy/hysteretic over it (what
    the loop dissipated: the exact Gauss integrals of the slabs)."""
    law = reference_law()
    gamma_a = amplitude * MKZ["gamma_ref"]
    scale = 2.0 * math.pi * float(law.backbone(gamma_a)) * gamma_a
    first = LOOPS[amplitude] * SLABS_PER_LEG
    rows = slice(first, first + 2 * SLABS_PER_LEG + 1)
    gamma = shear_strain(cyclic, "e")[rows].mean(axis=1)
    tau = cyclic.body("e").shear.stress[rows].mean(axis=1)
    assert gamma[0] == pytest.approx(gamma_a) and gamma[-1] == pytest.approx(gamma_a)
    closed = ref.loop_damping_closed_form(law, gamma_a)
    assert abs(np.trapz(tau, gamma)) / scale == pytest.approx(closed, rel=0.02)
    hysteretic = cyclic.energy["hysteretic"]
    dissipated = (hysteretic[rows.stop - 1] - hysteretic[first]) / H    # area 1
    assert dissipated / scale == pytest.approx(closed, rel=1e-6)


def test_cyclic_strain_max_and_energy(cyclic):
    gamma = shear_strain(cyclic, "e")
    peak = np.abs(gamma).max(axis=0)
    assert np.allclose(cyclic.body("e").shear.strain_max, peak, rtol=1e-12, atol=0)
    e = cyclic.energy
    assert abs(e["numerical"]).max() <= 1e-9 * e["external"][-1]
    # a closed path ends at zero strain: nearly everything put in was dissipated
    assert e["hysteretic"][-1] == pytest.approx(e["external"][-1] - e["strain"][-1], rel=1e-9)


def test_quasi_static_default_newton(tmp_path):
    """With G = 1e9 the rounding of the element forces (~1e-15) lies far
    above rtol |b| (~1e-18): Newton's scale takes the elements' own forces
    (it failed at slab 1 when it did not)."""
    case = cyclic_case(modulus=1e9).with_value("time.end", 2 * SLABS_PER_LEG * DT)
    r = solve(tmp_path, case)
    assert r.status == "completed"


# ---- 2. the nonlinear column on a Lysmer base ------------------------------

# (thickness, rho, Vs, gamma_ref) from the base up
LAYERS = ((12.0, 2000.0, 300.0, 6.0e-4), (8.0, 1900.0, 180.0, 4.0e-4))
ROCK = {"rho": 2200.0, "Vs": 900.0}
PERIODS = np.geomspace(0.1, 2.0, 30)


def outcrop(duration, amplitude):
    """(t, v): a synthetic outcrop velocity, three sines under a sin^2 taper."""
    t = np.arange(0.0, duration + 1e-9, 0.005)
    taper = np.sin(np.pi * t / duration) ** 2
    v = np.sin(2 * np.pi * 2.5 * t) + 0.6 * np.sin(2 * np.pi * 4.3 * t + 1.0) \
        + 0.4 * np.sin(2 * np.pi * 1.3 * t + 0.5)
    return t, amplitude * taper * v


def column_case(elements, dt, end, record, every=1):
    height = sum(layer[0] for layer in LAYERS)
    counts = [round(elements * layer[0] / height) for layer in LAYERS]
    counts[-1] = elements - sum(counts[:-1])
    layers, laws, bottom = [], [], 0.0
    for (thickness, rho, vs, gref), n in zip(LAYERS, counts):
        layers.append({"thickness": thickness, "Vs": vs, "rho": rho, "elements": n})
        laws.append({**MKZ, "gamma_ref": gref, "from": bottom, "to": bottom + thickness})
        bottom += thickness
    table = [[float(a), float(b)] for a, b in zip(*record)]
    doc = {"time": {"dt": dt, "end": end}, "output": {"every": every},
           "body": [{"name": "soil", "x": [0.0, height], "elements": elements,
                     "layers": layers, "shear_law": laws}],
           "bc": [{"body": "soil", "end": "left", "type": "absorbing", "component": "shear",
                   "rock": ROCK, "incident": {"table": table}, "motion": "outcrop"}],
           "gauge": [{"name": "top", "body": "soil", "x": height}]}
    return vstpetsc.Case.from_dict(doc)


def element_gamma_ref(r):
    """gamma_ref of every element of the column's result."""
    x = r.body("soil").x
    mid, top = 0.5 * (x[1:] + x[:-1]), np.cumsum([layer[0] for layer in LAYERS])
    return np.array([layer[3] for layer in LAYERS])[np.searchsorted(top, mid)]


def reference_column(h_max, end, record):
    column = ref.Column.layered([(th, rho, vs, gref, MKZ["beta"], MKZ["s"])
                                 for th, rho, vs, gref in LAYERS], h_max)
    base = ref.LysmerBase(ROCK["rho"] * ROCK["Vs"], record[0], 0.5 * record[1])
    return ref.run_column(column, base, end)


QUAKE = dict(end=2.5, record=outcrop(2.0, 0.035))


@pytest.fixture(scope="module")
def quake(tmp_path_factory):
    return solve(tmp_path_factory.mktemp("quake"), column_case(24, 0.005, **QUAKE))


@pytest.fixture(scope="module")
def quake_reference():
    """The explicit column at h = 0.5 and 0.25 m."""
    return [reference_column(h, **QUAKE) for h in (0.5, 0.25)]


def reference_spectrum(run):
    return ref.response_spectrum(run.t, run.surface_acceleration, PERIODS)


def test_column_surface_spectrum_against_the_reference(quake, quake_reference):
    coarse, fine = map(reference_spectrum, quake_reference)
    assert np.abs(coarse / fine - 1).max() <= 0.01          # the reference has converged
    got = vstpetsc.response_spectrum(quake.gauge("top").shear_acceleration, quake.attrs["dt"],
                                     PERIODS, 0.05)["psa"]
    assert np.abs(got / fine - 1).max() <= 0.05
    assert 2.0 <= (quake.body("soil").shear.strain_max / element_gamma_ref(quake)).max() <= 10.0


def test_column_energy(quake, quake_reference):
    e = quake.energy
    rounding = 1e-12 * e["external"].max()
    assert e["numerical"].min() >= -rounding
    assert np.diff(e["numerical"]).min() >= -rounding
    assert e["numerical"][-1] <= 1e-3 * e["external"][-1]
    assert e["hysteretic"][-1] > 0.1 * e["external"][-1]
    # per unit area, as the reference's (area 1)
    assert e["hysteretic"][-1] == pytest.approx(quake_reference[1].hysteretic[-1], rel=0.02)
    strain = shear_strain(quake, "soil")
    assert np.allclose(quake.body("soil").shear.strain_max, np.abs(strain).max(axis=0),
                       rtol=1e-12, atol=0)


# ---- 4. the same run by other routes ---------------------------------------

SHORT = dict(elements=12, dt=0.005, end=0.4, record=outcrop(0.4, 0.2))


def assert_close(a, b, rtol):
    """The state, stress, gauges and energies of two results within rtol of
    each dataset's largest value (energies: of the largest energy)."""
    da, db = datasets(a), datasets(b)
    keep = lambda d: {k: x for k, x in d.items() if k.startswith(("body/", "gauge/", "energy/",
                                                                   "time"))}
    assert_runs_agree(keep(da), keep(db), rtol, iterations=None)


@pytest.fixture(scope="module")
def short(tmp_path_factory):
    folder = tmp_path_factory.mktemp("short")
    r = solve(folder, column_case(**SHORT), "full")
    # beyond gamma_ref, with reversals
    assert (r.body("soil").shear.strain_max / element_gamma_ref(r)).max() >= 2.0
    return r


@pytest.mark.parametrize("options", [["-vst_fd_jacobian"], ["-newton_ksp_type", "preonly"]],
                         ids=["fd_jacobian", "modified_newton"])
def test_other_newton_gives_the_same_run(tmp_path, short, options):
    other = solve(tmp_path, column_case(**SHORT), options=options)
    assert_close(short, other, 1e-8)


def test_python_path_equals_the_compiled_one(tmp_path, short):
    """-vst_native 0: the numpy kernel and Newton with PETSc's LU, the
    compiled run's checked reference (the same steps; equal to rounding)."""
    assert "compiled" in short.attrs["solver"]
    other = solve(tmp_path, column_case(**SHORT), options=["-vst_native", "0"])
    assert "compiled" not in other.attrs["solver"]
    assert_close(short, other, 1e-12)
    assert np.array_equal(short.solver["newton_iterations"], other.solver["newton_iterations"])


def test_restart_continues_bit_for_bit(tmp_path, short):
    case = column_case(**SHORT)
    out = str(tmp_path / "part.h5")
    vstpetsc.run(case.with_value("time.end", 0.3), output=out, quiet=True)
    vstpetsc.run(case, output=out, quiet=True, restart=True)
    assert_same_files(out, short.path)


def test_two_ranks_equal_one(tmp_path, short):
    path = write_case(tmp_path, column_case(**SHORT))
    p = mpirun("run", path, "-o", tmp_path / "two.h5", "--quiet")
    assert p.returncode == 0, p.stderr
    two = vstpetsc.Result(str(tmp_path / "two.h5"))
    assert two.attrs["mpi_size"] == 2
    # every rank factors the whole tangent (PETSc's redundant PC): the same
    # Newton as one rank's (measured: bit for bit)
    assert_close(short, two, 1e-10)


LEAK = """
import io, sys
import vstpetsc
from test_api import bar_wall
runs = [vstpetsc.run(bar_wall(), output=sys.argv[1] + name, options=options, quiet=True,
                     out=io.StringIO()) for name, options in (("a.h5", ["-ksp_type", "bcgs"]),
                                                               ("b.h5", []))]
print(runs[1].attrs["solver"])
"""


def test_first_runs_options_stay_with_it(tmp_path):
    p = subprocess.run([sys.executable, "-c", LEAK, str(tmp_path / "r")], capture_output=True,
                       text=True, cwd=os.path.join(ROOT, "tests"), timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("KSP preonly"), p.stdout


# ---- 5. bad input ------------------------------------------------------------

def with_law(law, shear=True):
    body = {"name": "s", "x": [0.0, 10.0], "elements": 4, "E": 1.0e8, "rho": 2000.0,
            "shear_law": law, **({"Vs": 200.0} if shear else {})}
    return {"time": {"dt": 1e-3, "end": 1e-2}, "body": [body]}


BAD = [
    ("no shear component", with_law(MKZ, shear=False),
     "body[0] (s).shear_law: only for a body with a shear component"),
    ("unknown model", with_law({**MKZ, "model": "hardin"}),
     "body[0] (s).shear_law.model: must be one of 'mkz'"),
    ("gamma_ref zero", with_law({**MKZ, "gamma_ref": 0.0}),
     "body[0] (s).shear_law.gamma_ref: must be positive"),
    ("s zero", with_law({**MKZ, "s": 0.0}), "body[0] (s).shear_law.s: must be positive"),
    ("beta negative", with_law({**MKZ, "beta": -1.0}),
     "body[0] (s).shear_law.beta: must be positive"),
    ("beta zero", with_law({**MKZ, "beta": 0.0}),
     "body[0] (s).shear_law.beta: must be positive"),
    ("from after to", with_law([{**MKZ, "from": 6.0, "to": 4.0}]),
     "body[0] (s).shear_law[0].to: must be >= from (6)"),
    ("s above one", with_law({**MKZ, "s": 1.5}),
     "body[0] (s).shear_law.s: must be <= 1"),
    ("no element midpoint", with_law([{**MKZ, "from": 0.1, "to": 0.2}]),
     "body[0] (s).shear_law: [0.1, 0.2] holds no element midpoint"),
]


@pytest.mark.parametrize("doc, message", [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_bad_shear_law_is_one_line(tmp_path, doc, message):
    with pytest.raises(vstpetsc.CaseError, match=re.escape(message)):
        vstpetsc.Case.from_dict(doc)
    path = tmp_path / "bad.toml"
    path.write_text(toml_text.dumps(doc))
    p = cli("run", path, "-o", tmp_path / "r.h5")
    assert p.returncode == 2 and one_clean_line(p.stderr), p.stderr
    assert p.stderr.startswith(f"vstpetsc: error: {message}"), p.stderr
    assert not (tmp_path / "r.h5").exists()



def test_part_covering_no_element_is_bad_input(tmp_path):
    doc = with_law([{**MKZ, "from": 20.0, "to": 30.0}])
    doc["bc"] = [{"body": "s", "end": "left", "type": "velocity", "component": "shear",
                  "value": 0.1}]
    with pytest.raises(vstpetsc.CaseError, match=re.escape("body[0] (s).shear_law[0]")):
        solve(tmp_path, vstpetsc.Case.from_dict(doc))


# ---- the kernel's tangent ----------------------------------------------------

@pytest.mark.parametrize("D", [(2e-4, -3e-4), (-1e-4, 5e-5), (3e-4, 1e-4), (-6e-4, -2e-4)],
                         ids=["turns", "turns_at_start_and_inside", "loads", "unloads"])
def test_slab_tangent_is_the_derivative_of_the_gauss_sums(D):
    """dQ/dD of masing.slab_integrals against central differences of Q,
    from a state on a branch (a reversal behind it), for slabs that load
    on, turn inside, turn at the start (the velocity jump) and inside."""
    from vstpetsc.materials import masing

    one = np.ones(1)
    backbone = masing.Backbone(1e7 * one, 1e-3 * one, one, 0.9 * one)
    state = masing.MasingState(backbone, np.array([2e-3]))
    # unload from 2e-3 to 1e-3: a reversal point on the stack
    _, _, path = masing.slab_integrals(state, np.array([-1e-3]), np.array([-1e-3]), one,
                                       1e7 * one, 0.01, tangent=False)
    state.gamma, state.tau, state.stack, state.direction = path.end()
    D1, D2 = np.array([D[0]]), np.array([D[1]])
    _, dQ, _ = masing.slab_integrals(state, D1, D2, one, 1e7 * one, 0.01)
    h = 1e-9
    for b, step in enumerate((np.array([h, 0.0]), np.array([0.0, h]))):
        Qp, _, _ = masing.slab_integrals(state, D1 + step[0], D2 + step[1], one, 1e7 * one,
                                         0.01, tangent=False)
        Qm, _, _ = masing.slab_integrals(state, D1 - step[0], D2 - step[1], one, 1e7 * one,
                                         0.01, tangent=False)
        fd = (Qp - Qm)[0] / (2 * h)
        assert np.abs(fd - dQ[0, :, b]).max() <= 1e-6 * np.abs(dQ).max(), (b, fd, dQ[0, :, b])


def test_initial_shear_strain_keeps_the_balance(tmp_path):
    """A column released from an initial shear strain of 4 gamma_ref (on the
    backbone): hysteretic starts at 0 and the balance closes (numerical
    was the initial stored energy beyond 1/2 u^T K u before the fix)."""
    doc = {"time": {"dt": 2e-3, "end": 0.2}, "output": {"every": 1},
           "body": [{"name": "s", "x": [0.0, 10.0], "elements": 8, "E": 1e8, "rho": 2000.0,
                     "Vs": 200.0, "shear_law": MKZ,
                     "u0_shear": [[0.0, 0.0], [10.0, 10.0 * 4 * MKZ["gamma_ref"]]]}],
           "bc": [{"body": "s", "end": "left", "type": "fixed"},
                  {"body": "s", "end": "left", "type": "fixed", "component": "shear"}]}
    e = solve(tmp_path, vstpetsc.Case.from_dict(doc)).energy
    total = e["kinetic"] + e["strain"]
    assert e["hysteretic"][0] == 0.0 and e["hysteretic"][-1] > 0.0
    assert np.abs(e["numerical"]).max() <= 1e-3 * total[0]
    assert np.diff(e["numerical"]).min() >= -1e-12 * total[0]
