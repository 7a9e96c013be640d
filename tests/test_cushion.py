"""The cushion contact formulation: its slab integrals against a brute-force
quadrature of the hysteresis law, its tangent against finite differences,
a nearly rigid ram's rebound e v0 and peak force v0 sqrt(k m), the energy
it keeps, restarts in mid-blow, bad input."""

import io

import numpy as np
import pytest

import vstpetsc
from conftest import assert_tangent, bar, cli, make_case, write_case
from vstpetsc.line.laws.cushion import cushion_integrals


def brute(gn, d1, d2, dt, k, ku, M, n=200001):
    """(f1, f2, M at the end) by sampling the law along the slab: delta,
    its running maximum, the force, trapezoid sums."""
    th = np.linspace(0.0, 1.0, n)
    delta = -gn + d1 * dt * (th - th ** 2 / 2) + d2 * dt * th ** 2 / 2
    top = np.maximum.accumulate(np.maximum(delta, max(M, delta[0])))
    force = np.where(delta >= top, k * delta, np.maximum(0.0, k * top - ku * (top - delta)))
    force = np.maximum(force, 0.0)
    return dt * np.trapz(force * (1 - th), th), dt * np.trapz(force * th, th), top[-1]


def test_slab_integrals_and_tangent(rng):
    dt, k, e = 0.1, 3.0, 0.7
    ku = k / e ** 2
    checked = 0
    for _ in range(80):
        gn, M = rng.uniform(-0.3, 0.3), max(0.0, rng.uniform(-0.2, 0.5))
        d1, d2 = rng.uniform(-5, 5, 2)
        got = cushion_integrals(gn, d1, d2, dt, k, ku, M)
        f1, f2, top = brute(gn, d1, d2, dt, k, ku, M)
        if got is None:
            assert max(abs(f1), abs(f2)) < 1e-12
            continue
        checked += 1
        scale = max(abs(got[0]), abs(got[1]))
        assert abs(got[0] - f1) <= 1e-7 * scale and abs(got[1] - f2) <= 1e-7 * scale
        assert abs(got[6] - top) <= 1e-6
        assert_tangent(lambda a, b: cushion_integrals(gn, a, b, dt, k, ku, M), (d1, d2), got,
                       1e-6, 1e-5, 1e-3)
    assert checked > 30


def ram(e, end=3.0, k=1.0, v0=1.0):
    """A short ram (m = 0.1) whose own wave crosses it in 1e-3, 0.01 from a
    wall: a mass on a spring of period 2 pi sqrt(m / k) = 2."""
    return make_case(1e-3, end, [bar("ram", (0.0, 0.1), 4, E=1e4, rho=1.0, v0=v0)],
                     contacts=[dict(pair=["ram", "wall"], wall=0.11, formulation="cushion",
                                    stiffness=k, restitution=e)])


def mean_velocity(result, row=-1):
    v = result.body("ram").v[row]
    w = np.ones(v.size)
    w[0] = w[-1] = 0.5
    return float((v * w).sum() / w.sum())


@pytest.mark.parametrize("e", [0.5, 0.8, 1.0])
def test_rigid_ram_rebounds_at_e_v0_with_peak_force_v0_sqrt_km(tmp_path, e):
    m, k, v0 = 0.1, 1.0, 1.0
    r = vstpetsc.run(ram(e), output=str(tmp_path / "r.h5"), quiet=True, out=io.StringIO())
    assert abs(-mean_velocity(r) - e * v0) <= 0.01 * e * v0
    assert abs(r.contact(0).force.max() - v0 * np.sqrt(k * m)) <= 0.01 * v0 * np.sqrt(k * m)
    energy = {key: r.energy[key][-1] for key in ("kinetic", "contact", "numerical")}
    brought = 0.5 * m * v0 ** 2
    # the cushion keeps (1 - e^2) of the blow; nothing is left stored once apart
    assert abs(energy["contact"] - (1 - e * e) * brought) <= 1e-4 * brought
    assert abs(energy["numerical"]) <= 1e-6 * brought
    assert r.contact(0).compression_max[-1] == 0.0          # apart: the next blow starts fresh
    assert r.contact(0).episodes[-1] == 1


def test_restart_in_mid_blow_is_bit_for_bit(tmp_path):
    full = vstpetsc.run(ram(0.6), output=str(tmp_path / "full.h5"), quiet=True,
                        out=io.StringIO())
    part = str(tmp_path / "part.h5")
    vstpetsc.run(ram(0.6, end=0.9), output=part, quiet=True, out=io.StringIO())
    assert vstpetsc.Result(part).contact(0).compression_max[-1] > 0     # in unloading
    again = vstpetsc.run(ram(0.6), output=part, restart=True, quiet=True, out=io.StringIO())
    for key in ("force", "compression_max", "impulse_total"):
        assert np.array_equal(again.contact(0)[key], full.contact(0)[key]), key
    assert np.array_equal(again.body("ram").v[-1], full.body("ram").v[-1])


@pytest.mark.parametrize("extra, words", [
    ({"stiffness": 1.0, "restitution": 1.5}, "contact[0].restitution: must lie in (0, 1]"),
    ({"stiffness": 1.0, "restitution": 0.0}, "contact[0].restitution"),
    ({"restitution": 0.8}, "contact[0].stiffness: missing"),
    ({"stiffness": 1.0, "penalty": 3.0}, "contact[0].penalty: unknown key"),
])
def test_bad_cushion_tables(tmp_path, extra, words):
    doc = ram(0.8).to_dict()
    doc["contact"][0] = {"pair": ["ram", "wall"], "wall": 0.11, "formulation": "cushion",
                         **extra}
    path = tmp_path / "bad.toml"
    path.write_text(vstpetsc.input.toml_text.dumps(doc))
    p = cli("run", path, "-o", tmp_path / "r.h5")
    assert p.returncode == 2 and p.stderr.count("\n") == 1 and words in p.stderr, p.stderr


def test_info_names_the_cushion(tmp_path):
    case = write_case(tmp_path, ram(0.8, end=0.5))
    assert cli("run", case, "-o", tmp_path / "r.h5", "--quiet").returncode == 0
    p = cli("info", tmp_path / "r.h5")
    assert p.returncode == 0 and "cushion" in p.stdout
