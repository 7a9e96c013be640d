"""tests/references/yielding_interface.py, the explicit reference for MKZ
soil and Coulomb friction in one run, checked on its own: against the two
references it combines (mkz.py, coulomb_column.py) in the limits where it
must reduce to them, its energy balance, and convergence under refinement.

The cases: a column H = 10 m, rho = 2000 kg/m^3, Vs = 200 m/s, A = 1 m^2,
MKZ beta = 1, s = 0.919.
(a) on rigid ground through a Coulomb base, mu = 0.2, N = rho A H g; the
    ground velocity a triangle 0 -> 1 m/s at 0.4 s -> 0 at 0.8 s (ground
    acceleration +-2.5 m/s^2 > mu g); gamma_ref = 5e-4: the soil strains
    to about 10 gamma_ref and the base slides both ways (final slip 2 cm).
(b) on a Lysmer base (rock 2400 kg/m^3, 800 m/s) with the incident
    velocity 0.3 sin^2(pi t / 0.5) m/s for 0.5 s (outcrop peak 0.6 m/s),
    gamma_ref = 1e-3, carrying a 2400 kg point-mass block (1 m of rho
    2400) across mu = 0.2, N = its weight: the soil strains to about
    10 gamma_ref and the block slips (final 2.3 cm).
"""

import math

import numpy as np
import pytest

from references import coulomb_column as cc
from references import mkz
from references import yielding_interface as yi

G_ACC = 9.81
H, RHO, VS, AREA, BETA, S, MU = 10.0, 2000.0, 200.0, 1.0, 1.0, 0.919, 0.2
NORMAL = RHO * AREA * H * G_ACC
GROUND = ([0.0, 0.4, 0.8, 2.0], [0.0, 1.0, 0.0, 0.0])
ROCK_Z = 2400.0 * 800.0
_T_IN = np.linspace(0.0, 0.5, 201)
INCIDENT = (_T_IN, 0.3 * np.sin(np.pi * _T_IN / 0.5) ** 2)
BLOCK = yi.Block(1.0, 0, 2400.0)
END = 2.0


def on_base(elements, gamma_ref=5.0e-4, mu=MU, dt_factor=1.0):
    """Case (a) with dt = 0.5 h / Vs times dt_factor."""
    dt = dt_factor * 0.5 * H / elements / VS
    return yi.column_on_coulomb_base(H, elements, RHO, VS, AREA, gamma_ref, BETA, S, mu,
                                     NORMAL, *GROUND, END, dt=dt)


def under_block(elements, mu=MU, block=BLOCK, dt_factor=1.0, end=END):
    """Case (b) with dt = 0.5 h / Vs times dt_factor."""
    dt = dt_factor * 0.5 * H / elements / VS
    return yi.block_on_yielding_column(H, elements, RHO, VS, AREA, 1.0e-3, BETA, S, block,
                                       mu, ROCK_Z, *INCIDENT, end, dt=dt)


def scale(x):
    return np.abs(x).max()


def test_welded_base_is_the_mkz_column():
    """(i) mu = inf: mkz.py's column on RigidBase, the same operations, so
    the motion and the soil's energies are equal bit for bit; the input
    work differs only by the first step's convention (the ground's velocity
    at t_0 here and coulomb_column.py's, the mean over the first half kick
    in mkz.py): measured 5.0e-8 of the input. (Welded, this soil strains
    to 100 gamma_ref at the base.)"""
    ours = on_base(20, mu=math.inf)
    column = mkz.Column.uniform(H, 20, RHO, VS, 5.0e-4, BETA, S)
    ref = mkz.run_column(column, mkz.RigidBase(*GROUND), END, dt=ours.dt)
    assert ours.peak_strain.max() > 5.0 * 5.0e-4               # it yields
    pairs = ((ours.v_top, ref.surface_velocity), (ours.a_top, ref.surface_acceleration),
             (ours.v_base, ref.base_velocity), (ours.kinetic, ref.kinetic),
             (ours.stored, ref.stored), (ours.internal_work, ref.internal_work),
             (ours.peak_strain, ref.peak_strain))
    for mine, theirs in pairs:
        np.testing.assert_array_equal(mine, theirs)
    assert np.all(ours.slip == 0.0) and np.all(ours.friction == 0.0)
    assert scale(ours.input - ref.input) < 1e-6 * scale(ref.input)


def test_linear_soil_is_the_coulomb_column():
    """(ii) gamma_ref = inf: coulomb_column.py's column, the same up to the
    rounding of G (dw / h) against (G / h) dw: measured 2.4e-14 of the
    slip, 1.0e-14 of the friction energy, 6.1e-12 of the base force (its
    largest); it slides both ways (+2.0 cm, -6.3 cm)."""
    ours = on_base(20, gamma_ref=math.inf)
    ref = cc.column_on_coulomb_base(H, 20, RHO, VS, AREA, MU, NORMAL, *GROUND, END,
                                    dt=ours.dt)
    assert ref.slip.max() > 0.01 and ref.slip.min() < -0.01
    pairs = ((ours.slip, ref.slip), (ours.slip_rate, ref.slip_rate),
             (ours.shear_force, ref.base_shear), (ours.v_top, ref.top_velocity),
             (ours.friction, ref.friction_energy), (ours.kinetic, ref.kinetic_energy),
             (ours.stored, ref.strain_energy), (ours.input, ref.ground_work))
    for mine, theirs in pairs:
        assert scale(mine - theirs) < 1e-10 * scale(theirs)
    assert scale(ours.hysteretic) < 1e-12 * scale(ours.input)


def test_welded_block_is_a_layered_mkz_column():
    """(i) for (b): an elastic block welded on (mu = inf) is the top layer
    (gamma_ref = inf) of mkz.py's layered column on the same Lysmer base;
    the pair's node is updated as one (momentum-conserving common velocity):
    equal to rounding, measured at most 9.4e-13 of each quantity's scale
    (the block top's velocity)."""
    block = yi.Block(1.0, 2, 2400.0, 400.0)
    ours = under_block(20, mu=math.inf, block=block, dt_factor=0.5)
    column = mkz.Column.layered([(H, RHO, VS, 1.0e-3, BETA, S),
                                 (1.0, 2400.0, 400.0, math.inf, 1.0, 1.0)], 0.5)
    ref = mkz.run_column(column, mkz.LysmerBase(ROCK_Z, *INCIDENT), END, dt=ours.dt)
    assert ours.peak_strain.max() > 5.0 * 1.0e-3 and np.all(ours.slip == 0.0)
    pairs = ((ours.v_block_top, ref.surface_velocity), (ours.v_base, ref.base_velocity),
             (ours.internal_work, ref.internal_work), (ours.stored, ref.stored),
             (ours.kinetic, ref.kinetic), (ours.input, ref.input),
             (ours.dashpot, ref.dashpot), (ours.peak_strain, ref.peak_strain[:20]))
    for mine, theirs in pairs:
        assert scale(mine - theirs) < 1e-11 * scale(theirs)


def test_frictionless_block_leaves_the_column_alone():
    """mu = 0: the block stays at rest, the column is mkz.py's alone on the
    Lysmer base, bit for bit, and the slip is minus its top's displacement."""
    ours = under_block(20, mu=0.0)
    column = mkz.Column.uniform(H, 20, RHO, VS, 1.0e-3, BETA, S)
    ref = mkz.run_column(column, mkz.LysmerBase(ROCK_Z, *INCIDENT), END, dt=ours.dt)
    np.testing.assert_array_equal(ours.v_top, ref.surface_velocity)
    np.testing.assert_array_equal(ours.internal_work, ref.internal_work)
    np.testing.assert_array_equal(ours.input, ref.input)
    assert np.all(ours.v_block == 0.0) and np.all(ours.friction == 0.0)
    np.testing.assert_array_equal(ours.slip, -ours.w_top)
    assert scale(ours.slip) > 1e-3


REFINE = (10, 20, 40, 80)


@pytest.fixture(scope="module")
def base_runs():
    return {n: on_base(n) for n in REFINE}


@pytest.fixture(scope="module")
def block_runs():
    return {n: under_block(n) for n in REFINE}


def check_friction_law(run, limit):
    """|T| <= mu N; the friction energy is mu N times the slip path and
    never decreases."""
    assert scale(run.shear_force) <= limit * (1.0 + 1e-12)
    path = np.concatenate(([0.0], np.cumsum(np.abs(np.diff(run.slip)))))
    assert scale(run.friction - limit * path) < 1e-12 * run.friction[-1]
    assert np.all(np.diff(run.friction) >= -1e-12 * run.friction[-1])


def test_energy_balance_on_the_coulomb_base(base_runs):
    """(iii) (a), 20 elements: input = kinetic + stored + hysteretic +
    friction to 5.2e-6 of the input (its largest residual, a boundary term
    of leapfrog's half-step identity); the residual falls by 4.00 per
    halving of dt at this mesh. Hysteresis takes 13 % of the input,
    friction 87 %; peak strain 10 gamma_ref."""
    run = base_runs[20]
    residual = scale(run.energy_residual())
    assert residual < 2e-5 * scale(run.input)
    assert 0.05 < run.hysteretic[-1] / run.input[-1] < 0.3
    assert 0.6 < run.friction[-1] / run.input[-1] < 0.95
    assert run.peak_strain.max() > 5.0 * 5.0e-4
    check_friction_law(run, MU * NORMAL)
    finer = on_base(20, dt_factor=0.5)
    assert 3.5 < residual / scale(finer.energy_residual()) < 4.5


def test_energy_balance_under_the_block(block_runs):
    """(iii) (b), 20 elements: input = kinetic + stored + hysteretic +
    friction + dashpot to 6.3e-7 of the input (which mostly leaves through
    the dashpot again: 2.3e-5 of hysteretic + friction); the residual falls
    by 4.09, 4.03 per halving of dt. The block's friction takes 0.42 % of
    the input, hysteresis 2.3 %, the dashpot 97 %; peak strain 9.7 gamma_ref."""
    run = block_runs[20]
    residual = scale(run.energy_residual())
    assert residual < 1e-5 * scale(run.input)
    assert residual < 1e-4 * (run.hysteretic[-1] + run.friction[-1])
    assert run.friction[-1] > 0.002 * run.input[-1] and run.hysteretic[-1] > 0.01 * run.input[-1]
    assert run.peak_strain.max() > 5.0 * 1.0e-3
    check_friction_law(run, MU * BLOCK.rho * AREA * BLOCK.length * G_ACC)
    finer = under_block(20, dt_factor=0.5)
    assert 3.5 < residual / scale(finer.energy_residual()) < 5.0


def observed_changes(runs):
    """max |slip_h - slip_2h| over the coarser run's times, per halving of
    h and dt together (every coarse time is a fine one)."""
    changes = []
    for coarse, fine in zip(REFINE, REFINE[1:]):
        assert np.allclose(runs[fine].t[::2], runs[coarse].t, rtol=0.0, atol=1e-12)
        changes.append(scale(runs[fine].slip[::2] - runs[coarse].slip))
    return np.array(changes)


def test_slip_converges_on_the_coulomb_base(base_runs):
    """(iv) (a): halving h and dt (0.5 h / Vs) from 10 to 80 elements
    changes the slip history by 5.0e-4, 1.8e-4, 5.8e-5 m (final slip 1.97 cm,
    largest 6.6 cm):
    observed order 1.52, 1.59."""
    changes = observed_changes(base_runs)
    orders = np.log2(changes[:-1] / changes[1:])
    assert changes[-1] < 5e-3 * scale(base_runs[80].slip)
    assert np.all(orders > 1.2)


def test_slip_converges_under_the_block(block_runs):
    """(iv) (b): halving h and dt from 10 to 80 elements changes the
    block's slip history by 2.3e-4, 4.9e-5, 1.8e-5 m (final slip 2.30 cm,
    largest 4.4 cm):
    observed order 2.2, 1.4 (1.7 to 160 elements)."""
    changes = observed_changes(block_runs)
    orders = np.log2(changes[:-1] / changes[1:])
    assert changes[-1] < 1e-3 * scale(block_runs[80].slip)
    assert np.all(orders > 1.0)


def test_stiff_elastic_block_tends_to_the_point_mass():
    """(b) with the block an elastic chain (two elements, 1 m, rho 2400):
    as its Vs goes 500 -> 2000 m/s its slip history (to 1 s, dt = 1e-4 s,
    20 column elements) comes within 2.2e-3, then 5.3e-4 of the point
    mass's largest slip (4.4 cm), and the energy still balances (residual
    1.4e-7 of hysteretic + friction)."""
    factor = 1.0e-4 / (0.5 * H / 20 / VS)
    point = under_block(20, dt_factor=factor, end=1.0)
    gaps = []
    for vs in (500.0, 2000.0):
        run = under_block(20, block=yi.Block(1.0, 2, 2400.0, vs), dt_factor=factor, end=1.0)
        gaps.append(scale(run.slip - point.slip) / scale(point.slip))
        assert scale(run.energy_residual()) < 1e-6 * (run.hysteretic[-1] + run.friction[-1])
    assert gaps[1] < gaps[0] / 2.5 and gaps[1] < 1e-3
