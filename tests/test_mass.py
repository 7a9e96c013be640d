"""The element mass matrix per body (`mass` = "consistent", "averaged",
"lumped"): the same total mass, and the dispersion orders the theory gives
(the first modes of a fixed-free bar: frequency error of order 2 for the
consistent and lumped matrices, 4 for their average)."""

import numpy as np
import pytest

from conftest import bar, make_case

from vstpetsc.line import model as model_mod


def fixed_free(elements, mass):
    case = make_case(1e-3, 1e-2, [bar("bar", [0.0, 1.0], elements, E=1.0, rho=1.0, mass=mass)],
                     bcs=[{"body": "bar", "end": "left", "type": "fixed"}])
    return model_mod.build_model(case)


@pytest.mark.parametrize("mass", ["consistent", "averaged", "lumped"])
def test_every_mass_matrix_carries_the_bar_s_mass(mass):
    ops = fixed_free(7, mass).ops
    total = ops.m_diag.sum() + 2.0 * ops.m_off.sum()
    assert total == pytest.approx(1.0, rel=1e-14)


@pytest.mark.parametrize("mass, order", [("consistent", 2), ("averaged", 4), ("lumped", 2)])
def test_frequency_error_order(mass, order):
    """The third mode's frequency against the exact (2 k - 1) pi / 2."""
    errors = []
    for n in (20, 40, 80):
        w2, _, _ = model_mod.modes(fixed_free(n, mass).ops, fixed_nodes=[0])
        errors.append(abs(np.sqrt(w2[2]) / (5.0 * np.pi / 2.0) - 1.0))
    fitted = np.log2(errors[1] / errors[2])
    assert abs(fitted - order) <= 0.1


def test_averaged_is_the_default():
    default = fixed_free(5, "averaged").ops
    case = make_case(1e-3, 1e-2, [bar("bar", [0.0, 1.0], 5, E=1.0, rho=1.0)])
    ops = model_mod.build_model(case).ops
    assert np.array_equal(ops.m_diag[1:-1], default.m_diag[1:-1])
    assert np.array_equal(ops.m_off, default.m_off)


def test_an_unknown_mass_matrix_is_refused(tmp_path):
    from conftest import cli, write_case
    case = make_case(1e-3, 1e-2, [bar("bar", [0.0, 1.0], 5)])
    path = write_case(tmp_path, case)
    path.write_text(path.read_text().replace('elements = 5', 'elements = 5\nmass = "heavy"'))
    out = cli("run", path, "-o", tmp_path / "r.h5")
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1
    assert "body[0] (bar).mass: must be one of 'consistent', 'averaged', 'lumped'" in out.stderr
