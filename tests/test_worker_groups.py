"""`make test` runs the suite on two pytest-xdist workers, and the tests
that start several ranks all on one of them (tests/conftest.py): their
ids carry the group ``@mpi`` that --dist loadgroup deals by.  Without it
each worker started its own mpirun, four ranks on two cores, and the
two-rank runs timed out."""

import os
import subprocess
import sys

import pytest

from conftest import ROOT

pytest.importorskip("xdist")


def test_the_tests_of_several_ranks_share_one_worker():
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST_")}
    p = subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-n", "2",
                        "--dist", "loadgroup", "--setup-only", "-v", "tests/test_plane_run.py",
                        "-k", "restart_on_two_ranks or dry_run"],
                       cwd=ROOT, env=env, capture_output=True, text=True, timeout=240)
    ids = sorted(line.split()[0].split("::")[1] for line in p.stdout.splitlines()
                 if line.startswith("tests/test_plane_run.py::"))
    assert ids == ["test_a_dry_run_reads_and_checks_the_mesh"] + [
        f"test_a_restart_on_two_ranks_continues_the_run[{name}]@mpi"
        for name in ("blocks", "default", "mumps", "redundant")], p.stdout + p.stderr
