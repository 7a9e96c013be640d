"""Summaries of a result file, computed from its arrays (for `vstpetsc info`)."""

import numpy as np

from vstpetsc.runner.energy import DISSIPATED, HELD
from vstpetsc.results import layout
from vstpetsc.results.layout import text

# the energy a run holds: the bodies' and the contact pairs' (their springs)
HOLDS = HELD + ("contact",)
LISTED_CONTACTS = 3     # contacts `info` lists one by one (then the total)


def pair_summary(group, k, t_end):
    """Contact history of pair k from its group of the result: the running
    totals over every slab (their last kept value), the kept gaps and the
    events; ``t_end`` is the time of the last row.

    Keys: name, formulation, penalty, first_contact (start of the first slab
    with contact, nan: none), duration (see :func:`contact_duration`),
    episodes (runs of consecutive slabs with contact), peak_force
    (largest slab-mean force), mean_force (total impulse / duration),
    impulse (total), penetration (largest overlap at kept slab ends),
    contacts ([(close, open)] from the events, open nan while still closed;
    None for a file without events).
    """
    last = lambda key: float(group[key][-1])
    a = group.attrs
    spans = contact_spans(group["events"], t_end) if "events" in group.keys() else None
    duration = contact_duration(spans, t_end, last("contact_time"))
    return {"name": text(a.get("pair", str(k))).replace(",", " | "),
            "formulation": text(a.get("formulation", "")),
            "penalty": float(a.get("penalty", np.nan)), "first_contact": last("first_contact"),
            "restitution": float(a.get("restitution", np.nan)),
            "duration": duration, "episodes": int(last("episodes")),
            "peak_force": last("force_peak"),
            "mean_force": last("impulse_total") / duration if duration > 0 else 0.0,
            "impulse": last("impulse_total"),
            "penetration": float(max(0.0, -group["gap"].min())),
            "contacts": spans, **slip_summary(group)}


def contact_duration(spans, t_end, slab_time):
    """The one contact duration `info` and a sweep's summary give: the sum
    of the contacts' spans from close to open, a contact still closed
    counted to ``t_end`` (the end of the run); for a file without events
    (spans None), ``slab_time``, the total length of the slabs with
    contact."""
    if spans is None:
        return slab_time
    return float(sum((t_end if np.isnan(o) else o) - c for c, o in spans))


def slip_summary(group):
    """{friction, slip (the permanent slip), slip_max (largest |slip| at
    the kept rows)} of a pair with friction, {} without."""
    if "slip" not in group.keys():
        return {}
    slip = group["slip"]
    return {"friction": float(group.attrs.get("friction", np.nan)),
            "slip": float(slip[-1]) if slip.size else 0.0,
            "slip_max": float(np.abs(slip).max(initial=0.0))}


def contact_spans(events, t_end):
    """[(close, open)] of an (m, 2) events array up to ``t_end`` (a killed
    run's file may hold events of slabs after its last row); open nan for
    a contact still closed then."""
    spans = []
    for t, change in events[events[:, 0] <= t_end].tolist():
        if change > 0:
            spans.append((t, np.nan))
        elif spans:
            spans[-1] = (spans[-1][0], t)
    return spans


def contact_line(k, p, t_end):
    """`info`'s line of pair k (its summary ``p``): the number of contacts
    and each one's duration (close to open, or to ``t_end``, the end of the
    run, for one still closed); for many the total and the first few."""
    def one(close, open_):
        if np.isnan(open_):
            return f"{t_end - close:.6g} s (close {close:.6g}, still closed at the end)"
        return f"{open_ - close:.6g} s (close {close:.6g}, open {open_:.6g})"

    spans = p["contacts"]
    n = len(spans)
    head = f"    contact[{k}] {p['name']}: {n} contact{'' if n == 1 else 's'}"
    if n <= 1:
        return f"{head}, {one(*spans[0])}" if n else head
    listed = "; ".join(one(*s) for s in spans[:LISTED_CONTACTS])
    return (f"{head}, total {p['duration']:.6g} s; {listed}"
            f"{', ...' if n > LISTED_CONTACTS else ''}")


def summarize(result):
    """A dict of everything `vstpetsc info` prints, from a Result."""
    a = result.attrs
    time = result.time
    dt = float(a.get("dt", time[1] - time[0] if time.size > 1 else np.nan))
    every = int(a.get("every", 1))
    bodies = [body_summary(result, name) for name in result.bodies]
    t_end = float(time[-1]) if time.size else 0.0
    pairs = [pair_summary(result.contact(k), k, t_end) for k in range(result.ncontacts)]
    energies = {key: result.energy[key] for key in result.energy}
    totals = energy_totals(energies)
    newton = result.solver["newton_iterations"][1:]
    linear = result.solver["linear_iterations"][1:]
    return {
        "status": result.status, "version": text(a.get("version", "?")),
        "message": text(a.get("message", "")), "formulation": text(a.get("formulation", "")),
        "solver": text(a.get("solver", "")), "mpi_size": int(a.get("mpi_size", 1)),
        "dt": dt, "every": every, "slabs": int(a.get("slabs", 0)),
        "slabs_done": int(a.get("slabs_done", round(time[-1] / dt) if time.size else 0)),
        "kept": time.size, "t_end": float(time[-1]) if time.size else 0.0,
        "bodies": bodies, "pairs": pairs,
        "gauges": [(plane_gauge_summary if result.dimension == 2 else gauge_summary)(
            result, name) for name in result.gauges],
        "plane": plane_summary(result) if result.dimension == 2 else None,
        "soils": soil_summaries(result), "unit_length": text(a.get("unit_length", "m")),
        "newton_mean": float(newton.mean()) if newton.size else 0.0,
        "newton_max": int(newton.max()) if newton.size else 0,
        "linear_mean": float(linear.mean()) if linear.size else 0.0,
        "wall_time": float(a.get("wall_time", np.nan)),
        "energy": {key: float(val[-1]) for key, val in energies.items() if val.size},
        **{f"energy_{key}": value for key, value in totals.items()},
    }


def energy_totals(energies):
    """The run's energy in a few numbers from its energy datasets
    ({name: array}): ``initial`` (what the bodies and the contact pairs
    hold at t = 0: the balance's initial total), ``end`` (the same terms at
    the last row), ``work`` (the external work put in), ``dissipated``
    (damping, friction, soil, hysteresis), ``numerical`` (what the time
    discretisation dissipated) and ``peak`` (the largest |initial + work|
    at the rows): initial + work = end + dissipated + numerical."""
    def at(row):
        return lambda key: float(energies[key][row]) if key in energies and \
            energies[key].size else 0.0
    first, last = at(0), at(-1)
    initial = sum(first(k) for k in HOLDS)
    work = energies.get("external", np.zeros(0))
    return {"initial": initial, "end": sum(last(k) for k in HOLDS), "work": last("external"),
            "dissipated": sum(last(k) for k in DISSIPATED), "numerical": last("numerical"),
            "peak": float(np.abs(initial + work).max(initial=abs(initial)))}


def soil_summaries(result):
    """Per [[soil]] table: the set (the toe's plastic slip so far), blow
    count (1 / set, inf at refusal), largest toe and shaft forces, the
    energy the soil took."""
    out = []
    for k in range(len(result.keys("soil")) if "soil" in result else 0):
        s = result.series(f"soil/{k}")
        a = result.group_attrs(f"soil/{k}")
        slip = float(a.get("set", s["toe_slip"][-1]))
        out.append({"set": slip, "blow_count": 1.0 / slip if slip > 0 else np.inf,
                    "toe_force_max": float(s["toe_force"].max()),
                    "shaft_force_max": float(s["shaft_force"].max()),
                    "energy": float(s["energy"][-1])})
    return out


def plane_summary(result):
    """A plane-strain result's mesh and peaks at the kept rows: the largest
    speed (node, time) and the largest magnitude of each stress component
    (cell centre, time), read row by row."""
    mesh = result.mesh
    xy, cells = mesh.coordinates, mesh.cells
    corner = np.where(cells < 0, cells[:, [0]], cells)
    centre = xy[corner].mean(axis=1) if cells.size else np.zeros((0, 2))
    out = {"cells": len(cells), "nodes": len(xy), "regions": mesh.region_names,
           "triangles": int((cells[:, 3] < 0).sum()) if cells.size else 0}
    speed, stress = (0.0, 0, 0), [(0.0, 0, 0)] * 3
    time = result.time
    for i in range(time.size):
        v = np.hypot(*result.read("field/v", np.s_[i]).T)
        j = int(v.argmax()) if v.size else 0
        if v.size and v[j] > speed[0]:
            speed = (float(v[j]), j, i)
        s = result.read("field/stress", np.s_[i])
        for c in range(3):
            k = int(np.abs(s[:, c]).argmax()) if s.size else 0
            if s.size and abs(s[k, c]) > abs(stress[c][0]):
                stress[c] = (float(s[k, c]), k, i)
    out["speed"] = (speed[0], *map(float, xy[speed[1]]), float(time[speed[2]])) \
        if xy.size else None
    out["stress"] = [(value, *map(float, centre[k]), float(time[i])) for value, k, i in stress] \
        if cells.size else []
    out["interfaces"] = [interface_summary(result, name) for name in result.interfaces]
    out["waters"] = [water_summary(result, name) for name in result.waters]
    out["strain"] = largest_strain(result, centre)
    out["tension"] = largest_tension(result, centre)
    return out


def largest_tension(result, centre):
    """The largest principal stress over the run, the largest tension when
    positive (envelope_peak of /field/principal_max); None in a file of an
    earlier version."""
    return envelope_peak(result, centre, "principal_max")


def largest_strain(result, centre):
    """A yielding run's largest equivalent shear strain over the run
    (envelope_peak of /field/strain_max); None without one."""
    return envelope_peak(result, centre, "strain_max")


def envelope_peak(result, centre, name):
    """(the largest value of the per-cell envelope /field/NAME, its cell,
    the cell's centre x, y, the time it was reached from
    /field/NAME_time, NaN in a file without it); None without the
    envelope or with no cells."""
    if f"field/{name}" not in result:
        return None
    values = result.read(f"field/{name}")
    if not values.size:
        return None
    k = int(values.argmax())
    when = float(result.read(f"field/{name}_time")[k]) \
        if f"field/{name}_time" in result else float("nan")
    return float(values[k]), k, *map(float, centre[k]), when


def interface_summary(result, name):
    """An interface's largest |slip| (with its pair's point and time), the
    permanent slip (the largest |slip| at the end), the largest opening
    and the largest length open at once (with its time)."""
    g = result.interface(name)
    slip, gap, length = g.slip[:], g.gap[:], g.length[:]
    xy = result.mesh.coordinates[g.nodes[:][:, 0]]
    time = result.time
    out = {"name": name, "pairs": int(length.size), "length": float(length.sum()),
           "safety": sliding_safety(g, time)}
    if not slip.size:
        return {**out, "slip": None}
    i, j = np.unravel_index(np.abs(slip).argmax(), slip.shape)
    last = slip[-1]
    k = int(np.abs(last).argmax())
    opened = (gap > 0) @ length
    n = int(opened.argmax())
    m, p = np.unravel_index(gap.argmax(), gap.shape)
    return {**out, "slip": (float(slip[i, j]), *map(float, xy[j]), float(time[i])),
            "permanent": (float(last[k]), *map(float, xy[k])),
            "opening": (float(gap[m, p]), *map(float, xy[p]), float(time[m])),
            "open": (float(opened[n]), float(time[n]))}


ROUNDING = 1e-12       # a sum of pairs' shear forces that is zero, against the sum of |N|


def sliding_safety(g, time):
    """(mu sum(N) / |sum(T)|, sum(N), sum(T), its time) of an interface
    with friction (None without, or with no kept row after t = 0): its
    pairs' normal_force and shear_force at the first kept row after
    t = 0 (row 0 holds no slab's forces), the mean forces of the first
    kept slab: after a static start at rest, the static state's to
    rounding; inf when sum(T) is 0 to rounding (below ROUNDING of the sum
    of |N|: a dry block at rest on its joint sums its pairs' shear to
    1e-9 N against 5e6 N)."""
    mu = float(g.attrs.get("friction", -1.0))
    if mu < 0 or time.size < 2:
        return None
    normal, shear = float(g.normal_force[1].sum()), float(g.shear_force[1].sum())
    rounding = ROUNDING * float(np.abs(g.normal_force[1]).sum())
    factor = mu * normal / abs(shear) if abs(shear) > rounding else float("inf")
    return factor, normal, shear, float(time[1])


def water_summary(result, name):
    """A water table's largest resultant |F| over the kept rows: (its x and
    y components, the time), and its wetted nodes' count."""
    w = result.water(name)
    force = w.force[:]
    out = {"name": name, "nodes": int(w.nodes.shape[0])}
    if not force.size:
        return {**out, "force": None}
    i = int(np.hypot(*force.T).argmax())
    out["force"] = (*map(float, force[i]), float(result.time[i]))
    pressure = w.pressure[:]
    if pressure.size:           # water cannot pull: below zero it would cavitate
        k, j = np.unravel_index(int(pressure.argmin()), pressure.shape)
        out["lowest"] = (float(pressure[k, j]), int(w.nodes[j]), float(result.time[k]))
    return out


def plane_gauge_summary(result, name):
    """A 2-D gauge's point and its peak velocity per component (every slab)."""
    g = result.gauge(name)
    v, t = g.v, g.time
    out = {"name": name, "point": tuple(map(float, g.attrs.get("x", (np.nan, np.nan))))}
    for c, axis in enumerate("xy"):
        if len(v):
            k = int(np.abs(v[:, c]).argmax())
            out[f"v{axis}_peak"] = (float(v[k, c]), float(t[k]))
    return out


def gauge_summary(result, name):
    """A gauge's place and its stress and velocity extremes (every slab)."""
    g = result.gauge(name)
    a, stress, v, t = g.attrs, g.stress, g.v, g.time
    out = {"name": name, "body": a.get("body", "?"), "x": float(a.get("x", np.nan))}
    if v.size and not np.abs(v).max() and "shear_v" in g.keys():
        # only the shear field moves (a site-response column): report it
        stress, v = g.shear_stress, g.shear_v
        out["body"] += " (shear)"
    if stress.size:
        i, j, k = int(stress.argmin()), int(stress.argmax()), int(np.abs(v).argmax())
        out.update(stress_min=float(stress[i]), t_stress_min=float(t[i]),
                   stress_max=float(stress[j]), t_stress_max=float(t[j]),
                   v_peak=float(v[k]), t_v_peak=float(t[k]))
    return out


def body_summary(result, name):
    """A body's extent and its stress extremes: from the envelopes (every
    slab) with where, and when at the kept rows."""
    body = result.body(name)
    x = body.x
    out = {"name": name, "elements": x.size - 1, "x0": float(x[0]), "x1": float(x[-1])}
    keys = body.keys()
    if "stress_min" in keys:
        mid = 0.5 * (x[1:] + x[:-1])
        stress = body.stress
        for kind, env, pick in (("compression", body.stress_min, np.argmin),
                                ("tension", body.stress_max, np.argmax)):
            e = int(pick(env))
            row = int(pick(stress[:, e]))
            out[kind] = (float(env[e]), float(mid[e]), float(result.time[row]))
    if "shear" in keys:
        out["shear"] = shear_peaks(result, name, x)
    return out


def shear_peaks(result, name, x):
    """The shear field's peaks of body ``name`` (node coordinates ``x``):
    {"stress": (the signed stress of largest magnitude, from the envelopes:
    every slab), "strain": (the largest |strain| from ``strain_max``: every
    slab), "velocity": (the signed velocity of largest magnitude at the
    kept rows)}, each as (value, x, t): x an element's midpoint or a node,
    t the kept row where that element's (node's) value is largest in
    magnitude (only that element's column is read).  Without
    ``strain_max`` (a file of an older version) no "strain"."""
    shear, path = result.body(name).shear, f"{layout.BODY}/{name}/shear"
    mid, time, out = 0.5 * (x[1:] + x[:-1]), result.time, {}
    if not time.size:
        return out
    low, high = shear.stress_min, shear.stress_max
    env = np.where(-low > high, low, high)
    e = int(np.argmax(np.abs(env)))
    column = result.read(f"{path}/stress", np.s_[:, e])
    out["stress"] = (float(env[e]), float(mid[e]), float(time[np.argmax(np.abs(column))]))
    if "strain_max" in shear.keys():
        strain = shear.strain_max
        e = int(np.argmax(strain))
        u = result.read(f"{path}/u", np.s_[:, e:e + 2])
        kept = np.abs(u[:, 1] - u[:, 0]) / (x[e + 1] - x[e])
        out["strain"] = (float(strain[e]), float(mid[e]), float(time[np.argmax(kept)]))
    v = shear.v
    row, node = np.unravel_index(int(np.argmax(np.abs(v))), v.shape)
    out["velocity"] = (float(v[row, node]), float(x[node]), float(time[row]))
    return out


def energy_line(t):
    """The energy of a run in a line (``t``: :func:`energy_totals`), the
    same in the run's last line and in `info`: what the bodies and the
    contact pairs held at the start and at the end, the work put in, what
    the model dissipated and what the time discretisation did, as a share
    of the largest total energy (initial + work) the run reached, which a
    run from rest or driven from outside has as well as a free one."""
    share = (f"{100 * t['numerical'] / t['peak']:.3g} % of the largest total energy "
             f"{t['peak']:.6g}" if t["peak"] > 0 else "no energy in the run")
    return (f"{t['initial']:.6g} -> {t['end']:.6g}; work in {t['work']:.6g}; dissipated "
            f"{t['dissipated']:.6g} by damping, friction and soil and {t['numerical']:.6g} by "
            f"the time discretisation ({share})")


def energy_totals_of(s):
    """The :func:`energy_totals` a summary ``s`` holds."""
    return {key: s[f"energy_{key}"] for key in ("initial", "end", "work", "dissipated",
                                                "numerical", "peak")}


def balance_lines(s):
    """The energy balance at the last row: what came in, where it is."""
    e = s["energy"]
    if "numerical" not in e:
        return []
    held = " + ".join(f"{k} {e[k]:.4g}" for k in ("kinetic", "strain", "spring", "damping",
                                                    "contact", "soil", "friction", "hysteretic")
                      if k in e)
    budget = max(abs(s["energy_initial"]) + abs(e["external"]), 1e-300)
    return [f"  energy balance: initial {s['energy_initial']:.6g} + external {e['external']:.6g}"
            f" = {held} + numerical {e['numerical']:.4g} ({100 * e['numerical'] / budget:.3g} %"
            " dissipated by the time discretisation)"]


def slip_lines(p):
    """`info`'s line of a pair with friction (none without)."""
    if "slip" not in p:
        return []
    return [f"        friction mu = {p['friction']:g}: permanent slip {p['slip']:.6g} "
            f"(largest |slip| {p['slip_max']:.6g})"]


def interface_lines(i):
    """`info`'s lines of a plane-strain interface below its name: its
    largest slip and opening, then its sliding factor of safety."""
    lines = []
    if i["slip"] is not None:
        v, x, y, t = i["slip"]
        lines.append(f"    largest slip {v:.4g} at ({x:.6g}, {y:.6g}), t = {t:.6g}; permanent "
                     f"{i['permanent'][0]:.4g} at ({i['permanent'][1]:.6g}, "
                     f"{i['permanent'][2]:.6g})")
        v, x, y, t = i["opening"]
        lines.append(f"    largest opening {v:.4g} at ({x:.6g}, {y:.6g}), t = {t:.6g}; largest "
                     f"length open {i['open'][0]:.6g} at t = {i['open'][1]:.6g}")
    if i.get("safety") is not None:
        factor, normal, shear, t = i["safety"]
        lines.append(f"    sliding factor of safety mu sum(N) / |sum(T)| {factor:.6g} (sum N "
                     f"{normal:.6g}, sum T {shear:.6g} at t = {t:.6g}, the first kept slab's "
                     "forces)")
    return lines


def plane_lines(p):
    """The plane-strain lines of `vstpetsc info`."""
    lines = [f"  plane strain: {p['cells']} cells ({p['triangles']} triangles), {p['nodes']} "
             f"nodes; regions {', '.join(p['regions'])}"]
    if p["speed"] is not None:
        v, x, y, t = p["speed"]
        lines.append(f"    largest speed {v:.6g} at ({x:.6g}, {y:.6g}), t = {t:.6g}")
    for name, (value, x, y, t) in zip(("sigma_xx", "sigma_yy", "sigma_xy"), p["stress"]):
        lines.append(f"    largest |{name}| {value:.6g} at ({x:.6g}, {y:.6g}), t = {t:.6g}")
    if p.get("strain") is not None:
        value, cell, x, y, t = p["strain"]
        lines.append(f"    largest shear strain 2 sqrt(J2) {value:.4g} in cell {cell} at "
                     f"({x:.6g}, {y:.6g}), t = {t:.6g} (yielding regions, over the run)")
    if p.get("tension") is not None:
        value, cell, x, y, t = p["tension"]
        where = f"in cell {cell} at ({x:.6g}, {y:.6g}), t = {t:.6g} (every slab end)"
        lines.append(f"    largest tension (principal stress) {value:.6g} {where}" if value > 0
                     else f"    no tension: the largest principal stress {value:.6g} {where}")
    for i in p.get("interfaces", ()):
        lines.append(f"  interface {i['name']}: {i['pairs']} node pairs, length {i['length']:.6g}")
        lines += interface_lines(i)
    for w in p.get("waters", ()):
        line = f"  water {w['name']}: {w['nodes']} wetted nodes"
        if w["force"] is not None:
            fx, fy, t = w["force"]
            line += (f"; largest resultant ({fx:.6g}, {fy:.6g}), |F| {np.hypot(fx, fy):.6g} "
                     f"per unit thickness, t = {t:.6g}")
        lines.append(line)
        if w.get("lowest") is not None:
            value, node, t = w["lowest"]
            note = " (below zero: the water would cavitate there; vstpetsc's water pulls, " \
                "docs/water.md)" if value < 0 else ""
            lines.append(f"    lowest pressure on the faces {value:.6g} at node {node}, "
                         f"t = {t:.6g}{note}")
    return lines


def format_summary(s, path):
    """The one-screen text of `vstpetsc info`."""
    lines = [f"{path}: {s['status']}" + (f" ({s['message']})" if s["message"] else ""),
             f"  vstpetsc {s['version']}, {s['mpi_size']} rank(s), solver: {s['solver']}",
             f"  dt = {s['dt']:g}, {s['slabs_done']} of {s['slabs']} slabs to t = "
             f"{s['t_end']:g}, {s['kept']} kept times (every {s['every']})",
             *(["  bodies:"] if s.get("plane") is None else plane_lines(s["plane"]))]
    for b in s["bodies"]:
        lines.append(f"    {b['name']:<14} x = [{b['x0']:g}, {b['x1']:g}], {b['elements']} elements")
        for kind in ("compression", "tension"):
            if kind in b:
                value, where, when = b[kind]
                lines.append(f"      largest {kind} stress {value:.6g} at x = {where:.6g}, "
                             f"t = {when:.6g}")
        lines += shear_lines(b.get("shear", {}))
    lines += gauge_lines(s.get("gauges", []))
    lines += soil_lines(s.get("soils", []), s.get("unit_length", "m"),
                        s["energy"].get("transferred", 0.0))
    if s["pairs"]:
        lines.append(f"  contact ({s['formulation']}):")
    for k, p in enumerate(s["pairs"]):
        law = (f"stiffness {p['penalty']:.4g}, restitution {p['restitution']:g}"
               if p["formulation"] == "cushion" else f"penalty {p['penalty']:.4g}")
        if np.isnan(p["first_contact"]):
            lines.append(f"    [{k}] {p['name']}: no contact ({law}, {p['formulation']})")
            lines += slip_lines(p)
            continue
        lines += [f"    [{k}] {p['name']} ({p['formulation']}, {law})",
                  f"        first contact t = {p['first_contact']:.6g}, total duration "
                  f"{p['duration']:.6g}, {p['episodes']} episode(s)",
                  f"        force peak {p['peak_force']:.6g}, mean {p['mean_force']:.6g}; "
                  f"impulse {p['impulse']:.6g}; largest penetration {p['penetration']:.4g}"]
        if p.get("contacts") is not None:
            lines.append(contact_line(k, p, s["t_end"]))
        lines += slip_lines(p)
    lines.append(f"  energy: {energy_line(energy_totals_of(s))}")
    lines += balance_lines(s)
    lines.append(f"  Newton iterations per slab: mean {s['newton_mean']:.3g}, max "
                 f"{s['newton_max']}; linear solves per slab: mean {s['linear_mean']:.3g}")
    if not np.isnan(s["wall_time"]):
        lines.append(f"  wall time {s['wall_time']:.3f} s")
    if s["every"] > 1:
        lines.append("  (contact totals over every slab; penetration at kept times only)")
    return "\n".join(lines)


def gauge_lines(gauges):
    """The gauge lines of `vstpetsc info` (every slab)."""
    lines = ["  gauges (every slab):"] if gauges else []
    for g in gauges:
        if "point" in g:               # a plane-strain gauge
            peaks = "; ".join(f"peak v_{a} {g[f'v{a}_peak'][0]:.6g} (t = {g[f'v{a}_peak'][1]:.6g})"
                              for a in "xy" if f"v{a}_peak" in g) or "no rows"
            lines.append(f"    {g['name']:<14} ({g['point'][0]:g}, {g['point'][1]:g}): {peaks}")
            continue
        if "stress_min" not in g:
            lines.append(f"    {g['name']:<14} {g['body']} x = {g['x']:g}: no rows")
            continue
        lines.append(f"    {g['name']:<14} {g['body']} x = {g['x']:g}: stress "
                     f"{g['stress_min']:.6g} (t = {g['t_stress_min']:.6g}) .. "
                     f"{g['stress_max']:.6g} (t = {g['t_stress_max']:.6g}); peak v "
                     f"{g['v_peak']:.6g} (t = {g['t_v_peak']:.6g})")
    return lines


def soil_lines(soils, unit, transferred):
    """The soil lines of `vstpetsc info`."""
    lines = [f"  energy transferred into the pile {transferred:.6g}"] if soils else []
    for k, soil in enumerate(soils):
        count = soil["blow_count"]
        per = (f" ({0.25 * count:.4g} per 0.25 m)" if unit == "m" and np.isfinite(count) else "")
        lines += [f"  soil[{k}]: set {soil['set']:.6g} {unit}, blow count {count:.6g} per {unit}"
                  f"{per}",
                  f"    largest toe force {soil['toe_force_max']:.6g}, shaft force "
                  f"{soil['shaft_force_max']:.6g}; energy taken {soil['energy']:.6g}"]
    return lines


SHEAR_PEAKS = (("stress", "largest shear stress"), ("strain", "largest shear strain |dw/dx|"),
               ("velocity", "largest shear velocity"))


def shear_lines(peaks):
    """`info`'s lines of a body's shear peaks (:func:`shear_peaks`): where
    the largest value is, and when (at the kept rows)."""
    lines = []
    for key, label in SHEAR_PEAKS:
        if key in peaks:
            value, where, when = peaks[key]
            lines.append(f"      {label} {value:.6g} at x = {where:.6g}, t = {when:.6g}")
    return lines
