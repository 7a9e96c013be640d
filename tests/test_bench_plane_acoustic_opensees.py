"""bench/plane_acoustic_opensees.py: the motion both codes get, the face's
flux loads, the equal-error interpolation, and, where openseespy is
installed, that OpenSees' AC3D8 reservoir meets Chopra's closed form
(speed is reported by `make bench`, never asserted)."""

import importlib.util
import os
import sys

import numpy as np
import pytest

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "bench"))
import plane_acoustic_opensees as bench  # noqa: E402

needs_opensees = pytest.mark.skipif(importlib.util.find_spec("openseespy") is None,
                                    reason="openseespy is installed for `make bench` only")


def test_the_acceleration_is_the_velocity_s_derivative():
    """OpenSees' table is dv/dt of vstpetsc's (central differences)."""
    t = np.linspace(0.0, bench.end_time(0.5), 20001)
    v = bench.face_velocity(0.5, t)
    dv = np.gradient(v, t)
    a = bench.face_acceleration(0.5, t)
    assert np.abs(dv - a)[1:-1].max() < 1e-5 * np.abs(a).max()


class Loads:
    """A stand-in for openseespy's module recording the face's loads."""

    def __init__(self):
        self.loads = {}

    def timeSeries(self, *args):
        pass

    def pattern(self, *args):
        pass

    def load(self, tag, value):
        self.loads[tag] = value


def test_the_face_loads_sum_to_the_face_s_area():
    """The tributary areas of the face's free nodes sum to H x 1 less the
    held surface node's h / 2 (its share goes to the fixed pressure)."""
    ops = Loads()
    bench.opensees_face(ops, 0.5, 10)
    assert len(ops.loads) == 20
    assert sum(ops.loads.values()) == pytest.approx(bench.H - 0.5 * bench.H / 10)


def test_the_time_at_a_target_is_interpolated_on_the_frontier():
    rows = [{"error": 1e-2, "time_min": 1.0}, {"error": 1e-3, "time_min": 10.0},
            {"error": 2e-2, "time_min": 20.0}]          # the last is beaten by the first
    assert [r["error"] for r in bench.frontier(rows)] == [1e-3, 1e-2]
    assert bench.time_at(rows, 10 ** -2.5) == pytest.approx(10 ** 0.5)
    assert bench.time_at(rows, 0.5) == 1.0
    assert bench.time_at(rows, 1e-4) is None


@needs_opensees
def test_opensees_meets_chopra_below_the_cut_off():
    """OpenSees in the bench's child at h = H/10, 80 steps a period: the
    heel's amplitude within 2e-3 of the closed form (measured 1.27e-3:
    its lumped mass's space error)."""
    child = bench.OpenSeesChild()
    try:
        child.system = "ProfileSPD"
        _, error = child({"ratio": 0.5, "cells": 10, "steps": 80})
    finally:
        child.close()
    assert error < 2e-3
