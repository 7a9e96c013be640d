"""Site response on elastic rock (issue 28, item 4): an absorbing base given
as the rock below it (``rock = { rho, Vs }``), and a soil column given as a
profile of layers (``layers = [...]``, a node on every layer boundary).

The references are written here from the physics: the closed-form
amplification of a uniform layer on elastic rock, and Thomson-Haskell
propagator matrices for vertically travelling SH waves in a layered column.
The runs' ratios come from numpy's FFT of the surface velocity over the
outcrop velocity (twice the incident wave) of a broadband pulse."""

import io

import numpy as np
import pytest

import vstpetsc
from vstpetsc.line.model import build_model
from conftest import cli, make_case, solve, write_case
from test_energy_restart import assert_same_files

ROCK = {"rho": 2200.0, "Vs": 1000.0}
SOIL = {"rho": 1800.0, "Vs": 200.0}
H = 10.0                                   # column height, x up from the base at 0
PULSE_WIDTH, PULSE_AT = 0.02, 0.1          # Gaussian incident velocity: s, t0
LAYERS = [{"thickness": 2.3, "Vs": 320.0, "rho": 2000.0},      # from the base up
          {"thickness": 4.1, "Vs": 210.0, "rho": 1900.0},
          {"thickness": 3.6, "Vs": 140.0, "rho": 1750.0}]


def pulse(dt, end):
    """[[t, v], ...]: a Gaussian incident velocity sampled at the slab ends."""
    t = np.arange(int(round(end / dt)) + 1) * dt
    v = np.exp(-(((t - PULSE_AT) / PULSE_WIDTH) ** 2))
    return [[float(a), float(b)] for a, b in zip(t, v)]


def column(body, dt, end, base):
    """A column on an absorbing shear base ``base`` (rock or impedance)
    shaken by the pulse, with a gauge at its free top."""
    bc = {"body": "soil", "end": "left", "type": "absorbing", "component": "shear",
          "incident": {"table": pulse(dt, end)}, **base}
    return make_case(dt, end, [{"name": "soil", "x": [0.0, H], **body}], bcs=[bc],
                     gauge=[{"name": "top", "body": "soil", "x": H}])


def transfer(r, case):
    """(f, |surface / outcrop|) of a run, outcrop = 2 x incident, from
    zero-padded FFTs (both signals have died out by the end)."""
    incident = case.bcs[0].params["incident"]
    t = r.time
    n = 1 << 16
    surface = np.fft.rfft(r.gauge("top").shear_v, n)
    outcrop = np.fft.rfft(2.0 * incident(t), n)
    return np.fft.rfftfreq(n, case.dt), np.abs(surface / outcrop)


def uniform_layer(f, height, vs, a):
    """1 / sqrt(cos^2 kH + a^2 sin^2 kH), k = 2 pi f / Vs."""
    kh = 2 * np.pi * f / vs * height
    return 1.0 / np.sqrt(np.cos(kh) ** 2 + a ** 2 * np.sin(kh) ** 2)


def haskell(f, layers, rock):
    """|w(surface)| / |2 A| for an upgoing SH wave of amplitude A in the
    rock (time factor exp(i w t), z up): the propagator of each layer
    carries (w, tau) from its bottom to its top,
    [[cos kh, sin kh / (G k)], [-G k sin kh, cos kh]]; at the base
    w = A + B, tau = i w rho_r Vs_r (B - A); tau = 0 at the surface."""
    omega = 2 * np.pi * np.asarray(f, dtype=float)
    P = np.broadcast_to(np.eye(2, dtype=complex), omega.shape + (2, 2)).copy()
    for lay in layers:
        k = omega / lay["Vs"]
        gk = lay["rho"] * lay["Vs"] ** 2 * k
        kh = k * lay["thickness"]
        L = np.empty_like(P)
        L[..., 0, 0], L[..., 1, 1] = np.cos(kh), np.cos(kh)
        L[..., 0, 1] = np.sinc(kh / np.pi) * lay["thickness"] / (lay["rho"] * lay["Vs"] ** 2)
        L[..., 1, 0] = -gk * np.sin(kh)
        P = L @ P
    iz = 1j * omega * rock["rho"] * rock["Vs"]
    B = (iz * P[..., 1, 1] - P[..., 1, 0]) / (P[..., 1, 0] + iz * P[..., 1, 1])
    surface = P[..., 0, 0] * (1 + B) + P[..., 0, 1] * iz * (B - 1)
    return np.abs(surface) / 2.0


def peak(f, ratio, lo, hi):
    """(frequency, value) of the largest ratio in [lo, hi]."""
    band = (f >= lo) & (f <= hi)
    i = np.argmax(ratio[band])
    return f[band][i], ratio[band][i]


def test_uniform_layer_on_rock_against_the_closed_form(tmp_path):
    """Peak at Vs / 4H of height 1 / a, a = Z_soil / Z_rock = 0.164."""
    a = SOIL["rho"] * SOIL["Vs"] / (ROCK["rho"] * ROCK["Vs"])
    f1 = SOIL["Vs"] / (4 * H)
    body = {"elements": 16, "E": SOIL["rho"] * SOIL["Vs"] ** 2, **SOIL}
    case = column(body, 1.5e-3, 3.0, {"rock": dict(ROCK)})
    f, ratio = transfer(solve(tmp_path, case), case)
    fp, hp = peak(f, ratio, 0.5 * f1, 1.5 * f1)
    band = (f > 0.1 * f1) & (f < 3.5 * f1)
    exact = uniform_layer(f[band], H, SOIL["Vs"], a)
    err = np.abs(ratio[band] - exact).max() / exact.max()
    print(f"uniform layer: peak {fp:.4f} Hz (exact {f1:.4f}), height {hp:.4f} "
          f"(1/a = {1 / a:.4f}); largest error to 3.5 f1 {err:.2e} of the peak")
    assert abs(fp / f1 - 1) < 0.02
    assert abs(hp * a - 1) < 0.02
    assert err < 0.03


def test_layered_column_against_thomson_haskell(tmp_path):
    """Three layers whose thicknesses share no element size, 24 elements
    shared by travel time: the first two peaks and the whole ratio."""
    case = column({"elements": 24, "layers": LAYERS}, 1.0e-3, 3.0, {"rock": dict(ROCK)})
    assert haskell([0.7], [{"thickness": H, **SOIL}], ROCK)[0] == pytest.approx(
        uniform_layer(0.7, H, SOIL["Vs"], SOIL["rho"] * SOIL["Vs"] / (ROCK["rho"] * ROCK["Vs"])),
        rel=1e-12)                             # the reference on one layer is the closed form
    f, ratio = transfer(solve(tmp_path, case), case)
    fine = np.linspace(0.05, 25.0, 5000)
    exact = haskell(fine, LAYERS, ROCK)
    mode1 = fine[np.argmax(np.where(fine < 8.0, exact, 0))]
    mode2 = fine[np.argmax(np.where((fine > 1.5 * mode1) & (fine < 3.5 * mode1), exact, 0))]
    for mode in (mode1, mode2):
        fr, hr = peak(fine, exact, 0.7 * mode, 1.3 * mode)
        fp, hp = peak(f, ratio, 0.7 * mode, 1.3 * mode)
        print(f"layered: peak {fp:.4f} Hz (Haskell {fr:.4f}), height {hp:.4f} ({hr:.4f})")
        assert abs(fp / fr - 1) < 0.02 and abs(hp / hr - 1) < 0.02
    band = (f > 0.1) & (f < 2.5 * mode2)
    err = np.abs(ratio[band] - haskell(f[band], LAYERS, ROCK)).max() / exact.max()
    print(f"layered: largest error to {2.5 * mode2:.1f} Hz {err:.2e} of the peak")
    assert err < 0.03


def test_rock_is_its_impedance_bit_for_bit(tmp_path):
    """rock = { rho, Vs } on a shear end and { rho, Vp } on an axial end
    give Z = rho V A: the same run as those impedances given, bit for bit;
    the header says where each came from."""
    area, vp = 2.5, 1800.0
    body = {"elements": 8, "E": 5.0e8, "area": area, **SOIL}
    runs, headers = {}, {}
    for kind, axial, sheared in (
            ("rock", {"rock": {"rho": ROCK["rho"], "Vp": vp}}, {"rock": dict(ROCK)}),
            ("impedance", {"impedance": ROCK["rho"] * vp * area},
             {"impedance": ROCK["rho"] * ROCK["Vs"] * area})):
        case = column(body, 2e-3, 0.3, sheared)
        doc = case.doc
        doc["bc"].append({"body": "soil", "end": "left", "type": "absorbing",
                          "incident": doc["bc"][0]["incident"], **axial})
        out = io.StringIO()
        runs[kind] = vstpetsc.run(vstpetsc.Case.from_dict(doc),
                                  output=str(tmp_path / f"{kind}.h5"), out=out, err=io.StringIO())
        headers[kind] = out.getvalue()
    for field in (lambda r: r.body("soil"), lambda r: r.body("soil").shear):
        for series in ("u", "v", "stress"):
            assert np.array_equal(field(runs["rock"])[series], field(runs["impedance"])[series])
    z_shear, z_axial = ROCK["rho"] * ROCK["Vs"] * area, ROCK["rho"] * vp * area
    assert (f"bc: soil/shear left end absorbing (impedance {z_shear:.6g} = rho Vs A of the "
            f"rock, 2200 x 1000 x 2.5, incident wave)") in headers["rock"]
    assert (f"bc: soil left end absorbing (impedance {z_axial:.6g} = rho Vp A of the rock, "
            f"2200 x 1800 x 2.5, incident wave)") in headers["rock"]
    assert f"(impedance {z_shear:.6g} given, incident wave)" in headers["impedance"]


def test_plain_absorbing_end_keeps_the_soils_own_impedance():
    """The documented default: rho c A of the end element, said so."""
    case = column({"elements": 4, "E": 5.0e8, **SOIL}, 1e-3, 0.01, {})
    law = build_model(case).laws[0]
    assert law.impedance == float(np.sqrt(SOIL["rho"] ** 2 * SOIL["Vs"] ** 2))
    assert "= rho c A of the end element (the default" in law.describe()


def test_layered_mesh_has_a_node_on_every_boundary():
    """Each layer meshed with its own equal elements (24 shared by travel
    time, or a layer's own ``elements``), the material per layer exactly."""
    layers = [dict(LAYERS[0]), dict(LAYERS[1], elements=3), dict(LAYERS[2], Vp=700.0)]
    layers[0]["Vp"], layers[1]["E"] = 900.0, 6.0e8
    case = make_case(1e-3, 0.01, [{"name": "soil", "x": [5.0, 5.0 + H], "elements": 20,
                                   "layers": layers}])
    mesh = build_model(case).mesh
    edges = 5.0 + np.cumsum([0.0] + [lay["thickness"] for lay in LAYERS])
    axial = mesh.x[mesh.nodes(0)]
    assert np.array_equal(axial, mesh.x[mesh.nodes(1)])       # the shear twin's
    times = [LAYERS[0]["thickness"] / LAYERS[0]["Vs"], LAYERS[2]["thickness"] / LAYERS[2]["Vs"]]
    # 17 elements over travel times 0.0072, 0.0257: 17 x 0.219 = 3.7 -> 4, 13
    counts = [4, 3, 13]
    assert times[0] / 4 < times[1] / 13 < times[0] / 3
    at = np.concatenate(([0], np.cumsum(counts)))
    assert np.array_equal(axial[at[:-1]], edges[:-1]) and axial[-1] == edges[-1]
    h = np.diff(axial)
    for i, lay in enumerate(layers):
        el = slice(at[i], at[i + 1])
        assert np.allclose(h[el], LAYERS[i]["thickness"] / counts[i], rtol=1e-12, atol=0)
        E = lay.get("E", lay["rho"] * lay.get("Vp", 0.0) ** 2)
        assert np.all(mesh.rho[el] == lay["rho"]) and np.all(mesh.E[el] == E)
        assert np.all(mesh.E[mesh.elements(1)][el] == lay["rho"] * lay["Vs"] ** 2)


def test_layered_column_static_stress_is_exact(tmp_path):
    """A column of three layers (no E given: the axial field takes G) on a
    fixed base under gravity, started static: the element stress is the
    weight above the element's midpoint, rho g integrated, to rounding
    (linear elements are exact at the nodes, and the stress is linear in
    each layer): stiffness, gravity loads and stresses on unequal elements."""
    g = -9.81
    case = make_case(1e-3, 2e-3, [{"name": "soil", "x": [0.0, H], "elements": 11,
                                   "layers": LAYERS}],
                     bcs=[{"body": "soil", "end": "left", "type": "fixed"}],
                     gravity={"g": g, "initial": "static"})
    r = solve(tmp_path, case)
    x = r.body("soil").x
    mid = 0.5 * (x[1:] + x[:-1])
    edges = np.cumsum([0.0] + [lay["thickness"] for lay in LAYERS])
    rho = np.array([lay["rho"] for lay in LAYERS])

    def weight_above(z):                       # integral of rho g from z to the top
        inside = np.clip(edges[1:] - np.maximum(edges[:-1], z), 0.0, None)
        return g * float(rho @ inside)

    exact = np.array([weight_above(z) for z in mid])    # compression: negative
    err = np.abs(r.body("soil").stress[0] - exact).max() / np.abs(exact).max()
    print(f"static stress of a layered column: {err:.1e} of the largest")
    assert err < 1e-12


def test_layered_column_on_rock_extends_bit_for_bit(tmp_path):
    """A completed run of a layered column on rock continued to a later
    end equals one run to it (every dataset: the unequal elements' state,
    envelopes and gauges come back from the file)."""
    case = column({"elements": 11, "layers": LAYERS}, 2e-3, 0.3, {"rock": dict(ROCK)})
    full = solve(tmp_path, case, "full")
    out = str(tmp_path / "part.h5")
    vstpetsc.run(case.with_value("time.end", 0.15), output=out, quiet=True)
    vstpetsc.run(case, output=out, quiet=True, restart=True)
    assert_same_files(out, full.path)


BAD = [
    ({"rock": {"Vs": 0.0, "rho": 2200.0}}, "bc[0].rock.Vs: must be positive, got 0"),
    ({"rock": {"Vs": 1000.0, "rho": -1.0}}, "bc[0].rock.rho: must be positive, got -1"),
    ({"rock": {"Vs": 1000.0}}, "bc[0].rock.rho: missing required key"),
    ({"rock": dict(ROCK), "impedance": 1e6}, "bc[0].rock: give impedance or rock, not both"),
    ({"rock": {"Vp": 1000.0, "rho": 2200.0}},
     "bc[0].rock.Vp: a shear absorbing end takes the rock's Vs, not Vp"),
]


@pytest.mark.parametrize("base,line", BAD)
def test_bad_rock(base, line):
    with pytest.raises(vstpetsc.CaseError) as exc:
        column({"elements": 4, "E": 5e8, **SOIL}, 1e-3, 0.01, base)
    assert exc.value.problems == [line]


def layered(changes):
    return [dict(lay, **changes.get(i, {})) for i, lay in enumerate(LAYERS)]


BAD_LAYERS = [
    ({"layers": layered({1: {"thickness": -4.1}})},
     "body[0] (soil).layers[1].thickness: must be positive, got -4.1"),
    ({"layers": layered({0: {"Vs": 0.0}})},
     "body[0] (soil).layers[0].Vs: must be positive, got 0"),
    ({"layers": layered({2: {"rho": 0.0}})},
     "body[0] (soil).layers[2].rho: must be positive, got 0"),
    ({"layers": layered({2: {"thickness": 3.5}})},
     "body[0] (soil).layers: the thicknesses sum to 9.9; the body's x = [0, 10] has "
     "length 10"),
    ({"layers": LAYERS, "Vs": 200.0}, "body[0] (soil).Vs: not with layers (give it per layer)"),
    ({"layers": LAYERS, "E": [[0.0, 1e8], [10.0, 1e8]]},
     "body[0] (soil).E: not with layers (give it per layer)"),
    ({"layers": LAYERS, "rho": 1800.0}, "body[0] (soil).rho: not with layers (give it per layer)"),
    ({"layers": layered({0: {"E": 1e8}})},
     "body[0] (soil).layers[1]: gives neither E nor Vp while layer 0 does (give it on "
     "every layer or on none)"),
    ({"layers": layered({0: {"elements": 5}, 1: {"elements": 5}})},
     "body[0] (soil).elements: 6 is too few: the layers' own elements take 10 and each "
     "of the 1 other layers needs one"),
    ({"layers": [dict(LAYERS[0]), dict(LAYERS[1], thickness=1e-20),
                 dict(LAYERS[2], thickness=7.7)]},
     "body[0] (soil).layers[1].thickness: too thin to place at the body's coordinates "
     "(rounds to no length)"),
    ({"layers": layered({1: {"E": 1e8, "Vp": 300.0}})},
     "body[0] (soil).layers[1].Vp: give E or Vp (E = rho Vp^2), not both"),
    ({"layers": []}, "body[0] (soil).layers: must be a non-empty array of tables "
     "[{ thickness = ..., Vs = ..., rho = ... }, ...]"),
]


@pytest.mark.parametrize("body,line", BAD_LAYERS)
def test_bad_layers(body, line):
    with pytest.raises(vstpetsc.CaseError) as exc:
        make_case(1e-3, 0.01, [{"name": "soil", "x": [0.0, H], "elements": 6, **body}])
    assert exc.value.problems == [line]


def test_bad_profile_exits_2_with_one_line(tmp_path):
    case = make_case(1e-3, 0.01, [{"name": "soil", "x": [0.0, H], "elements": 6,
                                   "layers": LAYERS}])
    path = write_case(tmp_path, case)
    path.write_text(path.read_text().replace("thickness = 4.1", "thickness = 0.0"))
    p = cli("run", path)
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert p.stderr.strip().splitlines() == [
        "vstpetsc: error: body[0] (soil).layers[1].thickness: must be positive, got 0"]
