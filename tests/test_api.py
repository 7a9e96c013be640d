"""The Python API: Case (from_dict, from_text, with_value, to_toml), run,
Result, CaseError; the README's one-liner and examples/api.py."""

import os
import re
import subprocess
import sys
import threading

import numpy as np
import pytest

import vstpetsc
from conftest import ROOT, bar, cli, make_case, solve
from vstpetsc import bundled


def bar_wall(v0=1.0):
    """A steel bar 0.1 mm from a wall, E = rho = A = L = 1 units kept simple."""
    return make_case(0.01, 2.5, [bar("bar", (0.0, 1.0), 50, E=1.0, rho=1.0, v0=v0)],
                     contacts=[dict(pair=["bar", "wall"], wall=1.1)])


@pytest.mark.parametrize("name", bundled.names())
def test_to_toml_round_trip(name):
    case = vstpetsc.Case.from_toml(bundled.path(name))
    again = vstpetsc.Case.from_text(case.to_toml(), folder=case.folder)
    assert again == case and again.to_toml() == case.to_toml()
    assert vstpetsc.Case.from_dict(case.to_dict(), folder=case.folder) == case
    assert again.nslabs == case.nslabs and again.bodies == case.bodies


def test_to_toml_writes_readable_tables():
    text = bar_wall().to_toml()
    assert "[[body]]" in text and "[[contact]]" in text and "[time]" in text
    odd = make_case(0.1, 1.0, [bar("a.b-c_1", (0.0, 1.0), 5, v0=[[0.0, 1.5], [1.0, -2e-300]])],
                    units={"length": "mm \"x\"\\"})
    assert vstpetsc.Case.from_text(odd.to_toml()) == odd
    assert odd.with_value("body.a.b-c_1.elements", 7).bodies[0].elements == 7


def test_with_value_copies_and_validates():
    case = bar_wall()
    faster = case.with_value("body.bar.v0", 2.0)
    assert faster.bodies[0].v0(0.3) == 2.0 and case.bodies[0].v0(0.3) == 1.0
    assert faster.with_value("time.dt", 0.02).dt == 0.02
    assert case.with_value("contact.0.formulation", "power").contacts[0].formulation == "power"
    assert case.with_value("output.every", 5).every == 5
    with pytest.raises(vstpetsc.CaseError) as err:
        case.with_value("body.bar.E", -1.0)
    assert err.value.problems == ["body[0] (bar).E: must be positive, got -1"]
    for path in ("body.nosuch.E", "contact.3.penalty", "nodots", "time..dt"):
        with pytest.raises(vstpetsc.CaseError) as err:
            case.with_value(path, 1.0)
        assert len(err.value.problems) == 1 and path in err.value.problems[0]


def test_with_value_builds_the_case_once(monkeypatch):
    """One validation per with_value, for a key the case gives, one it does
    not (body.bar.area: it used to be built once with a placeholder to
    check the key, then again), a new table, a misspelled key and a bad
    value; the results and messages as before."""
    case = bar_wall()
    read = vstpetsc.input.case.schema.read
    calls = []
    monkeypatch.setattr(vstpetsc.input.case.schema, "read", lambda *a: calls.append(a) or read(*a))
    changes = [("body.bar.v0", 2.0, None), ("body.bar.area", 2.0, None),
               ("body.bar.damping.alpha", 0.5, None),
               ("body.bar.aera", 2.0, "body.bar.aera: unknown key (did you mean 'area'?"),
               ("body.bar.area", -1.0, "body[0] (bar).area: must be positive")]
    for path, value, problem in changes:
        calls.clear()
        if problem is None:
            assert case.with_value(path, value).to_dict() != case.to_dict()
        else:
            with pytest.raises(vstpetsc.CaseError) as err:
                case.with_value(path, value)
            assert len(err.value.problems) == 1 and err.value.problems[0].startswith(problem)
        assert len(calls) == 1, path
    assert case.with_value("body.bar.area", 2.0).bodies[0].area(0.5) == 2.0


def test_case_error_carries_the_cli_messages(tmp_path):
    doc = bar_wall().to_dict()
    doc["body"][0]["E"] = "steel"
    doc["time"]["dtt"] = 1.0
    with pytest.raises(vstpetsc.CaseError) as err:
        vstpetsc.Case.from_dict(doc)
    path = tmp_path / "bad.toml"
    path.write_text(vstpetsc.input.case.toml_text.dumps(doc))
    p = cli("run", path)
    assert p.returncode == 2
    printed = [line.removeprefix("vstpetsc: error: ") for line in p.stderr.splitlines()]
    assert printed == err.value.problems and len(printed) == 2
    assert "time.dtt: unknown key (did you mean 'dt'?" in printed[0]


def test_run_returns_a_lazy_result(tmp_path):
    result = solve(tmp_path, bar_wall())
    assert isinstance(result, vstpetsc.Result) and result.status == "completed"
    assert result.bodies == ["bar"] and result.ncontacts == 1
    assert result.time.shape == (251,) and result.body("bar").u.shape == (251, 51)
    pair = result.contact(0)
    # the wall turns the bar's momentum (m v0 = 1) round: impulse 2 m v0
    assert pair.impulse_total[-1] == pytest.approx(2.0, rel=1e-2)
    assert pair.attrs["formulation"] == "power" and result.run.slabs == 250
    assert set(result.energy) == {"kinetic", "strain", "spring", "damping", "external", "contact",
                                  "soil", "transferred", "friction", "hysteretic", "numerical"}
    summary = result.summary()
    assert summary["status"] == "completed" and summary["pairs"][0]["episodes"] == 1
    again = vstpetsc.Result(result.path)
    assert np.array_equal(again.body("bar").v, result.body("bar").v)
    with pytest.raises(KeyError):
        result.body("nosuch")
    with pytest.raises(vstpetsc.InputError):
        vstpetsc.Result(tmp_path / "missing.h5")


def test_run_outside_the_main_thread(tmp_path):
    """A notebook may run code in another thread: no signal handlers there."""
    out = {}
    worker = threading.Thread(target=lambda: out.setdefault("r", solve(tmp_path, bar_wall())))
    worker.start()
    worker.join(120)
    assert out["r"].status == "completed"


def test_failure_raises_and_keeps_the_file(tmp_path):
    with pytest.raises(vstpetsc.SolveFailed, match=r"slab \d+: Newton did not converge"):
        solve(tmp_path, bar_wall(), name="f", options=["-snes_max_it", "1",
                                                        "-snes_rtol", "1e-15"])
    failed = vstpetsc.Result(tmp_path / "f.h5")
    assert failed.status == "failed" and failed.time.size > 1


def test_options_apply_to_one_run_and_are_prefixed(tmp_path):
    from petsc4py import PETSc

    opts = PETSc.Options()
    opts["ksp_type"] = "gmres"             # a user's own setting: not vstpetsc's
    try:
        plain = solve(tmp_path, bar_wall(), name="plain")
        gmres = solve(tmp_path, bar_wall(), name="gmres", options=["-ksp_type", "bcgs"])
    finally:
        del opts["ksp_type"]
    assert plain.attrs["solver"].startswith("KSP preonly")
    assert gmres.attrs["solver"].startswith("KSP bcgs")
    assert not opts.hasName("vst_ksp_type")            # removed after the run
    with pytest.raises(vstpetsc.InputError, match="-vst_newton"):
        solve(tmp_path, bar_wall(), name="bad", options=["-vst_newton", "both"])


def test_readme_one_liner(tmp_path):
    """The README's `python -c` example, run as written."""
    readme = open(os.path.join(ROOT, "README.md")).read()
    command = re.search(r'python -c "(import vstpetsc;.*?)"\n', readme).group(1)
    p = subprocess.run([sys.executable, "-c", command], cwd=tmp_path, capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert float(p.stdout.split()[-1]) > 0


def test_examples_api_script(tmp_path):
    p = subprocess.run([sys.executable, os.path.join(ROOT, "examples", "api.py"), str(tmp_path)],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    rows = [line.split() for line in p.stdout.splitlines()[1:]]
    assert [float(r[0]) for r in rows] == [0.5, 1.0, 2.0]
    for _, peak, mean, zv0, _ in (map(float, r) for r in rows):
        assert abs(mean / zv0 - 1) < 0.03 and peak >= mean
    assert len(list(tmp_path.glob("*.h5"))) == 3
