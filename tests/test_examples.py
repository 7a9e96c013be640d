"""Every bundled example: written by `vstpetsc example`, identical to the
bundled file, run to completion, and its physics as its comment states."""

import numpy as np
import pytest

from conftest import Result, cli, run_text
from vstpetsc import bundled

STEEL_C = np.sqrt(2.0e11 / 7850.0)
STEEL_Z = 7850.0 * STEEL_C


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    """name -> Result, each example written by the CLI and run once."""
    folder = tmp_path_factory.mktemp("examples")
    out = {}
    for name in bundled.names():
        path = folder / f"{name}.toml"
        p = cli("example", name, "-o", path)
        assert p.returncode == 0, p.stderr
        assert path.read_text() == bundled.text(name)
        out[name] = run_text(folder, path.read_text(), name=name)
    return out


def test_example_list():
    p = cli("example")
    assert p.returncode == 0
    listed = [line.split()[0] for line in p.stdout.splitlines()]
    assert listed == bundled.names()
    assert set(listed) == {"bar-wall", "two-bars", "unequal-bars", "periodic-impacts",
                           "layered", "wave"}
    assert all(bundled.description(n) for n in listed)


def test_example_does_not_overwrite_silently(tmp_path):
    assert cli("example", "wave", cwd=tmp_path).returncode == 0
    p = cli("example", "wave", cwd=tmp_path)
    assert p.returncode == 2 and "exists" in p.stderr
    assert cli("example", "nosuch", cwd=tmp_path).returncode == 2


def test_all_complete(results):
    for name, r in results.items():
        assert r.attrs["status"] == "completed", name


def phase(r, k=0):
    t, J = r["time"], r[f"contact/{k}/impulse"]
    on = np.nonzero(J > 0)[0]
    return t[on[0] - 1], t[on[-1]], J.sum()


def test_bar_wall(results):
    r = results["bar-wall"]
    dt = r.attrs["dt"]
    start, end, J = phase(r)
    assert abs(start - 1e-3) <= 2 * dt
    assert abs((end - start) - 2 * 1.0 / STEEL_C) <= 2 * dt
    assert abs(J / (end - start) / (STEEL_Z * 1.0) - 1) <= 0.03
    assert abs(r["body/bar/v"][-1].mean() + 1.0) <= 0.03


def test_two_bars(results):
    r = results["two-bars"]
    start, end, J = phase(r)
    assert abs(J / (end - start) / (STEEL_Z * 0.5) - 1) <= 0.03
    assert abs(r["body/striker/v"][-1].mean()) <= 0.02
    assert abs(r["body/target/v"][-1].mean() - 1.0) <= 0.02


def test_unequal_bars_force_plateau(results):
    r = results["unequal-bars"]
    z1, z2, v0 = STEEL_Z, 4 * np.sqrt(3e10 * 2400.0), 2.0
    t, F = r["time"], r["contact/0/force"]
    impact = 1e-3 / v0
    window = (t > impact + 0.1 * 3.962e-4) & (t <= impact + 0.9 * 3.962e-4)
    assert abs(F[window].mean() / (z1 * z2 * v0 / (z1 + z2)) - 1) <= 0.03


def test_periodic_impacts_repeat(results):
    r = results["periodic-impacts"]
    assert r["contact/0/episodes"][-1] >= 3
    # the end separates between impacts: the gap is positive again after the first contact
    first = np.argmax(r["contact/0/impulse"] > 0)
    assert r["contact/0/gap"][first:].max() > 0.5e-4


def test_layered_interface_opens_and_closes(results):
    r = results["layered"]
    g, F = r["contact/0/gap"], r["contact/0/force"]
    opened = np.nonzero(g > 1e-4)[0]
    assert opened.size                                  # the interface opens
    assert np.any(F[opened[0]:] > 0)                    # and closes again
    assert r["contact/0/episodes"][-1] >= 2


def test_wave_vibrates_in_its_first_mode(results):
    r = results["wave"]
    t, u_end = r["time"], r["body/bar/u"][:, -1]
    w = np.pi * STEEL_C / 2.0
    assert np.abs(u_end - 1e-4 * np.cos(w * t)).max() <= 0.02 * 1e-4
    e = r["energy/kinetic"] + r["energy/strain"]
    assert e[-1] <= e[0] and e[-1] >= 0.99 * e[0]


def _numbers(pattern, text):
    import re
    m = re.search(pattern, text)
    assert m, (pattern, text)
    return [float(x) for x in m.groups()]


@pytest.mark.parametrize("name", ["two-bars", "layered"])
def test_info_agrees_with_arrays(results, name):
    r = results[name]
    p = cli("info", r.path)
    assert p.returncode == 0, p.stderr
    out = p.stdout
    t, J, F, g = (r["time"], r["contact/0/impulse"], r["contact/0/force"],
                  r["contact/0/gap"])
    dt = r.attrs["dt"]
    on = J[1:] > 0
    first, duration, episodes = _numbers(
        r"first contact t = (\S+), total duration (\S+), (\d+) episode", out)
    peak, mean, impulse, pen = _numbers(
        r"force peak (\S+), mean (\S+); impulse (\S+); largest penetration (\S+)", out)
    assert np.isclose(first, t[1:][on][0] - dt, rtol=1e-5)
    assert np.isclose(duration, dt * on.sum(), rtol=1e-5)
    assert episodes == np.count_nonzero(np.diff(np.r_[0, on.astype(int)]) == 1)
    assert np.isclose(peak, F.max(), rtol=1e-5)
    assert np.isclose(impulse, J.sum(), rtol=1e-5)
    assert np.isclose(mean, J.sum() / (dt * on.sum()), rtol=1e-5)
    assert np.isclose(pen, max(0.0, -g.min()), rtol=1e-3)
    e = r["energy/kinetic"] + r["energy/strain"]
    e0, e1 = _numbers(r"energy: start (\S+), end (\S+) ", out)
    assert np.isclose(e0, e[0], rtol=1e-5) and np.isclose(e1, e[-1], rtol=1e-5)
    nmean, nmax = _numbers(r"Newton iterations per slab: mean (\S+), max (\d+)", out)
    newton = r["solver/newton_iterations"][1:]
    assert np.isclose(nmean, newton.mean(), rtol=1e-2) and nmax == newton.max()
    assert "status" not in out and out.splitlines()[0].endswith("completed")


def test_plot_writes_three_panels(results, tmp_path):
    import matplotlib.image
    from vstpetsc.plot import result_figure

    png = tmp_path / "fig.png"
    p = cli("plot", results["layered"].path, "-o", png)
    assert p.returncode == 0, p.stderr
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 50_000
    img = matplotlib.image.imread(png)
    assert img.shape[0] > 600 and img.shape[1] > 800
    fig = result_figure(results["layered"].path)
    titles = [ax.get_title() for ax in fig.axes]
    assert any(x.startswith("(a)") for x in titles)
    assert any(x.startswith("(b)") for x in titles)
    assert any(x.startswith("(c)") for x in titles)
    assert any("velocity" in ax.get_ylabel() for ax in fig.axes)   # the colour bar


def test_info_and_plot_reject_bad_files(tmp_path):
    bad = tmp_path / "x.h5"
    bad.write_text("not hdf5")
    for cmd in ("info", "plot"):
        p = cli(cmd, bad)
        assert p.returncode == 2 and "not an HDF5 file" in p.stderr and "Traceback" not in p.stderr
        p = cli(cmd, tmp_path / "missing.h5")
        assert p.returncode == 2 and "no such file" in p.stderr
