"""Run every bundled example, draw its figure into docs/figures/ and write
docs/examples.md with its story, wall time and key number.  Run: make figures
"""

import io
import os
import sys
import tempfile

import h5py
import numpy as np

import vstpetsc
from vstpetsc import analysis, bundled
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
    c = float(np.sqrt(soil.E(0.0) / soil.rho(0.0)))
    H = soil.x[1] - soil.x[0]
    a = float(soil.rho(0.0)) * c / base["impedance"]
    t = result.time
    freq, ratio = analysis.transfer_function(t, result.body("soil").v[:, -1],
                                             2 * base["incident"](t))
    keep = freq <= 10.0
    fig, ax = plt.subplots(figsize=(8, 4.5), constrained_layout=True)
    ax.plot(freq[keep], ratio[keep], label="vstpetsc: smoothed spectral ratio surface / outcrop")
    ax.plot(freq[keep], analysis.layer_amplification(freq[keep], H, c, a), "k--", lw=1,
            label=f"closed form 1/sqrt(cos^2 kH + a^2 sin^2 kH), a = {a:.3f}")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("amplification")
    ax.set_title("site-response: surface velocity over rock-outcrop velocity")
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

    sys.path.insert(0, os.path.join(os.path.dirname(HERE), "bench"))
    from sliding_block import newmark

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


KEY = {"bar-wall": _bar_wall, "two-bars": _two_bars, "unequal-bars": _unequal,
       "periodic-impacts": _periodic, "layered": _layered, "wave": _wave,
       "site-response": _site, "uplift": _uplift, "drop": _drop, "pile": _pile,
       "bouncing-bar": _bouncing, "sliding-block": _sliding_block,
       "dam-interface": _dam_interface}
NEEDS_RESULT = {"site-response", "uplift", "drop", "pile", "bouncing-bar", "sliding-block",
                "dam-interface"}


def main():
    lines = ["# Examples", "",
             "Generated by `docs/make_figures.py` (`make figures`); do not edit.",
             "Write any of them with `vstpetsc example NAME`, run it with",
             "`vstpetsc run NAME.toml`, look at it with `vstpetsc info NAME.h5` and",
             "`vstpetsc plot NAME.h5`. Wall times: one rank, this project's 2-core machine.",
             ""]
    with tempfile.TemporaryDirectory() as folder:
        for name in bundled.names():
            text = bundled.text(name)
            out = os.path.join(folder, name + ".h5")
            result = vstpetsc.run(vstpetsc.Case.from_toml(bundled.path(name)), out, quiet=True,
                                  out=io.StringIO())
            res = result.run
            plot_result(out, os.path.join(HERE, "figures", name + ".png"))
            with h5py.File(out, "r", locking=False) as f:
                key = KEY[name](f, result) if name in NEEDS_RESULT else KEY[name](f)
            story = [l[2:] if l.startswith("# ") else "" for l in text.splitlines()[2:]
                     if l.startswith("#")]
            lines += [f"## {name}", "", bundled.description(name).capitalize() + ".", ""]
            lines += story + ["", f"- wall time: {res.wall:.1f} s for {res.slabs} slabs",
                              f"- {key}", "", f"![{name}](figures/{name}.png)", ""]
            print(f"{name}: {res.wall:.1f} s; {key}")
    with open(os.path.join(HERE, "examples.md"), "w") as f:
        f.write("\n".join(lines))


if __name__ == "__main__":
    sys.exit(main())
