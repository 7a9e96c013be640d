"""Helpers: cases are built through the Python API (vstpetsc.Case.from_dict)
and run in-process with vstpetsc.run; the command line is run as a
subprocess where its behaviour (exit status, messages) is what is tested."""

import io
import os
import subprocess
import sys

import numpy as np
import pytest

import vstpetsc

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VSTPETSC = os.path.join(os.path.dirname(sys.executable), "vstpetsc")
STEEL = dict(E=2.0e11, rho=7850.0)


def bar(name, x, elements, E=STEEL["E"], rho=STEEL["rho"], **extra):
    """A [[body]] table."""
    return {"name": name, "x": [float(x[0]), float(x[1])], "elements": elements,
            "E": E, "rho": rho, **extra}


def make_case(dt, end, bodies, contacts=(), bcs=(), every=1, folder=None, **tables):
    """A vstpetsc.Case from its tables (files relative to ``folder``)."""
    doc = {"time": {"dt": dt, "end": end}, "output": {"every": every},
           "body": list(bodies), **tables}
    if contacts:
        doc["contact"] = list(contacts)
    if bcs:
        doc["bc"] = list(bcs)
    return vstpetsc.Case.from_dict(doc, folder=None if folder is None else str(folder))


def solve(tmp_path, case, name="case", options=(), **kw):
    """Run ``case`` in-process, quietly; return its vstpetsc.Result."""
    return vstpetsc.run(case, output=str(tmp_path / f"{name}.h5"), options=options,
                        quiet=True, out=io.StringIO(), **kw)


def write_case(tmp_path, case, name="case"):
    """The case as a file (for the command line); returns its path."""
    path = tmp_path / f"{name}.toml"
    path.write_text(case.to_toml())
    return path


def cli(*args, cwd=None, timeout=120):
    """Run the vstpetsc command; return the CompletedProcess."""
    return subprocess.run([VSTPETSC, *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=timeout)


def run_and_info(tmp_path, case, name):
    """(the run's last line, `vstpetsc info`'s text, Result) of ``case`` run
    by the command line."""
    path = write_case(tmp_path, case, name)
    out = tmp_path / f"{name}.h5"
    p = cli("run", path, "-o", out, "--quiet")
    assert p.returncode == 0, p.stderr
    info = cli("info", out)
    assert info.returncode == 0, info.stderr
    return p.stdout.strip().splitlines()[-1], info.stdout, vstpetsc.Result(str(out))


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


def assert_tangent(law, y, got, h, rtol, floor):
    """The tangent ``got[2:6]`` (df1/dy1, df1/dy2, df2/dy1, df2/dy2) of a
    law's slab integrals ``law(y1, y2)`` (None: zero) against central
    finite differences with step h."""
    for j in range(2):
        plus, minus = list(y), list(y)
        plus[j] += h
        minus[j] -= h
        fp, fm = law(*plus) or (0.0,) * 6, law(*minus) or (0.0,) * 6
        for a in range(2):
            exact = got[2 + 2 * a + j]
            assert abs((fp[a] - fm[a]) / (2 * h) - exact) <= rtol * max(abs(exact), floor)


def compliance_delay(r, impedance):
    """2 Z / k: how much later a penalty spring of (slab-mean) stiffness k
    lets go than a rigid contact would, for the impedance Z the spring sees
    (a bar on a wall: the bar's; two bars: theirs in series).  The force
    rises and falls with the time constant Z / k of the spring loading a
    dashpot Z."""
    a = r.contact(0).attrs
    if a["formulation"] == "cushion":
        k = a["stiffness"]
    else:                    # the seed's eps dt / 2: its slab-mean force per penetration
        k = a["penalty"] * (0.5 * r.attrs["dt"] if a["formulation"] == "seed" else 1.0)
    return 2.0 * impedance / k


# Tests that start runs on several ranks: under `pytest -n 2` (make test)
# they share one worker, so that at most one mpirun runs at a time and the
# two cores are not asked for four ranks at once; the rest spread freely.
MPI_WORDS = ("mpirun", "mpi=", "mpiexec")


# first: pytest-xdist's own hook turns the group marks into the test ids
# (``@mpi``) that --dist loadgroup deals by, and marks added after it are
# not seen (the two workers each ran mpirun at once, 4 ranks on 2 cores)
@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    import inspect

    for item in items:
        try:
            source = inspect.getsource(item.function)
        except (OSError, TypeError):
            continue
        if item.module.__name__ == "test_parallel" or any(w in source for w in MPI_WORDS):
            item.add_marker(pytest.mark.xdist_group("mpi"))
