"""A plane-strain column one cell wide run from its case file (the whole
vstpetsc.run path: [mesh], [[region]], [[boundary]], the shared time loop
and writer), against the 1-D solver's bar of the same nodes: the sides
holding v_x leave the P wave (E = lambda + 2 mu), holding v_y the S wave
(G = mu).  Lysmer's absorbing base carries a sin^2 incident pulse sampled
off the slabs' grid.  The top's velocity, a gauge between the top nodes,
every energy term and the cells' stress at the end agree to 1e-9, for
the generated mesh and for the same mesh read from a Gmsh file."""

import numpy as np
import pytest

import vstpetsc
from conftest import bar, make_case, solve
from test_plane_matrices import E, LAM, MU, NU, RHO
from vstpetsc.plane import mesh as plane_mesh
from vstpetsc.plane.gmsh_file import write_gmsh22

WIDTH, HEIGHT, CELLS = 0.5, 3.0, 12
END = 0.02


def pulse():
    """A sin^2 velocity pulse of 0.1 m/s over 4 ms, sampled off the slabs' grid."""
    t = np.linspace(0.0, 0.004, 37)
    return np.column_stack([np.r_[t, END], np.r_[0.1 * np.sin(np.pi * t / 0.004) ** 2, 0.0]])


def column_case(component, dt, mesh, folder=None):
    """The 2-D column's case: ``component`` "y" (P) or "x" (S) moves."""
    other = "x" if component == "y" else "y"
    held = {"type": "velocity", "value": {other: 0.0}}
    return vstpetsc.Case.from_dict({
        "time": {"dt": dt, "end": dt * round(END / dt)}, "mesh": mesh,
        "region": [{"name": "domain", "E": E, "nu": NU, "rho": RHO}],
        "boundary": [{"name": "bottom", "type": "absorbing",
                      "incident": {component: pulse().tolist()}},
                     {"name": "left", **held}, {"name": "right", **held}],
        "gauge": [{"name": "top", "x": [WIDTH / 2, HEIGHT]}]}, folder=folder)


def meshes(tmp_path, kind):
    if kind == "generated":
        return {"rectangle": {"x": [0.0, WIDTH], "y": [0.0, HEIGHT], "nx": 1, "ny": CELLS}}
    m = plane_mesh.rectangle((0.0, WIDTH), (0.0, HEIGHT), 1, CELLS)
    write_gmsh22(tmp_path / "column.msh", m)
    return {"file": "column.msh"}


@pytest.mark.parametrize("kind", ["generated", "gmsh"])
@pytest.mark.parametrize("component, modulus", [("y", LAM + 2 * MU), ("x", MU)],
                         ids=["P", "S"])
def test_a_column_one_cell_wide_is_the_1d_bar(tmp_path, component, modulus, kind):
    c = np.sqrt(modulus / RHO)
    dt = 0.5 * HEIGHT / CELLS / c
    two = solve(tmp_path, column_case(component, dt, meshes(tmp_path, kind), tmp_path), "two")
    wave = pulse()
    case = make_case(dt, dt * round(END / dt), [bar("col", (0.0, HEIGHT), CELLS, E=modulus,
                                                    rho=RHO, area=WIDTH)],
                     bcs=[{"body": "col", "end": "left", "type": "absorbing",
                           "incident": wave.tolist()}])
    one = solve(tmp_path, case, "one")
    assert two.dimension == 2 and two.status == "completed"
    a = "xy".index(component)
    xy = two.mesh.coordinates
    top = np.flatnonzero(np.isclose(xy[:, 1], HEIGHT))
    v1 = one.body("col").v[:, -1]
    scale = np.abs(v1).max()
    assert scale > 0.05                    # the pulse arrives and doubles at the top
    v2 = two.field.v[:, top, a]
    error = np.abs(v2 - v1[:, None]).max() / scale
    gauge = np.abs(two.gauge("top").v[:, a] - v1).max() / scale       # every slab: every row
    largest = max(np.abs(one.energy[k]).max() for k in one.energy)
    gaps = {k: np.abs(two.energy[k] - one.energy[k]).max() / largest
            for k in ("kinetic", "strain", "damping", "external", "numerical")}
    assert two.energy["numerical"].min() >= -1e-12 * largest
    stress = two.field.stress[-1][:, 1 if component == "y" else 2]
    order = np.argsort(two.mesh.coordinates[two.mesh.cells[:, 0], 1])     # by height
    stress_gap = np.abs(stress[order] - one.body("col").stress[-1]).max() / np.abs(stress).max()
    print(component, kind, "2-D column against the 1-D bar:", error, gauge, gaps, stress_gap)
    # measured (P, S; both meshes alike): velocity 1.1e-14, 2.1e-15; energies
    # at most 1.1e-14, 1.6e-15 of the largest; stress 5.5e-13, 2.0e-15
    assert error <= 1e-9 and gauge <= 1e-9, (error, gauge)
    assert max(gaps.values()) <= 1e-9 and stress_gap <= 1e-9, (gaps, stress_gap)
