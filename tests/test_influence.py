"""The laws' terms go back into the unknowns only where their columns of
A^-1 are not zero (vstpetsc.line.solver.influence): the same numbers as
PETSc's VecMAXPY over the whole vector."""

import numpy as np
import pytest
from petsc4py import PETSc

from conftest import bar, make_case
from vstpetsc.line.model import build_model
from vstpetsc.line.solver.influence import groups_of
from vstpetsc.petsc.options import SolverOptions
from vstpetsc.line.solver.slab_solver import SlabSolver


def test_groups_merge_chains_of_overlaps():
    spans = [(0, 10), (50, 60), (5, 20), (19, 30), (100, 90)]     # the last is empty
    assert groups_of(spans) == [(0, 30, [0, 2, 3]), (50, 60, [1])]


def held_bar(elements, walls=2, gap=0.0):
    contacts = [dict(pair=["bar", "wall"], wall=1.0 + gap),
                dict(pair=["wall", "bar"], wall=-gap)][:walls]
    return make_case(0.5 / elements, 1.0, [bar("bar", (0.0, 1.0), elements, E=1.0, rho=1.0,
                                               v0=1.0)], contacts=contacts)


@pytest.mark.parametrize("elements, groups", [(40, 1), (4000, 2)])
def test_update_on_spans_equals_maxpy(elements, groups, rng):
    case = held_bar(elements)
    s = SlabSolver(build_model(case), case.dt, PETSc.COMM_SELF, SolverOptions())
    laws = s.nonlinear
    assert len(laws.influence.groups) == groups
    for _ in range(5):
        s.x[:] = rng.normal(size=s.x.size)
        start = s.x.copy()
        f = rng.normal(size=4)
        s.X.maxpy(-f, laws.coupling.Zred)
        whole = s.x.copy()
        s.x[:] = start
        laws.influence.subtract(f)
        assert np.array_equal(s.x, whole)
    if groups == 2:       # a long bar: each pair's columns reach a few hundred elements
        assert all(g[0].getSize() < s.x.size / 3 for g in laws.influence.groups)
