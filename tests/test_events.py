"""Contact events (/contact/<k>/events): the times at which a pair closes
(+1) and opens (-1), located inside the slab at the roots of the gap (or
of the cushion's force), written with the blocks, restarted bit for bit."""

import io
import shutil

import numpy as np
import pytest

import vstpetsc
from conftest import STEEL, bar, cli, compliance_delay, make_case, solve, write_case
from test_energy_restart import StopAfter, assert_same_files
# imported before any run of this process starts MPI (its environment
# would reach mpirun's ranks and stop their MPI_Init)
from test_parallel import mpirun
from vstpetsc import bundled
from vstpetsc.runner import driver
from vstpetsc.runner.driver import Interrupted
from vstpetsc.line.model import build_model

L, V0, G0, DT = 1.0, 1.0, 1.0e-3, 2.0e-6
C = np.sqrt(STEEL["E"] / STEEL["rho"])
Z = STEEL["rho"] * C                     # the bars' impedance (A = 1)
RELEASE = G0 / V0 + 2.0 * L / C          # a rigid wall lets the bar go after 2 L / c


def bar_wall(formulation, gap=G0, end=2.0e-3, every=1, **pair):
    """A steel bar, 1 m, 100 elements, thrown at v0 = 1 at a wall ``gap`` away."""
    return make_case(DT, end, [bar("bar", [0.0, L], 100, v0=V0)],
                     [{"pair": ["bar", "wall"], "wall": L + gap, "formulation": formulation,
                       **pair}], every=every)


def assert_alternating(events, ends_open=True):
    """In time order, closes and opens alternating from a close: each close
    followed by an open (the last one too when ``ends_open``: the run ends
    with the pair open)."""
    assert events.ndim == 2 and events.shape[1] == 2 and events.shape[0] >= 2
    assert np.all(np.diff(events[:, 0]) >= 0.0)
    m = events.shape[0]
    assert np.array_equal(events[:, 1], np.tile([1.0, -1.0], m)[:m])
    assert (m % 2 == 0) == ends_open


def contacts(events, apart):
    """[(first close, last open)] of the runs of events whose open-to-close
    gaps are shorter than ``apart`` (the seed's closes and opens inside one
    impact, see docs/contact-formulations.md)."""
    t = events[:, 0]
    starts = [0] + [i for i in range(2, t.size, 2) if t[i] - t[i - 1] > apart]
    ends = [i - 1 for i in starts[1:]] + [t.size - 1]
    return [(t[a], t[b]) for a, b in zip(starts, ends)]


FORMULATIONS = {"power": {}, "seed": {},
                "cushion": {"stiffness": 50.0 * STEEL["E"] / 0.01, "restitution": 1.0}}


@pytest.mark.parametrize("formulation", FORMULATIONS)
def test_bar_wall_closes_at_the_exact_time_and_opens_at_the_release(tmp_path, formulation):
    """The approach is rigid: the close is g0 / v0 to rounding; the last
    open (the bar leaves) lies within 3 dt of g0 / v0 + 2 L / c + 2 Z / k
    (the penalty spring's compliance delays the release by 2 Z / k)."""
    r = solve(tmp_path, bar_wall(formulation, **FORMULATIONS[formulation]))
    events = r.contact(0).events
    assert_alternating(events)
    t_close = events[0, 0]
    assert abs(t_close - G0 / V0) <= 1e-12 * t_close
    assert abs(events[-1, 0] - RELEASE - compliance_delay(r, Z)) <= 3.0 * DT
    # no open and close again at a slab end while the pair stays closed
    at_end = np.abs(events[:, 0] / DT - np.round(events[:, 0] / DT)) < 1e-6
    assert not np.any(at_end[1:-1:2] & at_end[2::2])


def test_close_inside_a_slab_is_not_rounded_to_its_ends(tmp_path):
    """A gap closing a quarter into a slab: the close lies inside that
    slab, nearer the exact time than either slab end."""
    gap = G0 + 0.25 * DT * V0
    exact = gap / V0
    events = solve(tmp_path, bar_wall("power", gap=gap)).contact(0).events
    assert_alternating(events)
    ends = np.floor(exact / DT) * DT, np.ceil(exact / DT) * DT
    assert ends[0] < events[0, 0] < ends[1]
    assert abs(events[0, 0] - exact) < min(abs(e - exact) for e in ends)


@pytest.mark.parametrize("options", [["-vst_native", "0"], ["-vst_newton", "full"],
                                     ["-vst_fd_jacobian"]])
def test_every_newton_gives_the_compiled_events(tmp_path, options):
    """The compiled Newton (the default) against the Python one, the full
    Newton and SNES: the same events (the compiled path recomputes the
    roots from its converged rates), on the first four impacts of
    periodic-impacts (seed)."""
    case = vstpetsc.Case.from_toml(bundled.path("periodic-impacts")).with_value("time.end",
                                                                                2.0e-3)
    native = solve(tmp_path, case, "native").contact(0).events
    other = solve(tmp_path, case, "other", options=options).contact(0).events
    assert native.shape[0] > 2 and native.shape == other.shape
    np.testing.assert_allclose(native, other, rtol=0, atol=1e-8 * case.dt)   # Newton tolerance


def penalty_law(formulation="power"):
    """The bar-wall pair as built for a run (a PenaltyContact)."""
    model = build_model(bar_wall(formulation))
    law, = [law for law in model.nonlinear if law.group == "contact/0"]
    return law


@pytest.mark.parametrize("formulation", ["power", "seed"])
def test_close_and_open_within_one_slab_are_two_events(formulation):
    """A gap dipping below zero in the middle of a slab only: a close and
    an open inside it, at the roots of the gap; the next free slab adds
    nothing."""
    law = penalty_law(formulation)
    t0, dt = 0.5, law.dt
    law.gn, d1, d2 = 1.0e-5, 1.0e-4 / dt, -1.0e-4 / dt   # g < 0 on (0.113, 0.887)
    assert law.force(d1, d2) is not None
    law.finish_slab(t0, dt)
    events = law.take_events()
    assert events[:, 1].tolist() == [1.0, -1.0]
    roots = 0.5 - 0.5 * np.sqrt(0.6), 0.5 + 0.5 * np.sqrt(0.6)
    np.testing.assert_allclose(events[:, 0], [t0 + r * dt for r in roots], rtol=1e-15, atol=0)
    law.last = None
    law.finish_slab(t0 + dt, dt)
    assert law.take_events().shape == (0, 2)


def test_open_at_the_start_of_a_free_slab_after_a_closed_end():
    """A pair closed at the end of a slab and free throughout the next (a
    gap rounded back to zero) opens at that slab's start."""
    law = penalty_law()
    law.gn, t0, dt = -1.0e-9, 0.0, law.dt
    law.force(0.0, 0.0)
    law.finish_slab(t0, dt)
    law.last = None
    law.finish_slab(t0 + dt, dt)
    assert law.take_events().tolist() == [[0.0, 1.0], [t0 + dt, -1.0]]


def test_two_equal_bars_one_impact(tmp_path):
    """two-bars: the striker meets the target at g0 / v0 to rounding and
    leaves it within 3 dt of 2 L / c + 2 Z_s / k later (the two bars'
    impedances in series, Z_s = Z / 2, load the spring); one impact."""
    case = vstpetsc.Case.from_toml(bundled.path("two-bars"))
    r = solve(tmp_path, case, "two-bars")
    events = r.contact(0).events
    assert_alternating(events)
    assert abs(events[0, 0] - G0 / V0) <= 1e-12 * G0 / V0
    assert abs(events[-1, 0] - RELEASE - compliance_delay(r, Z / 2)) <= 3.0 * case.dt
    assert len(contacts(events, 10 * case.dt)) == 1


def test_periodic_impacts_every_three_transit_times(tmp_path):
    """periodic-impacts: an impact of L / c every 3 L / c, the first at
    L / c; nine before time.end, the last still closed at the end; each
    impact's contact and the cycle longer by at most the penalty's delay
    2 Z / k."""
    case = vstpetsc.Case.from_toml(bundled.path("periodic-impacts"))
    r = solve(tmp_path, case, "periodic")
    events = r.contact(0).events
    assert_alternating(events, ends_open=False)
    impacts = contacts(events, 10 * case.dt)
    assert len(impacts) == 9
    delay = compliance_delay(r, Z)
    starts = np.array([a for a, _ in impacts]) - L / C
    late = starts - 3.0 * L / C * np.arange(9)
    assert np.all(late >= -3 * case.dt) and np.all(late <= delay * np.arange(9) + 3 * case.dt)
    longer = np.array([b - a for a, b in impacts[:-1]]) - L / C
    assert np.all(longer >= -3 * case.dt) and np.all(longer <= delay + 3 * case.dt)


CONCRETE = dict(E=3.0e10, rho=2400.0)


@pytest.mark.parametrize("formulation", ["seed", "power"])
def test_a_block_resting_on_a_column_records_one_close(tmp_path, formulation):
    """A block resting on a column under gravity from the static start,
    400 slabs: the pair is closed at every slab end, so the events hold the
    close at t = 0 and nothing else.  The seed's fixed point moves the
    contact node inside each slab (tests/test_static_start.py): its gap
    opens and closes again within every slab, which made 801 events (an
    open and a close per slab); an opening that closes within its slab
    changes nothing across a slab end and is not an event."""
    dt = 10.0 / 50 / np.sqrt(CONCRETE["E"] / CONCRETE["rho"])
    case = make_case(dt, 400 * dt, [bar("column", [0.0, 10.0], 50, **CONCRETE),
                                    bar("block", [10.0, 12.0], 10, **CONCRETE)],
                     contacts=[{"pair": ["column", "block"], "formulation": formulation}],
                     bcs=[{"body": "column", "end": "left", "type": "fixed"}],
                     gravity={"g": -9.81, "initial": "static"})
    pair = solve(tmp_path, case).contact(0)
    assert np.all(pair.gap[:] < 0.0) and np.all(pair.force[1:] > 0.0)
    assert pair.events.tolist() == [[0.0, 1.0]]


def test_seed_impact_is_one_contact(tmp_path):
    """bar-wall with the seed formulation: one close and one open (the gap
    opened and closed again inside nearly every slab of the impact: 388
    events before), at the times the inner events had at either end."""
    r = solve(tmp_path, bar_wall("seed"))
    events = r.contact(0).events
    assert events[:, 1].tolist() == [1.0, -1.0]
    assert abs(events[0, 0] - G0 / V0) <= 1e-12 * G0 / V0
    assert abs(events[1, 0] - RELEASE - compliance_delay(r, Z)) <= 3.0 * DT


def test_an_opening_within_a_slab_of_a_closed_pair_is_no_event():
    """A pair closed at both ends of a slab whose gap opens inside it (the
    pieces where it acts (0, p) and (q, 1)): no event; a close inside a
    slab of a pair open at both ends stays two events (a touch that passes
    an impulse: tests above)."""
    law = penalty_law()
    law.closed = True
    law.track(0.5, law.dt, [(0.0, 0.3), (0.7, 1.0)])
    assert law.take_events().shape == (0, 2) and law.closed
    law.track(0.5 + law.dt, law.dt, [(0.2, 0.4), (0.6, 0.8)])   # closed -> open at 0.8
    assert law.take_events().tolist() == [[0.5 + 1.8 * law.dt, -1.0]]
    law.track(0.5 + 2 * law.dt, law.dt, [(0.1, 0.2), (0.3, 0.4)])   # open -> open
    assert law.take_events()[:, 1].tolist() == [1.0, -1.0]


def stopped_in_contact(tmp_path, monkeypatch):
    """(case, its uninterrupted Result, the file of the same run stopped
    at slab 620, inside the contact)."""
    case = bar_wall("seed", every=7)
    full = solve(tmp_path, case, "full")
    out = tmp_path / "cut.h5"
    with monkeypatch.context() as m:
        m.setattr(driver, "StopSignals", lambda: StopAfter(620))
        with pytest.raises(Interrupted):
            vstpetsc.run(case, output=str(out), quiet=True, out=io.StringIO())
    return case, full, out


def test_restart_after_a_stop_equals_one_run(tmp_path, monkeypatch):
    """Stopped between kept slabs while the pair is closed, continued with
    --restart: the events equal the uninterrupted run's bit for bit."""
    case, full, out = stopped_in_contact(tmp_path, monkeypatch)
    cut = vstpetsc.Result(str(out)).contact(0).events
    assert 0 < cut.shape[0] < full.contact(0).events.shape[0] and cut[-1, 1] == 1.0
    vstpetsc.run(case, output=str(out), quiet=True, restart=True, out=io.StringIO())
    assert_same_files(out, full.path)


def test_file_of_a_killed_run_keeps_the_events_of_its_blocks(tmp_path, monkeypatch):
    """The events in a file end where its rows end: those of a run cut at
    a block are the first ones of the whole run (a killed run's file)."""
    case = bar_wall("power")
    full = solve(tmp_path, case, "full").contact(0).events
    part = solve(tmp_path, case.with_value("time.end", 1.2e-3), "part").contact(0).events
    assert np.array_equal(part, full[:part.shape[0]])
    assert part[-1, 1] == 1.0 and np.all(full[part.shape[0]:, 0] > 1.2e-3)


@pytest.mark.skipif(shutil.which("mpirun") is None, reason="no mpirun")
def test_two_ranks_equal_one(tmp_path):
    """bar-wall (seed: many events) on two ranks: the events of one rank."""
    case = write_case(tmp_path, bar_wall("seed"), "bar-wall")
    one = solve(tmp_path, bar_wall("seed"), "one").contact(0).events
    p = mpirun("run", case, "-o", tmp_path / "two.h5", "--quiet")
    assert p.returncode == 0, p.stderr
    two = vstpetsc.Result(str(tmp_path / "two.h5")).contact(0).events
    assert one.shape == two.shape
    np.testing.assert_allclose(two, one, rtol=0, atol=0)


def test_info_prints_the_contact_durations(tmp_path):
    """`vstpetsc info`: per pair the number of contacts and each duration."""
    r = solve(tmp_path, bar_wall("power"))
    events = r.contact(0).events
    closes, opens = events[events[:, 1] > 0, 0], events[events[:, 1] < 0, 0]
    p = cli("info", r.path)
    assert p.returncode == 0, p.stderr
    line, = [x for x in p.stdout.splitlines() if x.strip().startswith("contact[0]")]
    n = closes.size
    assert line.strip().startswith(f"contact[0] bar | wall: {n} contact{'s' * (n > 1)}, ")
    assert f"{opens[0] - closes[0]:.6g} s (close {closes[0]:.6g}, open {opens[0]:.6g})" in line


def info_durations(path):
    """(total duration of the first line, total of the contacts' line,
    [each contact's duration]) that `vstpetsc info` prints for pair 0."""
    import re
    p = cli("info", path)
    assert p.returncode == 0, p.stderr
    first = float(re.search(r"total duration (\S+),", p.stdout).group(1))
    line, = [x for x in p.stdout.splitlines() if x.strip().startswith("contact[0]")]
    total = re.search(r"contacts?, (?:total )?(\S+) s", line)
    each = [float(x) for x in re.findall(r"(\S+) s \(close", line)]
    return first, float(total.group(1)), each


@pytest.mark.parametrize("name, end", [("dam-interface", None), ("bar-wall", 1.2e-3)])
def test_info_counts_a_contact_still_closed_at_the_end(tmp_path, name, end):
    """The bundled dam-interface (its third contact still closed when the
    run ends: 1.711 s on one line, 1.06538 s on the other before) and
    bar-wall cut inside its one contact: `info` prints one contact
    duration on both lines, the sum of the contacts' spans from close to
    open, or to the end of the run for the contact still closed."""
    if name == "dam-interface":
        case = vstpetsc.Case.from_toml(bundled.path(name))
    else:
        case = bar_wall("power", end=end)
    r = solve(tmp_path, case)
    events = r.contact(0).events
    assert events[-1, 1] == 1.0                            # still closed at the end
    t_end = r.time[-1]
    closes, opens = events[events[:, 1] > 0, 0], np.append(events[events[:, 1] < 0, 0], t_end)
    first, total, each = info_durations(r.path)
    assert first == total
    assert total == float(f"{np.sum(opens - closes):.6g}")
    assert each == [float(f"{d:.6g}") for d in opens - closes]
    assert r.summary()["pairs"][0]["duration"] == pytest.approx(np.sum(opens - closes),
                                                                 rel=1e-14)


def test_info_keeps_many_contacts_short(tmp_path):
    """Many contacts (periodic-impacts: nine): the total and the first
    three only."""
    r = solve(tmp_path, vstpetsc.Case.from_toml(bundled.path("periodic-impacts")))
    events = r.contact(0).events
    n = int((events[:, 1] > 0).sum())
    assert n > 3
    line, = [x for x in cli("info", r.path).stdout.splitlines() if "contact[0]" in x]
    assert f": {n} contacts, total " in line
    assert line.count("(close ") == 3 and line.endswith(", ...")


def test_export_csv_writes_the_events(tmp_path):
    r = solve(tmp_path, bar_wall("power"))
    p = cli("export", r.path, "--csv", tmp_path / "csv")
    assert p.returncode == 0, p.stderr
    data = np.loadtxt(tmp_path / "csv" / "contact-0-events.csv", delimiter=",", skiprows=1,
                      ndmin=2)
    header = (tmp_path / "csv" / "contact-0-events.csv").read_text().splitlines()[0]
    assert header == "time,change"
    assert np.array_equal(data, r.contact(0).events)


def test_restart_cuts_events_written_after_the_last_row(tmp_path, monkeypatch):
    """A block killed between its events and its rows leaves events of
    slabs after the file's last row: the restart cuts them (each row counts
    the events up to its slab, ``event_count``) and ends bit for bit."""
    import h5py

    case, full, out = stopped_in_contact(tmp_path, monkeypatch)
    later = full.contact(0).events[:]
    with h5py.File(out, "r+") as f:                 # as a kill mid-block leaves it
        events = f["contact/0/events"]
        n = events.shape[0]
        assert f["contact/0/event_count"][-1] == n
        events.resize((later.shape[0], 2))
        events[n:] = later[n:]
    vstpetsc.run(case, output=str(out), quiet=True, restart=True, out=io.StringIO())
    assert_same_files(out, full.path)
