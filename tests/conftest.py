import contextlib
import io
import os
import subprocess
import sys

import h5py
import numpy as np
import pytest

from vstpetsc.case import parse_case

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VSTPETSC = os.path.join(os.path.dirname(sys.executable), "vstpetsc")
STEEL = dict(E=2.0e11, rho=7850.0)


def body(name, x, elements, E=STEEL["E"], rho=STEEL["rho"], **extra):
    """A [[body]] table as TOML text."""
    lines = ["[[body]]", f'name = "{name}"', f"x = [{x[0]!r}, {x[1]!r}]",
             f"elements = {elements}", f"E = {E!r}", f"rho = {rho!r}"]
    lines += [f"{k} = {_toml(v)}" for k, v in extra.items()]
    return "\n".join(lines) + "\n"


def table(kind, **kv):
    return "\n".join([f"[[{kind}]]"] + [f"{k} = {_toml(v)}" for k, v in kv.items()]) + "\n"


def _toml(v):
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml(x) for x in v) + "]"
    return repr(float(v)) if isinstance(v, float) else repr(v)


def time_table(dt, end, every=1):
    return f"[time]\ndt = {dt!r}\nend = {end!r}\n[output]\nevery = {every}\n"


class Result:
    """All datasets and root attributes of a result file, as numpy."""

    def __init__(self, path):
        self.path = str(path)
        self.data, self.attrs = {}, {}
        with h5py.File(path, "r") as f:
            f.visititems(lambda name, obj: self.data.__setitem__(name, obj[()])
                         if isinstance(obj, h5py.Dataset) else None)
            self.attrs = dict(f.attrs)
            self.contact_attrs = {k: dict(f["contact"][k].attrs) for k in f["contact"]}

    def __getitem__(self, key):
        return self.data[key]


def run_text(tmp_path, text, name="case", **kw):
    """Run a case given as TOML text in-process; return its Result."""
    from vstpetsc.run import run
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    case = parse_case(text, source=str(path))
    out = tmp_path / f"{name}.h5"
    run(case, str(out), quiet=True, out=io.StringIO(), **kw)
    return Result(out)


@contextlib.contextmanager
def petsc_options(**values):
    """Set PETSc options for the solvers created inside the block."""
    from petsc4py import PETSc
    opts = PETSc.Options()
    for k, v in values.items():
        opts[k] = v
    try:
        yield
    finally:
        for k in values:
            del opts[k]


def cli(*args, cwd=None, timeout=120):
    """Run the vstpetsc command; return the CompletedProcess."""
    return subprocess.run([VSTPETSC, *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=timeout)


@pytest.fixture
def rng():
    return np.random.default_rng(12345)
