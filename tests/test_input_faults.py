"""Input faults of issue 25: records read with the wrong units or header,
values beyond the range of doubles, restarts of cases with history files
from another folder, and numpy's warnings on failed solves."""

import copy
import os
import shutil

import h5py
import numpy as np
import pytest

import vstpetsc
import vstpetsc.input.toml_text
from conftest import ROOT, bar, cli, make_case, write_case
from faults import one_clean_line
from vstpetsc.spacetime import history as hist

EXAMPLES = os.path.join(ROOT, "vstpetsc", "examples")
SAMPLES = [0.0, 0.1, -0.2, 0.05]


def at2(path, units_line, head_line):
    path.write_text(f"PEER NGA STRONG MOTION DATABASE RECORD\nsynthetic\n{units_line}\n"
                    f"{head_line}\n" + "  ".join(map(repr, SAMPLES)) + "\n")
    return path


def record_case(tmp_path, value):
    """A bar whose left end moves with ``value`` (a {file = ...} table)."""
    case = {"time": {"dt": 0.01, "end": 0.1}, "body": [bar("bar", [0.0, 1.0], 4)],
            "bc": [dict(body="bar", end="left", type="velocity", value=value)]}
    path = tmp_path / "case.toml"
    path.write_text(vstpetsc.input.toml_text.dumps(case))
    return path


def refused(tmp_path, path, *words):
    """The case at ``path`` is refused: exit 2, one line holding ``words``,
    no result file."""
    out = tmp_path / "refused.h5"
    p = cli("run", path, "-o", out)
    assert p.returncode == 2 and one_clean_line(p.stderr), p.stderr
    assert all(w in p.stderr for w in words), p.stderr
    assert not out.exists()


# -- item 4: PEER units and headers, the CSV time column --------------------

@pytest.mark.parametrize("units", ["ACCELERATION TIME SERIES IN UNITS OF CM/S/S",
                                   "ACCELERATION TIME HISTORY IN UNITS OF CM/SEC/SEC",
                                   "UNITS: CM/S^2", "UNITS OF M/S2"])
def test_at2_in_other_units_than_g_is_refused(tmp_path, units):
    at2(tmp_path / "m.AT2", units, f"NPTS= {len(SAMPLES)}, DT= 0.01 SEC")
    refused(tmp_path, record_case(tmp_path, {"file": "m.AT2"}), "bc[0].value.file:",
            "line 3", units.split()[-1], "in g only")


@pytest.mark.parametrize("units", ["ACCELERATION TIME SERIES IN UNITS OF G", "UNITS: G",
                                   "Units of g.", "ACCELERATION"])
@pytest.mark.parametrize("head", ["NPTS=    4, DT=   .0100 SEC", "NPTS=4,DT=0.01",
                                  "4    .01000    NPTS, DT", "   4  0.0100 NPTS, DT"])
def test_at2_in_g_with_either_peer_header(tmp_path, units, head):
    """Both header forms (NGA-West2's and the older numbers-first one) and
    every way of saying g (or none) read the same samples at k DT."""
    t, values = hist.read_at2(at2(tmp_path / "m.AT2", units, head))
    assert np.array_equal(t, 0.01 * np.arange(len(SAMPLES)))
    assert np.array_equal(values, SAMPLES)


@pytest.mark.parametrize("head", ["NPTS= 4, DT= .", "NPTS= 4, DT= 1.2.3 SEC",
                                  "NPTS= 4, DT= 0 SEC", "NPTS= 4, DT= -0.01 SEC"])
def test_at2_with_an_unreadable_dt_is_refused(tmp_path, head):
    at2(tmp_path / "m.AT2", "UNITS OF G", head)
    refused(tmp_path, record_case(tmp_path, {"file": "m.AT2"}), "bc[0].value.file:",
            "DT is not a positive number")


def test_csv_column_naming_the_time_column_is_refused(tmp_path):
    (tmp_path / "m.csv").write_text("time,vel\n0,0\n1,2\n")
    refused(tmp_path, record_case(tmp_path, {"file": "m.csv", "column": "time"}),
            "bc[0].value.file:", "'time' is the time column")


# -- item 12: numbers beyond the range of doubles ---------------------------

BIG = 10**400


def small_case():
    return {"time": {"dt": 0.1, "end": 1.0}, "output": {"every": 1},
            "body": [bar("bar", [0.0, 1.0], 4, E=1.0, rho=1.0)],
            "contact": [{"pair": ["bar", "wall"], "wall": 1.1}]}


EDITS = {
    "dt": (lambda d: d["time"].update(dt=BIG), "time.dt: an integer beyond the 64-bit"),
    "E": (lambda d: d["body"][0].update(E=BIG), "body[0] (bar).E: an integer beyond"),
    "wall": (lambda d: d["contact"][0].update(wall=-BIG), "contact[0].wall: an integer beyond"),
    "x": (lambda d: d["body"][0].update(x=[0, BIG]), "body[0] (bar).x: an integer beyond"),
    "table": (lambda d: d["body"][0].update(v0=[[0, 1], [1, BIG]]),
              "body[0] (bar).v0 row 1: an integer beyond"),
    "every 2^63": (lambda d: d["output"].update(every=2**63), "output.every: an integer beyond"),
    "every 2^64": (lambda d: d["output"].update(every=2**64), "output.every: an integer beyond"),
    "tiny restitution": (lambda d: d["contact"][0].update(
        formulation="cushion", stiffness=1.0, restitution=1e-200),
        "contact[0].restitution: must lie in 1e-150 .. 1e+150 in magnitude"),
    "restitution too small for k": (lambda d: d["contact"][0].update(
        formulation="cushion", stiffness=1e9, restitution=1e-75),
        "contact[0].restitution: too small for stiffness 1e+09"),
    "tiny rho": (lambda d: d["body"][0].update(rho=1e-300), "must lie in 1e-150 .. 1e+150"),
    "huge v0": (lambda d: d["body"][0].update(v0=-1e300), "must lie in 1e-150 .. 1e+150"),
}


@pytest.mark.parametrize("edit,message", EDITS.values(), ids=EDITS.keys())
def test_numbers_beyond_doubles_are_refused(tmp_path, edit, message):
    """By the command line (exit 2, one line, nothing created) and by
    Case.from_dict (CaseError with the same line)."""
    doc = small_case()
    edit(doc)
    path = tmp_path / "c.toml"
    path.write_text(vstpetsc.input.toml_text.dumps(doc))
    before = sorted(os.listdir(tmp_path))
    refused(tmp_path, path, message)
    assert sorted(os.listdir(tmp_path)) == before          # not even a partial file
    with pytest.raises(vstpetsc.CaseError) as err:
        vstpetsc.Case.from_dict(doc)
    assert any(message in line for line in err.value.problems), err.value.problems


def numeric_keys(obj, path=()):
    """The paths of every number in a case document."""
    if isinstance(obj, dict):
        for key, value in obj.items():
            yield from numeric_keys(value, path + (key,))
    elif isinstance(obj, list):
        for i, value in enumerate(obj):
            yield from numeric_keys(value, path + (i,))
    elif isinstance(obj, (int, float)) and not isinstance(obj, bool):
        yield path


@pytest.mark.parametrize("name", sorted(n for n in os.listdir(EXAMPLES) if n.endswith(".toml")))
def test_every_number_of_the_examples_beyond_doubles(name):
    """Each number of each bundled example replaced by values beyond the
    range of doubles: validation refuses the huge ones with CaseError lines
    and answers the tiny ones with CaseError or a case (a tiny value in a
    history only multiplies), never another exception."""
    base = vstpetsc.Case.from_toml(os.path.join(EXAMPLES, name)).to_dict()
    for path in numeric_keys(base):
        for value in (BIG, -BIG, 2**63, -1e300, 1e-300, 5e-324):
            doc = copy.deepcopy(base)
            node = doc
            for part in path[:-1]:
                node = node[part]
            node[path[-1]] = value
            try:
                vstpetsc.Case.from_dict(doc, folder=EXAMPLES)
            except vstpetsc.CaseError:
                continue
            assert abs(value) < 1e-150, (path, value)


# -- item 11: a restart finds the history files from any folder -------------

def uplift_copy(folder, end):
    """The bundled uplift case (a CSV base motion) in ``folder``, ending at
    ``end``; its path."""
    folder.mkdir(exist_ok=True)
    shutil.copy(os.path.join(EXAMPLES, "uplift-base.csv"), folder)
    text = open(os.path.join(EXAMPLES, "uplift.toml")).read()
    assert "\nend = 0.5\n" in text
    path = folder / "uplift.toml"
    path.write_text(text.replace("\nend = 0.5\n", f"\nend = {end}\n"))
    return path


def test_restart_with_a_csv_history_from_another_folder(tmp_path):
    """Run to t = 0.01, raise time.end, restart from another current
    folder: equal bit for bit to a run straight to t = 0.02."""
    straight = uplift_copy(tmp_path / "straight", 0.02)
    assert cli("run", straight, "-o", tmp_path / "straight.h5", "--quiet").returncode == 0
    case = uplift_copy(tmp_path / "case", 0.01)
    out = tmp_path / "r.h5"
    assert cli("run", case, "-o", out, "--quiet", cwd=case.parent).returncode == 0
    case.write_text(case.read_text().replace("\nend = 0.01\n", "\nend = 0.02\n"))
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    p = cli("run", case, "--restart", out, "--quiet", cwd=elsewhere)
    assert p.returncode == 0, p.stderr
    with h5py.File(out, "r") as a, h5py.File(tmp_path / "straight.h5", "r") as b:
        assert np.array_equal(a["time"][...], b["time"][...])
        for group in ("body/column", "body/block"):
            for key in b[group]:
                assert np.array_equal(a[group][key][...], b[group][key][...]), key
        for key in b["energy"]:      # the running sums are restart state too
            assert np.array_equal(a["energy"][key][...], b["energy"][key][...]), key


def test_restart_after_a_history_file_changed_is_refused(tmp_path):
    case = uplift_copy(tmp_path / "case", 0.01)
    out = tmp_path / "r.h5"
    assert cli("run", case, "-o", out, "--quiet").returncode == 0
    case.write_text(case.read_text().replace("\nend = 0.01\n", "\nend = 0.02\n"))
    csv = case.parent / "uplift-base.csv"
    lines = csv.read_text().splitlines()
    csv.write_text("\n".join(lines[:-1]) + "\n")        # one sample fewer
    p = cli("run", case, "--restart", out, "--quiet")
    assert p.returncode == 2 and one_clean_line(p.stderr), p.stderr
    assert "uplift-base.csv changed since" in p.stderr


# -- item 14: values near overflow end in one line, without numpy warnings --

def run_cli(tmp_path, doc):
    path = tmp_path / "c.toml"
    path.write_text(vstpetsc.input.toml_text.dumps(doc))
    return cli("run", path, "-o", tmp_path / "r.h5", "--quiet")


def test_a_failing_soil_with_a_tiny_quake_prints_one_line(tmp_path):
    doc = vstpetsc.Case.from_toml(os.path.join(EXAMPLES, "pile.toml")).to_dict()
    doc["time"]["end"] = 20 * doc["time"]["dt"]
    doc["soil"][0]["shaft"]["quake"] = 1e-150
    p = run_cli(tmp_path, doc)
    assert p.returncode == 3 and "Warning" not in p.stderr, p.stderr
    assert one_clean_line(p.stderr) and "Newton did not converge" in p.stderr, p.stderr
    assert vstpetsc.Result(tmp_path / "r.h5").status == "failed"


def test_energies_beyond_doubles_fail_the_run(tmp_path):
    """A bar whose kinetic energy overflows (u and v themselves finite) used
    to complete with inf energies after a page of warnings: exit 3, one line."""
    doc = {"time": {"dt": 0.1, "end": 1.0},
           "body": [bar("bar", [0.0, 1.0], 4, E=1.0, rho=1e10, v0=1e150)]}
    p = run_cli(tmp_path, doc)
    assert p.returncode == 3 and "Warning" not in p.stderr, p.stderr
    assert one_clean_line(p.stderr) and "energies are not finite" in p.stderr, p.stderr
    assert vstpetsc.Result(tmp_path / "r.h5").status == "failed"


def test_every_on_the_command_line_beyond_64_bits_is_refused(tmp_path):
    case = uplift_copy(tmp_path / "case", 0.001)
    p = cli("run", case, "-o", tmp_path / "r.h5", "--every", str(2 ** 63))
    assert p.returncode == 2 and one_clean_line(p.stderr) and "--every" in p.stderr
    assert not (tmp_path / "r.h5").exists()


# -- issue 35 item 1: recorded samples against the limits of inline values --

def record_text(form, samples):
    """A record file's text holding ``samples`` [(t, value)]: CSV with a
    header, or AT2 (times k dt: ``samples`` must be evenly spaced)."""
    if form == "csv":
        return "t,acc\n" + "".join(f"{t!r},{v!r}\n" for t, v in samples)
    dt = samples[1][0] - samples[0][0]
    return ("PEER NGA STRONG MOTION DATABASE RECORD\nsynthetic\nUNITS OF G\n"
            f"NPTS= {len(samples)}, DT= {dt!r} SEC\n" + "  ".join(repr(v) for _, v in samples))


def refused_without_warnings(tmp_path, value, *words):
    """Exit 2, stderr exactly one line holding ``words``, no numpy warning."""
    path = record_case(tmp_path, value)
    p = cli("run", path, "-o", tmp_path / "r.h5")
    assert p.returncode == 2 and "Warning" not in p.stderr, p.stderr
    assert len(p.stderr.splitlines()) == 1 and one_clean_line(p.stderr), p.stderr
    assert all(w in p.stderr for w in words), p.stderr
    assert not (tmp_path / "r.h5").exists()


HUGE_SAMPLES = {"values": [(0.0, 0.0), (1.0, 1e308), (2.0, 1e308), (3.0, -1e308)],
                "beyond 1e150": [(0.0, 0.0), (1.0, 2e150), (2.0, 1.0), (3.0, 0.0)]}


@pytest.mark.parametrize("integrate", [True, False])
@pytest.mark.parametrize("form", ["csv", "AT2"])
@pytest.mark.parametrize("samples", HUGE_SAMPLES.values(), ids=HUGE_SAMPLES.keys())
def test_record_samples_beyond_the_inline_limits_are_refused(tmp_path, samples, form,
                                                             integrate):
    """Samples an inline table refuses (exit 2, "must lie in 1e-150 ..
    1e+150") are refused from a file too, naming the key, the file and the
    sample, before numpy ever sees them (four warning lines before)."""
    (tmp_path / f"m.{form}").write_text(record_text(form, samples))
    where = "row 3" if form == "csv" else "sample 2"
    limits = "must lie in 1e-150 .. 1e+150 in magnitude (or be 0)"
    refused_without_warnings(tmp_path, {"file": f"m.{form}", "integrate": integrate},
                             "bc[0].value.file:", f"m.{form}, {where}: {limits}",
                             f"got {samples[1][1]:g}")
    inline = {"table": [list(s) for s in samples], "integrate": integrate}
    refused_without_warnings(tmp_path, inline, "bc[0].value.table row 1:", limits)


def test_csv_times_beyond_the_inline_limits_are_refused(tmp_path):
    (tmp_path / "m.csv").write_text("0,0\n1e200,1\n")
    refused_without_warnings(tmp_path, {"file": "m.csv"}, "bc[0].value.file:",
                             "m.csv, row 2: must lie in 1e-150 .. 1e+150", "got 1e+200")


@pytest.mark.parametrize("form", ["file", "table"])
def test_a_record_that_overflows_once_integrated_is_refused(tmp_path, form):
    """Samples within the limits whose exact integral a double cannot hold
    (a slope of 1e150 / 1e-200 between two samples; a scale of 1e150 on
    values of 1e150 integrated over a time of 1e150): one line, from a file
    or inline alike, instead of numpy's warnings and a failed run."""
    for samples, scale in (([(0.0, 0.0), (1e-200, 1e150), (1.0, 0.0)], 1.0),
                           ([(0.0, 1e150), (1e150, 1e150)], 1e150)):
        if form == "file":
            (tmp_path / "m.csv").write_text(record_text("csv", samples))
            value = {"file": "m.csv"}
        else:
            value = {"table": [list(s) for s in samples]}
        refused_without_warnings(tmp_path, {**value, "scale": scale, "integrate": True},
                                 f"bc[0].value: scaled by {scale:g} and integrated",
                                 "beyond the range of a double")


# -- issue 35 item 5: the vectorised CSV reader reads what the rows did -----

ODD_CSV = {
    "plain": "t,a\n0,1\n1,2\n2,3\n", "no header": "0,1\n1,2\n",
    "crlf": "t,a\r\n0,1\r\n1,2\r\n", "cr": "t,a\r0,1\r1,2\r",
    "blank lines": "\n\nt,a\n\n0,1\n   \n1,2\n,,\n2,5\n", "spaces": "t , a\n 0 , 1 \n 1\t, 2\n",
    "quoted": 't,a\n"0","1"\n"1",2\n', "trailing comma": "t,a,\n0,1,\n1,2,\n",
    "ragged": "t,a,b\n0,1,5\n1,2\n", "underscore": "t,a\n0,1_0\n1,2\n",
    "unicode minus": "t,a\n0,\u22121\n1,2\n", "no-break space": "t,a\n0,\u00a01\n1,2\n",
    "empty cell": "t,a\n0,\n1,2\n", "nan": "t,a\n0,nan\n1,2\n", "text": "t,a\n0,1\n1,x\n",
    "text time": "t,a\n0,1\nx,1\n", "hex": "t,a\n0,0x10\n1,2\n", "fortran": "t,a\n0,1d5\n1,2\n",
    "signs and dots": "t,a\n+0.,.5\n1.,-2e-3\n", "one row": "t,a\n0,1\n", "header only": "t,a\n",
    "empty": "", "blank only": "\n  \n,\n", "decreasing": "0,1\n1,2\n0.5,3\n",
    "nul": "t,a\n0,1\x00\n1,2\n", "comment": "t,a\n0,1 # c\n1,2\n", "tabs": "t\ta\n0\t1\n",
    "vertical tab": "t,a\n0,\x0b1\n1,2\n", "line separator": "t,a\n0,1\u2028\n1,2\n",
    "byte order mark": "\ufefft,a\n0,1\n1,2\n", "text column": "t,a,note\n0,1,hi\n1,2,yo\n",
    "overflow": "t,a\n0,1e400\n1,2\n", "numeric header": "1,2\n0,1\n",
    "empty lines": "t,a\n\n0,1\n\n\n1,2\n\n", "infinity": "t,a\n0,-Infinity\n1,2\n",
    "arabic digit": "t,a\n0,\u0661\n1,2\n", "cut exponent": "t,a\n0,1e+\n1,2\n",
    "blank cell": "t,a\n0, \n1,2\n", "minus zero": "t,a\n-0,-0.0\n1,2\n",
    "huge time": "0,0\n1e200,1\n", "more cells than the header": "t,a\n0,1,7\n1,2,8\n",
}


@pytest.mark.parametrize("text", ODD_CSV.values(), ids=ODD_CSV.keys())
@pytest.mark.parametrize("column", [2, "a", 3])
def test_csv_reader_equals_the_row_by_row_reading(tmp_path, text, column):
    """The vectorised reader (numpy's loadtxt on plain files) gives the
    samples, or the error, of the row-by-row reading (csv.reader) it falls
    back to, for every file: blank lines, quotes, odd numbers, bad rows."""
    path = tmp_path / "m.csv"
    path.write_text(text, encoding="utf-8", newline="")

    def outcome(read):
        try:
            return read()
        except hist.RecordError as exc:
            return str(exc)

    fast = outcome(lambda: hist.read_csv(str(path), column))
    rows = outcome(lambda: hist.read_csv_rows(str(path), column))
    if isinstance(rows, str):
        assert fast == rows
    else:
        assert not isinstance(fast, str), fast
        assert all(np.array_equal(a, b) for a, b in zip(fast, rows))
