"""vstpetsc's runs keep numpy's BLAS on one thread (issue 29: its threads
only spin on vstpetsc's tiny matrices, and a run with a busy second core
took three times as long, bench/blas_threads.py) and give the user's
setting back."""

import pytest

import vstpetsc
from vstpetsc.runner import driver

threadpoolctl = pytest.importorskip("threadpoolctl")


def blas_threads():
    return [i["num_threads"] for i in threadpoolctl.threadpool_info()
            if i["user_api"] == "blas"]


def test_one_blas_thread_inside_and_the_users_setting_after():
    before = blas_threads()
    with driver.one_blas_thread():
        assert blas_threads() and all(n == 1 for n in blas_threads())
    assert blas_threads() == before


def test_a_run_solves_on_one_blas_thread(tmp_path, monkeypatch):
    from vstpetsc.line.solver import slab_solver

    seen = []
    real = slab_solver.SlabSolver.solve

    def solve(self, k):
        seen.append(max(blas_threads()))
        return real(self, k)
    monkeypatch.setattr(slab_solver.SlabSolver, "solve", solve)
    before = blas_threads()
    case = vstpetsc.Case.from_dict({"time": {"dt": 1e-5, "end": 1e-4},
                                    "body": [{"name": "b", "x": [0.0, 1.0], "elements": 4,
                                              "E": 1e9, "rho": 1000.0, "v0": 1.0}]})
    vstpetsc.run(case, output=str(tmp_path / "r.h5"), quiet=True)
    assert seen and set(seen) == {1}
    assert blas_threads() == before
