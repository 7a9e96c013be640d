"""Stiffness that grows with confinement (issue 46 item 3: [[region]]
confinement = { p_ref, exponent }; vstpetsc.plane.confinement).

- a laterally confined column (sides holding v_x, base fixed) under
  gravity with a static start: each cell's G (lambda and mu, the zone's G
  and gamma_ref) is its region's times (p / p_ref)^n, p the closed form
  (1 + 2 K0) / 3 rho g (H - y) at its centre, K0 = nu / (1 - nu); the
  start's stresses are the closed form's and the run stays at rest;
- the column's first shear frequency from the model's own confined
  matrices (simple-shear kinematics: each row's u_x, base fixed) against
  a fine 1-D finite-element eigen solution of rho w_tt = (G(y) w_y)_y of
  the same piecewise-constant G (each cell cut in 40);
- two ranks equal one within 1e-10 with a confined yielding column (its
  cells' factors travel by their numbers as read);
- the bad inputs name their key (and the cell and its centre)."""

import h5py
import numpy as np
import pytest
import scipy.linalg

from test_plane_run import mpirun_against_one_rank, run_cli
from vstpetsc.input.toml_text import dumps

H, CELLS, RHO, VS, NU, G_ACC = 20.0, 20, 2000.0, 200.0, 0.3, 9.81
CONF = {"p_ref": 1.0e5, "exponent": 0.5}
MKZ = {"model": "mkz", "gamma_ref": 5.0e-4, "beta": 1.0, "s": 0.919}
# 20 cells of averaged mass against the fine 1-D solution: measured 2.7e-4
# (the discretisation's, O(h^2)); the profile moves the frequency by 10 %
FREQUENCY_TOLERANCE = 5e-4


def column_doc(law=MKZ, confinement=CONF, end=0.1, gravity="static", top=None):
    """A column one cell wide, its sides holding v_x, its base fixed."""
    region = {"name": "domain", "Vs": VS, "nu": NU, "rho": RHO}
    if law is not None:
        region["shear_law"] = law
    if confinement is not None:
        region["confinement"] = confinement
    doc = {"time": {"dt": 5.0e-3, "end": end}, "output": {"every": 1},
           "mesh": {"rectangle": {"x": [0.0, 1.0], "y": [0.0, H], "nx": 1, "ny": CELLS}},
           "region": [region],
           "boundary": [{"name": "bottom", "type": "fixed"},
                        {"name": "left", "type": "velocity", "value": {"x": 0.0}},
                        {"name": "right", "type": "velocity", "value": {"x": 0.0}}],
           "gravity": {"g": -G_ACC, "initial": gravity}}
    if top is not None:
        doc["boundary"].append({"name": "top", "type": "traction", "value": {"y": top}})
    return doc


def write(folder, doc):
    path = folder / "column.toml"
    path.write_text(dumps(doc))
    return path


def closed_form():
    """(cell centres' y, sigma_yy, sigma_xx, p, factor) of the column."""
    y = (np.arange(CELLS) + 0.5) * H / CELLS
    syy = -RHO * G_ACC * (H - y)
    k0 = NU / (1.0 - NU)
    p = (1.0 + 2.0 * k0) / 3.0 * RHO * G_ACC * (H - y)
    return y, syy, k0 * syy, p, (p / CONF["p_ref"]) ** CONF["exponent"]


def confined_model(doc):
    """The PlaneModel of a case document after run_parts (one rank)."""
    from petsc4py import PETSc
    import vstpetsc
    from vstpetsc.plane.parts import run_parts

    return run_parts(vstpetsc.Case.from_dict(doc), PETSc.COMM_WORLD).model


def test_moduli_follow_the_closed_form_mean_stress(tmp_path):
    model = confined_model(column_doc())
    y, _, _, _, factor = closed_form()
    centre = model.mesh.coordinates[model.mesh.cells].mean(axis=1)[:, 1]
    order = np.argsort(centre)
    assert np.allclose(centre[order], y)
    G_ref = RHO * VS ** 2
    lam_ref = 2.0 * G_ref * NU / (1.0 - 2.0 * NU)
    mat = model.materials
    assert np.allclose(mat["mu"][order], G_ref * factor, rtol=1e-12, atol=0)
    assert np.allclose(mat["lam"][order], lam_ref * factor, rtol=1e-12, atol=0)
    zone = model.zone
    G = np.zeros(CELLS)
    G[zone.cell] = zone.G
    gamma_ref = np.zeros(CELLS)
    gamma_ref[zone.cell] = zone.law.backbone.gamma_ref[:, 0]
    assert np.allclose(G[order], G_ref * factor, rtol=1e-12, atol=0)
    assert np.allclose(gamma_ref[order], MKZ["gamma_ref"] * factor, rtol=1e-12, atol=0)


def test_the_run_header_states_the_confined_moduli(tmp_path):
    """The header's region line gives the range of its cells' factors
    (the closed form's, at the cell centres) and of their speeds'."""
    p = run_cli("run", write(tmp_path, column_doc(end=0.01)), "-o", tmp_path / "r.h5")
    assert p.returncode == 0, p.stderr
    line = next(x for x in p.stdout.splitlines() if x.startswith("  region domain"))
    factor = closed_form()[4]
    assert (f"confined: moduli times {factor.min():.3g} to {factor.max():.3g} (speeds times "
            f"{np.sqrt(factor.min()):.3g} to {np.sqrt(factor.max()):.3g})") in line, line
    dry = run_cli("run", write(tmp_path, column_doc(end=0.01)), "--dry-run")
    assert "confined: moduli scaled by the static start's mean stress" in dry.stdout, dry.stdout


@pytest.mark.parametrize("law", [None, MKZ])
def test_the_static_start_is_the_closed_form_and_stays_at_rest(tmp_path, law):
    """(A yielding cell's /field/stress is its points', whose strains count
    from the start: the start's stress is checked on a linear region.)"""
    out = tmp_path / "r.h5"
    p = run_cli("run", write(tmp_path, column_doc(law=law)), "-o", out, "-q")
    assert p.returncode == 0, p.stderr
    _, syy, sxx, _, _ = closed_form()
    with h5py.File(out, "r") as f:
        stress = f["field/stress"][...]
        v = f["field/v"][...]
        u = f["field/u"][...]
        xy = f["mesh/coordinates"][...] if "mesh/coordinates" in f else None
        cells = f["mesh/cells"][...] if "mesh/cells" in f else None
    if cells is not None and xy is not None:
        corners = np.where(cells[:, :, None] >= 0, xy[np.maximum(cells, 0)], np.nan)
        order = np.argsort(np.nanmean(corners, axis=1)[:, 1])
    else:
        order = np.arange(CELLS)
    scale = RHO * G_ACC * H
    for s in stress if law is None else ():     # every kept time: the start's stress
        assert np.abs(s[order, 1] - syy).max() < 1e-9 * scale
        assert np.abs(s[order, 0] - sxx).max() < 1e-9 * scale
        assert np.abs(s[:, 2]).max() < 1e-9 * scale
    assert np.abs(v).max() < 1e-9 * G_ACC * 5.0e-3
    assert np.abs(u - u[0]).max() < 1e-9 * np.abs(u[0]).max()


def fine_frequency(G, rho, h, parts=40):
    """The lowest frequency (Hz) of rho w_tt = (G w_y)_y on a column of
    cells of height h and shear moduli G (bottom first), fixed at its base
    and free at its top: linear elements, each cell cut in ``parts``,
    consistent masses."""
    g = np.repeat(G, parts)
    e = h / parts
    n = g.size
    K, M = np.zeros((n + 1, n + 1)), np.zeros((n + 1, n + 1))
    for i in range(n):
        K[i:i + 2, i:i + 2] += g[i] / e * np.array([[1.0, -1.0], [-1.0, 1.0]])
        M[i:i + 2, i:i + 2] += rho * e / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
    w2 = scipy.linalg.eigh(K[1:, 1:], M[1:, 1:], eigvals_only=True, subset_by_index=[0, 0])
    return np.sqrt(w2[0]) / (2.0 * np.pi)


def model_shear_frequency(model):
    """The lowest frequency (Hz) of the model's assembled M and K (one
    rank: global = as read) restricted to simple shear: u_x the same at a
    row's two nodes, u_y = 0, the base row held."""
    M, _, K = model.matrices()
    y = model.local.mesh.coordinates[:, 1]
    rows = np.unique(y)
    T = np.zeros((M.shape[0], rows.size))
    T[2 * np.arange(y.size), np.searchsorted(rows, y)] = 1.0
    Kr, Mr = (T.T @ (A @ T) for A in (K, M))
    w2 = scipy.linalg.eigh(Kr[1:, 1:], Mr[1:, 1:], eigvals_only=True, subset_by_index=[0, 0])
    return np.sqrt(w2[0]) / (2.0 * np.pi)


def test_the_first_shear_frequency_is_that_of_the_profile():
    model = confined_model(column_doc(law=None))
    _, _, _, _, factor = closed_form()
    G = RHO * VS ** 2 * factor
    reference = fine_frequency(G, RHO, H / CELLS)
    uniform = fine_frequency(np.full(CELLS, RHO * VS ** 2), RHO, H / CELLS)
    assert abs(uniform / (VS / (4.0 * H)) - 1.0) < 1e-5          # the reference's own check
    found = model_shear_frequency(model)
    print(f"first shear frequency {found:.6g} Hz, the profile's {reference:.6g} Hz "
          f"({found / reference - 1:.2e}); unconfined {uniform:.4g} Hz")
    assert abs(found / reference - 1.0) < FREQUENCY_TOLERANCE
    assert abs(reference / uniform - 1.0) > 0.05       # the profile matters
    finer = fine_frequency(G, RHO, H / CELLS, parts=80)
    assert abs(finer / reference - 1.0) < 1e-6         # the reference converged


def test_two_ranks_equal_one_with_confinement(tmp_path):
    from test_plane_yielding import column
    import tomllib

    path = column(tmp_path, end=0.1)
    doc = tomllib.loads(path.read_text())
    doc["region"][0]["confinement"] = CONF
    path.write_text(dumps(doc))
    mpirun_against_one_rank(tmp_path, path)


@pytest.mark.parametrize("change, key, words", [
    ({"confinement": {"p_ref": 0.0, "exponent": 0.5}}, "confinement.p_ref", "positive"),
    ({"confinement": {"p_ref": 1e5, "exponent": -0.1}}, "confinement.exponent", ">= 0"),
    ({"confinement": {"p_ref": 1e5, "exponent": 1.5}}, "confinement.exponent", "<= 1"),
    ({"confinement": {"p_ref": 1e5}}, "confinement.exponent", "missing"),
    ({"confinement": {"p_ref": 1e5, "exponent": 0.5, "n": 1}}, "confinement.n", "unknown"),
    ({"confinement": 0.5}, "confinement", "must be a table"),
    ({"gravity": "rest"}, "confinement", "initial = \"static\""),
    ({"top": 1.2 * RHO * G_ACC}, "confinement", f"cell {CELLS - 1} at (0.5, 19.5)")])
def test_bad_confinement_is_named(tmp_path, change, key, words):
    args = {k: v for k, v in change.items() if k in ("gravity", "top", "confinement")}
    path, out = write(tmp_path, column_doc(**args)), tmp_path / "r.h5"
    p = run_cli("run", path, "-o", out, "-q")
    assert p.returncode == 2 and p.stderr.count("\n") == 1, p.stderr
    assert f"region[0] (domain).{key}" in p.stderr and words in p.stderr, p.stderr
    assert not out.exists()
