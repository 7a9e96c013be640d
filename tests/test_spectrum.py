"""What earthquake engineers read (issue 28, docs/seismic-outputs.md): the
response spectrum against the closed-form response of the damped
oscillator to a ramp-hold and against an ODE integration, the transfer
function of known linear filters, Konno-Ohmachi smoothing, a gauge's
acceleration on a real run, `vstpetsc spectrum` and `vstpetsc transfer`,
and the plot of a case with gauges."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import vstpetsc
from conftest import bar, cli, make_case, solve
from faults import one_clean_line
from vstpetsc import InputError, cli as cli_module
from vstpetsc.results.spectrum import acceleration, konno_ohmachi

PERIODS = np.array([0.02, 0.1, 0.37, 1.0, 4.0, 10.0])


def ramp_response(t, k, w, z):
    """u(t) of u'' + 2 z w u' + w^2 u = -k t from rest (0 for t < 0):
    particular A t + B, A = -k / w^2, B = 2 z k / w^3, plus the decaying
    oscillation that starts it at rest."""
    t = np.maximum(t, 0.0)
    wd = w * math.sqrt(1.0 - z * z)
    a, b = -k / w ** 2, 2.0 * z * k / w ** 3
    c1 = -b
    c2 = (z * w * c1 - a) / wd
    return a * t + b + np.exp(-z * w * t) * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))


def ramp_hold(t, a0, t1, w, z):
    """The response to a(t) = a0 min(t / t1, 1): a ramp of slope a0 / t1
    minus the same ramp started at t1."""
    k = a0 / t1
    return ramp_response(t, k, w, z) - np.where(t > t1, ramp_response(t - t1, k, w, z), 0.0)


@pytest.mark.parametrize("damping", [0.0, 0.05, 0.2])
def test_spectrum_of_a_ramp_hold_is_the_closed_form(damping):
    dt, t1, a0 = 1e-3, 0.25, 3.0
    t = np.arange(4001) * dt
    acc = a0 * np.minimum(t / t1, 1.0)          # linear between samples: t1 is a sample
    spec = vstpetsc.response_spectrum(acc, dt, PERIODS, damping)
    w = 2 * np.pi / PERIODS
    sd = np.array([np.abs(ramp_hold(t, a0, t1, wk, damping)).max() for wk in w])
    assert np.allclose(spec["sd"], sd, rtol=1e-6, atol=0)
    assert np.array_equal(spec["period"], PERIODS)
    assert np.allclose(spec["psv"], w * sd, rtol=1e-6) and np.allclose(spec["psa"], w * w * sd,
                                                                         rtol=1e-6)


def test_spectrum_of_a_random_piecewise_linear_record_is_the_ode_solution(rng):
    """A second method: an adaptive Runge-Kutta integration of the
    oscillator over each linear piece of a random record."""
    dt, damping = 0.01, 0.05
    acc = rng.normal(size=121)
    spec = vstpetsc.response_spectrum(acc, dt, PERIODS[:4], damping)
    for T, sd in zip(PERIODS[:4], spec["sd"]):
        w, y, peak = 2 * np.pi / T, np.zeros(2), 0.0
        for i in range(acc.size - 1):
            slope = (acc[i + 1] - acc[i]) / dt
            rhs = lambda s, y: [y[1], -w * w * y[0] - 2 * damping * w * y[1]
                                - (acc[i] + slope * s)]
            y = solve_ivp(rhs, (0, dt), y, method="DOP853", rtol=1e-12, atol=1e-15).y[:, -1]
            peak = max(peak, abs(y[0]))
        assert abs(sd / peak - 1) < 1e-6, T


def test_spectrum_defaults_and_bad_arguments():
    spec = vstpetsc.response_spectrum(np.ones(11), 0.01)
    assert spec["period"].size == 200 and spec["period"][0] == pytest.approx(0.01, rel=1e-15)
    assert spec["period"][-1] == pytest.approx(10.0, rel=1e-15)
    assert np.allclose(np.diff(np.log(spec["period"])), np.log(1000) / 199)
    for kw, key in ((dict(damping=-0.1), "damping"), (dict(damping=1.0), "damping"),
                    (dict(periods=[0.1, -1.0]), "periods")):
        with pytest.raises(InputError, match=f"^{key}: "):
            vstpetsc.response_spectrum(np.ones(11), 0.01, **kw)


def test_acceleration_is_central_differences():
    v = np.array([0.0, 1.0, 4.0, 9.0, 7.0])
    assert np.array_equal(acceleration(v, 0.5), [2.0, 4.0, 8.0, 3.0, -4.0])


@pytest.mark.parametrize("n", [64, 65])
def test_transfer_function_of_delays_is_exact(rng, n):
    dt, m = 0.02, 5
    x = rng.normal(size=n)
    f, amp = vstpetsc.transfer_function(x, np.roll(x, m), dt)      # a circular delay
    assert np.array_equal(f, np.arange(n // 2 + 1) / (n * dt))
    assert np.allclose(amp, 1.0, rtol=1e-12, atol=0)
    f, amp = vstpetsc.transfer_function(x, x + np.roll(x, m), dt)
    assert np.allclose(amp, 2 * np.abs(np.cos(np.pi * f * m * dt)), rtol=1e-9, atol=1e-12)
    quiet = np.zeros(n)
    quiet[0] = 1.0                      # amplitude 1 at every f
    assert np.allclose(vstpetsc.transfer_function(quiet, x, dt)[1],
                       np.abs(np.fft.rfft(x)), rtol=1e-12)
    assert np.isnan(vstpetsc.transfer_function(np.zeros(n), x, dt)[1]).all()
    with pytest.raises(InputError, match="^acc_to: the records need equal lengths"):
        vstpetsc.transfer_function(x, x[1:], dt)


def test_konno_ohmachi_keeps_a_constant_and_is_the_weighted_mean(rng):
    f = np.arange(40) * 0.25
    assert np.allclose(konno_ohmachi(f, np.full(40, 3.7), 20.0), 3.7, rtol=1e-14, atol=0)
    amp = rng.uniform(1.0, 2.0, 40)
    got = konno_ohmachi(f, amp, 20.0)
    assert got[0] == amp[0]
    for c in range(1, 40):
        w = [1.0 if j == c else (math.sin(x) / x) ** 4 for j in range(1, 40)
             for x in [20.0 * math.log10(f[j] / f[c])]]
        assert got[c] == pytest.approx(np.dot(w, amp[1:]) / sum(w), rel=1e-12)
    # the smoothed transfer function: the ratio of the smoothed amplitudes
    x, y = rng.normal(size=79), rng.normal(size=79)
    freq, ratio = vstpetsc.transfer_function(x, y, 0.1, smooth=20.0)
    fx, fy = (np.abs(np.fft.rfft(s)) for s in (x, y))
    assert np.allclose(ratio, konno_ohmachi(freq, fy, 20.0) / konno_ohmachi(freq, fx, 20.0),
                       rtol=1e-12)


# ---- a real run: a soil column with a shear component, and a bare bar

@pytest.fixture(scope="module")
def run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("spectrum")
    soil = bar("col", (0.0, 10.0), 10, E=1e8, rho=2000.0, Vs=200.0,
               v0=[[0.0, 0.0], [10.0, 0.3]], v0_shear=[[0.0, 0.0], [10.0, 1.0]])
    case = make_case(1e-3, 0.2, [bar("bare", (-5.0, -3.0), 4, E=1e8, rho=2000.0), soil],
                     every=7,
                     bcs=[{"body": "col", "end": "left", "type": "fixed", "component": c}
                          for c in ("axial", "shear")],
                     gauge=[{"name": "top", "body": "col", "x": 10.0},
                            {"name": "mid", "body": "col", "x": 4.5},
                            {"name": "side", "body": "bare", "x": -4.0}])
    return solve(folder, case), folder


def test_gauge_acceleration_is_the_central_difference_of_its_velocity(run):
    r, _ = run
    dt = r.attrs["dt"]
    for name in ("top", "mid"):
        g = r.gauge(name)
        for v, a in ((g.v, g.acceleration), (g.shear_v, g.shear_acceleration)):
            want = np.concatenate([[(v[1] - v[0]) / dt], (v[2:] - v[:-2]) / (2 * dt),
                                   [(v[-1] - v[-2]) / dt]])
            assert a.shape == v.shape and np.array_equal(a, want)
            assert np.abs(a).max() > 0
    with pytest.raises(AttributeError):
        r.gauge("side").shear_acceleration


def main(capsys, *args):
    """vstpetsc.cli.main in-process: (exit status, stdout, stderr)."""
    code = cli_module.main([str(a) for a in args])
    out = capsys.readouterr()
    return code, out.out, out.err


def read_csv(path):
    lines = path.read_text().splitlines()
    return lines[0], [row.split(",") for row in lines[1:]]


def test_spectrum_csv_has_the_header_and_17_digits(run, capsys):
    r, folder = run
    csv = folder / "top.csv"
    code, out, _ = main(capsys, "spectrum", r.path, "--gauge", "top", "--periods", "0.05:2:7",
                        "--damping", "0.02", "--csv", csv)
    assert code == 0 and out == f"wrote {csv}\n"
    header, rows = read_csv(csv)
    want = vstpetsc.response_spectrum(r.gauge("top").shear_acceleration, r.attrs["dt"],
                                      np.geomspace(0.05, 2, 7), 0.02)     # shear by default
    assert header == "period,sd,psv,psa" and len(rows) == 7
    assert float(rows[0][0]) == 0.05 and float(rows[-1][0]) == 2.0
    for k, key in enumerate(("period", "sd", "psv", "psa")):
        assert [row[k] for row in rows] == [f"{x:.17g}" for x in want[key]], key
    axial = folder / "axial.csv"
    main(capsys, "spectrum", r.path, "--gauge", "top", "--component", "axial", "--csv", axial)
    sd = [float(row[1]) for row in read_csv(axial)[1]]
    assert sd == list(vstpetsc.response_spectrum(r.gauge("top").acceleration,
                                                 r.attrs["dt"])["sd"])


def test_spectrum_summary(run, capsys):
    r, _ = run
    code, out, _ = main(capsys, "spectrum", r.path, "--gauge", "mid")
    acc = r.gauge("mid").shear_acceleration
    spec = vstpetsc.response_spectrum(acc, r.attrs["dt"])
    k = np.argmax(spec["psa"])
    assert code == 0
    assert out.splitlines()[0] == "response spectrum of gauge mid, shear acceleration, damping 0.05"
    assert f"peak acceleration {np.abs(acc).max():.6g} m/s^2 over {acc.size} slab ends" in out
    assert f"psa peak {spec['psa'][k]:.6g} m/s^2 at T = {spec['period'][k]:.4g} s" in out


def test_transfer_csv_summary_and_figures(run, capsys):
    r, folder = run
    csv, png = folder / "t.csv", folder / "t.png"
    code, out, _ = main(capsys, "transfer", r.path, "--from", "mid", "--to", "top",
                        "--smooth", "30", "--csv", csv, "-o", png)
    assert code == 0 and out == f"wrote {csv}\nwrote {png}\n"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    header, rows = read_csv(csv)
    f, amp = vstpetsc.transfer_function(r.gauge("mid").shear_acceleration,
                                        r.gauge("top").shear_acceleration, r.attrs["dt"], 30.0)
    assert header == "frequency,amplitude"
    assert [row[1] for row in rows] == [f"{x:.17g}" for x in amp]
    code, out, _ = main(capsys, "transfer", r.path, "--from", "mid", "--to", "top")
    assert code == 0 and out.startswith("transfer function top / mid, shear acceleration\n")
    assert f"{f.size} frequencies 0 .. {f[-1]:.6g} 1/s" in out
    lower = np.abs(np.fft.rfft(r.gauge("mid").shear_acceleration))
    ratio = np.abs(np.fft.rfft(r.gauge("top").shear_acceleration)) / lower
    band = np.flatnonzero(lower >= 0.01 * lower[1:].max())
    k = band[band > 0][np.argmax(ratio[band[band > 0]])]
    assert f"largest amplitude ratio {ratio[k]:.6g} at f = {f[k]:.6g} 1/s" in out
    spec_png = folder / "s.png"
    assert main(capsys, "spectrum", r.path, "--gauge", "top", "-o", spec_png)[0] == 0
    assert spec_png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


BAD = [
    (("spectrum", "--gauge", "nope"), "--gauge: no gauge 'nope' in"),
    (("spectrum",), "--gauge: give a gauge name (gauges: mid, side, top)"),
    (("spectrum", "--gauge", "top", "--damping", "-0.05"), "--damping: a damping ratio in [0, 1)"),
    (("spectrum", "--gauge", "top", "--damping", "x"), "--damping: a damping ratio"),
    (("spectrum", "--gauge", "top", "--periods", "1:0.1:5"), "--periods: A:B:N"),
    (("spectrum", "--gauge", "top", "--periods", "0:1:5"), "--periods: A:B:N"),
    (("spectrum", "--gauge", "top", "--periods", "0.1:1"), "--periods: A:B:N"),
    (("spectrum", "--gauge", "top", "--periods", "0.1:1:1.5"), "--periods: A:B:N"),
    (("spectrum", "--gauge", "top", "--periods", "0.1:1:100001"), "--periods: A:B:N"),
    (("spectrum", "--gauge", "top", "--periods", "0.1:1:5:6"), "--periods: A:B:N"),
    (("spectrum", "--gauge", "side", "--component", "shear"),
     "--component: gauge 'side' has no shear component"),
    (("spectrum", "--gauge", "top", "--component", "vertical"), "--component: shear or axial"),
    (("transfer", "--from", "top", "--to", "side", "--component", "shear"),
     "--component: gauge 'side' has no shear component"),
    (("transfer", "--from", "top", "--to", "nope"), "--to: no gauge 'nope'"),
    (("transfer", "--from", "top", "--to", "mid", "--smooth", "-3"), "--smooth: a positive"),
    (("transfer", "--from", "top", "--to", "mid", "--smooth", "nan"), "--smooth: a positive"),
    (("spectrum", "--gauge", "top", "--damping", "1"), "--damping: a damping ratio in [0, 1)"),
    (("transfer", "--from", "top", "--to", "mid", "--csv", "/nonexistent/t.csv"),
     "--csv: folder /nonexistent does not exist"),
    (("spectrum", "--gauge", "top", "-o", "/nonexistent/s.png"),
     "-o: folder /nonexistent does not exist"),
]


@pytest.mark.parametrize("args, message", BAD, ids=[" ".join(a) for a, _ in BAD])
def test_bad_options_are_one_line_exit_2(run, capsys, args, message):
    r, _ = run
    code, out, err = main(capsys, args[0], r.path, *args[1:])
    assert code == 2 and out == "" and one_clean_line(err), err
    assert err.startswith(f"vstpetsc: error: {message}"), err


def test_bad_option_from_the_shell(run):
    r, _ = run
    p = cli("spectrum", r.path, "--gauge", "top", "--damping", "-1")
    assert p.returncode == 2 and one_clean_line(p.stderr) and "--damping" in p.stderr


def test_transfer_defaults_to_axial_when_a_gauge_has_no_shear(run, capsys):
    r, _ = run
    code, out, _ = main(capsys, "transfer", r.path, "--from", "side", "--to", "top")
    assert code == 0 and "axial acceleration" in out.splitlines()[0]


def test_plot_shows_what_the_case_has(run):
    from vstpetsc.results import seismic
    from vstpetsc.results.plot import result_figure

    r, _ = run
    fig = result_figure(r)
    titles = [ax.get_title() for ax in fig.axes]
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert not any("contact" in t for t in titles) and "no contact pairs" not in texts
    for part in ("energy", "gauge acceleration", "gauge top (shear)", "peak |strain|",
                 "peak stress", "peak acceleration"):
        assert sum(part in t for t in titles) == 1, (part, titles)
    # the profiles: strain from the envelopes over G, acceleration of the kept rows
    p = seismic.peak_profiles(r, "col")
    shear = r.body("col").shear
    G = 2000.0 * 200.0 ** 2
    assert p["shear"] and np.allclose(
        p["strain"], np.maximum(-shear.stress_min, shear.stress_max) / G, rtol=1e-14)
    t, v = r.time, shear.v
    assert t.size > 3 and t[-1] - t[-2] != t[1] - t[0]      # a shorter last kept step
    a = np.vstack([(v[1] - v[0]) / (t[1] - t[0]),
                   (v[2:] - v[:-2]) / (t[2:] - t[:-2])[:, None],
                   (v[-1] - v[-2]) / (t[-1] - t[-2])])
    assert np.array_equal(p["acceleration"], np.abs(a).max(axis=0))


def test_the_strain_profile_needs_no_case_when_the_file_has_strain_max(run, monkeypatch):
    """A shear component writes shear/strain_max: the profile reads it, so
    a case that can no longer be read (a moved record) loses nothing."""
    from vstpetsc.results import seismic

    r, _ = run

    def gone():
        raise vstpetsc.CaseError(["motion.csv: no such file"])
    monkeypatch.setattr(r, "case", gone)
    p = seismic.peak_profiles(r, "col")
    assert np.array_equal(p["strain"], r.body("col").shear.strain_max)
    assert p["stress_max"].shape == (10,)


def test_site_response_example_has_surface_and_base_gauges():
    from vstpetsc import bundled

    case = vstpetsc.Case.from_toml(bundled.path("site-response"))
    gauges = {g.name: (case.bodies[g.body].name, g.x) for g in case.gauges}
    assert gauges == {"surface": ("soil", 30.0), "base": ("soil", 0.0)}


def test_the_package_exports_them_without_petsc():
    import subprocess
    import sys

    code = ("import sys, vstpetsc; from vstpetsc import response_spectrum, transfer_function; "
            "sys.exit('petsc4py' in sys.modules or 'mpi4py' in sys.modules)")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
