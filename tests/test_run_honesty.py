"""What a run reports about itself (issue 44): an interface penalty stiffer
than double precision resolves is refused (exit 2, one line naming the
key and the limit); a run whose energy balance goes negative beyond
rounding stops (exit 3, status "failed" with the reason) instead of
completing; `info` prints one initial energy; the run's last line says
what a user can judge, driven or free: the energy at the start and the
end, the work put in, what the model and what the time discretisation
dissipated (docs/troubleshooting.md, docs/interfaces.md)."""

import math
import re
import subprocess
import sys

import numpy as np
import pytest

import vstpetsc
from conftest import bar, cli, make_case, run_and_info, solve, write_case
from vstpetsc.runner import energy as energy_mod
from vstpetsc.errors import SolveFailed
from vstpetsc.plane import pairs as pairs_mod

E, NU, RHO = 1.0e8, 0.3, 2000.0
M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))          # lambda + 2 mu
# the column's cells are 0.5 wide and 1 high, the joint horizontal: h = 1
# on both sides, their series stiffness M / 2 per unit length
SERIES = M / 2.0
NUMBER = r"(-?[\d.]+(?:e[+-]\d+)?)"


def pressed(penalty=None, formulation="power", dt=1.0, end=20.0, gravity=False):
    """A column of 2 x 2 cells split by a horizontal joint at half height,
    its bottom fixed, its top pressed slowly (a traction rising to 1e5 Pa,
    dt = 1: the issue's quasi-static press); or at rest under gravity from
    a static start (``gravity``)."""
    interface = {"name": "j", "formulation": formulation}
    if penalty is not None:
        interface["penalty"] = penalty
    boundary = [{"name": "bottom", "type": "fixed"}]
    doc = {"time": {"dt": dt, "end": end},
           "mesh": {"rectangle": {"x": [0.0, 1.0], "y": [0.0, 2.0], "nx": 2, "ny": 2,
                                  "joints": {"j": 1.0}}},
           "region": [{"name": "domain", "E": E, "nu": NU, "rho": RHO}],
           "boundary": boundary, "interface": [interface]}
    if gravity:                 # friction holds the upper block along the joint
        doc["gravity"] = {"g": -9.81, "initial": "static"}
        interface["friction"] = 0.5
    else:
        boundary.append({"name": "top", "type": "traction",
                         "value": {"y": [[0.0, 0.0], [end, -1.0e5]]}})
    return vstpetsc.Case.from_dict(doc)


def limit(formulation, dt=1.0):
    """The documented limit: a spring (the power penalty, the seed's
    penalty dt / 2) of 1e8 times the cells' series stiffness."""
    spring = 1e8 * SERIES
    return spring if formulation == "power" else 2.0 * spring / dt


# ---- (A) the penalty's limit ---------------------------------------------

BAD = [
    ("power 1e40", dict(penalty=1e40), "interface[0] (j).penalty: 1e+40 is stiffer than"),
    ("seed 1e40", dict(penalty=1e40, formulation="seed"),
     "interface[0] (j).penalty: 1e+40 is stiffer than"),
    ("power 1e150", dict(penalty=1e150), "interface[0] (j).penalty: 1e+150 is stiffer than"),
    ("power just beyond", dict(penalty=1.01 * limit("power")),
     f"at most {limit('power'):.3g} (1e+08 times"),
    ("seed just beyond", dict(penalty=1.01 * limit("seed"), formulation="seed"),
     f"at most {limit('seed'):.3g} (1e+08 times"),
]


@pytest.mark.parametrize("what, keys, message", BAD, ids=[b[0] for b in BAD])
def test_a_penalty_beyond_the_limit_is_refused(tmp_path, what, keys, message):
    """exit 2, one line naming interface[0] (j).penalty and the limit, no
    result file (the issue: 1e40 completed with a numerical energy of
    -1.34e6 J; 1e150 gave forces of 5.7e136 from a gap of -2.3e-13)."""
    case = write_case(tmp_path, pressed(**keys), "bad")
    p = cli("run", case, "-o", tmp_path / "bad.h5", "--quiet")
    assert p.returncode == 2, (p.stdout, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], p.stderr
    assert "Traceback" not in p.stderr and not (tmp_path / "bad.h5").exists()


@pytest.mark.parametrize("formulation", ["power", "seed"])
def test_a_penalty_just_within_the_limit_is_taken(tmp_path, formulation):
    """The limit is the documented rule of the cells beside the curve, not
    a round number: 0.99 of it runs (and its balance holds)."""
    case = pressed(0.99 * limit(formulation), formulation, dt=1e-4, end=2e-3)
    r = solve(tmp_path, case)
    assert r.interface("j").attrs["penalty"] == 0.99 * limit(formulation)
    assert r.status == "completed"


def test_the_limit_follows_the_softest_cells_beside_the_curve():
    """penalty_limit: per edge of the curve the series stiffness
    1 / (h_1 / M_1 + h_2 / M_2) of its two cells (M = lambda + 2 mu), the
    softest edge's, times 1e8 (the seed's as its slab-mean penalty dt / 2):
    a stiffer cell above one edge leaves the other edge's the limit."""
    from vstpetsc.plane.model import cell_materials, read_mesh

    plane = pressed().plane
    mesh = read_mesh(plane.mesh)
    materials = cell_materials(plane.regions, mesh.region)
    edges = mesh.curves["j"]
    got, series = pairs_mod.penalty_limit(mesh, materials, edges, "power", 1.0)
    assert series == pytest.approx(SERIES, rel=1e-12) and got == pytest.approx(1e8 * SERIES)
    seed, _ = pairs_mod.penalty_limit(mesh, materials, edges, "seed", 0.01)
    assert seed == pytest.approx(2e8 * SERIES / 0.01)
    # the cell above the first edge four times as stiff: that edge's series
    # stiffness rises to 4/5 M, the other edge's stays M / 2
    centre = mesh.coordinates[mesh.cells].mean(axis=1)
    above_first = np.flatnonzero((centre[:, 1] > 1.0) & (centre[:, 0] < 0.5))
    for key in ("lam", "mu"):
        materials[key][above_first] *= 4.0
    _, series = pairs_mod.penalty_limit(mesh, materials, edges, "power", 1.0)
    assert series == pytest.approx(SERIES, rel=1e-12)
    # every cell above four times as stiff: 4/5 M on both edges
    above = np.flatnonzero((centre[:, 1] > 1.0) & (centre[:, 0] > 0.5))
    for key in ("lam", "mu"):
        materials[key][above] *= 4.0
    _, stiffer = pairs_mod.penalty_limit(mesh, materials, edges, "power", 1.0)
    assert stiffer == pytest.approx(0.8 * M, rel=1e-12)


def test_a_1d_penalty_of_1e40_never_completes_with_a_false_balance(tmp_path):
    """1-D keeps a pair's penalty out of the slab matrix (Newton on the
    pair's own coordinates): a penalty of 1e40 makes its Newton fail (exit
    3, honest) rather than complete with a negative balance; whatever it
    does, it does not report "completed" with numerical < 0 beyond
    rounding."""
    case = make_case(2e-6, 4e-4, [bar("bar", (0.0, 1.0), 20, v0=1.0)],
                     contacts=[dict(pair=["bar", "wall"], wall=1.0001, penalty=1e40)])
    try:
        r = solve(tmp_path, case)
    except SolveFailed as exc:
        assert "Newton" in str(exc) or "energy balance" in str(exc)
        r = vstpetsc.Result(str(tmp_path / "case.h5"))
        assert r.status == "failed"
        return
    e = r.energy
    largest = max(np.abs(e[k]).max() for k in energy_mod.BALANCE)
    assert e["numerical"].min() >= -energy_mod.NEGATIVE * largest


# ---- (A) the guard in the time loop ------------------------------------

def test_the_guard_is_relative_to_the_largest_term():
    """balance_problem: a numerical energy of -0.5e-6 of the largest term
    is rounding (None), -2e-6 of it is not (the message names the slab);
    the largest term is the largest at the rows so far, not this row's."""
    book = object.__new__(energy_mod.EnergyBook)         # only its guard
    book.largest = 0.0
    row = dict.fromkeys(energy_mod.BALANCE, 0.0)
    assert book.balance_problem({**row, "external": 100.0, "numerical": 0.0}, 1) is None
    quiet = {**row, "kinetic": 1.0, "numerical": -0.5e-6 * 100.0}
    assert book.balance_problem(quiet, 2) is None            # 100 is still the reference
    loud = {**row, "kinetic": 1.0, "numerical": -2e-6 * 100.0}
    problem = book.balance_problem(loud, 3)
    assert problem.startswith("slab 3: the energy balance went negative")
    assert "-0.0002" in problem and "100" in problem


# A penalty far beyond the limit: what its slabs make of the press depends
# on the rounding of the slab matrix's factors (1e30 to 1e80 break both the
# AIJ's and the 4 x 4 blocks' LU, 1e40 the AIJ's but not the blocks': there
# it completes with its balance closed; the limit refuses all of them).
STIFF = 1e30


def test_a_run_that_creates_energy_stops_with_exit_3(tmp_path):
    """The issue's press with the limit lifted (what it would do without
    it): the balance goes negative in the first slabs; the run stops with
    exit 3, one line, status "failed" and the reason in the file's
    message, not "completed"."""
    path = write_case(tmp_path, pressed(STIFF), "press")
    out = tmp_path / "press.h5"
    script = ("import sys; from vstpetsc.plane import pairs; pairs.PENALTY_LIMIT = float('inf');"
              " from vstpetsc.cli import main; sys.exit(main(sys.argv[1:]))")
    p = subprocess.run([sys.executable, "-c", script, "run", str(path), "-o", str(out),
                        "--quiet"], capture_output=True, text=True, timeout=120)
    assert p.returncode == 3, (p.stdout, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "the energy balance went negative" in lines[0], p.stderr
    r = vstpetsc.Result(str(out))
    assert r.status == "failed" and "the energy balance went negative" in r.attrs["message"]
    # every kept row holds a balance within the tolerance
    e = r.energy
    largest = max(np.abs(e[k]).max() for k in energy_mod.BALANCE)
    assert e["numerical"].min() >= -energy_mod.NEGATIVE * largest
    info = cli("info", out)
    assert info.returncode == 0 and "failed (slab" in info.stdout.splitlines()[0]


def test_the_limit_is_what_keeps_the_balance(tmp_path, monkeypatch):
    """In-process, the limit lifted: STIFF fails the run (SolveFailed, file
    "failed"); the largest penalty the limit allows completes with its
    balance within the tolerance."""
    monkeypatch.setattr(pairs_mod, "PENALTY_LIMIT", math.inf)
    with pytest.raises(SolveFailed, match="energy balance went negative"):
        solve(tmp_path, pressed(STIFF), "stiff")
    assert vstpetsc.Result(str(tmp_path / "stiff.h5")).status == "failed"
    r = solve(tmp_path, pressed(limit("power")), "limit")
    e = r.energy
    largest = max(np.abs(e[k]).max() for k in energy_mod.BALANCE)
    # rounding at the limit: about 2 eps 1e8 = 4.4e-8 of the largest term
    assert r.status == "completed" and e["numerical"].min() >= -0.1 * \
        energy_mod.NEGATIVE * largest


# ---- (B) and (C): one initial energy; the last line ------------------

def parsed(line):
    """{initial, end, work, dissipated, numerical, share, peak} of an energy line."""
    m = re.search(rf"energy:? {NUMBER} -> {NUMBER}; work in {NUMBER}; dissipated {NUMBER} by "
                  rf"damping, friction and soil and {NUMBER} by the time discretisation "
                  rf"\({NUMBER} % of the largest total energy {NUMBER}\)", line)
    assert m, line
    keys = ("initial", "end", "work", "dissipated", "numerical", "share", "peak")
    return dict(zip(keys, map(float, m.groups())))


def from_file(r):
    """The same numbers from the file's datasets, computed here."""
    e = r.energy
    holds = sum(e[k] for k in ("kinetic", "strain", "spring", "contact"))
    peak = np.abs(holds[0] + e["external"]).max()
    return {"initial": holds[0], "end": holds[-1], "work": e["external"][-1],
            "dissipated": sum(e[k][-1] for k in ("damping", "soil", "friction", "hysteretic")),
            "numerical": e["numerical"][-1], "peak": peak,
            "share": 100 * e["numerical"][-1] / peak}


def assert_line_is_the_file(numbers, r):
    """Each printed number is the file's, to its printed digits; the line
    closes: initial + work = end + dissipated + numerical."""
    expected = from_file(r)
    for key, value in numbers.items():
        digits = 3 if key == "share" else 6
        assert value == float(f"{expected[key]:.{digits}g}"), (key, value, expected[key])
    left = numbers["initial"] + numbers["work"]
    right = numbers["end"] + numbers["dissipated"] + numbers["numerical"]
    assert abs(left - right) <= 1e-5 * expected["peak"]


def test_info_prints_one_initial_energy(tmp_path):
    """A column resting on its closed joint (static start): most of its
    energy at t = 0 is the joint's springs' (it printed "start" without
    them and "initial" with them).  info's energy line and its balance
    line print the same initial energy, the one of the file's first row
    with the contact term."""
    _, info, r = run_and_info(tmp_path, pressed(gravity=True, dt=1e-3, end=5e-3), "rest")
    e = r.energy
    assert e["contact"][0] > 0 and e["strain"][0] > 0
    energy = [l for l in info.splitlines() if l.startswith("  energy: ")][0]
    balance = [l for l in info.splitlines() if l.startswith("  energy balance: ")][0]
    numbers = parsed(energy)
    initial = float(re.search(rf"initial {NUMBER} \+", balance).group(1))
    assert numbers["initial"] == initial
    assert initial == float(f"{e['kinetic'][0] + e['strain'][0] + e['spring'][0] + e['contact'][0]:.6g}")
    assert_line_is_the_file(numbers, r)


def shaken(tmp_path):
    """A column on a base driven sideways: the work put in dwarfs the
    initial energy (the issue's +263.5 %)."""
    drive = [[0.0, 0.0], [0.01, 0.2], [0.04, 0.2]]
    return vstpetsc.Case.from_dict({
        "time": {"dt": 1e-3, "end": 0.04},
        "mesh": {"rectangle": {"x": [0.0, 1.0], "y": [0.0, 2.0], "nx": 2, "ny": 2}},
        "region": [{"name": "domain", "E": E, "nu": NU, "rho": RHO,
                    "damping": {"beta": 1e-4}, "v0": [0.0, 0.01]}],
        "boundary": [{"name": "bottom", "type": "velocity", "value": {"x": drive, "y": 0.0}}]})


@pytest.mark.parametrize("kind", ["driven", "free"])
def test_the_last_line_reads_right_driven_or_free(tmp_path, kind):
    """The run's last line and info's energy line: the same text, every
    number the file's (computed here from its datasets), and they close.
    A driven run (work in much more than the initial energy) prints no
    percent change of its energy, only the scheme's share of the largest
    total energy; a free one (a bar on a wall) its work 0."""
    case = shaken(tmp_path) if kind == "driven" else \
        make_case(2e-6, 6e-4, [bar("bar", (0.0, 1.0), 40, v0=1.0)],
                  contacts=[dict(pair=["bar", "wall"], wall=1.0001)])
    line, info, r = run_and_info(tmp_path, case, kind)
    numbers = parsed(line)
    assert_line_is_the_file(numbers, r)
    assert line.split("; energy ")[1].split("; result: ")[0] in info
    if kind == "driven":
        assert abs(numbers["work"]) > 10 * numbers["initial"] and numbers["dissipated"] > 0
        assert line.count("%") == 1          # the scheme's share only: no +263.5 %
    else:
        assert numbers["work"] == 0 and numbers["dissipated"] == 0
        assert numbers["end"] < numbers["initial"]
