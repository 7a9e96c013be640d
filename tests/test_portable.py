"""tests/portable.py (`make test-portable`): its settings narrow only what
this CPU has, and a library of the C kernels built for another CPU is the
one a run loads when VSTPETSC_NATIVE_LIB names it."""

import os
import subprocess
import sys

import numpy.core._multiarray_umath as umath
import portable
from conftest import ROOT

LOADED = ("from vstpetsc import native; lib = native.library(); "
          "print(native.LIBRARY, lib is not None)")


def test_settings_switch_off_only_dispatched_features_of_this_cpu():
    names = set()
    for name, off, core, march in portable.settings():
        env = portable.environment(off, core, "lib.so")
        disabled = env["NPY_DISABLE_CPU_FEATURES"].split()
        assert set(disabled) <= set(umath.__cpu_dispatch__), name
        assert all(umath.__cpu_features__[f] for f in disabled), name
        names.add(name)
    assert len(names) == len(portable.settings()) >= 1


def test_a_library_built_for_the_baseline_is_loaded_by_name(tmp_path, monkeypatch):
    monkeypatch.setattr(portable, "BUILD", str(tmp_path))
    lib = portable.build("x86-64")
    env = dict(os.environ, VSTPETSC_NATIVE_LIB=lib)
    p = subprocess.run([sys.executable, "-c", LOADED], cwd=ROOT, env=env,
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and p.stdout.split() == [lib, "True"], p.stderr


def test_a_library_named_but_missing_is_an_error_not_the_python_path(tmp_path):
    name = "missing.so"
    env = dict(os.environ, VSTPETSC_NATIVE_LIB=str(tmp_path / name))
    p = subprocess.run([sys.executable, "-c", LOADED], cwd=ROOT, env=env,
                       capture_output=True, text=True, timeout=60)
    assert p.returncode != 0 and name in p.stderr
