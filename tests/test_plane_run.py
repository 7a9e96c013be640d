"""Plane-strain runs from case files through the shared time loop,
writer and command line: every boundary kind in one energy balance, the
dam section (mixed cells, two regions, absorbing base with an incident
wave, gravity, damping) on two ranks against one, a restart bit for bit,
and the bad inputs of the 2-D tables (exit 2, one line naming the key)."""

import io
import subprocess
import sys

import numpy as np
import pytest

import vstpetsc
from agreement import datasets, unequal
from conftest import solve
from test_parallel import assert_same_result, mpirun

PULSE = [[0.0, 0.0], [0.01, 0.2], [0.02, 0.0], [1.0, 0.0]]
DAM = """
[time]
dt = 2.5e-3
end = {end}
[mesh]
dam = {{ height = 20.0, crest = 4.0, upstream = 2.0, downstream = 1.5, foundation_depth = 12.0, foundation_width = 120.0, h = 4.0 }}
[[region]]
name = "dam"
Vs = 300.0
nu = 0.3
rho = 2000.0
damping = {{ beta = 1.0e-3 }}
mass = "consistent"
[[region]]
name = "foundation"
Vs = 800.0
Vp = 1600.0
rho = 2400.0
[[boundary]]
name = "base"
type = "absorbing"
incident = {{ x = [[0.0, 0.0], [0.03, 0.3], [0.06, 0.0]], y = [[0.0, 0.0], [0.04, 0.1], [0.08, 0.0]] }}
[[boundary]]
name = "left"
type = "absorbing"
[[boundary]]
name = "right"
type = "absorbing"
rock = {{ rho = 2400.0, Vs = 800.0, Vp = 1600.0 }}
[gravity]
g = -9.81
initial = "static"
[[gauge]]
name = "crest"
x = [0.0, 20.0]
[[gauge]]
name = "inside"
x = [1.3, 7.7]
"""


def dam_case(tmp_path, end=0.2, name="dam"):
    path = tmp_path / f"{name}.toml"
    path.write_text(DAM.format(end=end))
    return path


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "vstpetsc", *map(str, args)],
                          capture_output=True, text=True, timeout=240)


def test_a_static_start_is_the_exact_equilibrium(tmp_path):
    """A column one cell wide under gravity (sides holding v_x), its base
    absorbing: [gravity] initial = "static" solves K u = f with the base
    held; u_y at the nodes is the exact rho g / (lambda + 2 mu) (H y -
    y^2 / 2) (linear elements with the consistent load are exact at the
    nodes), and the run, the base's reactions kept as forces, stays at
    rest in it: v = 0 and u unchanged to rounding."""
    H = 10.0
    case = vstpetsc.Case.from_dict({
        "time": {"dt": 1e-3, "end": 0.05},
        "mesh": {"rectangle": {"x": [0.0, 1.0], "y": [0.0, H], "nx": 1, "ny": 10}},
        "region": [{"name": "domain", "E": 2e8, "nu": 0.3, "rho": 1800.0}],
        "boundary": [{"name": "bottom", "type": "absorbing"},
                     {"name": "left", "type": "velocity", "value": {"x": 0.0}},
                     {"name": "right", "type": "velocity", "value": {"x": 0.0}}],
        "gravity": {"g": -9.81, "initial": "static"}})
    r = solve(tmp_path, case)
    region = case.plane.regions[0]
    y = r.mesh.coordinates[:, 1]
    exact = 1800.0 * -9.81 / (region.lam + 2 * region.mu) * (H * y - y * y / 2)
    u = r.field.u
    scale = np.abs(exact).max()
    print("static start: u_y against exact", np.abs(u[0, :, 1] - exact).max() / scale,
          "drift of u", np.abs(u - u[0]).max() / scale, "largest v", np.abs(r.field.v).max())
    assert np.abs(u[0, :, 1] - exact).max() <= 1e-12 * scale
    assert np.abs(u - u[0]).max() <= 1e-12 * scale
    assert np.abs(r.field.v).max() <= 1e-12 * scale / case.dt


def test_every_boundary_kind_keeps_the_energy_balance(tmp_path):
    """A plate of triangles: its bottom driven (velocity in x, held in y),
    a traction on its top, an absorbing right side, gravity; undamped. The
    balance initial + external = kinetic + strain + damping (the dashpots')
    + numerical leaves a numerical term that is >= 0, never decreases (the
    jumps' dissipation) and is a small part of the work put in."""
    case = vstpetsc.Case.from_dict({
        "time": {"dt": 1e-3, "end": 0.15},
        "mesh": {"rectangle": {"x": [0.0, 20.0], "y": [0.0, 8.0], "nx": 10, "ny": 4,
                               "triangles": True}},
        "region": [{"name": "domain", "Vs": 200.0, "Vp": 400.0, "rho": 2000.0}],
        "boundary": [{"name": "bottom", "type": "velocity", "value": {"x": PULSE, "y": 0.0}},
                     {"name": "top", "type": "traction", "value": {"y": [[0.0, 0.0],
                                                                         [0.05, -1e4],
                                                                         [0.1, 0.0]]}},
                     {"name": "right", "type": "absorbing"}],
        "gravity": {"g": -9.81}})
    r = solve(tmp_path, case)
    e = r.energy
    scale = np.abs(e["external"]).max()
    assert scale > 0 and np.abs(e["damping"]).max() > 0
    numerical = e["numerical"]
    print("numerical / external:", numerical[-1] / scale, "largest drop:",
          np.diff(numerical).min() / scale)
    assert numerical.min() >= -1e-12 * scale
    assert np.diff(numerical).min() >= -1e-12 * scale
    assert numerical[-1] <= 0.05 * scale
    # the driven bottom follows its history, the other component is held
    bottom = np.isclose(r.mesh.coordinates[:, 1], 0.0)
    t = r.time
    assert np.allclose(r.field.v[:, bottom, 0], np.interp(t, *np.array(PULSE).T)[:, None],
                       rtol=0, atol=1e-12)
    assert np.abs(r.field.v[:, bottom, 1]).max() == 0.0


def test_the_dam_on_two_ranks_equals_one(tmp_path):
    """The dam (triangles on quadrilaterals, two regions, consistent and
    averaged masses, damping, absorbing sides, incident P and SV waves,
    gravity from a static start, two gauges) by `mpirun -n 2 vstpetsc run`: every dataset
    within 1e-10 of its largest value of the one-rank run."""
    two = mpirun_against_one_rank(tmp_path, dam_case(tmp_path))
    r = vstpetsc.Result(two)
    assert r.dimension == 2 and np.abs(r.gauge("crest").v).max() > 0.1


def mpirun_against_one_rank(tmp_path, case, *options):
    """Run ``case`` on one rank and under `mpirun -n 2` (with PETSc
    ``options``); assert every dataset of the two within 1e-10 of its
    largest; the two-rank file."""
    one, two = tmp_path / "one.h5", tmp_path / "two.h5"
    p = run_cli("run", case, "-o", one, "-q")
    assert p.returncode == 0, p.stderr
    p = mpirun("run", case, "-o", two, "-q", *options)
    assert p.returncode == 0, p.stderr
    assert_same_result(one, two, rtol=1e-10)
    return two


def test_a_restart_continues_bit_for_bit(tmp_path):
    whole = vstpetsc.run(vstpetsc.Case.from_toml(dam_case(tmp_path, 0.2)),
                         output=str(tmp_path / "whole.h5"), quiet=True)
    part = str(tmp_path / "part.h5")
    vstpetsc.run(vstpetsc.Case.from_toml(dam_case(tmp_path, 0.1, "half")), output=part,
                 quiet=True)
    vstpetsc.run(vstpetsc.Case.from_toml(dam_case(tmp_path, 0.2, "half")), output=part,
                 quiet=True, restart=True, out=io.StringIO())
    a, b = datasets(whole), datasets(part)
    assert set(a) == set(b)
    for key in a:
        if key != "solver/wall_time":
            assert np.array_equal(a[key], b[key]), key


BAD = [
    ("body", "[[body]]\nname = 'b'\n", "body: [[body]] is a 1-D table"),
    ("interface curve", "[[interface]]\nname = 'contact'\n",
     "interface[0] (contact).name: the mesh has no curve 'contact'"),
    ("interface on the boundary", "[[interface]]\nname = 'top'\n",
     "interface[0] (top).name: curve 'top' runs along the mesh's boundary"),
    ("interface with a boundary", "[[boundary]]\nname = 'top'\ntype = 'fixed'\n"
     "[[interface]]\nname = 'top'\n", "interface[0] (top).name: curve 'top' has a [[boundary]]"),
    ("negative friction", "[[interface]]\nname = 'top'\nfriction = -0.1\n",
     "interface[0] (top).friction"),
    ("formulation", "[[interface]]\nname = 'top'\nformulation = 'lagrange'\n",
     "interface[0] (top).formulation"),
    ("penalty", "[[interface]]\nname = 'top'\npenalty = 0.0\n", "interface[0] (top).penalty"),
    ("interface key", "[[interface]]\nname = 'top'\nfricton = 0.3\n",
     "interface[0].fricton: unknown key"),
    ("joint off the grid", "JOINT", "mesh.rectangle.joints.joint: must be the y of a grid row"),
    ("region name", None, "region[0] (dam).name: the mesh has no region 'dam'"),
    ("boundary name", "[[boundary]]\nname = 'nowhere'\ntype = 'fixed'\n",
     "boundary[0] (nowhere).name: the mesh has no curve 'nowhere'"),
    ("mesh file", "FILE", "mesh.file: no such file"),
    ("gauge", "[[gauge]]\nname = 'far'\nx = [50.0, 50.0]\n", "gauge (far).x"),
    ("Vp", "VP", "region[0] (domain).Vp: must exceed sqrt(2) Vs"),
    ("boundary key", "[[boundary]]\nname = 'top'\ntype = 'fixed'\nvalue = { x = 1.0 }\n",
     "boundary[0] (top).value: not a key of a 'fixed' boundary"),
    ("static with u0", "U0", "gravity.initial: \"static\" computes the initial displacements"),
    ("outcrop without incident", "[[boundary]]\nname = 'bottom'\ntype = 'absorbing'\n"
     "motion = 'outcrop'\n", "boundary[0] (bottom).motion: \"outcrop\" halves an incident"),
    ("rock key", "[[boundary]]\nname = 'bottom'\ntype = 'absorbing'\nrock = { rho = 2.0e3, Vp = 800.0 }\n",
     "boundary[0] (bottom).rock.Vs: missing required key"),
    ("second boundary", "[[boundary]]\nname = 'top'\ntype = 'fixed'\n[[boundary]]\n"
     "name = 'top'\ntype = 'fixed'\n", "boundary[1].name: a second [[boundary]] on curve 'top'"),
    ("two meshes", "MESHES", "mesh: give exactly one of file, rectangle, dam (got rectangle, dam)"),
    ("reversed", "REVERSED", "mesh.rectangle.x: must be [low, high] with low < high"),
    ("huge", "HUGE", "mesh.rectangle.x: an integer beyond the 64-bit range"),
]


@pytest.mark.parametrize("what, extra, message", BAD, ids=[b[0] for b in BAD])
def test_bad_inputs_exit_2_with_one_line(tmp_path, what, extra, message):
    region = "name = 'dam'" if what == "region name" else "name = 'domain'"
    speeds = "Vs = 200.0\nVp = 250.0" if extra == "VP" else "Vs = 200.0\nVp = 400.0"
    if extra == "U0":
        speeds += "\nu0 = [0.0, 1.0]"
        extra = "[gravity]\ng = -9.81\ninitial = 'static'\n"
    x = {"REVERSED": "[4.0, 0.0]", "HUGE": "[0.0, 1" + "0" * 30 + "]"}.get(extra, "[0.0, 4.0]")
    mesh = "file = 'missing.msh'" if extra == "FILE" else \
        f"rectangle = {{ x = {x}, y = [0.0, 2.0], nx = 2, ny = 1 }}"
    if extra == "MESHES":
        mesh += "\ndam = { height = 1.0 }"
    if extra == "JOINT":
        mesh = mesh.replace(" }", ", joints = { joint = 0.5 } }")
    text = (f"[time]\ndt = 1e-3\nend = 0.01\n[mesh]\n{mesh}\n[[region]]\n{region}\n{speeds}\n"
            f"rho = 2000.0\n" + (extra if extra not in (None, "FILE", "VP", "MESHES", "REVERSED",
                                                       "HUGE", "JOINT") else ""))
    case = tmp_path / "bad.toml"
    case.write_text(text)
    p = run_cli("run", case, "-o", tmp_path / "bad.h5", "-q")
    assert p.returncode == 2, (p.stdout, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], p.stderr
    assert not (tmp_path / "bad.h5").exists()


def test_a_sweep_of_a_plane_case(tmp_path):
    """`vstpetsc sweep` over a 2-D case's region and boundary keys: every
    run completes, and motion = "outcrop" (the record halved) gives a
    quarter of the energies of the incident motion (a linear run)."""
    import csv

    from vstpetsc import bundled

    p = run_cli("sweep", bundled.path("plane-column"), "--set", "region.domain.Vs=150,200",
                "--set", "boundary.bottom.motion=incident,outcrop", "-o", tmp_path / "sw",
                "--quiet")
    assert p.returncode == 0, p.stderr
    rows = list(csv.DictReader(open(tmp_path / "sw" / "summary.csv")))
    assert [r["status"] for r in rows] == ["completed"] * 4
    for incident, outcrop in ((rows[0], rows[1]), (rows[2], rows[3])):
        a = vstpetsc.Result(tmp_path / "sw" / incident["file"]).energy
        b = vstpetsc.Result(tmp_path / "sw" / outcrop["file"]).energy
        for key in ("kinetic", "external", "damping"):
            assert np.allclose(b[key], 0.25 * a[key], rtol=1e-12, atol=1e-12 * a[key].max())


def mpirun_continued(tmp_path, *options):
    """(the whole two-rank run's datasets, those of one stopped at 0.1 s
    and continued with --restart to 0.2 s), both with ``options``."""
    whole, part = tmp_path / "whole.h5", tmp_path / "part.h5"
    for end, name, args in ((0.2, "dam", ("-o", whole)), (0.1, "half", ("-o", part)),
                            (0.2, "half", ("--restart", part))):
        p = mpirun("run", dam_case(tmp_path, end, name), *args, "-q", *options)
        assert p.returncode == 0, p.stderr
    return datasets(whole), datasets(part)


MUMPS = ("-vst_plane_ksp_type", "preonly", "-vst_plane_pc_type", "lu",
         "-vst_plane_pc_factor_mat_solver_type", "mumps")


@pytest.mark.parametrize("options, exact", [
    ((), True), (("-vst_flush_interval", "0"), True), (("-vst_plane_pc_type", "redundant"), True),
    (MUMPS, False)], ids=["default", "blocks", "redundant", "mumps"])
def test_a_restart_on_two_ranks_continues_the_run(tmp_path, options, exact):
    """The dam on two ranks stopped at 0.1 s and continued with two ranks:
    with the default (GMRES with Schwarz blocks at this Courant number),
    with a block to the file on the writer's thread after every slab (what
    a loaded machine does now and then: blocks go by wall time) and with
    -vst_plane_pc_type redundant (every rank factors the whole slab
    matrix) bit for bit, each rank taking its own energy sums back
    (solver/energy_sums); with MUMPS, whose parallel factorisation is not
    repeatable bit for bit (two runs of one case differ by 9e-15 m/s
    here), within 1e-10 of each dataset's largest value."""
    a, b = mpirun_continued(tmp_path, *options)
    assert set(a) == set(b)
    if exact:           # every dataset that differs, and its first row
        assert unequal(a, b) == {}
        return
    for key in a:
        if key not in ("solver/wall_time", "solver/energy_sums"):
            assert np.abs(a[key] - b[key]).max() <= 1e-10 * np.abs(a[key]).max(), key


def test_a_dry_run_reads_and_checks_the_mesh(tmp_path):
    """--dry-run of a 2-D case: the mesh read and checked, its size and
    each region's Courant number printed, nothing solved or written; a
    region the mesh has not: exit 2, one line."""
    case = dam_case(tmp_path)
    p = run_cli("run", case, "--dry-run")
    assert p.returncode == 0, p.stderr
    assert "plane strain: 193 cells (100 triangles), 174 nodes" in p.stdout
    assert "region foundation: Vp = 1600, Vs = 800, rho = 2400, Vp dt / h up to 1" in p.stdout
    assert not list(tmp_path.glob("*.h5"))
    case.write_text(case.read_text().replace('name = "foundation"', 'name = "rock"'))
    p = run_cli("run", case, "--dry-run")
    assert p.returncode == 2 and p.stderr.count("\n") == 1 and "region[1] (rock).name" in p.stderr
