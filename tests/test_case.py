"""Case validation: every malformed case names its key; the CLI turns it into
exit status 2 with no traceback."""

import pytest

from conftest import cli
from vstpetsc import Case, CaseError


def parse_case(text):
    return Case.from_text(text)

GOOD = """
[time]
dt = 1e-5
end = 1e-3
[[body]]
name = "a"
x = [0.0, 1.0]
elements = 10
E = 2e11
rho = 7850.0
[[body]]
name = "b"
x = [1.1, 2.0]
elements = 10
E = 2e11
rho = 7850.0
[[contact]]
pair = ["a", "b"]
[[contact]]
pair = ["b", "wall"]
wall = 2.5
[[bc]]
body = "a"
end = "left"
type = "velocity"
value = [[0.0, 0.0], [1e-4, 1.0]]
"""


def mutate(old, new):
    assert old in GOOD, old
    return GOOD.replace(old, new, 1)


BAD = [
    ("syntax", "[time\n", "TOML syntax"),
    ("unknown top", GOOD + "[solver]\nx = 1\n", "solver: unknown key"),
    ("unknown key", mutate("dt = 1e-5", "dt = 1e-5\nsteps = 3"), "time.steps: unknown key"),
    ("missing dt", mutate("dt = 1e-5\n", ""), "time.dt: missing"),
    ("string dt", mutate("dt = 1e-5", 'dt = "1e-5"'), "time.dt: must be a number"),
    ("nan", mutate("E = 2e11", "E = nan"), "body[0] (a).E: must be finite"),
    ("inf", mutate("rho = 7850.0", "rho = inf"), "body[0] (a).rho: must be finite"),
    ("negative E", mutate("E = 2e11", "E = -2e11"), "body[0] (a).E: must be positive"),
    ("zero dt", mutate("dt = 1e-5", "dt = 0.0"), "time.dt: must be positive"),
    ("end <= dt", mutate("end = 1e-3", "end = 1e-6"), "time.end: must be greater"),
    ("elements", mutate("elements = 10", "elements = 0"), "body[0] (a).elements: must be >= 1"),
    ("float elements", mutate("elements = 10", "elements = 2.5"), "body[0] (a).elements: must be a whole"),
    ("length", mutate("x = [0.0, 1.0]", "x = [1.0, 1.0]"), "body[0] (a).x: right end must exceed"),
    ("overlap", mutate("x = [1.1, 2.0]", "x = [0.5, 2.0]"), "body[1] (b).x: overlaps"),
    ("duplicate", mutate('name = "b"', 'name = "a"'), "body[1] (a).name: duplicate"),
    ("unknown body", mutate('pair = ["a", "b"]', 'pair = ["a", "c"]'), "contact[0].pair: unknown body 'c'"),
    ("not neighbours", mutate('pair = ["a", "b"]', 'pair = ["b", "a"]'), "contact[0].pair: 'b' and 'a' are not neighbours"),
    ("wall wrong side", mutate("wall = 2.5", "wall = 1.5"), "contact[1].wall: a wall on the right"),
    ("wall missing", mutate("wall = 2.5\n", ""), "contact[1].wall: missing"),
    ("formulation", mutate('pair = ["a", "b"]', 'pair = ["a", "b"]\nformulation = "lagrange"'), "contact[0].formulation: must be one of"),
    ("penalty", mutate('pair = ["a", "b"]', 'pair = ["a", "b"]\npenalty = -1.0'), "contact[0].penalty: must be positive"),
    ("bc on contact end", mutate('end = "left"', 'end = "right"'), "bc[0].end: the right end of 'a' is in contact[0]"),
    ("bc type", mutate('type = "velocity"', 'type = "spring"'), "bc[0].type: must be one of"),
    ("bc value missing", mutate("value = [[0.0, 0.0], [1e-4, 1.0]]\n", ""), "bc[0].value: missing"),
    ("history order", mutate("value = [[0.0, 0.0], [1e-4, 1.0]]", "value = [[1e-4, 0.0], [0.0, 1.0]]"), "bc[0].value: the t column must be strictly increasing"),
    ("history short", mutate("value = [[0.0, 0.0], [1e-4, 1.0]]", "value = [[0.0, 0.0]]"), "bc[0].value: a table needs at least two"),
    ("history row", mutate("value = [[0.0, 0.0], [1e-4, 1.0]]", "value = [[0.0, 0.0], [1e-4]]"), "bc[0].value: row 1"),
    ("every", GOOD + "[output]\nevery = 0\n", "output.every: must be >= 1"),
    ("fixed with value", mutate('type = "velocity"\nvalue = [[0.0, 0.0], [1e-4, 1.0]]', 'type = "fixed"\nvalue = 3.0'), "bc[0].value: a fixed end"),
    ("no body", "[time]\ndt = 1.0\nend = 2.0\n", "body: at least one"),
    ("syntax line", GOOD.replace("E = 2e11", "E = = 2e11", 1), "(at line 9"),
    ("wall inside body", mutate("wall = 2.5", "wall = 1.2").replace('pair = ["b", "wall"]', 'pair = ["a", "wall"]').replace('[[contact]]\npair = ["a", "b"]\n', ''), "contact[0].wall: lies inside or beyond body 'b'"),
    ("wall left inside", mutate('pair = ["b", "wall"]', 'pair = ["wall", "a"]').replace("wall = 2.5", "wall = 0.5"), "contact[1].wall: a wall on the left of 'a'"),
    ("too many elements", mutate("elements = 10", "elements = 1000000000"), "body[0] (a).elements: at most"),
    ("too many slabs", mutate("dt = 1e-5", "dt = 1e-140"), "time.end: end / dt"),
    ("subnormal dt", mutate("dt = 1e-5", "dt = 1e-300"), "time.dt: must lie in"),
    ("string in table", mutate("value = [[0.0, 0.0], [1e-4, 1.0]]", 'value = [[0.0, "x"], [1e-4, 1.0]]'), "bc[0].value: row 0"),
    ("unknown bc body", mutate('body = "a"', 'body = "q"'), "bc[0].body: unknown body 'q'"),
    ("contact both walls", mutate('pair = ["a", "b"]', 'pair = ["wall", "wall"]'), "contact[0].pair: needs at least one body"),
]


def test_good_case_parses():
    case = parse_case(GOOD)
    assert case.nslabs == 100 and len(case.bodies) == 2 and len(case.contacts) == 2
    assert case.contacts[1].right is None and case.contacts[1].wall == 2.5


@pytest.mark.parametrize("name,text,message", BAD, ids=[b[0] for b in BAD])
def test_bad_case_names_the_key(name, text, message):
    with pytest.raises(CaseError) as err:
        parse_case(text)
    assert any(message in p for p in err.value.problems), err.value.problems


def test_all_problems_reported_at_once():
    text = mutate("E = 2e11", "E = -1.0").replace("dt = 1e-5", "dt = -1.0")
    with pytest.raises(CaseError) as err:
        parse_case(text)
    assert len(err.value.problems) == 2


@pytest.mark.parametrize("name,text,message", BAD[:6], ids=[b[0] for b in BAD[:6]])
def test_cli_exit_2_one_line_no_traceback(tmp_path, name, text, message):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    p = cli("run", path, "-o", tmp_path / "r.h5")
    assert p.returncode == 2
    assert "Traceback" not in p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], p.stderr
    assert not (tmp_path / "r.h5").exists()


@pytest.mark.parametrize("args,message", [
    (["run", "/nonexistent/case.toml"], "cannot read case file"),
    (["run"], "missing CASE.toml"),
    (["frobnicate"], "unknown command"),
    (["run", "CASE", "--bogus"], "--bogus: unknown option"),
])
def test_cli_bad_arguments(tmp_path, args, message):
    p = cli(*args, cwd=tmp_path)
    assert p.returncode == 2 and message in p.stderr and "Traceback" not in p.stderr


def test_cli_unwritable_output(tmp_path):
    path = tmp_path / "ok.toml"
    path.write_text(GOOD)
    p = cli("run", path, "-o", tmp_path / "no" / "such" / "r.h5")
    assert p.returncode == 2 and "-o: folder" in p.stderr


def test_dry_run_prints_model_and_solves_nothing(tmp_path):
    path = tmp_path / "ok.toml"
    path.write_text(GOOD)
    p = cli("run", path, "--dry-run")
    assert p.returncode == 0, p.stderr
    assert "2 bodies, 22 nodes, 20 elements" in p.stdout and "100 slabs" in p.stdout
    assert "contact[0] a | b: gap 0.1, power penalty" in p.stdout and "(default)" in p.stdout
    assert "contact[1] b | wall: gap 0.5" in p.stdout
    assert not (tmp_path / "result.h5").exists()


def test_every_override(tmp_path):
    path = tmp_path / "ok.toml"
    path.write_text(GOOD)
    p = cli("run", path, "--every", "25", "--quiet", "-o", tmp_path / "r.h5")
    assert p.returncode == 0, p.stderr
    import h5py
    with h5py.File(tmp_path / "r.h5") as f:
        assert f["time"].shape == (5,) and f.attrs["every"] == 25
    for bad in ("0", "x", "2.5"):
        p = cli("run", path, "--every", bad)
        assert p.returncode == 2 and "--every" in p.stderr


def test_control_characters_in_names_stay_on_one_line():
    """Found by the fuzz test: a carriage return in a body name split the
    message into two lines."""
    text = GOOD.replace('name = "a"', 'name = "a\\rx"', 1)
    with pytest.raises(CaseError) as err:
        parse_case(text)
    assert all("\r" not in p and "\n" not in p for p in err.value.problems)
    assert any("a\\rx" in p for p in err.value.problems)
