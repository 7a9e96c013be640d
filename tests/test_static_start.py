"""The static start (`[gravity] initial = "static"`, docs/loads.md section 5):
the state that the slab equations which follow keep, with every contact
formulation, on fine meshes, with absorbing ends, soil and loads that
change; and what it refuses, with the reason."""

import numpy as np
import pytest

from conftest import STEEL, bar, cli, make_case, solve, write_case

import vstpetsc

Z_STEEL = np.sqrt(STEEL["E"] * STEEL["rho"])
CONCRETE = dict(E=3.0e10, rho=2400.0)
G = -9.81


def pressed_bar(formulation, elements=100, slabs=200):
    """A steel bar pressed on a wall at its right end by a constant traction P."""
    pair = {"pair": ["bar", "wall"], "wall": 1.0, "formulation": formulation}
    if formulation == "cushion":
        pair["stiffness"] = 50.0 * STEEL["E"] * elements
    dt = 1.0 / (elements * np.sqrt(STEEL["E"] / STEEL["rho"]))
    return make_case(dt, slabs * dt, [bar("bar", [0, 1], elements)], contacts=[pair],
                     bcs=[{"body": "bar", "end": "left", "type": "traction", "value": 1e6}],
                     gravity={"g": 0.0, "initial": "static"})


def drift(series):
    """Largest change of a series (rows: kept times) from its first row."""
    series = np.asarray(series)
    return np.abs(series - series[0]).max()


@pytest.mark.parametrize("formulation", ["seed", "power", "cushion"])
def test_a_pressed_bar_stays_as_it_starts(tmp_path, formulation):
    r = solve(tmp_path, pressed_bar(formulation))
    P, bar_ = 1e6, r.body("bar")
    scale = P / Z_STEEL
    assert drift(bar_.v[:]) <= 1e-9 * scale
    assert drift(bar_.u[:]) <= 1e-9 * np.abs(bar_.u[0]).max()
    assert np.abs(r.contact(0).force[1:] / P - 1.0).max() <= 1e-9
    if formulation != "seed":       # forces tested with T_a: at rest
        assert np.abs(bar_.v[:]).max() <= 1e-9 * scale


def test_the_seed_fixed_point_moves_only_inside_its_slabs(tmp_path):
    """The seed penalty weighs the slab's two time levels 2 : 1, so no state
    at rest carries a contact force; its fixed point moves the contact node
    inside each slab (v^{n+} = w, v^{(n+1)-} = -w) and brings it back."""
    r = solve(tmp_path, pressed_bar("seed"))
    v, u = r.body("bar").v[:], r.body("bar").u[:]
    assert np.abs(v[0, -1]) > 0.1 * 1e6 / Z_STEEL           # it does move
    assert drift(u[:, -1]) <= 1e-9 * abs(u[0, -1])


def column(elements, length=10.0, **extra):
    return bar("column", [0.0, length], elements, **CONCRETE, **extra)


def courant_dt(elements, length=10.0, courant=1.0):
    return courant * length / elements / np.sqrt(CONCRETE["E"] / CONCRETE["rho"])


@pytest.mark.parametrize("formulation, elements", [("seed", 50), ("power", 50),
                                                   ("seed", 1000), ("power", 1000)])
def test_a_block_resting_on_a_column(tmp_path, formulation, elements):
    """Two bodies and a contact under gravity (the uplift example's
    statics, also at 1000 + 200 elements): at rest to 1e-9 m/s (the seed:
    unchanged from slab to slab)."""
    dt = courant_dt(elements)
    case = make_case(dt, 50 * dt, [column(elements), bar("block", [10.0, 12.0], elements // 5)],
                     contacts=[{"pair": ["column", "block"], "formulation": formulation}],
                     bcs=[{"body": "column", "end": "left", "type": "fixed"}],
                     gravity={"g": G, "initial": "static"})
    r = solve(tmp_path, case)
    for name in ("column", "block"):
        assert drift(r.body(name).v[:]) <= 1e-9
        if formulation == "power":
            assert np.abs(r.body(name).v[:]).max() <= 1e-9
    weight = STEEL["rho"] * 2.0 * abs(G)
    assert np.abs(r.contact(0).force[1:] / weight - 1.0).max() <= 1e-9
    numerical = r.energy["numerical"][:]
    if formulation == "power":
        assert np.abs(numerical).max() <= 1e-9 * r.energy["strain"][0]
    else:       # the seed's jumps at every slab start: the same energy each slab
        steps = np.diff(numerical)
        assert steps.min() > 0 and np.ptp(steps) <= 1e-6 * steps.mean()


@pytest.mark.parametrize("end, elements", [("wall", 10_000), ("fixed", 10_000),
                                           ("absorbing", 8_000)])
def test_fine_columns_start_at_rest(tmp_path, end, elements):
    """A column standing on a wall (default seed contact), fixed at its base,
    or on an absorbing base, at 8000-10 000 elements: accepted, and the
    stress stays the static one."""
    dt = courant_dt(elements)
    if end == "wall":
        contacts, bcs = [{"pair": ["wall", "column"], "wall": 0.0}], []
    else:
        contacts, bcs = [], [{"body": "column", "end": "left", "type": end}]
    case = make_case(dt, 20 * dt, [column(elements)], contacts=contacts, bcs=bcs,
                     gravity={"g": G, "initial": "static"})
    r = solve(tmp_path, case)
    stress = r.body("column").stress[:]
    base = CONCRETE["rho"] * abs(G) * 10.0
    assert drift(stress) <= 1e-9 * base
    assert drift(r.body("column").v[:]) <= 1e-9
    mid = elements // 2               # the weight above it (the seed's first element
    above = base * (1.0 - (mid + 0.5) / elements)   # differs: see docs/loads.md)
    assert abs(stress[0, mid] / above + 1.0) <= 1e-7    # condition ~ elements^2


def shaken_column(gravity, traction, incident):
    """A 10 m column on an absorbing base with an incident wave and a top
    traction that both act at t = 0 and stop later."""
    elements = 100
    dt = courant_dt(elements, courant=0.5)
    bcs = [{"body": "column", "end": "left", "type": "absorbing", "incident": incident},
           {"body": "column", "end": "right", "type": "traction", "value": traction}]
    tables = {"gravity": {"g": G, "initial": "static"}} if gravity else {}
    return make_case(dt, 0.02, [column(elements)], bcs=bcs, **tables)


def test_loads_that_change_act_as_after_a_start_from_rest(tmp_path):
    """An incident pulse non-zero at t = 0 and a top traction removed at
    10 ms: the static start is the static state under gravity plus the run
    started from rest without gravity (the system is linear)."""
    incident = [[0.0, 0.1], [2e-3, 0.1], [4e-3, 0.0]]
    traction = [[0.0, -2e5], [0.01, -2e5], [0.0101, 0.0]]
    static = solve(tmp_path, shaken_column(True, traction, incident), "static")
    rest = solve(tmp_path, shaken_column(False, traction, incident), "rest")
    us, vs = static.body("column").u[:], static.body("column").v[:]
    ur, vr = rest.body("column").u[:], rest.body("column").v[:]
    assert np.abs(vs - vr).max() <= 1e-9 * np.abs(vr).max()
    assert np.abs(us - us[0] - ur).max() <= 1e-9 * np.abs(ur).max()
    # the column moves (0.1 m/s while the pulse lasts) and comes back to rest
    assert np.abs(vr).max() > 0.05
    assert np.abs(vs[-1]).max() <= 1e-3 * np.abs(vr).max()


def test_an_absorbing_base_carries_the_weight(tmp_path):
    """Gravity alone on an absorbing base: at rest, the base's frozen
    reaction the column's weight."""
    case = shaken_column(True, 0.0, 0.0)
    r = solve(tmp_path, case)
    assert np.abs(r.body("column").v[:]).max() <= 1e-9
    base = CONCRETE["rho"] * abs(G) * 10.0
    assert abs(r.body("column").stress[-1, 0] / base + 1.0) <= 0.5 / 100 + 1e-9


def pile(capacity, elements=50):
    """A steel pile standing in Smith soil under its own weight (x down)."""
    dt = 20.0 / elements / np.sqrt(STEEL["E"] / STEEL["rho"])
    soil = {"body": "pile", "capacity": capacity, "toe_share": 0.3,
            "shaft": {"quake": 2.5e-3, "damping": 0.16},
            "toe": {"quake": 2.5e-3, "damping": 0.5, "end": "right"}}
    return make_case(dt, 40 * dt, [bar("pile", [0.0, 20.0], elements, area=0.02)],
                     soil=[soil], gravity={"g": 9.81, "initial": "static"})


def test_a_pile_in_soil_starts_at_rest(tmp_path):
    r = solve(tmp_path, pile(1.5e6))
    assert np.abs(r.body("pile").v[:]).max() <= 1e-9
    weight = STEEL["rho"] * 0.02 * 20.0 * 9.81
    soil = r.series("soil/0")
    shaft, toe = soil["shaft_force"][1:], soil["toe_force"][1:]
    assert np.abs((shaft + toe) / weight - 1.0).max() <= 1e-9


def test_soil_too_weak_for_the_pile_is_named(tmp_path):
    weight = STEEL["rho"] * 0.02 * 20.0 * 9.81
    out = cli("run", write_case(tmp_path, pile(0.5 * weight)), "-o", tmp_path / "r.h5")
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1
    assert "soil[0].capacity" in out.stderr and "yields" in out.stderr


def test_a_body_nothing_holds_is_named(tmp_path):
    """A block above a column with a gap: it would fall."""
    dt = courant_dt(20)
    case = make_case(dt, 10 * dt, [column(20), bar("block", [10.5, 12.0], 5)],
                     contacts=[{"pair": ["column", "block"]}],
                     bcs=[{"body": "column", "end": "left", "type": "fixed"}],
                     gravity={"g": G, "initial": "static"})
    out = cli("run", write_case(tmp_path, case), "-o", tmp_path / "r.h5")
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1
    assert "gravity.initial" in out.stderr and "body 'block' is free" in out.stderr
    with pytest.raises(vstpetsc.InputError, match="body 'block' is free"):
        solve(tmp_path, case, "api")
