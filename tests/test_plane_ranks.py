"""Plane strain on several ranks (issue 48): the bundled dams on two and
three ranks against one (every dataset within 1e-10 of its largest, the
interfaces' included; the static start, rank 0's solve, the same bits)
and stopped half way and continued with --restart on as many ranks, bit
for bit; an interface whose every pair's two nodes belong to two ranks,
the ownership read from the model the run itself builds; sweeps of a 2-D
case dealt to 2 and 4 ranks (one rank a run: every file the one-rank
sweep's bit for bit) and to two ranks a run (within 1e-10)."""

import json
import sys

import numpy as np
import pytest

from agreement import datasets, energy_scale, unequal
from conftest import cli
from test_parallel import assert_same_result, mpirun
from vstpetsc import Case, Result
from vstpetsc.runner.sweep import read_summary

# until every interface of each dam has moved (gravity-dam: 0.8 mm of
# slip, its heel open from 0.52 s; rockfill-dam: each of its three
# interfaces 18-66 um of slip)
DAMS = {"gravity-dam": 0.6, "rockfill-dam": 0.6}
WALL = ("solver/wall_time",)


def shortened(tmp_path, name, end, stem):
    """The bundled example ``name`` (its companion files beside it) run to
    ``end``, as tmp_path/<stem>.toml."""
    source = tmp_path / f"{name}.toml"
    if not source.exists():
        assert cli("example", name, "-o", source).returncode == 0
    path = tmp_path / f"{stem}.toml"
    path.write_text(Case.from_toml(source).with_value("time.end", end).to_toml())
    return path


def assert_bad_option_named(tmp_path, option, value):
    """A short gravity-dam with ``-option value`` (one rank: the options are
    read on every rank, before any collective): exit 2, one line naming
    the option and the value, no traceback."""
    path = shortened(tmp_path, "gravity-dam", 0.02, "bad")
    p = cli("run", path, "-o", tmp_path / "r.h5", f"-{option}", value)
    assert p.returncode == 2
    ours = [l for l in p.stderr.splitlines() if l.startswith("vstpetsc: error")]
    assert len(ours) == 1 and f"-{option}: '{value}'" in ours[0], p.stderr
    assert "Traceback" not in p.stderr


def mpirun_ok(*args, n):
    p = mpirun(*args, "--quiet", n=n)
    assert p.returncode == 0, p.stderr
    return p


@pytest.fixture(scope="module")
def one_rank(tmp_path_factory):
    """(the folder, the one-rank run's file) of a dam shortened to
    DAMS[name], run once for the module (the runs on several ranks read
    their case in the same folder: the file's case_folder the same)."""
    runs = {}

    def run(name):
        if name not in runs:
            folder = tmp_path_factory.mktemp(name)
            runs[name] = folder, folder / "one.h5"
            p = cli("run", shortened(folder, name, DAMS[name], "whole"), "-o", runs[name][1],
                    "--quiet")
            assert p.returncode == 0, p.stderr
        return runs[name]
    return run


# (gravity-dam on two ranks: the whole run in test_parallel's bundled
# examples, a dam on its interface restarted on two ranks in
# test_plane_interface_runs)
@pytest.mark.parametrize("name, ranks", [("gravity-dam", 3), ("rockfill-dam", 2),
                                         ("rockfill-dam", 3)])
def test_a_dam_on_several_ranks_equals_one_and_restarts_bit_for_bit(one_rank, name, ranks):
    """The dam on 2 and 3 ranks against one: every dataset within 1e-10
    (assert_same_result: interfaces included), the static start's row the
    same bits (assert_static_start_same); stopped half way and continued
    with --restart on as many ranks: the whole run's file bit for bit
    (the energy sums each rank keeps included)."""
    folder, one = one_rank(name)
    end = DAMS[name]
    whole, half = folder / "whole.toml", shortened(folder, name, end / 2, f"half{ranks}")
    many, part = folder / f"many{ranks}.h5", folder / f"part{ranks}.h5"
    mpirun_ok("run", whole, "-o", many, n=ranks)
    mpirun_ok("run", half, "-o", part, n=ranks)
    shortened(folder, name, end, f"half{ranks}")    # the stopped run's case, to the end
    mpirun_ok("run", half, "--restart", part, n=ranks)
    assert_same_result(one, many, ranks=ranks)
    a = datasets(one)
    interfaces = Case.from_toml(whole).plane.interfaces
    for spec in interfaces:               # each moved: its datasets carry a run
        assert np.abs(a[f"interface/{spec.name}/slip"]).max() > 1e-5, spec.name
    assert_static_start_same(a, datasets(many), interfaces)
    assert unequal(datasets(many), datasets(part), skip=WALL) == {}


def assert_static_start_same(a, b, interfaces):
    """Row 0 (t = 0) of two runs' datasets is the static start ([gravity]
    initial = "static": the dam settled under its weight, its interfaces
    closed): its u, stresses, gauges and the interfaces' gaps and
    stretches the same bits (rank 0 solves it in the mesh's numbering on
    any number of ranks), the strain energy (summed over the ranks) to
    rounding."""
    assert a["time"][0] == 0.0 and np.abs(a["field/u"][0]).max() > 1e-4
    gaps = [f"interface/{spec.name}/gap" for spec in interfaces]
    keys = ["field/u", "field/stress", *gaps, *(f"interface/{spec.name}/stretch"
                                                for spec in interfaces),
            *(k for k in a if k.startswith("gauge/") and k.endswith("/u"))]
    for key in keys:
        assert np.array_equal(a[key][0], b[key][0]), key
    assert all((a[k][0] < 0).any() for k in gaps)      # pressed together by the dam
    strain = a["energy/strain"][0]
    assert strain > 0 and abs(b["energy/strain"][0] - strain) <= 1e-12 * strain


DRIVE_X = [[0.0, 0.0], [0.1, 1.0], [0.25, 1.0]]       # 10 m/s^2 > mu g: it slides
DRIVE_Y = [[0.0, 0.0], [0.05, 0.0], [0.1, -1.5], [0.15, 0.0], [0.25, 0.0]]   # 30 > g: it lifts


def block(tmp_path):
    """A block on a base across a horizontal joint (6 x 3 cells each side:
    once split, two meshes of 18 cells each that no face joins, which the
    partition of two ranks puts one on each), the base driven along x
    and, down faster than g, along y: the block slides and lifts off."""
    case = Case.from_dict({
        "time": {"dt": 1e-3, "end": 0.25}, "output": {"every": 5},
        "mesh": {"rectangle": {"x": [0.0, 2.0], "y": [-1.0, 1.0], "nx": 6, "ny": 6,
                               "joints": {"joint": 0.0}}},
        "region": [{"name": "domain", "E": 1e9, "nu": 0.25, "rho": 2000.0}],
        "boundary": [{"name": "bottom", "type": "velocity",
                      "value": {"x": DRIVE_X, "y": DRIVE_Y}}],
        "interface": [{"name": "joint", "friction": 0.3}],
        "gravity": {"g": -9.81, "initial": "static"},
        "gauge": [{"name": "top", "x": [1.0, 1.0]}]})
    path = tmp_path / "block.toml"
    path.write_text(case.to_toml())
    return path


# the run, with the owners of each pair's two nodes noted from the model
# the run builds (each rank owns the global vertices [first, next rank's first))
OWNERS = """
import json, sys
import numpy as np
from mpi4py import MPI
import vstpetsc
from vstpetsc.plane.model import PlaneModel

seen, built = [], PlaneModel.__init__

def noting(model, case, comm):
    built(model, case, comm)
    firsts = comm.tompi4py().allgather(model.first)
    seen.append(np.searchsorted(firsts, model.pairs.global_nodes, side="right") - 1)

PlaneModel.__init__ = noting
vstpetsc.run(vstpetsc.Case.from_toml(sys.argv[1]), output=sys.argv[2], quiet=True)
if MPI.COMM_WORLD.rank == 0:
    with open(sys.argv[3], "w") as f:
        json.dump([owners.tolist() for owners in seen], f)
"""


def test_an_interface_whose_pairs_straddle_two_ranks(tmp_path):
    """Every pair of the block's joint has its lower node on one rank and
    its upper node on the other (read from the run's own model): the run
    on two ranks equals the run on one within 1e-10, interface datasets
    included, and the block slid and lifted off its joint."""
    case, one, two = block(tmp_path), tmp_path / "one.h5", tmp_path / "two.h5"
    script, owners = tmp_path / "owners.py", tmp_path / "owners.json"
    script.write_text(OWNERS)
    p = cli("run", case, "-o", one, "--quiet")
    assert p.returncode == 0, p.stderr
    p = mpirun(script, case, two, owners, program=sys.executable)
    assert p.returncode == 0, p.stderr
    built = json.loads(owners.read_text())
    assert len(built) == 1                             # the run's one model
    pairs, joint = np.array(built[0]), Result(one).interface("joint")
    assert pairs.shape == joint.nodes.shape == (7, 2)  # the joint's 6 + 1 nodes
    assert (pairs[:, 0] != pairs[:, 1]).all()          # every pair across the two ranks
    assert_same_result(one, two)
    assert np.abs(joint.slip[:]).max() > 1e-3 and joint.gap[:].max() > 1e-2


SCALES = ["--set", "boundary.base.incident.x.scale=0.5,1,1.5,2"]


def sweep_rows(folder):
    return read_summary(str(folder / "summary.csv"))


@pytest.fixture(scope="module")
def dam_sweep(tmp_path_factory):
    """gravity-dam to 0.6 s swept over its horizontal record's scale on
    one rank: (the case, the folder)."""
    tmp_path = tmp_path_factory.mktemp("sweep")
    case = shortened(tmp_path, "gravity-dam", 0.6, "dam")
    p = cli("sweep", case, *SCALES, "-o", tmp_path / "one", "--quiet")
    assert p.returncode == 0, p.stderr
    return case, tmp_path


@pytest.mark.parametrize("ranks", [2, 4])
def test_a_2d_sweep_dealt_to_ranks_equals_one_rank(dam_sweep, ranks):
    """`mpirun -n 2|4 vstpetsc sweep` of the dam (4 ranks oversubscribed
    on 2 cores): each run on one rank, so each file is the one-rank
    sweep's bit for bit and the summary's rows the same, wall times aside;
    the summary's interface and tension columns are the files' own."""
    case, tmp_path = dam_sweep
    out = tmp_path / f"n{ranks}"
    p = mpirun_ok("sweep", case, *SCALES, "-o", out, n=ranks)
    assert p.stdout.count("sweep:") == 1
    (header, one), (header2, many) = sweep_rows(tmp_path / "one"), sweep_rows(out)
    assert header == header2 and many["status"] == ["completed"] * 4
    assert {"slip_contact", "slip_max_contact", "opening_max_contact", "tension_max"} <= set(header)
    for key in header:
        if key != "wall_time":
            assert one[key] == many[key], key
    for i, name in enumerate(many["file"]):
        a, b = datasets(tmp_path / "one" / name), datasets(out / name)
        assert unequal(a, b, skip=WALL) == {}, name
        assert Result(out / name).attrs["mpi_size"] == 1
        slip = a["interface/contact/slip"]
        assert many["slip_max_contact"][i] == np.abs(slip).max()
        assert many["slip_contact"][i] == slip[-1][np.abs(slip[-1]).argmax()]
        assert many["opening_max_contact"][i] == a["interface/contact/gap"].max()
        assert many["tension_max"][i] == a["field/principal_max"].max()
    assert len(set(one["slip_max_contact"])) == 4       # the scale changed every run


def test_a_2d_sweep_with_two_ranks_a_run(dam_sweep):
    """`mpirun -n 4 vstpetsc sweep --ranks-per-run 2`: two runs at once,
    each on two ranks (mpi_size 2 in its file): every file within 1e-10
    of the one-rank sweep's (assert_same_result), every summary number
    within 1e-10 of its largest over the sweep, the numerical energy (a
    small difference of large energies) of its run's largest energy."""
    case, tmp_path = dam_sweep
    out = tmp_path / "pairs"
    mpirun_ok("sweep", case, *SCALES, "-o", out, "--ranks-per-run", "2", n=4)
    (header, one), (header2, two) = sweep_rows(tmp_path / "one"), sweep_rows(out)
    assert header == header2 and two["status"] == ["completed"] * 4
    assert one["file"] == two["file"]
    energy = np.array([energy_scale(datasets(tmp_path / "one" / f)) for f in one["file"]])
    for key in header:
        if key not in ("wall_time", "file", "status", "message"):
            a, b = np.array(one[key]), np.array(two[key])
            scale = energy if key == "numerical_energy" else np.abs(a).max()
            assert (np.abs(a - b) <= 1e-10 * scale).all(), key
    for name in two["file"]:
        assert_same_result(tmp_path / "one" / name, out / name, ranks=2)


def test_coupling_columns_dealt_to_the_ranks_are_the_collective_ones(tmp_path):
    """With ``-vst_plane_whole_lu 1`` every rank factors the whole slab
    matrix (vstpetsc.plane.solver.redundant), and the interfaces' coupling
    columns, formed as pairs start to slide, are dealt to the ranks, each
    solving its share alone: rockfill-dam (Vp dt / h up to 6) on two ranks
    equals the run with PETSc's redundant PC (every column a collective
    solve with the same factors) bit for bit, its three interfaces slid."""
    path = shortened(tmp_path, "rockfill-dam", DAMS["rockfill-dam"], "dam")
    mpirun_ok("run", path, "-o", tmp_path / "dealt.h5", "-vst_plane_whole_lu", "1", n=2)
    mpirun_ok("run", path, "-o", tmp_path / "collective.h5", "-vst_plane_pc_type", "redundant",
              n=2)
    a, b = datasets(tmp_path / "dealt.h5"), datasets(tmp_path / "collective.h5")
    assert not unequal(a, b, skip=WALL)
    for name in ("contact", "core_upstream", "core_downstream"):
        assert np.abs(a[f"interface/{name}/slip"]).max() > 1e-5, name


FAILING = """
import sys
import vstpetsc.plane.solver.pair_newton as pair_newton
from vstpetsc.cli import main

pair_newton.MAX_IT = 1          # the block's sliding slabs need more
sys.exit(main(["run", sys.argv[1], "-o", sys.argv[2], "--quiet"]))
"""


@pytest.mark.parametrize("ranks", [3])
def test_a_failed_interface_newton_ends_every_rank(tmp_path, ranks):
    """Rank 0 runs the pairs' Newton and tells the other ranks its end:
    when it fails, every rank stops with its message (no rank left
    waiting), and the result file says "failed"."""
    script, out = tmp_path / "failing.py", tmp_path / "r.h5"
    script.write_text(FAILING)
    p = mpirun(block(tmp_path), out, n=ranks, timeout=120, program=f"{sys.executable} {script}")
    assert p.returncode == 3, p.stderr          # (cli.EXIT_SOLVE_FAILED)
    ours = [l for l in p.stderr.splitlines() if l.startswith("vstpetsc: error")]
    assert len(ours) == 1 and "the interfaces' Newton did not converge in 1" in ours[0], p.stderr
    assert "Traceback" not in p.stderr
    assert Result(out).status == "failed"
