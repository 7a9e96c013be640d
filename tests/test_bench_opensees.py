"""bench/opensees.py's pure helpers: the choice of the cheapest run and
its README section (speed is reported by `make bench`, never asserted;
the problems' exact solutions are checked in test_waves_reference.py).
The OpenSees model itself only where openseespy is installed."""

import importlib.util
import math
import os
import sys

import pytest

from conftest import ROOT
from references import waves

sys.path.insert(0, os.path.join(ROOT, "bench"))
import opensees as bench  # noqa: E402


def test_cheapest_is_the_least_work_that_meets_the_target():
    rows = [{"elements": 8, "steps": 90, "error": 2e-3},
            {"elements": 16, "steps": 50, "error": 5e-4},
            {"elements": 8, "steps": 400, "error": 4e-4},
            {"elements": 4, "steps": 10, "error": None}]
    assert bench.cheapest(rows, 1e-3) is rows[1]
    assert bench.cheapest(rows, 4.5e-4) is rows[2]
    assert bench.cheapest(rows, 3e-3) is rows[0]
    assert bench.cheapest(rows, 1e-4) is None


def test_readme_section_is_replaced_and_the_rest_kept(tmp_path):
    path = tmp_path / "README.md"
    path.write_text("# Benchmarks\n\n## A\n\na\n")
    bench.write_readme(str(path), bench.SECTION + "\n\nold\n")
    path.write_text(path.read_text() + "\n## B\n\nb\n")
    bench.write_readme(str(path), bench.SECTION + "\n\nnew\n")
    assert path.read_text() == ("# Benchmarks\n\n## A\n\na\n\n" + bench.SECTION
                                + "\n\nnew\n\n## B\n\nb\n")


@pytest.mark.skipif(importlib.util.find_spec("openseespy") is None,
                    reason="openseespy is installed for `make bench` only")
def test_opensees_wave_has_newmarks_period_error():
    """Newmark average acceleration at c dt/h = r with lumped mass lengthens
    the period by delta = (kh)^2 (1/24 + r^2/12) (mass and time step alike);
    over two periods (omega t_end = 4 pi) the tip's relative L2 error is
    then 4 pi delta / sqrt(3). With consistent mass at r = 1/sqrt(2) the
    two h^2 terms cancel (the issue's Courant number)."""
    child = bench.OpenSeesChild()
    try:
        err = {m: child(waves.job_for("wave", {"mass": m}, 16, bench.SQRT_HALF))[1]["error"]
               for m in ("consistent", "lumped")}
    finally:
        child.close()
    kh = 0.5 * math.pi / 16
    delta = kh ** 2 * (1 / 24 + 0.5 / 12)
    assert err["lumped"] == pytest.approx(4 * math.pi * delta / math.sqrt(3), rel=0.05)
    assert err["consistent"] < 0.1 * err["lumped"]
