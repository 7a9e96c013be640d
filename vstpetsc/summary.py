"""Summaries of a result file, computed from its arrays (for `vstpetsc info`)."""

from dataclasses import dataclass

import h5py
import numpy as np


@dataclass
class PairSummary:
    """Contact history of one pair over the kept slabs."""

    name: str
    formulation: str
    penalty: float
    first_contact: float     # start of the first slab with contact (nan: none)
    duration: float          # total length of the slabs with contact
    episodes: int            # runs of consecutive slabs with contact
    peak_force: float        # largest slab-mean force
    mean_force: float        # total impulse / total contact time
    impulse: float           # total impulse
    penetration: float       # largest overlap at kept slab ends (0: none)


def pair_summary(group, k):
    """Summarise pair k from its group in the result file: the running
    totals over every slab (the last kept value), and the kept arrays."""
    last = lambda key: float(group[key][-1])
    a = dict(group.attrs)
    name = a.get("pair", str(k))
    name = name.decode() if isinstance(name, bytes) else str(name)
    force, impulse = group["force"][1:], group["impulse"][1:]
    duration = last("contact_time")
    return PairSummary(
        name=name.replace(",", " | "), formulation=str(a.get("formulation", "")),
        penalty=float(a.get("penalty", np.nan)), first_contact=last("first_contact"),
        duration=duration, episodes=int(last("episodes")), peak_force=last("force_peak"),
        mean_force=last("impulse_total") / duration if duration > 0 else 0.0,
        impulse=last("impulse_total"),
        penetration=float(max(0.0, -group["gap"][:].min())))


def summarize(path):
    """A dict of everything `vstpetsc info` prints."""
    with h5py.File(path, "r") as f:
        a = dict(f.attrs)
        time = f["time"][:]
        dt = float(a.get("dt", time[1] - time[0] if time.size > 1 else np.nan))
        every = int(a.get("every", 1))
        bodies = [(name, g["x"].size - 1, float(g["x"][0]), float(g["x"][-1]))
                  for name, g in f["body"].items()]
        bodies.sort(key=lambda b: b[2])
        pairs = [pair_summary(f[f"contact/{k}"], k) for k in sorted(f["contact"], key=int)]
        energy = f["energy/kinetic"][:] + f["energy/strain"][:]
        newton = f["solver/newton_iterations"][1:]
        linear = f["solver/linear_iterations"][1:]
    text = lambda v: v.decode() if isinstance(v, bytes) else str(v)
    return {
        "status": text(a.get("status", "?")), "version": text(a.get("version", "?")),
        "message": text(a.get("message", "")), "formulation": text(a.get("formulation", "")),
        "solver": text(a.get("solver", "")), "mpi_size": int(a.get("mpi_size", 1)),
        "dt": dt, "every": every, "slabs": int(a.get("slabs", 0)),
        "slabs_done": int(a.get("slabs_done", round(time[-1] / dt) if time.size else 0)),
        "kept": time.size, "t_end": float(time[-1]) if time.size else 0.0,
        "bodies": bodies, "pairs": pairs,
        "energy_start": float(energy[0]) if energy.size else np.nan,
        "energy_end": float(energy[-1]) if energy.size else np.nan,
        "newton_mean": float(newton.mean()) if newton.size else 0.0,
        "newton_max": int(newton.max()) if newton.size else 0,
        "linear_mean": float(linear.mean()) if linear.size else 0.0,
        "wall_time": float(a.get("wall_time", np.nan)),
    }


def format_summary(s, path):
    """The one-screen text of `vstpetsc info`."""
    lines = [f"{path}: {s['status']}" + (f" ({s['message']})" if s["message"] else ""),
             f"  vstpetsc {s['version']}, {s['mpi_size']} rank(s), solver: {s['solver']}",
             f"  dt = {s['dt']:g}, {s['slabs_done']} of {s['slabs']} slabs to t = "
             f"{s['t_end']:g}, {s['kept']} kept times (every {s['every']})",
             "  bodies:"]
    for name, ne, x0, x1 in s["bodies"]:
        lines.append(f"    {name:<14} x = [{x0:g}, {x1:g}], {ne} elements")
    if s["pairs"]:
        lines.append(f"  contact ({s['formulation']}):")
    for k, p in enumerate(s["pairs"]):
        if np.isnan(p.first_contact):
            lines.append(f"    [{k}] {p.name}: no contact (penalty {p.penalty:.4g}, {p.formulation})")
            continue
        lines += [f"    [{k}] {p.name} ({p.formulation}, penalty {p.penalty:.4g})",
                  f"        first contact t = {p.first_contact:.6g}, total duration "
                  f"{p.duration:.6g}, {p.episodes} episode(s)",
                  f"        force peak {p.peak_force:.6g}, mean {p.mean_force:.6g}; impulse "
                  f"{p.impulse:.6g}; largest penetration {p.penetration:.4g}"]
    e0, e1 = s["energy_start"], s["energy_end"]
    rel = (e1 - e0) / e0 * 100 if e0 else float("nan")
    lines.append(f"  energy: start {e0:.6g}, end {e1:.6g} ({rel:+.3f} %)")
    lines.append(f"  Newton iterations per slab: mean {s['newton_mean']:.3g}, max "
                 f"{s['newton_max']}; linear solves per slab: mean {s['linear_mean']:.3g}")
    if not np.isnan(s["wall_time"]):
        lines.append(f"  wall time {s['wall_time']:.3f} s")
    if s["every"] > 1:
        lines.append(f"  (contact totals over every slab; penetration at kept times only)")
    return "\n".join(lines)
