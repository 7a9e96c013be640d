"""A plane-strain column one cell wide (vstpetsc.plane: quadrilaterals,
Lysmer's absorbing base, an incident pulse) against the 1-D solver's bar
of the same nodes (the whole vstpetsc.run path, its own algebra): the
sides holding v_x leave the P wave (E = lambda + 2 mu), holding v_y the
S wave (G = mu): the top's velocity, every energy term (kinetic, strain,
damping of the dashpots, external of the incident wave, numerical) and
the cells' stress at the end, all to 1e-9."""

import numpy as np
import pytest

from conftest import bar, make_case, solve
from test_plane_matrices import LAM, MU, RHO
from vstpetsc.history import History
from vstpetsc.plane import assembly, mesh as plane_mesh
from vstpetsc.plane.boundaries import AbsorbingBoundary
from vstpetsc.plane.energy import EnergyBook, centre_stress
from vstpetsc.plane.stepper import PlaneSlabs

WIDTH, HEIGHT, CELLS = 0.5, 3.0, 12
END = 0.02


def pulse():
    """A sin^2 velocity pulse of 0.1 m/s over 4 ms, sampled off the slabs' grid."""
    t = np.linspace(0.0, 0.004, 37)
    return History(np.column_stack([np.r_[t, END], np.r_[0.1 * np.sin(np.pi * t / 0.004) ** 2,
                                                      0.0]]))


def plane_run(component, dt):
    """(v of the top nodes' moving component (nt, 2), the energy terms of
    every slab end {name: (nt,)}, the cells' centre stresses at the end)
    of the 2-D column."""
    m = plane_mesh.rectangle((0.0, WIDTH), (0.0, HEIGHT), 1, CELLS)
    M, K = assembly.matrices(m, LAM, MU, RHO, "averaged")
    vp, vs = np.sqrt((LAM + 2 * MU) / RHO), np.sqrt(MU / RHO)
    zero = History(value=0.0)
    incident = (pulse(), zero) if component == "x" else (zero, pulse())
    base = AbsorbingBoundary(m, "bottom", RHO, vp, vs, incident)
    held_comp = 1 if component == "x" else 0                 # the other component
    held = 2 * np.arange(m.nnodes) + held_comp
    C = base.damping()
    stepper = PlaneSlabs(M, C, K, dt, held=held)
    n = int(round(END / dt))
    forces = base.forces(dt, 0, n)
    u, v = np.zeros(2 * m.nnodes), np.zeros(2 * m.nnodes)
    book = EnergyBook(M, C, K, dt, u, v)
    top = m.curve_nodes("top")
    moving = 2 * top + (0 if component == "x" else 1)
    out, energies = [v[moving]], [book.terms(u, v)]
    for k in range(n):
        f = forces[k].ravel()
        u_next, v_next = stepper.step(u, v, f)
        v1 = 2.0 * (u_next - u) / dt - v_next               # u' = u + dt/2 (v1 + v2)
        book.add_slab(v1, v_next, f)
        u, v = u_next, v_next
        out.append(v[moving])
        energies.append(book.terms(u, v))
    energies = {key: np.array([e[key] for e in energies]) for key in energies[0]}
    return np.array(out), energies, centre_stress(m, u, LAM, MU)


@pytest.mark.parametrize("component, modulus", [("y", LAM + 2 * MU), ("x", MU)],
                         ids=["P", "S"])
def test_a_column_one_cell_wide_is_the_1d_bar(tmp_path, component, modulus):
    c = np.sqrt(modulus / RHO)
    dt = 0.5 * HEIGHT / CELLS / c
    two, energies, stress2 = plane_run(component, dt)
    wave = pulse()
    case = make_case(dt, dt * round(END / dt), [bar("col", (0.0, HEIGHT), CELLS, E=modulus,
                                                    rho=RHO, area=WIDTH)],
                     bcs=[{"body": "col", "end": "left", "type": "absorbing",
                           "incident": np.column_stack([wave.t, wave.f]).tolist()}])
    r = solve(tmp_path, case)
    one = r.body("col").v[:, -1]
    scale = np.abs(one).max()
    assert scale > 0.05                    # the pulse arrives and doubles at the top
    assert np.abs(two[:, 0] - two[:, 1]).max() <= 1e-12 * scale      # both top nodes alike
    error = np.abs(two[:, 0] - one).max() / scale
    # the energy terms, each against the 1-D run's, on the largest energy
    largest = max(np.abs(r.energy[k]).max() for k in energies)
    gaps = {k: np.abs(energies[k] - r.energy[k]).max() / largest for k in energies}
    assert energies["numerical"].min() >= -1e-12 * largest
    # the cells' stress: sigma_yy (P) or sigma_xy (S) is the bar's, by height
    stress = stress2[:, 1 if component == "y" else 2]
    stress_gap = np.abs(stress - r.body("col").stress[-1]).max() / np.abs(stress).max()
    print(component, "2-D column against the 1-D bar:", error, gaps, stress_gap)
    # measured (P, S): velocity 6.8e-15, 1.8e-15; energies at most 1.1e-14,
    # 1.6e-15 of the largest; stress 5.5e-13, 2.0e-15
    assert error <= 1e-9, error
    assert max(gaps.values()) <= 1e-9 and stress_gap <= 1e-9, (gaps, stress_gap)
