"""Sliding-block analysis as users do it (issue 27, docs/sliding-block.md).

(a) D(ky): the bundled sliding-block case (a stiff 2 m block on a wall
shaking with one cycle of 3 sin(2 pi t) m/s^2) swept with ``vstpetsc.sweep``
over ``contact.0.friction`` (ky = mu) for the record and the record reversed
(``contact.0.wall_shear_velocity.scale = -1``), against Newmark's rigid block
(tests/references/sliding_block.py) on the same ground motion: the case integrates the
acceleration samples exactly, so the ground acceleration is the record's,
linear between samples.

(b) A flexible 20 m soil column on the same moving wall, its fixed-base
period 4 H / Vs below, at and above the record's (1 s), for a few ky:
vstpetsc against the single-mode coupled model of Rathje & Bray (2000)
(``coupled_single_mode``, omega = pi Vs / (2 H), the uniform shear column's
modal constants) and against the rigid block; and the welded column's peak
base shear against the single mode's (what the higher modes add).

    .venv/bin/python studies/sliding_study.py [--keep DIR]

Prints markdown tables, writes docs/figures/sliding-block-dky.png and
docs/figures/sliding-column.png. About 90 s on one core.
"""

import argparse
import io
import math
import os
import sys
import tempfile
import time

import numpy as np

import vstpetsc
from vstpetsc import bundled

# Newmark's block and the single mode live beside the tests that check them
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.append(os.path.join(ROOT, "tests"))
from references.sliding_block import (UNIFORM_SHEAR_COLUMN,  # noqa: E402
                                      coupled_single_mode, ground_acceleration, newmark,
                                      rigid_block)

G_ACC = 9.81
FIGURES = os.path.join(ROOT, "docs", "figures")
FRICTIONS = [0.05, 0.075, 0.1, 0.15, 0.2, 0.25, 0.3, 0.5]
SCALE_KEY = "contact.0.wall_shear_velocity.scale"

# the column of (b): height, density, elements, dt, end, and the sweep
H, RHO, COLUMN_ELEMENTS, COLUMN_DT, COLUMN_END = 20.0, 2000.0, 40, 1e-3, 5.0
SPEEDS = [320.0, 160.0, 80.0, 40.0]          # 4 H / Vs = 0.25, 0.5, 1, 2 s
COLUMN_FRICTIONS = [0.05, 0.1, 0.2]


def run_sweep(case, settings, folder):
    """vstpetsc.sweep, timed: (rows, seconds)."""
    start = time.perf_counter()
    rows = vstpetsc.sweep(case, settings, folder)
    bad = [r for r in rows if r["status"] != "completed"]
    if bad:
        raise SystemExit(f"sweep: {len(bad)} runs failed: {bad[0].get('message')}")
    return rows, time.perf_counter() - start


def rigid_slips(rigid):
    """(permanent slip, largest |slip|) of a Newmark rigid block's result:
    what both parts set beside vstpetsc's slips."""
    return rigid.permanent, float(np.abs(rigid.u).max())


# ---------------------------------------------------------------- (a) D(ky)

def block_study(folder):
    """The D(ky) sweep of the bundled case, both polarities: rows with the
    rigid block's permanent and largest slip added."""
    case = vstpetsc.Case.from_toml(bundled.path("sliding-block"))
    rows, seconds = run_sweep(case, {SCALE_KEY: [1.0, -1.0], "contact.0.friction": FRICTIONS},
                              folder)
    for row in rows:
        rigid = rigid_block(case.with_value(SCALE_KEY, row[SCALE_KEY])
                            .with_value("contact.0.friction", row["contact.0.friction"]))
        row["rigid"], row["rigid_max"] = rigid_slips(rigid)
    return rows, seconds


def block_table(rows):
    """The markdown table of (a)."""
    lines = ["| scale | ky = mu | D vstpetsc [m] | D Newmark [m] | max abs slip vstpetsc [m] | "
             "max abs slip Newmark [m] | D error / max abs slip | max abs slip rel. error |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        big = r["rigid_max"]
        d_err = abs(r["slip_0"] - r["rigid"]) / big if big else abs(r["slip_0"])
        m_err = abs(r["slip_max_0"] / big - 1) if big else r["slip_max_0"]
        lines.append(f"| {r[SCALE_KEY]:+g} | {r['contact.0.friction']:g} | {r['slip_0']:+.5g} | "
                     f"{r['rigid']:+.5g} | {r['slip_max_0']:.5g} | {big:.5g} | {d_err:.1e} | "
                     f"{m_err:.1e} |")
    return "\n".join(lines)


def mirror_line(rows):
    """How exactly the reversed record mirrors the slips."""
    n = len(FRICTIONS)
    worst = max(abs(a["slip_0"] + b["slip_0"]) for a, b in zip(rows[:n], rows[n:]))
    worst_max = max(abs(a["slip_max_0"] - b["slip_max_0"]) for a, b in zip(rows[:n], rows[n:]))
    return (f"reversed record: largest |D(+1) + D(-1)| = {worst:.2e} m, largest "
            f"|max(+1) - max(-1)| = {worst_max:.2e} m")


def block_figure(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(FRICTIONS)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for part, scale, marker in ((rows[:n], "+1", "o"), (rows[n:], "-1", "s")):
        ky = [r["contact.0.friction"] for r in part]
        axes[0].plot(ky, [r["rigid_max"] for r in part], "-", color="0.6")
        axes[0].plot(ky, [r["slip_max_0"] for r in part], marker, mfc="none",
                     label=f"vstpetsc, scale = {scale}")
        axes[1].plot(ky, [r["rigid"] for r in part], "-", color="0.6")
        axes[1].plot(ky, [r["slip_0"] for r in part], marker, mfc="none",
                     label=f"vstpetsc, scale = {scale}")
    for ax, what in zip(axes, ("(a) largest |slip| [m]", "(b) permanent slip D [m]")):
        ax.plot([], [], "-", color="0.6", label="Newmark rigid block")
        ax.set_xlabel("ky = mu (yield acceleration / g)")
        ax.set_title(what)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("sliding-block: one cycle of 3 sin(2 pi t) m/s^2 (PGA 0.31 g)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ---------------------------------------------------------- (b) the column

def column_case(Vs=SPEEDS[0], mu=COLUMN_FRICTIONS[0], every=5):
    """A 20 m soil column (x up, A = 1) resting under its weight on the
    bundled case's shaking wall, undamped."""
    record = bundled.companions("sliding-block")[0]
    return vstpetsc.Case.from_dict({
        "time": {"dt": COLUMN_DT, "end": COLUMN_END}, "output": {"every": every},
        "gravity": {"g": -G_ACC, "initial": "static"},
        "body": [{"name": "col", "x": [0.0, H], "elements": COLUMN_ELEMENTS, "E": 1e9,
                  "rho": RHO, "Vs": Vs}],
        "contact": [{"pair": ["wall", "col"], "wall": 0.0, "friction": mu,
                     "wall_shear_velocity": {"file": record, "column": "acc",
                                             "integrate": True}}]})


def omega(Vs):
    """The fixed-base first mode of a uniform shear column, pi Vs / (2 H)."""
    return math.pi * Vs / (2.0 * H)


def column_study(folder):
    """Sweep Vs x mu; per run the vstpetsc, single-mode and rigid slips
    (permanent, largest |.|) and the histories for the figure."""
    from vstpetsc.results.reader import Result

    case = column_case()
    rows, seconds = run_sweep(case, {"body.col.Vs": SPEEDS, "contact.0.friction":
                                     COLUMN_FRICTIONS}, folder)
    t, a = ground_acceleration(case, COLUMN_END)
    for row in rows:
        mu, Vs = row["contact.0.friction"], row["body.col.Vs"]
        r = Result(os.path.join(folder, row["file"]))
        row["history"] = (r.time, r.contact(0).slip[:])
        ct, cs, *_ = coupled_single_mode(t, a, mu * G_ACC, omega(Vs))
        row["coupled"], row["coupled_max"] = cs[-1], np.abs(cs).max()
        row["coupled_history"] = (ct, cs)
        rigid = newmark(t, a, mu * G_ACC)
        row["rigid"], row["rigid_max"] = rigid_slips(rigid)
        row["rigid_history"] = (rigid.t, rigid.u)
    return rows, seconds


def column_table(rows):
    lines = ["| 4H/Vs [s] | Vs [m/s] | ky | D vstpetsc [m] | D single mode [m] | D rigid [m] | "
             "max abs slip vstpetsc [m] | single mode [m] | rigid [m] |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        Vs = r["body.col.Vs"]
        lines.append(f"| {4 * H / Vs:g} | {Vs:g} | {r['contact.0.friction']:g} | "
                     f"{r['slip_0']:+.4f} | {r['coupled']:+.4f} | {r['rigid']:+.4f} | "
                     f"{r['slip_max_0']:.4f} | {r['coupled_max']:.4f} | {r['rigid_max']:.4f} |")
    return "\n".join(lines)


def welded_base_shear(folder):
    """Per Vs: the peak base shear of the welded column (friction 10: no
    slip) over its weight, from vstpetsc (slab means, every slab kept) and
    from the single mode, whose base asks a_g + kappa q'' per unit mass."""
    case = column_case(every=1)
    t, a = ground_acceleration(case, COLUMN_END)
    gamma, kappa = UNIFORM_SHEAR_COLUMN
    out = []
    for Vs in SPEEDS:
        r = vstpetsc.run(case.with_value("body.col.Vs", Vs).with_value("contact.0.friction", 10.0),
                         output=os.path.join(folder, f"welded-{Vs:g}.h5"), quiet=True,
                         out=io.StringIO())
        continuum = np.abs(r.contact(0).shear_force).max() / (RHO * H * G_ACC)
        ct, _, _, q, _ = coupled_single_mode(t, a, 1e9, omega(Vs))
        demand = np.interp(ct, t[::2], a[::2]) * (1 - gamma * kappa) - kappa * omega(Vs) ** 2 * q
        out.append((Vs, continuum, np.abs(demand).max() / G_ACC))
    return out


def welded_table(welded):
    lines = ["| 4H/Vs [s] | peak base shear / weight, continuum | single mode | ratio |",
             "|---|---|---|---|"]
    lines += [f"| {4 * H / Vs:g} | {c:.3f} | {s:.3f} | {c / s:.2f} |" for Vs, c, s in welded]
    return "\n".join(lines)


def refinement_check(rows, folder):
    """A few runs of (b) again on twice the elements at half the step, and
    the single mode on finer sub-steps: how much of a difference between
    the models is discretisation. Markdown lines."""
    t, a = ground_acceleration(column_case(), COLUMN_END)
    lines = ["| 4H/Vs [s] | ky | D vstpetsc, 40 el. / 80 el. half dt [m] | D single mode, "
             "default / 4x finer sub-steps [m] |", "|---|---|---|---|"]
    for Vs, mu in ((40.0, 0.1), (160.0, 0.1), (80.0, 0.2)):
        row = next(r for r in rows if (r["body.col.Vs"], r["contact.0.friction"]) == (Vs, mu))
        case = column_case(Vs, mu).with_value("body.col.elements", 2 * COLUMN_ELEMENTS)
        fine = vstpetsc.run(case.with_value("time.dt", COLUMN_DT / 2),
                            output=os.path.join(folder, f"fine-{Vs:g}-{mu:g}.h5"), quiet=True,
                            out=io.StringIO()).contact(0).slip[-1]
        _, cs, *_ = coupled_single_mode(t, a, mu * G_ACC, omega(Vs), substeps=16,
                                        steps_per_radian=40)
        lines.append(f"| {4 * H / Vs:g} | {mu:g} | {row['slip_0']:+.5f} / {fine:+.5f} | "
                     f"{row['coupled']:+.5f} / {cs[-1]:+.5f} |")
    return "\n".join(lines)


def column_figure(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    chosen = [r for r in rows if r["contact.0.friction"] == 0.1]
    fig, axes = plt.subplots(1, len(chosen), figsize=(3.2 * len(chosen), 3.6), sharey=True)
    for ax, r in zip(axes, chosen):
        ax.plot(*r["history"], "-", label="vstpetsc column")
        ax.plot(*r["coupled_history"], "--", label="single mode (R&B 2000)")
        ax.plot(*r["rigid_history"], ":", color="k", label="rigid (Newmark)")
        ax.set_title(f"4H/Vs = {4 * H / r['body.col.Vs']:g} s", fontsize=9)
        ax.set_xlabel("t [s]")
        ax.set_xlim(0, COLUMN_END)
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel("slip at the base [m]")
    axes[0].legend(fontsize=7)
    fig.suptitle(f"{H:g} m column on the shaking wall, ky = 0.1", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--keep", help="keep the runs in this folder (default: a temporary one)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as temp:
        folder = args.keep or temp
        rows, seconds = block_study(os.path.join(folder, "block"))
        print(f"## (a) D(ky) of the sliding-block case ({len(rows)} runs, {seconds:.1f} s)\n")
        print(block_table(rows) + "\n\n" + mirror_line(rows) + "\n")
        block_figure(rows, os.path.join(FIGURES, "sliding-block-dky.png"))
        start = time.perf_counter()
        rows, seconds = column_study(os.path.join(folder, "column"))
        print(f"## (b) a {H:g} m column, {COLUMN_ELEMENTS} elements, dt {COLUMN_DT:g} "
              f"({len(rows)} runs, {seconds:.1f} s)\n")
        print(column_table(rows) + "\n")
        column_figure(rows, os.path.join(FIGURES, "sliding-column.png"))
        print(welded_table(welded_base_shear(folder)) + "\n")
        print(refinement_check(rows, folder))
        print(f"\n(b) with the references and the welded runs: {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
