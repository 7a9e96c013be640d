"""Yielding regions in plane strain (issue 46: [[region]] shear_law; the
law vstpetsc.materials.deviatoric, the zone vstpetsc.plane.yielding), run
from case files: a shaken column with a horizontal frictional joint under
gravity, strong enough to reach tens of gamma_ref, against what must hold
whatever the law does.

- the energy balance closes: numerical energy >= 0 and below 1e-4 of the
  largest term, the hysteretic energy a real share of the input;
- `mpirun -n 2` equals one rank within 1e-10 of every dataset (the zone's
  kernels run on rank 0 on gathered unknowns, as the pairs' do);
- a static start stays at rest (the zone's strains count from it);
- a restart continues bit for bit (the points' state in
  /solver/soil_state), and the bad inputs of a shear_law name their key.

(The law against the 1-D law, exactly: tests/test_plane_mkz_column.py and
tests/test_plane_interface_column.py; the law itself:
tests/test_deviatoric_law.py, tests/test_deviatoric_slab.py.)"""

import h5py
import numpy as np
import pytest

from test_plane_run import mpirun_against_one_rank, run_cli
from vstpetsc.input.toml_text import dumps

MKZ = {"model": "mkz", "gamma_ref": 2.0e-4, "beta": 1.0, "s": 0.919}


def column(folder, end=0.4, law=MKZ, static=True, interface=True):
    """A column 2 cells wide and 12 high, split at mid-height by a
    frictional joint, its base shaken sideways (an absorbing base with an
    incident pulse), under gravity with a static start; the case file."""
    doc = {"time": {"dt": 2.5e-3, "end": end},
           "mesh": {"rectangle": {"x": [0.0, 2.0], "y": [0.0, 12.0], "nx": 2, "ny": 12,
                                  **({"joints": {"joint": 6.0}} if interface else {})}},
           "region": [{"name": "domain", "Vs": 150.0, "nu": 0.3, "rho": 1900.0,
                       **({"shear_law": law} if law else {})}],
           "boundary": [{"name": "bottom", "type": "absorbing",
                         "incident": {"x": [[0.0, 0.0], [0.05, 0.5], [0.1, -0.5],
                                            [0.15, 0.4], [0.2, 0.0]]}}],
           "gravity": {"g": -9.81, "initial": "static" if static else "rest"}}
    if interface:
        doc["interface"] = [{"name": "joint", "friction": 0.05}]
    path = folder / "column.toml"
    path.write_text(dumps(doc))
    return path


def assert_same_bits(one, two):
    """Every dataset of result file ``one`` the same bits in ``two`` (but the
    wall time); their names."""
    with h5py.File(one, "r") as a, h5py.File(two, "r") as b:
        names = []
        a.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
        for name in names:
            if name != "solver/wall_time":
                assert np.array_equal(a[name][...], b[name][...], equal_nan=True), name
    return names


def run(path, out, *extra):
    p = run_cli("run", path, "-o", out, "-q", *extra)
    assert p.returncode == 0, p.stderr
    return h5py.File(out, "r")


def test_the_energy_balance_closes_with_yielding_and_sliding(tmp_path):
    with run(column(tmp_path), tmp_path / "r.h5") as f:
        energy = {k: f[f"energy/{k}"][...] for k in f["energy"]}
        strain_max, when = f["field/strain_max"][...], f["field/strain_max_time"][...]
        slip = np.abs(f["interface/joint/slip"][...]).max()
    largest = max(np.abs(energy[k]).max() for k in ("kinetic", "strain", "external"))
    print(f"strain_max {strain_max.max() / MKZ['gamma_ref']:.3g} gamma_ref, slip {slip:.3g} m, "
          f"hysteretic {energy['hysteretic'][-1] / energy['external'][-1]:.3g} of the work in, "
          f"numerical {energy['numerical'].min() / largest:.3g} .. "
          f"{energy['numerical'].max() / largest:.3g} of the largest term")
    assert strain_max.max() > 10.0 * MKZ["gamma_ref"]             # it yields strongly
    p = run_cli("info", tmp_path / "r.h5")
    line = next(x for x in p.stdout.splitlines() if "largest shear strain" in x)
    assert f"{strain_max.max():.4g} in cell {int(strain_max.argmax())} at" in line
    assert f"t = {when[strain_max.argmax()]:.6g}" in line
    # the time each cell's envelope was reached: a run stopped half-way has
    # the same envelope where it was reached by then, a smaller one elsewhere
    with run(column(tmp_path, end=0.2), tmp_path / "half.h5") as f:
        half = f["field/strain_max"][...]
    early = when <= 0.2 + 1e-9
    assert early.any() and (~early).any()
    assert np.array_equal(half[early], strain_max[early]) and (half[~early] < strain_max[~early]).all()
    assert energy["hysteretic"][-1] > 0.05 * energy["external"][-1]
    # (a branch unloading gives back part of what it stored beyond tau^2 / 2G
    # alone: the loops' work is positive per loop, not at every slab)
    assert energy["hysteretic"].min() >= -1e-9 * largest
    assert slip > 1e-3                                              # and the joint slides
    assert energy["numerical"].min() >= -1e-9 * largest
    assert energy["numerical"].max() <= 1e-3 * largest


def test_two_ranks_equal_one_with_yielding_and_an_interface(tmp_path):
    mpirun_against_one_rank(tmp_path, column(tmp_path, end=0.25))


def test_a_static_start_stays_at_rest(tmp_path):
    """No shaking: the zone's strains count from the static equilibrium,
    whose stress the linear K carries; nothing moves."""
    path = column(tmp_path, end=0.1)
    text = path.read_text().replace("0.5", "0.0").replace("-0.5", "0.0").replace("0.4", "0.0")
    path.write_text(text)
    with run(path, tmp_path / "r.h5") as f:
        v = f["field/v"][...]
        u = f["field/u"][...]
        hysteretic = f["energy/hysteretic"][...]
    assert np.abs(v).max() <= 1e-12 * np.abs(u).max() / 2.5e-3
    assert np.abs(u - u[0]).max() <= 1e-12 * np.abs(u).max()
    assert np.abs(hysteretic).max() == 0.0


def test_a_restart_continues_bit_for_bit(tmp_path):
    """Cut at t = 0.15 and continued to 0.3: every dataset as the run
    that went through (the zone's points' state, /solver/soil_state, taken
    back whole)."""
    whole = tmp_path / "whole"
    whole.mkdir()
    run(column(whole, end=0.3), whole / "r.h5").close()
    path, out = column(tmp_path, end=0.15), tmp_path / "r.h5"
    run(path, out).close()
    column(tmp_path, end=0.3)
    run(path, out, "--restart", out).close()
    names = assert_same_bits(whole / "r.h5", out)
    assert "field/strain_max" in names and "solver/soil_state" in names


def test_a_restart_on_two_ranks_continues_bit_for_bit(tmp_path):
    """The same on two ranks: the zone's state is rank 0's, the energy
    sums each rank's; every dataset as the two-rank run that went through."""
    from test_parallel import mpirun

    whole = tmp_path / "whole"
    whole.mkdir()
    path, out = column(tmp_path, end=0.15), tmp_path / "r.h5"
    for args in ((column(whole, end=0.3), "-o", whole / "r.h5"), (path, "-o", out)):
        p = mpirun("run", *args, "-q")
        assert p.returncode == 0, p.stderr
    column(tmp_path, end=0.3)
    p = mpirun("run", path, "-o", out, "-q", "--restart", out)
    assert p.returncode == 0, p.stderr
    assert_same_bits(whole / "r.h5", out)


def test_a_restart_without_the_zone_state_is_refused(tmp_path):
    path, out = column(tmp_path, end=0.05), tmp_path / "r.h5"
    run(path, out).close()
    with h5py.File(out, "r+") as f:
        f["solver/soil_state"].attrs["slab"] = -1       # as after a failed last slab
    before = out.read_bytes()
    column(tmp_path, end=0.1)
    p = run_cli("run", path, "-o", out, "-q", "--restart", out)
    assert p.returncode == 2 and p.stderr.count("\n") == 1, p.stderr
    assert "yielding zone state" in p.stderr
    assert out.read_bytes() == before


@pytest.mark.parametrize("law, key, words", [
    ({"model": "mkzz", "gamma_ref": 1e-4}, "shear_law.model", "must be 'mkz'"),
    ({"model": "mkz", "gamma_ref": 0.0}, "shear_law.gamma_ref", "positive"),
    ({"model": "mkz", "gamma_ref": -1e-4}, "shear_law.gamma_ref", "positive"),
    ({"model": "mkz"}, "shear_law.gamma_ref", "missing"),
    ({"model": "mkz", "gamma_ref": 1e-4, "s": 1.5}, "shear_law.s", "<= 1"),
    ({"model": "mkz", "gamma_ref": 1e-4, "beta": float("nan")}, "shear_law.beta", ""),
    ({"model": "mkz", "gamma_ref": 1e-4, "gamma": 1.0}, "shear_law.gamma", "unknown key"),
    ("mkz", "shear_law", "must be a table")])
def test_a_bad_shear_law_names_its_key(tmp_path, law, key, words):
    path, out = column(tmp_path, law=law), tmp_path / "r.h5"
    p = run_cli("run", path, "-o", out, "-q")
    assert p.returncode == 2 and p.stderr.count("\n") == 1, p.stderr
    assert f"region[0] (domain).{key}" in p.stderr and words in p.stderr, p.stderr
    assert not out.exists()


def test_a_sweep_summary_has_the_strain_and_the_loops(tmp_path):
    """`vstpetsc sweep` over a yielding plane-strain case: each row's
    strain_max and hysteretic are its file's largest /field/strain_max and
    last /energy/hysteretic."""
    import csv

    path = column(tmp_path, end=0.1)
    p = run_cli("sweep", path, "--set", "region.domain.shear_law.gamma_ref=2e-4,4e-4",
                "-o", tmp_path / "sweep", "-q")
    assert p.returncode == 0, p.stderr
    with open(tmp_path / "sweep" / "summary.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 2
    for row in rows:
        with h5py.File(tmp_path / "sweep" / row["file"], "r") as r:
            assert float(row["strain_max"]) == pytest.approx(r["field/strain_max"][...].max(),
                                                             rel=1e-12)
            assert float(row["hysteretic"]) == pytest.approx(r["energy/hysteretic"][-1],
                                                             rel=1e-12)
    assert float(rows[0]["strain_max"]) > float(rows[1]["strain_max"])   # softer yields more


def test_strain_max_in_xdmf_and_plot(tmp_path):
    """/field/strain_max and strain_max_time reach ParaView's reader (VTK's
    vtkXdmfReader) bit for bit at every kept time, and `plot --color
    strain_max` draws them; a linear run's file refuses that colour in one
    line."""
    from test_plane_outputs import vtk_arrays, vtk_reader

    out = tmp_path / "r.h5"
    run(column(tmp_path, end=0.1, interface=False), out).close()   # one grid collection
    assert run_cli("export", out, "--xdmf").returncode == 0
    reader = vtk_reader(tmp_path / "r.xdmf")
    with h5py.File(out, "r") as f:
        strain, when, t = (f[k][...] for k in ("field/strain_max", "field/strain_max_time",
                                               "time"))
    assert strain.max() > 0.0 and when.max() > 0.0
    for row in (0, t.size - 1):
        got = vtk_arrays(reader, t[row])
        assert np.array_equal(got["strain_max"], strain)
        assert np.array_equal(got["strain_max_time"], when)
    p = run_cli("plot", out, "--color", "strain_max", "-o", tmp_path / "s.png")
    assert p.returncode == 0 and (tmp_path / "s.png").stat().st_size > 10000, p.stderr
    linear = tmp_path / "linear.h5"
    run(column(tmp_path, end=0.02, law=None, interface=False), linear).close()
    p = run_cli("plot", linear, "--color", "strain_max", "-o", tmp_path / "l.png")
    assert p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1
    assert "strain_max" in p.stderr and not (tmp_path / "l.png").exists()
