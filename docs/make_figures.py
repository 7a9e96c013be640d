"""Run every bundled example, draw its figure into docs/figures/ and write
docs/examples.md with its story, wall time and key number.  Run: make figures
"""

import io
import os
import sys
import tempfile

import numpy as np

import vstpetsc
from vstpetsc.results import analysis
from vstpetsc import bundled
from vstpetsc.results.hdf5 import open_to_read
from vstpetsc.results.plot import plot_result

HERE = os.path.dirname(os.path.abspath(__file__))
C = np.sqrt(2.0e11 / 7850.0)          # steel
Z = 7850.0 * C


def _phase(f):
    t, J = f["time"][:], f["contact/0/impulse"][:]
    on = np.nonzero(J > 0)[0]
    return t[on[0] - 1], t[on[-1]], J.sum()


def _bar_wall(f):
    start, end, J = _phase(f)
    F = f["contact/0/force"][:]
    return (f"contact force: median {np.median(F[F > 0]) / 1e6:.2f} MN, peak "
            f"{F.max() / 1e6:.2f} MN (exact Z v0 = {Z / 1e6:.2f} MN), contact "
            f"{1e3 * (end - start):.4f} ms (exact 2L/c = {2e3 / C:.4f} ms against a rigid "
            f"wall, plus up to the penalty's 2 Z / k = {2e3 * Z / f['contact/0'].attrs['penalty']:.4f}"
            f" ms), rebound {f['body/bar/v'][-1].mean():.3f} m/s (exact -1)")


def _two_bars(f):
    F = f["contact/0/force"][:]
    return (f"contact force: median {np.median(F[F > 0]) / 1e6:.2f} MN, peak "
            f"{F.max() / 1e6:.2f} MN (exact Z v0/2 = {Z / 2e6:.2f} MN); after: striker {f['body/striker/v'][-1].mean():.3f} m/s, "
            f"target {f['body/target/v'][-1].mean():.3f} m/s (exact 0 and 1)")


def _unequal(f):
    z2 = 4 * np.sqrt(3e10 * 2400.0)
    exact = Z * z2 * 2.0 / (Z + z2)
    t, F = f["time"][:], f["contact/0/force"][:]
    w = (t > 5e-4 + 0.4e-4) & (t <= 5e-4 + 3.6e-4)
    return f"force plateau {F[w].mean() / 1e6:.2f} MN (exact Z1 Z2 v0/(Z1+Z2) = {exact / 1e6:.2f} MN)"


def _periodic(f):
    return (f"{int(f['contact/0/episodes'][-1])} contact episodes in 5 ms; first contact at "
            f"{1e3 * f['contact/0/first_contact'][-1]:.3f} ms (exact L/c = {1e3 / C:.3f} ms)")


def _layered(f):
    t, g, F = f["time"][:], f["contact/0/gap"][:], f["contact/0/force"][:]
    opened = np.nonzero(g > 1e-6)[0]
    close = opened[0] + np.argmax(F[opened[0]:] > 0)
    return (f"interface opens at t = {1e3 * t[opened[0]]:.1f} ms, largest gap "
            f"{1e3 * g.max():.2f} mm, recloses at t = {1e3 * t[close]:.1f} ms; "
            f"{int(f['contact/0/episodes'][-1])} contact episodes in 0.2 s")


def _wave(f):
    t, u = f["time"][:], f["body/bar/u"][:, -1]
    exact = 1e-4 * np.cos(np.pi * C / 2 * t)
    error = np.sqrt(np.mean((u - exact) ** 2) / np.mean(exact ** 2))
    return (f"free-end displacement within {error:.1e} (relative L2 over two periods) of "
            f"1e-4 cos(pi c t / 2L)")


def _site(f, result):
    """Key numbers and the transfer-function figure of site-response."""
    import matplotlib.pyplot as plt

    case = result.case()
    soil, base = case.bodies[0], case.bcs[0].params
    c = float(np.sqrt(soil.G(0.0) / soil.rho(0.0)))      # the layer's Vs
    H = soil.x[1] - soil.x[0]
    rho_rock, vs_rock, _ = base["rock"]
    a = float(soil.rho(0.0)) * c / (rho_rock * vs_rock)
    t = result.time
    freq, ratio = analysis.transfer_function(t, result.body("soil").shear.v[:, -1],
                                             2 * base["incident"](t))
    keep = freq <= 10.0
    fig, ax = plt.subplots(figsize=(8, 4.5), constrained_layout=True)
    ax.plot(freq[keep], ratio[keep], label="vstpetsc: smoothed spectral ratio surface / outcrop")
    ax.plot(freq[keep], analysis.layer_amplification(freq[keep], H, c, a), "k--", lw=1,
            label=f"closed form 1/sqrt(cos^2 kH + a^2 sin^2 kH), a = {a:.3f}")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("amplification")
    ax.set_title("site-response: surface shear velocity over rock-outcrop velocity")
    ax.legend(fontsize=8)
    fig.savefig(os.path.join(HERE, "figures", "site-response-transfer.png"), dpi=110)
    plt.close(fig)
    band = (freq > 1.0) & (freq < 2.5)
    return (f"spectral ratio peaks at {freq[band][np.argmax(ratio[band])]:.3f} Hz (c/4H = "
            f"{c / (4 * H):.3f} Hz) with {ratio[band].max():.2f} (1/a = {1 / a:.2f}, "
            f"smoothed over 10 % of f); at c/2H it is "
            f"{ratio[np.argmin(np.abs(freq - c / (2 * H)))]:.3f} (exact 1)\n\n"
            "![site-response transfer function](figures/site-response-transfer.png)")


def _uplift(f, result):
    fl = analysis.flights(result.time, result.contact(0).impulse)
    times = ", ".join(f"{1e3 * a:.1f}-{1e3 * b:.1f} ms" for a, b in fl)
    return (f"first lift-off at {1e3 * fl[0][0]:.1f} ms (rigid-block estimate 121.5 ms); "
            f"flights {times}")


def _drop(f, result):
    eps = analysis.episodes(result.time, result.contact(0).impulse)
    return (f"first impact at {1e3 * eps[0][0]:.2f} ms (exact sqrt(2h/g) = 63.86 ms), "
            f"second at {1e3 * eps[1][0]:.1f} ms (elastic estimate 63.86 + 127.7 + 1.3 = "
            f"192.8 ms)")


def _pile(f, result):
    s = result.summary()
    soil = s["soils"][0]
    pile = [b for b in s["bodies"] if b["name"] == "pile"][0]
    return (f"set {1e3 * soil['set']:.3f} mm, blow count {soil['blow_count']:.1f} per m "
            f"({0.25 * soil['blow_count']:.1f} per 0.25 m); largest compression "
            f"{-1e-6 * pile['compression'][0]:.1f} MPa, tension {1e-6 * pile['tension'][0]:.1f} "
            f"MPa; energy into the pile {1e-3 * s['energy']['transferred']:.2f} kJ of the "
            f"ram's 29.44 kJ (docs/pile-driving.md: the bearing graph, the Smith peer)")


def _bouncing(f, result):
    """Key numbers and the force-and-energy figure of bouncing-bar, against
    the exact solution of tests/test_bouncing_bar.py."""
    import matplotlib.pyplot as plt

    sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))
    from test_bouncing_bar import Exact, contacts

    case = result.case()
    ex = Exact(case)
    closes, opens = contacts(result)
    t, e = result.time, result.energy
    fine = np.linspace(0.0, t[-1], 200_001)
    potential = ex.energy - e["external"]          # m g (height of the undeformed foot)
    total = e["kinetic"] + e["strain"] + e["contact"] + potential
    fig, (top, bottom, lost) = plt.subplots(3, 1, figsize=(9, 8.5), sharex=True,
                                            constrained_layout=True,
                                            gridspec_kw={"height_ratios": [3, 3, 1.5]})
    top.plot(t, result.contact(0).force, label="vstpetsc (slab-mean force)")
    top.plot(fine, ex.force(fine), "k--", lw=0.8, label="exact (its contacts start about 2 Z / k "
             "earlier per bounce: the penalty's release delay)")
    top.set_ylabel("contact force")
    top.set_title("bouncing-bar: contact A ramps Z (v0 + g t) up, contact B "
                  "Z v0 + 2 m g - Z g t down", fontsize=10)
    top.legend(fontsize=8, loc="upper right")
    for name, values in (("kinetic", e["kinetic"]), ("strain", e["strain"]),
                         ("potential (m g h0 - gravity's work)", potential),
                         ("total", total)):
        bottom.plot(t, values, label=name)
    bottom.axhline(ex.energy, color="k", ls="--", lw=0.8, label="exact total m g h0")
    bottom.set_ylabel("energy")
    bottom.legend(fontsize=8, loc="center right")
    lost.plot(t, 100 * (1 - total / ex.energy))
    lost.set_ylabel("energy lost [%]")
    lost.set_xlabel("time")
    fig.savefig(os.path.join(HERE, "figures", "bouncing-bar-bounces.png"), dpi=110)
    plt.close(fig)
    delay = 2 * ex.Z / f["contact/0"].attrs["penalty"]         # the default, as the run used it
    peak = f["contact/0/force_peak"][-1] / (ex.Z * ex.v0 + 2 * ex.m * ex.g)    # every slab
    return (f"{closes.size} bounces; largest force {peak:.3f} of the exact Z v0 + 2 m g; contacts last "
            f"{(opens - closes).min():.4f} to {(opens - closes).max():.4f} (exact 2L/c = "
            f"{ex.tau:.4f}, plus the penalty's 2 Z / k = {delay:.4f}); bounce period "
            f"{np.diff(closes).mean():.4f} (exact {ex.period:.4f}); energy lost "
            f"{100 * (1 - total[-1] / ex.energy):.2f} % of m g h0\n\n"
            "![bouncing-bar force and energy](figures/bouncing-bar-bounces.png)")


def _sliding_block(f, result):
    """Key numbers and the slip figure of sliding-block against Newmark's
    rigid block on the same (piecewise-constant) ground acceleration."""
    import matplotlib.pyplot as plt

    sys.path.append(os.path.join(os.path.dirname(HERE), "tests"))
    from references.sliding_block import newmark

    case = result.case()
    pair = case.contacts[0]
    wall = pair.wall_shear_velocity
    acc = np.diff(wall.f) / np.diff(wall.t)
    ky = pair.friction * -case.gravity.g(0.0)
    rigid = newmark(np.repeat(wall.t, 2)[1:-1], np.repeat(acc, 2), ky)
    slip = result.contact(0).slip
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), sharex=True,
                                      constrained_layout=True)
    top.step(wall.t[:-1], acc, where="post", label="ground acceleration")
    for level in (ky, -ky):
        top.axhline(level, color="k", ls=":", lw=0.8)
    top.set_ylabel("m/s^2")
    top.legend(fontsize=8)
    top.set_title("sliding-block: the block slides while the ground outruns ky g = "
                  f"{ky:.3g} m/s^2 (dotted)", fontsize=10)
    bottom.plot(result.time, slip, label="vstpetsc: contact/0/slip")
    bottom.plot(rigid.t, rigid.u, "k--", lw=0.8, label="Newmark rigid block (exact)")
    bottom.set_ylabel("slip relative to the ground [m]")
    bottom.set_xlabel("t [s]")
    bottom.legend(fontsize=8)
    fig.savefig(os.path.join(HERE, "figures", "sliding-block-slip.png"), dpi=110)
    plt.close(fig)
    return (f"largest slip {np.abs(slip).max():.4f} m (Newmark {np.abs(rigid.u).max():.4f}), "
            f"permanent {slip[-1]:.4f} m (Newmark {rigid.permanent:.4f}); friction dissipated "
            f"{f['energy/friction'][-1] / 1e3:.2f} kJ\n\n"
            "![sliding-block slip](figures/sliding-block-slip.png)")


def _dam_interface(f, result):
    """Key numbers and the interface figure of dam-interface."""
    import matplotlib.pyplot as plt

    pair = result.contact(0)
    mu = result.case().contacts[0].friction
    t = result.time
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), sharex=True,
                                      constrained_layout=True)
    top.plot(t, pair.force / 1e6, label="normal force N")
    top.plot(t, mu * pair.force / 1e6, "k:", lw=0.8, label="mu N")
    top.plot(t, np.abs(pair.shear_force) / 1e6, label="|shear force|")
    top.set_ylabel("MN (slab means)")
    top.legend(fontsize=8)
    top.set_title("dam-interface: the interface slides at |T| = mu N and carries nothing "
                  "while open", fontsize=10)
    bottom.plot(t, 1e3 * pair.slip)
    bottom.set_ylabel("slip [mm]")
    bottom.set_xlabel("t [s]")
    fig.savefig(os.path.join(HERE, "figures", "dam-interface-slip.png"), dpi=110)
    plt.close(fig)
    flights = analysis.flights(t, pair.impulse)
    times = ", ".join(f"{a:.3f}-{b:.3f} s" for a, b in flights)
    return (f"lifts off {len(flights)} time(s) ({times}); permanent slip "
            f"{1e3 * pair.slip[-1]:.2f} mm (largest {1e3 * np.abs(pair.slip).max():.2f} mm); "
            f"friction dissipated {f['energy/friction'][-1] / 1e3:.1f} kJ\n\n"
            "![dam-interface slip](figures/dam-interface-slip.png)")


def _rockfill_column(f, result):
    """Key numbers and the figure of rockfill-column: the interface (forces,
    gap, slip), the fill's hysteresis loops and the spectra at crest and base."""
    import matplotlib.pyplot as plt

    pair, t = result.contact(0), result.time
    mu = result.case().contacts[0].friction
    fig, ((forces, loops), (slip, spectra)) = plt.subplots(2, 2, figsize=(11, 8),
                                                          constrained_layout=True)
    forces.plot(t, pair.force / 1e6, lw=0.8, label="normal force N")
    forces.plot(t, mu * pair.force / 1e6, "k:", lw=0.8, label="mu N")
    forces.plot(t, np.abs(pair.shear_force) / 1e6, lw=0.8, label="|shear force|")
    forces.set_ylabel("MN (slab means)")
    forces.set_title("(a) the interface: slides at |T| = mu N, nothing while open",
                     fontsize=10)
    forces.legend(fontsize=8)
    slip.plot(t, 1e3 * pair.slip, label="slip (fill relative to plinth)")
    slip.plot(t, 1e3 * np.maximum(pair.gap, 0.0), label="gap (opening)")
    slip.set_xlabel("t [s]")
    slip.set_ylabel("mm")
    slip.set_title("(b) slip and opening", fontsize=10)
    slip.legend(fontsize=8)
    for name in ("base", "mid"):
        g = result.gauge(name)
        loops.plot(1e2 * g.shear_strain, g.shear_stress / 1e3, lw=0.6, label=f"gauge {name}")
    loops.set_xlabel("shear strain [%]")
    loops.set_ylabel("shear stress [kPa]")
    loops.set_title("(c) hysteresis loops (MKZ, Masing)", fontsize=10)
    loops.legend(fontsize=8)
    periods = np.geomspace(0.02, 5.0, 200)
    peaks = {}
    for name in ("crest", "plinth"):
        acc = result.gauge(name).shear_acceleration
        psa = vstpetsc.response_spectrum(acc, result.case().dt * result.case().every,
                                         periods, 0.05)["psa"]
        peaks[name] = np.abs(acc).max()
        spectra.loglog(periods, psa / 9.81, label=f"{name} (peak {peaks[name] / 9.81:.2f} g)")
    spectra.set_xlabel("period [s]")
    spectra.set_ylabel("psa [g] (5 % damping), horizontal")
    spectra.set_title("(d) response spectra: crest and the plinth's top", fontsize=10)
    spectra.legend(fontsize=8)
    fig.savefig(os.path.join(HERE, "figures", "rockfill-column-response.png"), dpi=110)
    plt.close(fig)
    flights = analysis.flights(t, pair.impulse)
    e = f["energy"]
    return (f"lifts off {len(flights)} time(s), {sum(b - a for a, b in flights):.3f} s in "
            f"all; permanent slip {1e3 * pair.slip[-1]:.1f} mm (largest "
            f"{1e3 * np.abs(pair.slip).max():.1f} mm); largest strain "
            f"{result.body('fill').shear.strain_max.max():.2e}; peak horizontal "
            f"acceleration at the crest {peaks['crest'] / 9.81:.2f} g; dissipated by "
            f"yielding {e['hysteretic'][-1] / 1e3:.1f} kJ, by sliding "
            f"{e['friction'][-1] / 1e3:.1f} kJ, numerical {e['numerical'][-1] / 1e3:.3f} kJ"
            "\n\n![rockfill-column interface, loops and spectra]"
            "(figures/rockfill-column-response.png)")


def _nonlinear_site(f, result):
    """Key numbers and the figure of nonlinear-site: the bundled (strong)
    run against the same column under the weak record (tests/test_examples.py
    asserts the comparisons)."""
    sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))
    from test_examples import NONLINEAR_WEAK, site_numbers

    with tempfile.TemporaryDirectory() as folder:
        case = result.case().with_value("bc.0.incident.scale", NONLINEAR_WEAK)
        weak = vstpetsc.run(case, os.path.join(folder, "weak.h5"), quiet=True,
                            out=io.StringIO())
        runs = {"strong": site_numbers(result), "weak": site_numbers(weak)}
    _site_figure(result.case(), runs)
    scale = result.case().to_dict()["bc"][0]["incident"]["scale"]
    text = []
    for (name, n), g in zip(runs.items(), (scale, NONLINEAR_WEAK)):
        text.append(f"{name} ({g:g} g): peak surface acceleration {n['peak_surface']:.3f} "
                    f"m/s^2, {n['amplification']:.2f} times the outcrop's; surface "
                    f"spectrum peaks at {n['period_surface']:.2f} s, spectral ratio at "
                    f"{n['period_ratio']:.2f} s ({n['ratio'].max():.2f}; "
                    f"{n['ratio_short']:.2f} over 0.05-0.15 s); transfer function peaks at "
                    f"{n['freq_transfer']:.2f} Hz ({n['transfer_peak']:.2f}); "
                    f"largest strain {n['strain_max']:.2e} ({n['yield']:.2f} gamma_ref); "
                    f"hysteresis dissipated {100 * n['hysteretic'] / n['external']:.1f} % of "
                    f"the work that came in, numerical {n['numerical'] / n['external']:.1e}")
    text.append(f"weak run: {weak.run.wall:.1f} s for {weak.run.slabs} slabs")
    return ("\n- ".join(text) + "\n\n![nonlinear-site spectra, transfer functions and "
            "strains](figures/nonlinear-site-response.png)")


def _site_figure(case, runs):
    """Four panels: spectra, spectral ratios, transfer functions (with the
    linear elastic column's, Thomson-Haskell), peak strain profiles."""
    import matplotlib.pyplot as plt
    from test_site_profile import haskell

    doc = case.to_dict()
    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5), constrained_layout=True)
    (spec, ratio), (transfer, strain) = axes
    for (name, n), colour in zip(runs.items(), ("C3", "C0")):
        label = f"{name}: peak outcrop {n['peak_outcrop'] / 9.81:.2f} g"
        spec.loglog(n["period"], n["psa_surface"] / n["peak_outcrop"], colour, label=label)
        ratio.semilogx(n["period"], n["ratio"], colour, label=label)
        keep = (n["freq"] > 0.2) & (n["freq"] < 20.0)
        transfer.semilogx(n["freq"][keep], n["transfer"][keep], colour, label=label)
        strain.semilogx(n["strain"], n["x_mid"], colour, marker=".", label=label)
    spec.loglog(n["period"], n["psa_outcrop"] / n["peak_outcrop"], "k--", lw=1,
                label="rock outcrop")
    spec.set_ylabel("psa / peak outcrop acceleration (5 % damping)")
    spec.set_title("(a) surface response spectra", fontsize=10)
    ratio.axhline(1.0, color="k", lw=0.6)
    ratio.set_ylabel("psa surface / psa outcrop")
    ratio.set_title("(b) spectral ratio surface / outcrop", fontsize=10)
    for ax in (spec, ratio):
        ax.set_xlabel("period [s]")
        ax.set_xlim(0.02, 5.0)
    f = np.geomspace(0.2, 20.0, 2000)
    bc = doc["bc"][0]
    transfer.semilogx(f, haskell(f, doc["body"][0]["layers"], bc["rock"]), "k:", lw=0.8,
                      label="linear elastic column (Thomson-Haskell, undamped)")
    transfer.set_xlabel("frequency [Hz]")
    transfer.set_ylabel("|A surface| / |A outcrop| (Konno-Ohmachi, b = 40)")
    transfer.set_ylim(0.0, 8.0)
    transfer.set_title("(c) transfer function surface / outcrop", fontsize=10)
    x = n["x"]              # gamma_ref of each element over its span
    strain.plot(np.repeat(n["gamma_ref"], 2), np.column_stack([x[:-1], x[1:]]).ravel(), "k--",
                lw=1, label="gamma_ref")
    strain.set_xlabel("peak |shear strain| (strain_max)")
    strain.set_ylabel("x [m] (elevation above the rock)")
    strain.set_title("(d) peak strain over the column", fontsize=10)
    for ax in axes.flat:
        ax.legend(fontsize=8)
    fig.savefig(os.path.join(HERE, "figures", "nonlinear-site-response.png"), dpi=110)
    plt.close(fig)


def _plane_column(f, result):
    """Key numbers of plane-column: the top's peak and the balance."""
    top = result.gauge("top").v[:, 0]
    e = f["energy"]
    return (f"peak v_x at the top {np.abs(top).max():.4f} m/s (the incident 0.2 m/s "
            f"doubled at the free surface); numerical energy {e['numerical'][-1]:.3g} J of "
            f"{e['external'][:].max():.4g} J put in")


def _dam_modes(f, result):
    """Key numbers of dam-modes: the crest's peak and the energy the time
    scheme took from the high modes."""
    crest = result.gauge("crest").v
    e = f["energy"]
    held = e["kinetic"][0] + e["strain"][0]
    return (f"peak crest v_x {np.abs(crest[:, 0]).max():.3f} m/s, v_y "
            f"{np.abs(crest[:, 1]).max():.3f} m/s; numerical dissipation "
            f"{100 * e['numerical'][-1] / held:.1f} % of the initial energy")


def _lamb(f, result):
    """The lamb figure: the surface velocity at the three gauges against the
    closed form (tests/references/lamb.py), and the largest differences."""
    import matplotlib.pyplot as plt

    sys.path.insert(0, os.path.join(HERE, "..", "tests"))
    from references import lamb

    region = result.case().plane.regions[0]
    force = lamb.ricker_pulse(2.0, 1.0e4, delay=0.6)
    fig, axes = plt.subplots(2, 1, figsize=(9, 7), sharex=True, constrained_layout=True)
    worst = 0.0
    for name in result.gauges:
        g = result.gauge(name)
        x, t = float(g.attrs["x"][0]), g.time
        exact = lamb.surface_velocity(np.array([x]), t, force, region.rho, region.vp,
                                      region.vs)
        for c, ax in enumerate(axes):
            line, = ax.plot(t, 1e3 * g.v[:, c], lw=1.0, label=f"vstpetsc, x = {x:g} m")
            ax.plot(t, 1e3 * exact[c][0], "k:", lw=1.0)
            worst = max(worst, np.abs(g.v[:, c] - exact[c][0]).max()
                        / np.abs(exact[c][0]).max())
    for c, ax in enumerate(axes):
        ax.set_ylabel(f"surface v_{'xy'[c]} [mm/s]")
        ax.legend(fontsize=8, title="dotted: closed form (Lamb 1904)")
    axes[1].set_xlabel("t [s]")
    axes[0].set_title("Lamb's problem: surface velocity under a 2 Hz Ricker line load",
                      fontsize=10)
    fig.savefig(os.path.join(HERE, "figures", "lamb-surface.png"), dpi=110)
    plt.close(fig)
    return (f"largest difference from the closed form {100 * worst:.1f} % of a trace's peak"
            "\n\n![lamb surface velocity](figures/lamb-surface.png)")



def _crest_spectrum(axis, result, label):
    """The crest gauge's horizontal 5 % response spectrum (psa in g)."""
    from vstpetsc.results.spectrum import acceleration

    gauge = result.gauge("crest")
    periods = np.logspace(-2, 1, 120)
    s = vstpetsc.response_spectrum(acceleration(gauge.v[:, 0], gauge.dt), gauge.dt, periods,
                                   0.05)
    axis.loglog(periods, s["psa"] / 9.81, label=label)
    axis.set_xlabel("period [s]")
    axis.set_ylabel("psa [g], 5 %")
    return s


def _interface_figure(result, name, title):
    """Each interface's largest |slip| and opening over time, the crest's
    spectrum and the energy balance: figures/NAME-interfaces.png."""
    import matplotlib.pyplot as plt

    t = result.time
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.6), constrained_layout=True)
    for face in result.interfaces:
        g = result.interface(face)
        axes[0].plot(t, 1e3 * np.abs(g.slip[:]).max(axis=1), label=f"{face}: largest |slip|")
        axes[0].plot(t, 1e3 * np.maximum(g.gap[:], 0).max(axis=1), ":",
                     label=f"{face}: largest opening")
    axes[0].set_xlabel("t [s]")
    axes[0].set_ylabel("mm")
    axes[0].legend(fontsize=7)
    _crest_spectrum(axes[1], result, "crest, x")
    e = result.energy
    for key in ("kinetic", "strain", "contact", "friction", "numerical"):
        axes[2].plot(t, e[key] / 1e3, label=key)
    axes[2].set_xlabel("t [s]")
    axes[2].set_ylabel("kJ per m")
    axes[2].legend(fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.savefig(os.path.join(HERE, "figures", f"{name}-interfaces.png"), dpi=110)
    plt.close(fig)


def _gravity_dam(f, result):
    """Key numbers and the interface figure of gravity-dam: its slip
    against a rigid block's (tests/references/rigid_block.py)."""
    sys.path.insert(0, os.path.join(HERE, "..", "tests"))
    from references.rigid_block import rigid_block_slip

    g = result.interface("contact")
    mu = result.case().plane.interfaces[0].friction
    record = np.loadtxt(bundled.companions("gravity-dam")[0], delimiter=",", skiprows=1)
    rigid = rigid_block_slip(record[:, 0], record[:, 1], 0.5 * record[:, 2], mu, 9.81)[-1]
    slip, nodes, u = g.slip[-1], g.nodes[:], result.field.u[-1]
    moved = np.einsum("mc,mc->m", g.tangent[:], u[nodes[:, 1]] - u[nodes[:, 0]])
    _interface_figure(result, "gravity-dam", "gravity-dam: the base's slip and opening, "
                      "the crest's spectrum, the energy")
    return (f"the dam moved {1e3 * moved.min():.1f} to {1e3 * moved.max():.1f} mm along its "
            f"base relative to the rock (a rigid block on the same records: {1e3 * rigid:.1f} "
            f"mm); slip recorded in contact {1e3 * slip.min():.1f} to {1e3 * slip.max():.1f} mm "
            f"pair by pair (the heel was open as the base slid); heel open up to "
            f"{1e3 * g.gap[:].max():.2f} mm; friction "
            f"dissipated {f['energy/friction'][-1] / 1e3:.1f} kJ per m\n\n"
            "![gravity-dam interfaces](figures/gravity-dam-interfaces.png)")


def _gravity_dam_reservoir(f, result):
    """Key numbers of gravity-dam-reservoir: the static sliding factor of
    safety (info's: mu sum(N) / |sum(T)| at the first kept slab) and the
    largest slip, with the water's resultant."""
    g = result.interface("contact")
    mu = result.case().plane.interfaces[0].friction
    normal, shear = g.normal_force[1].sum(), g.shear_force[1].sum()
    slip, nodes, u = g.slip[:], g.nodes[:], result.field.u[-1]
    moved = np.einsum("mc,mc->m", g.tangent[:], u[nodes[:, 1]] - u[nodes[:, 0]])
    force = result.water("reservoir").force[0]
    return (f"the reservoir pushes ({force[0] / 1e6:.2f}, {force[1] / 1e6:.2f}) MN per m; the "
            f"base carries sum N {normal / 1e6:.2f} MN per m (W - U plus the water above the "
            f"face) and sum T {abs(shear) / 1e6:.2f} MN per m at rest: sliding factor of safety "
            f"mu sum(N) / |sum(T)| {mu * normal / abs(shear):.3g}; largest slip in contact "
            f"{1e3 * np.abs(slip).max():.1f} mm, the dam moved {1e3 * moved.mean():.1f} mm "
            f"along its base relative to the rock (the dry dam: gravity-dam's section); "
            f"friction dissipated {f['energy/friction'][-1] / 1e3:.1f} kJ per m")


def _koyna_panels(axes, f, result, heel):
    """koyna's four panels: the crest's horizontal acceleration, the heel's
    hydrodynamic pressure, the largest principal stress over the section
    (tension positive) and the energy."""
    from matplotlib.collections import PolyCollection

    t, water = result.time, result.water("reservoir")
    gauge = result.gauge("crest")
    axes[0].plot(np.arange(gauge.v.shape[0]) * gauge.dt, acceleration_of(result) / 9.81)
    axes[0].set(xlabel="t [s]", ylabel="g", title="(a) crest, horizontal acceleration")
    pressure = water.pressure[:, heel]
    axes[1].plot(t, (pressure - pressure[0]) / 1e3)
    axes[1].set(xlabel="t [s]", ylabel="kPa", title="(b) heel, hydrodynamic pressure")
    xy, cells = f["mesh/coordinates"][:], f["mesh/cells"][:]
    dam = _dam_cells(f)
    polygons = [xy[c[c >= 0]] for c in cells[dam]]
    art = PolyCollection(polygons, array=f["field/principal_max"][:][dam] / 1e6, cmap="viridis")
    axes[2].add_collection(art)
    axes[2].autoscale_view()
    axes[2].set_aspect("equal")
    axes[2].figure.colorbar(art, ax=axes[2], label="MPa")
    axes[2].set(xlabel="x [m]", ylabel="y [m]", title="(c) largest principal stress, envelope")
    e = result.energy
    for key in ("kinetic", "strain", "external", "damping", "numerical"):
        axes[3].plot(t, e[key] / 1e6, label=key)
    axes[3].set(xlabel="t [s]", ylabel="MJ per m", title="(d) energy")
    axes[3].legend(fontsize=7)


def _dam_cells(f):
    """The dam's cells: region 0 of the generated mesh (regions "dam",
    "foundation", "water" in this order, docs/case-file.md)."""
    return f["mesh/region"][:] == 0


def _koyna(f, result):
    """Key numbers and the response figure of koyna (the first frequencies
    are tests/test_examples.py's, test_koyna_first_frequency_empty_and_full)."""
    import matplotlib.pyplot as plt

    water = result.water("reservoir")
    xy = f["mesh/coordinates"][:]
    heel = int(np.flatnonzero(np.hypot(*xy[water.nodes[:]].T) < 1e-9)[0])
    fig, axes = plt.subplots(1, 4, figsize=(17, 3.8), constrained_layout=True)
    _koyna_panels(axes, f, result, heel)
    fig.savefig(os.path.join(HERE, "figures", "koyna-response.png"), dpi=110)
    plt.close(fig)
    pressure = water.pressure[:]
    dynamic = np.abs(pressure[:, heel] - pressure[0, heel])
    drift = result.gauge("crest").u[:, 0] - result.gauge("heel").u[:, 0]
    drift = drift - drift[0]                        # from the static state
    tension, dam = f["field/principal_max"][:], _dam_cells(f)
    k = int(np.flatnonzero(dam)[tension[dam].argmax()])
    centre = xy[f["mesh/cells"][k][f["mesh/cells"][k] >= 0]].mean(axis=0)
    e = result.energy
    largest = max(np.abs(e[key]).max() for key in ("kinetic", "strain", "external"))
    low = np.unravel_index(int(pressure.argmin()), pressure.shape)
    return (f"crest's peak horizontal acceleration {np.abs(acceleration_of(result)).max() / 9.81:.2f} g, "
            f"peak horizontal displacement relative to the heel {1e3 * np.abs(drift).max():.1f} mm; "
            f"heel's "
            f"peak hydrodynamic pressure {dynamic.max() / 1e3:.0f} kPa at t = "
            f"{result.time[dynamic.argmax()]:.2f} s (hydrostatic {pressure[0, heel] / 1e3:.1f} kPa); "
            f"lowest total pressure on the faces {pressure[low] / 1e3:.0f} kPa at "
            f"({xy[water.nodes[low[1]]][0]:.1f}, {xy[water.nodes[low[1]]][1]:.1f}) m, t = "
            f"{result.time[low[0]]:.2f} s (below zero: the linear water pulls, no cavitation); "
            f"largest principal tension in the dam {tension[k] / 1e6:.2f} MPa (cell {k} at "
            f"({centre[0]:.1f}, {centre[1]:.1f}) m, t = {f['field/principal_max_time'][k]:.2f} s); "
            f"numerical energy {e['numerical'][-1] / largest:.2g} of the largest "
            f"({largest / 1e6:.0f} MJ per m)\n\n"
            "![koyna response](figures/koyna-response.png)")


def _rockfill_dam(f, result):
    """Key numbers and the interface figure of rockfill-dam."""
    _interface_figure(result, "rockfill-dam", "rockfill-dam: each interface's slip and "
                      "opening, the crest's spectrum, the energy")
    parts = []
    for face in result.interfaces:
        g = result.interface(face)
        parts.append(f"{face} {1e3 * np.abs(g.slip[:]).max():.1f} mm")
    return ("largest slip: " + ", ".join(parts) + f"; friction dissipated "
            f"{f['energy/friction'][-1] / 1e3:.1f} kJ per m\n\n"
            "![rockfill-dam interfaces](figures/rockfill-dam-interfaces.png)")


def _variant(name, drop, folder, dt=None):
    """The bundled example ``name`` without the lines starting with the
    keys ``drop`` (and with slabs of ``dt``), run in ``folder`` beside its
    companions: its Result."""
    import shutil

    text = "\n".join(l for l in bundled.text(name).splitlines()
                     if not l.startswith(tuple(drop)))
    if dt is not None:
        text = text.replace("\ndt  = ", f"\ndt  = {dt!r}  # was ", 1)
    for companion in bundled.companions(name):
        shutil.copy(companion, folder)
    path = os.path.join(folder, f"{name}-{'-'.join(drop)}.toml")
    with open(path, "w") as f:
        f.write(text)
    return vstpetsc.run(vstpetsc.Case.from_toml(path), path[:-5] + ".h5", quiet=True,
                        out=io.StringIO())


def _strain_panel(ax, result):
    """The largest equivalent shear strain of each cell over the run (%)
    on the undeformed section, the dam only."""
    from matplotlib.collections import PolyCollection
    from vstpetsc.results.plane_plot import outlines

    mesh = result.mesh
    xy = mesh.coordinates[outlines(mesh.cells)]
    strain = 1e2 * result.read("field/strain_max")
    dam = strain > 0
    shade = PolyCollection(xy[dam], array=strain[dam], cmap="magma_r", edgecolors="none")
    ax.add_collection(shade)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.figure.colorbar(shade, ax=ax, label="largest 2 sqrt(J2) [%]", shrink=0.8)
    ax.set_title("(a) the largest shear strain of each cell over the run", fontsize=10)


def _rockfill_dam_mkz(f, result):
    """Key numbers and the figure of rockfill-dam-mkz: the largest strain
    over the section, the crest's spectrum against the linear dam's and the
    unconfined yielding dam's, the joints' slip, the energy."""
    import matplotlib.pyplot as plt

    with tempfile.TemporaryDirectory() as folder:
        others = {"linear (rockfill-dam)": _variant("rockfill-dam-mkz",
                                                    ("shear_law", "confinement"), folder),
                  # (slabs of 4 ms: with 2 ms its Newton stalls at slab 2738)
                  "yielding, unconfined, 4 ms": _variant("rockfill-dam-mkz", ("confinement",), folder,
                                                   dt=4.0e-3)}
        fig, ((strain, spectra), (slip, energy)) = plt.subplots(2, 2, figsize=(12, 8),
                                                                constrained_layout=True)
        _strain_panel(strain, result)
        peaks = {"yielding, confined": _crest_spectrum(spectra, result, "yielding, confined")}
        for label, other in others.items():
            peaks[label] = _crest_spectrum(spectra, other, label)
        spectra.set_title("(b) the crest's horizontal acceleration spectrum", fontsize=10)
        spectra.legend(fontsize=8)
        t = result.time
        for k, face in enumerate(result.interfaces):
            slip.plot(t, 1e3 * np.abs(result.interface(face).slip[:]).max(axis=1),
                      color=f"C{k}", label=f"{face}, yielding")
            linear = others["linear (rockfill-dam)"]
            slip.plot(linear.time, 1e3 * np.abs(linear.interface(face).slip[:]).max(axis=1),
                      ":", color=f"C{k}", label=f"{face}, linear")
        slip.set_xlabel("t [s]")
        slip.set_ylabel("largest |slip| [mm]")
        slip.set_title("(c) the joints' slip", fontsize=10)
        slip.legend(fontsize=7)
        e = result.energy
        for key in ("kinetic", "strain", "friction", "hysteretic", "numerical"):
            energy.plot(t, e[key] / 1e3, label=key)
        energy.set_xlabel("t [s]")
        energy.set_ylabel("kJ per m")
        energy.set_title(f"(d) the energy (damped and absorbed, not drawn: "
                         f"{e['damping'][-1] / 1e6:.0f} MJ/m)", fontsize=10)
        energy.legend(fontsize=8)
        fig.savefig(os.path.join(HERE, "figures", "rockfill-dam-mkz-response.png"), dpi=110)
        plt.close(fig)
        crest = {label: float(np.abs(acceleration_of(r)).max()) / 9.81
                 for label, r in [("yielding, confined", result)] + list(others.items())}
    strain_max = result.read("field/strain_max")
    k = int(strain_max.argmax())
    slips = ", ".join(f"{face} {1e3 * np.abs(result.interface(face).slip[:]).max():.1f} mm"
                      for face in result.interfaces)
    return (f"largest shear strain {1e2 * strain_max[k]:.3g} % (cell {k}, t = "
            f"{result.read('field/strain_max_time')[k]:.3g} s); crest's peak horizontal "
            "acceleration " + ", ".join(f"{label} {a:.2f} g" for label, a in crest.items())
            + f"; largest slip: {slips}; hysteretic {f['energy/hysteretic'][-1] / 1e3:.1f}, "
            f"friction {f['energy/friction'][-1] / 1e3:.1f} kJ per m\n\n"
            "![rockfill-dam-mkz response](figures/rockfill-dam-mkz-response.png)")


def acceleration_of(result):
    """The crest gauge's horizontal acceleration (slab by slab)."""
    from vstpetsc.results.spectrum import acceleration

    gauge = result.gauge("crest")
    return acceleration(gauge.v[:, 0], gauge.dt)


KEY = {"bar-wall": _bar_wall, "two-bars": _two_bars, "unequal-bars": _unequal,
       "periodic-impacts": _periodic, "layered": _layered, "wave": _wave,
       "site-response": _site, "uplift": _uplift, "drop": _drop, "pile": _pile,
       "bouncing-bar": _bouncing, "sliding-block": _sliding_block,
       "dam-interface": _dam_interface, "nonlinear-site": _nonlinear_site,
       "rockfill-column": _rockfill_column, "plane-column": _plane_column,
       "dam-modes": _dam_modes, "lamb": _lamb, "gravity-dam": _gravity_dam,
       "gravity-dam-reservoir": _gravity_dam_reservoir, "koyna": _koyna,
       "rockfill-dam": _rockfill_dam, "rockfill-dam-mkz": _rockfill_dam_mkz}
NEEDS_RESULT = {"rockfill-dam-mkz", "nonlinear-site", "site-response", "uplift", "drop", "pile", "bouncing-bar",
                "sliding-block", "dam-interface", "rockfill-column", "plane-column",
                "dam-modes", "lamb", "gravity-dam", "gravity-dam-reservoir", "koyna",
                "rockfill-dam"}


def main(only=None):
    """docs/examples.md anew (``only``: print the section of that example)."""
    lines = ["# Examples", "",
             "Generated by `docs/make_figures.py` (`make figures`); do not edit.",
             "Write any of them with `vstpetsc example NAME`, run it with",
             "`vstpetsc run NAME.toml`, look at it with `vstpetsc info NAME.h5` and",
             "`vstpetsc plot NAME.h5`. Wall times: one rank, this project's 2-core machine.",
             ""]
    with tempfile.TemporaryDirectory() as folder:
        for name in [only] if only else bundled.names():
            text = bundled.text(name)
            out = os.path.join(folder, name + ".h5")
            result = vstpetsc.run(vstpetsc.Case.from_toml(bundled.path(name)), out, quiet=True,
                                  out=io.StringIO())
            res = result.run
            plot_result(out, os.path.join(HERE, "figures", name + ".png"))
            # opened as every reader of a result opens it (SWMR: HDF5 refuses
            # a second open of one file in another mode)
            with open_to_read(out) as f:
                key = KEY[name](f, result) if name in NEEDS_RESULT else KEY[name](f)
            story = [l[2:] if l.startswith("# ") else "" for l in text.splitlines()[2:]
                     if l.startswith("#")]
            lines += [f"## {name}", "", bundled.description(name).capitalize() + ".", ""]
            lines += story + ["", f"- wall time: {res.wall:.1f} s for {res.slabs} slabs",
                              f"- {key}", "", f"![{name}](figures/{name}.png)", ""]
            print(f"{name}: {res.wall:.1f} s; {key}")
    if only:
        print("\n".join(lines[7:]))
        return
    with open(os.path.join(HERE, "examples.md"), "w") as f:
        f.write("\n".join(lines))


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:2]))
