"""The interface pairs' slab kernels (vstpetsc.plane.pair_kernels): the
compiled loop over all pairs (native/plane_pairs.c) against the 1-D laws'
Python kernels pair by pair, on random states that open, close, stick and
slide; and a closed, sticking pair's terms are the slab algebra of its
springs, W = k dt^2 HK (what A_c holds, vstpetsc.plane.pairs)."""

import numpy as np
import pytest

from vstpetsc import native
from vstpetsc.plane import pair_kernels as pk
from vstpetsc.spacetime.slab import HK

DT = 1e-3


def random_pairs(rng, m, power):
    w = rng.uniform(1e8, 1e10, m) * (1.0 if power else 2.0 / DT)
    kt = np.where(rng.random(m) < 0.2, 0.0, rng.uniform(1e9, 1e11, m))
    return (w, kt, rng.uniform(0.0, 0.8, m)), (rng.normal(0.0, 1e-5, m),
                                               rng.normal(0.0, 1e-2, (m, 4)),
                                               rng.normal(0.0, 1e-7, m))


@pytest.mark.skipif(native.library() is None, reason="the native library is not built")
@pytest.mark.parametrize("power", [True, False], ids=["power", "seed"])
def test_compiled_pairs_are_the_python_kernels(power):
    """Built with -ffp-contract=off and the same operations in the same
    order as the Python kernels (native/coulomb.h, pair.h): bit for bit."""
    rng = np.random.default_rng(7)
    laws, state = random_pairs(rng, 3000, power)
    compiled = pk.PairKernels(*laws, DT, power).evaluate(*state).copy()
    python = pk.PairKernels(*laws, DT, power, compiled=False).evaluate(*state)
    acted, slid = python[:, pk.ACTED] > 0, python[:, pk.SLIP] != 0
    assert 0.2 < acted.mean() < 0.8 and slid.sum() > 100        # every regime is there
    assert np.array_equal(compiled, python)


def test_a_closed_sticking_pair_is_its_springs():
    w, kt = 3.0e9, 5.0e9
    kernel = pk.PairKernels([w], [kt], [0.5], DT, True, compiled=False)
    # pressed by 1 mm, closing slowly, sheared a little: closed and elastic all slab
    out = kernel.evaluate(np.array([-1e-3]), np.array([[1e-4, 2e-4, 1e-5, -1e-5]]),
                          np.array([1e-6]))[0]
    assert out[pk.ACTED] == 1.0 and out[pk.SLIP] == 0.0
    np.testing.assert_allclose(out[pk.W_N].reshape(2, 2), w * DT * DT * HK, rtol=1e-14)
    np.testing.assert_allclose(out[pk.W_T].reshape(2, 2), kt * DT * DT * HK, rtol=1e-12)
