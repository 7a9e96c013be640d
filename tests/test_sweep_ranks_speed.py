"""A sweep on several ranks (issue 29): runs dealt to the rank that asks
(each exactly once, the one-rank results), and a rank done with its runs
waits for the others without spinning on a core.  No wall-time speed-ups
here (bench/sweep_speed.py measures them)."""

import json
import os
import shutil
import sys

import numpy as np
import pytest

from conftest import ROOT, cli, write_case
from test_parallel import mpirun
from test_sweep import wall_case
from vstpetsc import Result
from vstpetsc.runner.sweep import read_summary

needs_mpirun = pytest.mark.skipif(shutil.which("mpirun") is None, reason="no mpirun")

# The sweep started by every rank of `mpirun`, its run_one wrapped: each
# rank logs the runs it ran and the CPU and wall seconds spent in them and
# in the whole sweep; HOLD (below) may keep rank 0 in its first run.
SCRIPT = """
import json, os, sys, time, vstpetsc
from vstpetsc import petsc
sw = sys.modules['vstpetsc.runner.sweep']    # vstpetsc.sweep is the function
real = sw.run_one
ran, inside = [], [0.0, 0.0]

def cpu():
    t = os.times()
    return t.user + t.system

def logged(case, values, path, options, comm):
    if petsc.rank() == 0 and not ran:
        hold(sys.argv[2])
    ran.append(os.path.basename(path))
    c, w = cpu(), time.perf_counter()
    row = real(case, values, path, options, comm)
    inside[0] += cpu() - c
    inside[1] += time.perf_counter() - w
    # whole or not at all: the other rank may read it at any moment
    name = f'{sys.argv[2]}.ran.{petsc.rank()}'
    with open(name + '.part', 'w') as f:
        f.write(json.dumps(ran))
    os.replace(name + '.part', name)
    return row

HOLD

sw.run_one = logged
case = vstpetsc.Case.from_toml(sys.argv[1])
c, w = cpu(), time.perf_counter()
vstpetsc.sweep(case, {'body.bar.v0': json.loads(sys.argv[3])}, sys.argv[2])
with open(f'{sys.argv[2]}.times.{petsc.rank()}', 'w') as f:
    f.write(json.dumps({'cpu': cpu() - c, 'wall': time.perf_counter() - w,
                        'run_cpu': inside[0], 'run_wall': inside[1]}))
"""


def two_rank_sweep(tmp_path, values, hold):
    """`mpirun -n 2` of SCRIPT with ``hold`` (a def of hold(out)) over
    ``values`` of v0 into tmp_path/two: {rank: runs it ran}, {rank: its
    times}."""
    script = tmp_path / "script.py"
    script.write_text(SCRIPT.replace("HOLD", hold))
    out = tmp_path / "two"
    p = mpirun(script, write_case(tmp_path, wall_case()), out, json.dumps(values),
               program=sys.executable, timeout=120)
    assert p.returncode == 0, p.stderr
    ran = {r: json.loads((tmp_path / f"two.ran.{r}").read_text()) for r in (0, 1)}
    times = {r: json.loads((tmp_path / f"two.times.{r}").read_text()) for r in (0, 1)}
    return ran, times


@needs_mpirun
def test_runs_go_to_the_rank_that_asks_each_exactly_once(tmp_path):
    """Rank 0 held in its first run until rank 1 has run every other run
    (at most 20 s): rank 1 takes runs 1 to 5 as it asks (dealt in turn, it
    would have had 1, 3, 5 only); every run once; the summary is the
    one-rank sweep's, wall times aside, and every run on one rank."""
    values = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0]
    hold = ("def hold(out):\n"
            "    end = time.monotonic() + 20\n"
            "    while time.monotonic() < end and not (os.path.exists(out + '.ran.1') and\n"
            "            len(json.load(open(out + '.ran.1'))) >= 5):\n"
            "        time.sleep(0.05)\n")
    ran, _ = two_rank_sweep(tmp_path, values, hold)
    assert ran == {0: ["run-0.h5"], 1: [f"run-{i}.h5" for i in range(1, 6)]}
    sets = ["--set", "body.bar.v0=" + ",".join(map(str, values))]
    assert cli("sweep", tmp_path / "case.toml", *sets, "-o", tmp_path / "one",
               "--quiet").returncode == 0
    (header, one), (header2, two) = (read_summary(str(tmp_path / d / "summary.csv"))
                                     for d in ("one", "two"))
    assert header == header2 and two["status"] == ["completed"] * 6
    for key in header:
        if key != "wall_time":
            assert one[key] == two[key], key
    assert all(Result(tmp_path / "two" / f).attrs["mpi_size"] == 1 for f in two["file"])


@needs_mpirun
def test_a_rank_done_with_its_runs_waits_without_spinning(tmp_path):
    """Rank 0 sleeps 2 s in its run (no CPU): rank 1, with the other run,
    waits that long for it; the CPU time it spends outside its own run is
    a small part of that wait (an MPI wait of Open MPI spins: about the
    whole wait)."""
    hold = "def hold(out):\n    time.sleep(2.0)\n"
    ran, times = two_rank_sweep(tmp_path, [1.0, 2.0], hold)
    assert ran == {0: ["run-0.h5"], 1: ["run-1.h5"]}
    waiting = times[1]["wall"] - times[1]["run_wall"]
    assert waiting > 1.5, times
    assert times[1]["cpu"] - times[1]["run_cpu"] < 0.1 * waiting, times


@needs_mpirun
def test_groups_of_two_ranks_take_runs_as_they_ask(tmp_path):
    """`mpirun -n 4 --ranks-per-run 2`: two groups share five runs, each
    run once on two ranks (mpi_size 2), the summary the one-rank one to the
    two-rank bound."""
    case = write_case(tmp_path, wall_case())
    sets = ["--set", "body.bar.v0=0.5,1,1.5,2,2.5"]
    assert cli("sweep", case, *sets, "-o", tmp_path / "one", "--quiet").returncode == 0
    p = mpirun("sweep", case, *sets, "-o", tmp_path / "four", "--quiet", "--ranks-per-run", "2",
               n=4, timeout=180)
    assert p.returncode == 0 and p.stdout.count("sweep:") == 1, p.stderr
    (header, one), (_, four) = (read_summary(str(tmp_path / d / "summary.csv"))
                                for d in ("one", "four"))
    assert four["status"] == ["completed"] * 5
    assert four["file"] == [f"run-{i}.h5" for i in range(5)]
    for key in header:
        if key not in ("wall_time", "file", "status", "message"):
            assert np.allclose(one[key], four[key], rtol=1e-10, atol=0), key
    assert all(Result(tmp_path / "four" / f).attrs["mpi_size"] == 2 for f in four["file"])


def test_bench_table_rows_match_the_head():
    """bench/sweep_speed.py's README table: a row has the head's columns."""
    sys.path.insert(0, os.path.join(ROOT, "bench"))
    import sweep_speed
    row = dict.fromkeys(("one_min_s", "one_median_s", "two_min_s", "two_median_s", "speedup",
                         "speedup_median", "cpu_one_s", "cpu_two_s", "cores_one", "cores_two",
                         "run_sum_one_s", "run_sum_two_s"), 1.0)
    text = sweep_speed.section([{**row, "case": "c"}], 3, 0.5)
    lines = text.splitlines()
    assert lines[0] == sweep_speed.SECTION
    assert [line.count("|") for line in lines[-3:]] == [8, 8, 8]


@pytest.mark.parametrize("env, expected", [
    ({}, "singleton"),
    ({"OMPI_COMM_WORLD_SIZE": "2", "OMPI_COMM_WORLD_LOCAL_SIZE": "2"}, "one node"),
    ({"OMPI_COMM_WORLD_SIZE": "4", "OMPI_COMM_WORLD_LOCAL_SIZE": "2"}, "none"),
    ({"OMPI_COMM_WORLD_SIZE": "2", "OMPI_COMM_WORLD_LOCAL_SIZE": "2",
      "OMPI_MCA_pml": "ucx"}, "none"),
])
def test_open_mpi_start_up_settings(env, expected):
    """A singleton and ranks on one node start without probing the network
    (pml ob1, shared memory); ranks on several nodes, or a user who chose,
    keep Open MPI's own."""
    from vstpetsc import petsc

    want = {"singleton": petsc.SINGLETON_MPI, "one node": petsc.ONE_NODE_MPI,
            "none": {}}[expected]
    assert petsc._mpi_defaults(env) == want


@needs_mpirun
def test_ranks_of_one_node_start_with_shared_memory(tmp_path):
    """Each rank writes its settings to a file of its own: two ranks'
    prints on one stdout may interleave within a line ("ob1ob1 self,vader")."""
    code = ("import os, sys; from vstpetsc import petsc; petsc.initialize(); "
            "open(f'{sys.argv[1]}.{petsc.rank()}', 'w').write("
            "f\"{os.environ.get('OMPI_MCA_pml')} {os.environ.get('OMPI_MCA_btl')}\\n\")")
    p = mpirun("-c", code, tmp_path / "settings", program=sys.executable)
    assert p.returncode == 0, p.stderr
    for rank in range(2):
        assert (tmp_path / f"settings.{rank}").read_text() == "ob1 self,vader\n"


def test_a_summary_opens_the_result_file_once(tmp_path, monkeypatch):
    """A sweep reads each run's summary: one open of the file for all its
    reads (some 30 opens before), the same summary, the file closed after."""
    import vstpetsc
    from conftest import solve
    from vstpetsc.results.reader import Result

    result = solve(tmp_path, wall_case(), "one")
    want, time = Result(result.path).summary(), result["time"]
    opens = []
    real = Result._open
    monkeypatch.setattr(Result, "_open", lambda self: opens.append(1) or real(self))
    fresh = Result(result.path)
    opens.clear()
    assert fresh.summary() == want and len(opens) == 1 and fresh._file is None
    with fresh.session():
        with fresh.session():                # nested: the same open file
            assert np.array_equal(fresh["time"], time)
    assert len(opens) == 2 and fresh._file is None
    assert vstpetsc.Result is Result
