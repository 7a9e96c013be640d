"""The energy balance against its rounding bounds (docs/loads.md section 4,
"Rounding"), and restarts of the cases with soil, cushions, gravity,
absorbing or moving ends bit for bit (docs/troubleshooting.md)."""

import shutil
import signal

import h5py
import numpy as np
import pytest

import vstpetsc
from conftest import bar, make_case, solve, write_case
# imported before any run of this process starts MPI (its environment
# would reach mpirun's ranks and stop their MPI_Init: the file run alone
# failed test_restart_on_two_ranks_bit_for_bit)
from test_parallel import mpirun
from vstpetsc import bundled
from vstpetsc.runner import driver
from vstpetsc.line import model as model_mod
from vstpetsc.errors import Interrupted

EPS = np.finfo(float).eps
WORKS = ("external", "damping", "contact", "soil")


def balance_bound(result, model):
    """Per row (every = 1), the rounding bound of the balance itself: the
    state's energies are sums of about 2 n products (n nodes), the summed
    terms sums of k slab works; recursive summation errs by at most
    (count) eps times the sum of the magnitudes."""
    e = {key: np.asarray(result.energy[key]) for key in ("kinetic", "strain", "spring") + WORKS}
    v = np.abs(np.concatenate([np.asarray(result.body(b.name).v) for b in model.case.bodies],
                              axis=1))
    ops = model.ops
    moving = np.array([v_k @ model_mod.band_mult(ops.m_diag, np.abs(ops.m_off), v_k)
                       for v_k in v])                                   # |v|^T |M| |v|
    state = moving + e["strain"] + e["spring"]
    works = sum(np.abs(np.diff(e[key], prepend=e[key][0])) for key in WORKS)
    slabs = np.arange(len(state))
    magnitudes = state + sum(np.abs(e[key]) for key in WORKS) + state[0]
    return EPS * (2 * model.mesh.nnodes * state + slabs * np.cumsum(works) + 8 * magnitudes)


def solve_bound(result, model, dt):
    """Per row (every = 1), the rounding of the slab solves: each solve's
    residual is at most gamma (|A| |x|) per row, and it stays in the running
    right-hand side, so after n slabs at most gamma n sum_k P_k of work,
    P_k = 2 V^T (|M| + dt/2 |C| + dt^2/3 |K + S|) V, V the larger slab-end
    speed of each node; gamma = 10 eps."""
    ops = model.ops
    v = np.abs(np.concatenate([np.asarray(result.body(b.name).v) for b in model.case.bodies],
                              axis=1))
    diag = ops.m_diag + dt / 2 * np.abs(ops.c_diag) + dt * dt / 3 * np.abs(ops.k_diag + ops.s_diag)
    off = (np.abs(ops.m_off) + dt / 2 * np.abs(ops.c_off)
           + dt * dt / 3 * np.abs(ops.k_off + ops.s_off))
    speeds = np.maximum(v[1:], v[:-1])
    P = np.r_[0.0, [2 * s @ model_mod.band_mult(diag, off, s) for s in speeds]]
    slabs = np.arange(len(P))
    return 10 * EPS * slabs * np.cumsum(P)


def assert_within(result, bound):
    """numerical >= -bound, and never below its largest earlier value by
    more than the bound."""
    num = np.asarray(result.energy["numerical"])
    assert np.all(num >= -bound), (num.min(), bound[num.argmin()])
    fall = np.maximum.accumulate(num) - num
    assert np.all(fall <= bound), (fall.max(), bound[fall.argmax()])


def uplift(elements=1000, end=0.06, every=1):
    case = vstpetsc.Case.from_toml(bundled.path("uplift"))
    return (case.with_value("body.column.elements", elements).with_value("time.end", end)
            .with_value("output.every", every))


def absorbing_base(case):
    """The column's base absorbing, the base motion its incident wave."""
    doc = case.to_dict()
    doc["bc"][0] = {"body": "column", "end": "left", "type": "absorbing",
                    "incident": doc["bc"][0]["value"]}
    return vstpetsc.Case.from_dict(doc, folder=case.folder)


@pytest.mark.parametrize("base", [lambda c: c, absorbing_base], ids=["moving base", "absorbing"])
def test_uplift_column_of_1000_elements_keeps_the_balance_to_rounding(tmp_path, base):
    """The column moving nearly as a whole at c dt / h = 18: numerical
    stays >= 0 and non-decreasing to the balance's own rounding (it fell to
    -2e-5 J by t = 0.06 s when b += G z multiplied z_2 by K's plain rows)."""
    case = base(uplift())
    result = solve(tmp_path, case)
    assert_within(result, balance_bound(result, model_mod.build_model(case)))


EXTREME = {
    "E over ten orders": dict(E=[[0.0, 1e2], [0.25, 1e12], [0.5, 1e2], [0.75, 1e12],
                                 [1.0, 1e2]], rho=1000.0),
    "huge rho": dict(E=2e11, rho=1e12),
    "tiny rho": dict(E=2e11, rho=1e-6),
    "rho over twelve orders": dict(E=2e11, rho=[[0.0, 1e-3], [1.0, 1e9]]),
}


@pytest.mark.parametrize("flight", [True, False], ids=["free flight", "pushed"])
@pytest.mark.parametrize("table", EXTREME, ids=list(EXTREME))
def test_extreme_material_tables_stay_within_the_solve_bound(tmp_path, table, flight):
    bcs = () if flight else [{"body": "a", "end": "right", "type": "velocity",
                              "value": [[0.0, 0.0], [0.01, 5.0]]}]
    case = make_case(1e-4, 1e-2, [bar("a", [0.0, 1.0], 200, v0=1.0 if flight else 0.0,
                                      **EXTREME[table])], bcs=bcs)
    result = solve(tmp_path, case)
    model = model_mod.build_model(case)
    assert_within(result, balance_bound(result, model) + solve_bound(result, model, case.dt))


def test_the_bars_stiffness_rows_sum_to_zero_exactly():
    """K of E A / h over ten orders along a body: every row sums to 0, so a
    body moving as a whole feels no force (no springs to the ground of
    rounding), and the element stiffnesses stay within 1e-15 of E A / h."""
    case = make_case(1e-4, 1e-2, [bar("a", [0.0, 1.0], 200, **EXTREME["E over ten orders"]),
                                  bar("b", [1.5, 2.0], 37, E=[[1.5, 3.3e9], [2.0, 7.1e3]])])
    model = model_mod.build_model(case)
    ops, mesh = model.ops, model.mesh
    rows = ops.k_diag.copy()
    rows[:-1] += ops.k_off
    rows[1:] += ops.k_off
    assert np.all(rows == 0.0)
    ke = mesh.E * mesh.A / mesh.h
    within = mesh.elem_body[1:] == mesh.elem_body[:-1]
    stiffness = -ops.k_off[mesh.elem_node[:-1][within]]
    assert np.allclose(stiffness, ke[:-1][within], rtol=1e-15, atol=0)


# ---- restarts bit for bit --------------------------------------------------

SKIP = ("solver/wall_time",)


def assert_same_files(a, b):
    """Every dataset of result file a equals b's bit for bit (wall times
    aside); rows of a at slabs that b does not keep (the slab an
    interruption wrote) are left out."""
    with h5py.File(a, "r", locking=False) as fa, h5py.File(b, "r", locking=False) as fb:
        names = []
        fa.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
        other = []
        fb.visititems(lambda n, o: other.append(n) if isinstance(o, h5py.Dataset) else None)
        assert sorted(names) == sorted(other)
        slabs = fa["solver/slab"][...]
        kept = np.isin(slabs, fb["solver/slab"][...])
        rows = lambda x: x[kept] if x.shape[:1] == slabs.shape and not kept.all() else x
        differ = [n for n in names if n not in SKIP
                  and not np.array_equal(rows(fa[n][...]), fb[n][...], equal_nan=True)]
        assert differ == []
        assert kept.sum() == fb["solver/slab"].shape[0]


class StopAfter:
    """StopSignals that report SIGUSR1 after ``slabs`` slabs (the loop
    reads the flag once a slab): a deterministic interruption."""

    def __init__(self, slabs):
        self.reads = 0
        self.slabs = slabs

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    @property
    def signum(self):
        self.reads += 1
        return signal.SIGUSR1 if self.reads >= self.slabs else 0


def pile(end=0.02):
    return vstpetsc.Case.from_toml(bundled.path("pile")).with_value("time.end", end)


RESTARTED = {"pile": (pile, 237), "uplift": (lambda: uplift(elements=120, end=0.15, every=10),
                                              1313)}


@pytest.mark.parametrize("name", RESTARTED)
def test_interrupted_run_restarts_bit_for_bit(tmp_path, monkeypatch, name):
    """Stopped mid-run (not on a kept slab) and restarted: every dataset,
    the energies included, equals the uninterrupted run's."""
    make, stop_at = RESTARTED[name]
    case = make()
    full = solve(tmp_path, case, "full")
    out = tmp_path / "cut.h5"
    with monkeypatch.context() as m:
        m.setattr(driver, "StopSignals", lambda: StopAfter(stop_at))
        with pytest.raises(Interrupted):
            vstpetsc.run(case, output=str(out), quiet=True)
    assert vstpetsc.Result(str(out)).status == "interrupted"
    vstpetsc.run(case, output=str(out), quiet=True, restart=True)
    assert_same_files(out, full.path)


@pytest.mark.parametrize("name", RESTARTED)
def test_completed_run_extended_bit_for_bit(tmp_path, name):
    """A completed run continued to a later time.end equals one run to it."""
    make, _ = RESTARTED[name]
    case = make()
    full = solve(tmp_path, case, "full")
    out = str(tmp_path / "part.h5")
    half = round(case.nslabs / 2 / case.every) * case.every * case.dt
    vstpetsc.run(case.with_value("time.end", half), output=out, quiet=True)
    vstpetsc.run(case, output=out, quiet=True, restart=True)
    assert_same_files(out, full.path)


@pytest.mark.skipif(shutil.which("mpirun") is None, reason="no mpirun")
def test_restart_on_two_ranks_bit_for_bit(tmp_path):
    """pile on two ranks, completed half-way and continued on two ranks:
    every dataset equals the uninterrupted two-rank run's (each rank's
    share of the external work is kept)."""
    case = pile()
    path = write_case(tmp_path, case, "pile")
    half = write_case(tmp_path, case.with_value("time.end", 0.01), "half")
    full, out = tmp_path / "full.h5", tmp_path / "part.h5"
    for args in ((path, "-o", full), (half, "-o", out), (path, "--restart", out)):
        p = mpirun("run", *args, "--quiet")
        assert p.returncode == 0, p.stderr
    assert_same_files(out, full)


# ---- the last line's energy reference over the whole file -------------------

def pulse_case(end):
    """A free bar from rest pushed by a traction pulse at its left end and
    pulled back: the external work rises, peaks (0.82 at t = 2.33) and
    falls; the run's last line reports the energy change against that
    peak (a run from rest)."""
    pulse = [[0.0, 0.0], [1.0, 1.0], [2.0, -1.0], [3.0, 0.0]]
    return make_case(0.01, end, [bar("bar", [0.0, 1.0], 10, E=1.0, rho=1.0)],
                     bcs=[{"body": "bar", "end": "left", "type": "traction", "value": pulse}])


def largest_total_energy(stdout):
    """The reference of the energy change the run's last line prints."""
    import re
    last = stdout.strip().splitlines()[-1]
    found = re.search(r"of the largest total energy (\S+)\)", last)
    assert found, last
    return found.group(1)


def test_restart_takes_the_peak_energy_over_the_whole_file(tmp_path):
    """Run to t = 2.5 (past the peak of the external work), continue to
    t = 4 with --restart: the last line's largest total energy is the
    uninterrupted run's (0.821266; it was the restarted part's, 0.795688)."""
    from conftest import cli

    full, half = write_case(tmp_path, pulse_case(4.0), "full"), \
        write_case(tmp_path, pulse_case(2.5), "half")
    one = cli("run", full, "-o", tmp_path / "one.h5", "--quiet")
    assert one.returncode == 0, one.stderr
    assert cli("run", half, "-o", tmp_path / "two.h5", "--quiet").returncode == 0
    two = cli("run", full, "--restart", tmp_path / "two.h5", "--quiet")
    assert two.returncode == 0, two.stderr
    r = vstpetsc.Result(str(tmp_path / "one.h5"))
    external = r.energy["external"]
    assert external[r.time > 2.5].max() < 0.99 * external.max()   # the peak: in the first part
    assert largest_total_energy(two.stdout) == largest_total_energy(one.stdout)
