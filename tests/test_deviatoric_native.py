"""The compiled slab integrals of the plane-strain MKZ-Masing law
(vstpetsc/native/deviatoric.c) against their Python twin
(vstpetsc.materials.deviatoric_slab.slab_integrals, the reference):

- from random mixed states (30 committed slabs of every kind: reversals at
  slab starts, turns inside, rejoins), for slabs that load, reverse and
  turn: the same decisions at every point, Q within 1e-12 of the point's
  largest |Q|, dQ/dD within 1e-12 of dt G (the linear slab tangent's
  scale, as tests/test_deviatoric_slab.py);
- with decisions kept (frozen) and D moved: the same;
- driven separately through 20 slabs, the two states (strains, stresses,
  stacks, depths) agree to rounding and their decisions stay the same;
- a yielding run with a joint: ``-vst_native 0`` against the default
  within 1e-8 of each dataset's largest value (both Newtons converge to
  1e-12 of the residual's scale).

Why rounding only: the kernel sums in its own order and calls the C
library's pow where numpy uses its SIMD pow (tests/agreement.py:
TRANSCENDENTAL_RTOL a call); the differences measured here are below
1e-15 of |Q| and 2e-14 of dt G.
"""

import copy

import h5py
import numpy as np
import pytest

from test_deviatoric_slab import DT, random_laws, wander
from test_plane_yielding import column, run
from vstpetsc.materials import deviatoric as dv
from vstpetsc.materials import deviatoric_slab as ds
from vstpetsc.native import library

pytestmark = pytest.mark.skipif(library() is None, reason="the compiled library is not built")
TOL = 1e-12


def native():
    from vstpetsc.native.deviatoric import NativeSlabIntegrals

    return NativeSlabIntegrals(library())


def compare(law, Q, dQ, Qc, dQc):
    scale_q = np.abs(Q).max(axis=(1, 2))[:, None, None]
    assert np.all(np.abs(Q - Qc) <= TOL * scale_q)
    scale_d = DT * law.backbone.G[:, 0][:, None, None, None, None]
    assert np.all(np.abs(dQ - dQc) <= TOL * scale_d)
    return float(np.max(np.abs(Q - Qc) / scale_q)), float(np.max(np.abs(dQ - dQc) / scale_d))


def mixed_state(rng, n=3000):
    law = dv.PlaneMasing(*random_laws(rng, n))
    motion = wander(rng, law, 30, 2.0)
    return law, motion


def increments(rng, law, scale=2.0):
    gr = law.backbone.gamma_ref
    D1 = rng.normal(size=(law.K.size, 3)) * scale * gr
    return D1, D1 + rng.normal(size=D1.shape) * scale * gr


def test_the_kernel_is_the_python_slab_to_rounding(rng):
    law, motion = mixed_state(rng)
    kernel = native()
    for _ in range(3):
        D1, D2 = increments(rng, law)
        Q, dQ, path = ds.slab_integrals(law, D1, D2, DT, motion)
        Qc, dQc, pc = kernel(law, D1, D2, DT, motion)
        mine, theirs = path.decisions(), pc.decisions()
        assert not mine.differ(theirs).any()
        assert mine.reverses.sum() > 300 and mine.turned.sum() > 300   # both kinds are there
        print("Q, dQ:", compare(law, Q, dQ, Qc, dQc))
        # residual only: the same Q
        Qr, none, _ = kernel(law, D1, D2, DT, motion, tangent=False)
        assert none is None and np.array_equal(Qr, Qc)


def test_frozen_decisions_give_the_same_slab(rng):
    law, motion = mixed_state(rng)
    kernel = native()
    D1, D2 = increments(rng, law)
    _, _, path = ds.slab_integrals(law, D1, D2, DT, motion)
    kept = path.decisions()
    moved = (D1 * 1.05, D2 * 0.97)          # decisions that the rules would change in places
    Q, dQ, p1 = ds.slab_integrals(law, *moved, DT, motion, frozen=kept)
    Qc, dQc, p2 = kernel(law, *moved, DT, motion, frozen=kept)
    assert not p1.decisions().differ(p2.decisions()).any()
    print("frozen Q, dQ:", compare(law, Q, dQ, Qc, dQc))


def test_states_driven_by_each_stay_together(rng):
    law, motion = mixed_state(rng, 2000)
    twin, motion_c = copy.deepcopy(law), motion.copy()
    kernel = native()
    for _ in range(20):
        D1, D2 = increments(rng, law, 1.5)
        _, _, path = ds.slab_integrals(law, D1, D2, DT, motion, tangent=False)
        _, _, pc = kernel(twin, D1, D2, DT, motion_c, tangent=False)
        assert not path.decisions().differ(pc.decisions()).any()
        motion, motion_c = path.commit(), pc.commit()
    scale = np.abs(law.sigma).max()
    assert np.array_equal(law.stack.k, twin.stack.k)
    assert np.allclose(law.eps, twin.eps, rtol=0.0, atol=TOL * np.abs(law.eps).max())
    assert np.allclose(law.sigma, twin.sigma, rtol=0.0, atol=TOL * scale)
    assert np.allclose(law.stack.s, twin.stack.s, rtol=0.0, atol=TOL * scale)
    assert np.allclose(motion, motion_c, rtol=0.0, atol=TOL)


def test_a_run_with_the_python_path_agrees(tmp_path):
    case = column(tmp_path, end=0.25)
    with run(case, tmp_path / "c.h5") as a, run(case, tmp_path / "p.h5", "-vst_native", "0") as b:
        names = []
        a.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
        checked = 0
        for name in names:
            x, y = a[name][...], b[name][...]
            if name == "solver/wall_time" or x.dtype.kind not in "fi":
                continue
            scale = max(float(np.nanmax(np.abs(x), initial=0.0)), 1e-300)
            assert np.nanmax(np.abs(x - y), initial=0.0) <= 1e-8 * scale, name
            checked += 1
        assert checked > 10 and float(np.max(a["field/strain_max"][...])) > 10 * 2.0e-4
