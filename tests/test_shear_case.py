"""The case-file side of the shear component and Coulomb friction (issue 27,
first slice): G or Vs, v0_shear, u0_shear; bc.component; contact.friction
and wall_shear_velocity.  Validated, kept by the round trip, and run: the
result file holds the shear datasets of docs/result-file.md."""

import numpy as np
import pytest

import vstpetsc
from conftest import bar, cli, make_case, write_case
from faults import one_clean_line
from vstpetsc import CaseError
from vstpetsc.input import toml_text

RHO, VS = 2000.0, 200.0


def column_doc():
    """A column with a shear component on a wall pair with friction, and a
    bare body beside it."""
    return {"time": {"dt": 1e-3, "end": 1e-2},
            "body": [bar("col", (0.0, 10.0), 10, E=1e8, rho=RHO, Vs=VS),
                     bar("bare", (10.0, 12.0), 4, E=1e8, rho=RHO)],
            "contact": [{"pair": ["wall", "col"], "wall": 0.0, "friction": 0.5}],
            "bc": [{"body": "col", "end": "right", "type": "absorbing",
                    "component": "shear"}]}


def edited(change):
    doc = column_doc()
    change(doc)
    return doc


def set_in(table, index, **keys):
    def change(doc):
        doc[table][index].update(keys)
    return change


def drop_in(table, index, key):
    def change(doc):
        del doc[table][index][key]
    return change


def also(table, **keys):
    def change(doc):
        doc.setdefault(table, []).append(keys)
    return change


def both(*changes):
    def change(doc):
        for c in changes:
            c(doc)
    return change


BAD = [
    ("G and Vs", set_in("body", 0, G=8e7), "body[0] (col).Vs: give G or Vs"),
    ("negative G", both(drop_in("body", 0, "Vs"), set_in("body", 0, G=-8e7)),
     "body[0] (col).G: must be positive"),
    ("Vs table short", set_in("body", 0, Vs=[[0.0, 100.0], [5.0, 200.0]]),
     "body[0] (col).Vs: the table covers x in [0, 5]"),
    ("rho Vs^2 overflows", set_in("body", 0, Vs=1e100),
     "body[0] (col).Vs: G = rho Vs^2 must lie in"),
    ("v0_shear without shear", set_in("body", 1, v0_shear=1.0),
     "body[1] (bare).v0_shear: only for a body with a shear component"),
    ("u0_shear without shear", set_in("body", 1, u0_shear=[[10.0, 0.0], [12.0, 1e-3]]),
     "body[1] (bare).u0_shear: only for a body with a shear component"),
    ("v0_shear not a history", set_in("body", 0, v0_shear="fast"),
     "body[0] (col).v0_shear: must be a number or a [[x, value], ...] table"),
    ("unknown component", set_in("bc", 0, component="torsion"),
     "bc[0].component: must be one of 'axial', 'shear'"),
    ("shear bc on a bare body", also("bc", body="bare", end="right", type="fixed",
                                     component="shear"),
     "bc[1].component: body 'bare' has no shear component"),
    ("two shear bcs at an end", also("bc", body="col", end="right", type="fixed",
                                     component="shear"),
     "bc[1].end: the right end of 'col' already has a shear bc, bc[0]"),
    ("shear bc at a friction end", also("bc", body="col", end="left", type="fixed",
                                        component="shear"),
     "bc[1].end: the left end of 'col' is in contact[0] with friction"),
    ("negative friction", set_in("contact", 0, friction=-0.1),
     "contact[0].friction: must be >= 0"),
    ("friction on a cushion", set_in("contact", 0, formulation="cushion", stiffness=1e9),
     "contact[0].friction: not available with formulation 'cushion'"),
    ("friction with a bare body", also("contact", pair=["col", "bare"], friction=0.3),
     "contact[1].friction: body 'bare' has no shear component"),
    ("wall velocity without a wall", both(set_in("body", 1, Vs=100.0), also(
        "contact", pair=["col", "bare"], friction=0.3, wall_shear_velocity=1.0)),
     "contact[1].wall_shear_velocity: only for a pair with \"wall\""),
    ("wall velocity without friction", both(drop_in("contact", 0, "friction"),
                                            set_in("contact", 0, wall_shear_velocity=1.0)),
     "contact[0].wall_shear_velocity: only for a pair with friction"),
    ("wall velocity file missing", set_in("contact", 0,
                                          wall_shear_velocity={"file": "none.csv"}),
     "contact[0].wall_shear_velocity.file:"),
]


@pytest.mark.parametrize("change, message", [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_bad_shear_input_is_one_line_naming_the_key(tmp_path, change, message):
    path = tmp_path / "bad.toml"
    path.write_text(toml_text.dumps(edited(change)))
    out = tmp_path / "r.h5"
    p = cli("run", path, "-o", out)
    assert p.returncode == 2 and one_clean_line(p.stderr), p.stderr
    assert p.stderr.startswith(f"vstpetsc: error: {message}"), p.stderr
    assert not out.exists()


def case_of(doc):
    return vstpetsc.Case.from_dict(doc)


def test_vs_gives_g_equal_to_rho_vs_squared():
    doc = column_doc()
    doc["body"][0].update(rho=[[0.0, 1800.0], [10.0, 2200.0]],
                          Vs=[[0.0, 150.0], [4.0, 150.0], [4.0, 250.0], [10.0, 300.0]])
    body = case_of(doc).bodies[0]
    x = np.linspace(0.0, 10.0, 41)
    # G is rho Vs^2 wherever the mesh evaluates it, across Vs's step too
    assert np.array_equal(body.G(x), body.rho(x) * body.G.Vs(x) ** 2)
    assert body.G(2.0) == pytest.approx(1880.0 * 150.0 ** 2, rel=1e-15)
    assert body.G(7.0) == pytest.approx(2080.0 * 275.0 ** 2, rel=1e-15)


def test_g_given_and_the_initial_shear_fields():
    doc = column_doc()
    del doc["body"][0]["Vs"]
    doc["body"][0].update(G=[[0.0, 6e7], [10.0, 9e7]], v0_shear=0.25,
                          u0_shear=[[0.0, 0.0], [10.0, 1e-3]])
    col, bare = case_of(doc).bodies
    assert col.G(5.0) == 7.5e7 and col.v0_shear(3.0) == 0.25 and col.u0_shear(5.0) == 5e-4
    assert col.has_shear and not bare.has_shear
    assert (bare.G, bare.v0_shear, bare.u0_shear) == (None, None, None)
    assert case_of(column_doc()).bodies[0].G(1.0) == RHO * VS ** 2
    assert case_of(column_doc()).bodies[0].v0_shear.is_zero


def test_bc_component_and_contact_friction():
    doc = column_doc()
    # the ends of a pair without friction may take shear bcs (not axial ones)
    doc["contact"].append({"pair": ["col", "bare"]})
    doc["body"][1]["Vs"] = 100.0
    doc["bc"] += [{"body": "bare", "end": "left", "type": "traction", "value": 5.0,
                   "component": "shear"},
                  {"body": "bare", "end": "right", "type": "velocity", "value": 1.0},
                  {"body": "bare", "end": "right", "type": "fixed", "component": "shear"}]
    case = case_of(doc)
    assert [(b.body, b.end, b.type, b.component) for b in case.bcs] == [
        (0, "right", "absorbing", "shear"), (1, "left", "traction", "shear"),
        (1, "right", "velocity", "axial"), (1, "right", "fixed", "shear")]
    assert case.bcs[1].params["value"](0.0) == 5.0
    wall, inner = case.contacts
    assert wall.friction == 0.5 and wall.wall_shear_velocity.is_zero
    assert inner.friction is None and inner.wall_shear_velocity is None


def test_wall_shear_velocity_takes_every_history_form(tmp_path):
    (tmp_path / "ground.csv").write_text("t,acc\n0,2\n1,2\n")
    forms = {"number": (1.5, 1.5),
             "table": ([[0.0, 0.0], [1.0, 3.0]], 1.5),
             "integrated": ({"table": [[0.0, 2.0], [1.0, 2.0]], "integrate": True}, 1.0),
             "file": ({"file": "ground.csv", "column": "acc", "scale": -1.0,
                       "integrate": True}, -1.0)}
    for form, (value, at_half) in forms.items():
        doc = column_doc()
        doc["contact"][0]["wall_shear_velocity"] = value
        contact = vstpetsc.Case.from_dict(doc, folder=str(tmp_path)).contacts[0]
        assert contact.wall_shear_velocity(0.5) == at_half, form


def test_round_trip_keeps_the_shear_keys(tmp_path):
    doc = column_doc()
    doc["body"][0].update(v0_shear=[[0.0, 0.0], [10.0, 0.5]], u0_shear=1e-4)
    doc["body"][1]["G"] = [[10.0, 5e7], [12.0, 6e7]]
    doc["contact"][0]["wall_shear_velocity"] = {"table": [[0.0, 0.0], [1.0, 2.0]],
                                                "integrate": True, "scale": 0.5}
    doc["contact"].append({"pair": ["col", "bare"], "formulation": "seed", "friction": 0.0})
    doc["bc"][0]["body"] = "bare"
    case = case_of(doc)
    again = vstpetsc.Case.from_text(case.to_toml(), folder=case.folder)
    assert again == case and again.to_dict() == doc
    assert again.bodies == case.bodies and again.contacts == case.contacts
    assert again.bcs == case.bcs
    assert again.contacts[1].friction == 0.0


@pytest.mark.parametrize("flags", [(), ("--dry-run",)])
def test_a_case_using_shear_runs_and_writes_its_datasets(tmp_path, flags):
    path = write_case(tmp_path, case_of(column_doc()))
    out = tmp_path / "r.h5"
    p = cli("run", path, "-o", out, *flags)
    assert p.returncode == 0, p.stderr
    assert "body col/shear: x = [0, 10], 10 elements, Vs = 200" in p.stdout
    if flags:
        assert not out.exists()
        return
    r = vstpetsc.Result(out)
    nt = r.time.size
    shear = r.body("col").shear
    assert shear.u.shape == shear.v.shape == (nt, 11)
    assert shear.stress.shape == (nt, 10) and shear.stress_max.shape == (10,)
    pair = r.contact(0)
    assert pair.shear_force.shape == pair.slip.shape == (nt,)
    assert pair.attrs["permanent_slip"] == pair.slip[-1] and pair.attrs["friction"] == 0.5
    assert r.energy.friction.shape == (nt,)
    assert "shear" not in r.keys("body/bare")
    # a shear absorbing end: rho Vs A by default
    assert f"bc: col/shear right end absorbing (impedance {RHO * VS:.6g} = rho c A of the end element" in p.stdout
    info = cli("info", out)
    assert f"friction mu = 0.5: permanent slip {pair.slip[-1]:.6g}" in info.stdout
    assert "+ friction " in info.stdout                 # in the balance line


def test_plot_shows_the_slip_of_a_pair_with_friction(tmp_path):
    from vstpetsc.results.plot import result_figure

    r = vstpetsc.run(case_of(column_doc()), output=str(tmp_path / "r.h5"), quiet=True)
    labels = [ax.get_ylabel() for ax in result_figure(r).axes]
    assert any(label.startswith("slip [m]") for label in labels), labels


def test_other_problems_are_reported_first(tmp_path):
    doc = column_doc()
    doc["time"]["dt"] = -1.0
    path = tmp_path / "bad.toml"
    path.write_text(toml_text.dumps(doc))
    p = cli("run", path, "--dry-run")
    assert p.returncode == 2 and one_clean_line(p.stderr)
    assert p.stderr.startswith("vstpetsc: error: time.dt: must be positive"), p.stderr


def test_a_case_without_shear_still_runs(tmp_path):
    case = make_case(1e-3, 1e-2, [bar("bare", (0.0, 2.0), 4, E=1e8, rho=RHO)],
                     bcs=[{"body": "bare", "end": "left", "type": "fixed",
                           "component": "axial"}])
    p = cli("run", write_case(tmp_path, case), "-o", tmp_path / "r.h5", "--quiet")
    assert p.returncode == 0, p.stderr


def test_gauges_read_the_shear_component_and_export_it(tmp_path):
    doc = column_doc()
    doc["gauge"] = [{"name": "mid", "body": "col", "x": 5.0},
                    {"name": "side", "body": "bare", "x": 11.0}]
    doc["body"][0]["v0_shear"] = [[0.0, 0.0], [10.0, 1.0]]
    r = vstpetsc.run(case_of(doc), output=str(tmp_path / "r.h5"), quiet=True)
    mid, shear = r.gauge("mid"), r.body("col").shear
    # at the node x = 5, as the body's shear series (every slab against kept rows)
    assert np.array_equal(mid.shear_v[::1], shear.v[:, 5])
    assert np.array_equal(mid.shear_stress, shear.stress[:, 4])
    assert "shear_u" not in r.gauge("side").keys()
    r.to_csv(tmp_path / "csv")
    header = (tmp_path / "csv" / "gauge.csv").read_text().splitlines()[0].split(",")
    assert header == ["time"] + [f"mid.{p}{k}" for p in ("", "shear_")
                                 for k in ("u", "v", "stress", "strain")] + \
        [f"side.{k}" for k in ("u", "v", "stress", "strain")]
