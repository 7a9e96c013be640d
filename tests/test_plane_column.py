"""A plane-strain column one cell wide (vstpetsc.plane: quadrilaterals,
Lysmer's absorbing base, an incident pulse) against the 1-D solver's bar
of the same nodes (the whole vstpetsc.run path, its own algebra): the
sides holding v_x leave the P wave (E = lambda + 2 mu), holding v_y the
S wave (G = mu); both to 1e-9 of the motion."""

import numpy as np
import pytest

from conftest import bar, make_case, solve
from test_plane_matrices import LAM, MU, RHO
from vstpetsc.history import History
from vstpetsc.plane import assembly, mesh as plane_mesh
from vstpetsc.plane.boundaries import AbsorbingBoundary
from vstpetsc.plane.stepper import PlaneSlabs

WIDTH, HEIGHT, CELLS = 0.5, 3.0, 12
END = 0.02


def pulse():
    """A sin^2 velocity pulse of 0.1 m/s over 4 ms, sampled off the slabs' grid."""
    t = np.linspace(0.0, 0.004, 37)
    return History(np.column_stack([np.r_[t, END], np.r_[0.1 * np.sin(np.pi * t / 0.004) ** 2,
                                                      0.0]]))


def plane_run(component, dt):
    """(time, v of the top nodes' moving component (nt, 2)) of the 2-D column."""
    m = plane_mesh.rectangle((0.0, WIDTH), (0.0, HEIGHT), 1, CELLS)
    M, K = assembly.matrices(m, LAM, MU, RHO, "averaged")
    vp, vs = np.sqrt((LAM + 2 * MU) / RHO), np.sqrt(MU / RHO)
    zero = History(value=0.0)
    incident = (pulse(), zero) if component == "x" else (zero, pulse())
    base = AbsorbingBoundary(m, "bottom", RHO, vp, vs, incident)
    held_comp = 1 if component == "x" else 0                 # the other component
    held = 2 * np.arange(m.nnodes) + held_comp
    stepper = PlaneSlabs(M, base.damping(), K, dt, held=held)
    n = int(round(END / dt))
    forces = base.forces(dt, 0, n)
    u, v = np.zeros(2 * m.nnodes), np.zeros(2 * m.nnodes)
    top = m.curve_nodes("top")
    moving = 2 * top + (0 if component == "x" else 1)
    out = [v[moving]]
    for k in range(n):
        u, v = stepper.step(u, v, forces[k].ravel())
        out.append(v[moving])
    return np.array(out)


@pytest.mark.parametrize("component, modulus", [("y", LAM + 2 * MU), ("x", MU)],
                         ids=["P", "S"])
def test_a_column_one_cell_wide_is_the_1d_bar(tmp_path, component, modulus):
    c = np.sqrt(modulus / RHO)
    dt = 0.5 * HEIGHT / CELLS / c
    two = plane_run(component, dt)
    wave = pulse()
    case = make_case(dt, dt * round(END / dt), [bar("col", (0.0, HEIGHT), CELLS, E=modulus,
                                                    rho=RHO, area=WIDTH)],
                     bcs=[{"body": "col", "end": "left", "type": "absorbing",
                           "incident": np.column_stack([wave.t, wave.f]).tolist()}])
    one = solve(tmp_path, case).body("col").v[:, -1]
    scale = np.abs(one).max()
    assert scale > 0.05                    # the pulse arrives and doubles at the top
    assert np.abs(two[:, 0] - two[:, 1]).max() <= 1e-12 * scale      # both top nodes alike
    error = np.abs(two[:, 0] - one).max() / scale
    print(component, "2-D column against the 1-D bar:", error)
    # measured: 6.8e-15 (P), 1.8e-15 (S)
    assert error <= 1e-9, error
