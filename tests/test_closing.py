"""The compiled end of a slab on one rank (vstpetsc.line.native.closing) does
what the Python path does: u, v, the elongations and their envelopes and
b += G z bit for bit, the energies to rounding (numpy's dot sums in
blocks); whole runs are bit for bit but for the energies."""

import numpy as np
import pytest
from petsc4py import PETSc

from conftest import bar, make_case, solve
from vstpetsc.line.energy import LineEnergyBook as EnergyBook
from vstpetsc.line.model import build_model
from vstpetsc.line.native.closing import SlabClose
from vstpetsc.petsc.options import SolverOptions
from vstpetsc.line.solver.slab_solver import SlabSolver


def two_bodies():
    """Two bars of other materials, one damped on a foundation, one end
    fixed: every band of G and every term of the energies is used."""
    return make_case(0.004, 0.2, [bar("a", (0.0, 1.0), 30, E=2.0, rho=1.5, v0=1.0,
                                      damping={"alpha": 0.3, "beta": 0.01},
                                      foundation={"stiffness": 0.5, "damping": 0.2}),
                                  bar("b", (1.1, 2.0), 20, E=1.0, rho=1.0)],
                     bcs=[dict(body="a", end="left", type="fixed")])


def solvers(case):
    """(compiled, Python) SlabSolvers of ``case`` on one rank."""
    model = build_model(case)
    out = [SlabSolver(model, case.dt, PETSc.COMM_SELF, SolverOptions(native=flag))
           for flag in (True, False)]
    assert isinstance(out[0].end, SlabClose) and not isinstance(out[1].end, SlabClose)
    return model, out


def test_one_close_against_the_python_path(rng):
    model, (c, p) = solvers(two_bodies())
    n = model.mesh.nnodes
    u0, v0 = rng.normal(size=n), rng.normal(size=n)
    for s in (c, p):
        s.set_state(u0, v0)
    b0 = c.br.copy()
    assert np.array_equal(b0, p.br)
    book = EnergyBook(model)
    for _ in range(3):                  # the envelopes move on every slab
        z = rng.normal(size=2 * n)
        for s in (c, p):
            s.x[:] = z
            s.advance()
        (uc, vc), (up, vp) = c.gather_state(), p.gather_state()
        assert np.array_equal(uc, up) and np.array_equal(vc, vp)
        assert np.array_equal(c.elongation(), p.elongation())
        assert np.array_equal(c.envelope.lo, p.envelope.lo)
        assert np.array_equal(c.envelope.hi, p.envelope.hi)
        assert np.array_equal(c.br, p.br)
        ours = book.state(up, vp, p.elongation())
        kinetic, strain = c.state_energies()
        assert kinetic == pytest.approx(ours["kinetic"], rel=1e-13)
        assert strain == pytest.approx(ours["strain"], rel=1e-13)
    assert not np.array_equal(c.envelope.lo, c.envelope.hi)


def test_whole_runs_are_the_python_runs(tmp_path):
    case = two_bodies()
    a = solve(tmp_path, case, "c")
    b = solve(tmp_path, case, "p", options=["-vst_native", "0"])
    for key in ("body/a/u", "body/a/v", "body/b/stress", "body/a/stress_max",
                "energy/damping"):
        assert np.array_equal(a[key], b[key]), key
    for key in ("energy/kinetic", "energy/strain"):
        x, y = a[key], b[key]
        assert np.abs(x - y).max() <= 1e-13 * np.abs(x).max(), key


@pytest.mark.parametrize("n", [1, 2, 7, 10])
def test_row_copier_writes_numpys_rows(rng, n):
    """Copies and products into every row of 2-D buffers, whatever the
    alignment of the row (odd sizes: every other row starts between
    16-byte boundaries), equal to numpy's bit for bit."""
    from vstpetsc.native.rows import RowCopier

    values, other, factor = rng.normal(size=n), rng.normal(size=n + 1), rng.normal(size=n)
    copier = RowCopier.of([(values, None), (other, None), (values, factor)])
    targets = [np.zeros((3, n)), np.zeros((3, n + 1)), np.zeros((3, n))]
    copier.bind(targets)
    expected = []
    for i in range(3):
        copier.post(i)
        expected.append((values.copy(), other.copy(), values * factor))
        values += 1.0
        other -= 1.0
    for i, rows in enumerate(expected):
        for target, row in zip(targets, rows):
            assert np.array_equal(target[i], row)
    with pytest.raises(IndexError):
        copier.post(3)
    with pytest.raises(ValueError):
        copier.bind([np.zeros((3, n)), np.zeros((3, n)), np.zeros((3, n))])
