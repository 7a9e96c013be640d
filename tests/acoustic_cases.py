"""Reservoirs for the acoustic water's tests (tests/test_water_acoustic*.py):
a rectangle of water [0, L] x [0, H] beside a one-cell column of dam
[-T, 0] x [0, H] whose every node moves as prescribed (a rigid face),
written as a Gmsh file.  Curves: "face" (x = 0, between dam and water),
"far" (x = L), "bottom" (y = 0 under the water), "outer" (the dam's
other sides: x = -T and its base), "base" (the dam's base alone)."""

import numpy as np

from vstpetsc.plane.gmsh_file import write_gmsh22
from vstpetsc.plane.mesh import PlaneMesh, rectangle

RHO_W, BULK = 1000.0, 2.25e9        # c = 1500 m/s


def reservoir_mesh(H, L, nx, ny, T=None):
    """The PlaneMesh: nx x ny quadrilaterals of water and one column of dam."""
    T = L / nx if T is None else T
    m = rectangle((-T, L), (0.0, H), nx + 1, ny)
    xs = np.r_[-T, np.linspace(0.0, L, nx + 1)]
    X, Y = np.meshgrid(xs, np.linspace(0.0, H, ny + 1))
    coordinates = np.column_stack([X.ravel(), Y.ravel()])
    node = np.arange(coordinates.shape[0]).reshape(ny + 1, nx + 2)
    edges = lambda nodes: np.column_stack([nodes[:-1], nodes[1:]])
    region = (np.arange(m.ncells) % (nx + 1) > 0).astype(int)       # 0 dam, 1 water
    curves = {"face": edges(node[:, 1]), "far": edges(node[:, -1]),
              "bottom": edges(node[0, 1:]),
              "outer": np.concatenate([edges(node[:, 0]), edges(node[0, :2])]),
              "base": edges(node[0, :2])}
    return PlaneMesh(coordinates, m.cells, region, ("dam", "water"), curves)


WATER = """[[water]]
name = "reservoir"
level = {H}
faces = ["face"]
hydrodynamic = "acoustic"
region = "water"
bulk = {bulk}
{far}
{bottom}
"""
DAM = """
[time]
dt = {dt}
end = {end}
[output]
every = {every}
[mesh]
file = "{mesh}"
[[region]]
name = "dam"
E = 3.0e10
nu = 0.2
rho = 2400.0
"""
CASE = DAM + """[[boundary]]
name = "face"
type = "velocity"
value = {{ x = {vx}, y = 0.0 }}
[[boundary]]
name = "outer"
type = "velocity"
value = {{ x = {vx}, y = 0.0 }}
[gravity]
g = -9.81
initial = "{initial}"
""" + WATER


def reservoir_case(tmp_path, H, L, nx, ny, dt, end, vx, name="reservoir", every=1,
                   far=True, alpha=None, initial="rest"):
    """The case file of a rigid face moving with v_x = ``vx`` (a TOML
    history), its mesh beside it."""
    mesh = write_gmsh22(tmp_path / f"{name}.msh", reservoir_mesh(H, L, nx, ny))
    text = CASE.format(dt=dt, end=end, every=every, mesh=mesh, vx=vx, H=H, bulk=BULK,
                       initial=initial, far='far = "far"' if far else "",
                       bottom="" if alpha is None else
                       f'bottom = {{ name = "bottom", alpha = {alpha} }}')
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


FREE = DAM.replace("E = 3.0e10", "E = 1.0e8") + """v0 = [1.0, 0.0]
[gravity]
g = 0.0
""" + WATER


def free_dam_case(tmp_path, dt, end, name="free", H=10.0, L=20.0):
    """A free dam column (3 m wide, E 1e8, nothing holds it) thrown at its
    reservoir (4 x 3 cells, c = 150 m/s: every mode resolved by slabs of
    a few ms) at v_x = 1, without gravity's pull (g = 0): a far end and a
    half-absorbing bottom."""
    mesh = write_gmsh22(tmp_path / f"{name}.msh", reservoir_mesh(H, L, 4, 3, T=3.0))
    path = tmp_path / f"{name}.toml"
    path.write_text(FREE.format(dt=dt, end=end, every=int(round(end / dt)), mesh=mesh, H=H,
                                bulk=2.25e7, far='far = "far"',
                                bottom='bottom = { name = "bottom", alpha = 0.5 }'))
    return path


def shaken_case(tmp_path, end, name="shaken", dt=1e-3):
    """A flexible dam column (2 m wide, E 1e9) on a base moving along x
    (a velocity pulse), its reservoir (20 x 10 cells) at rest under its
    weight (static start): far end, bottom with alpha 0.8."""
    mesh = write_gmsh22(tmp_path / f"{name}.msh", reservoir_mesh(10.0, 40.0, 20, 10, T=2.0))
    vx = "[[0.0, 0.0], [0.05, 0.05], [0.1, 0.0], [10.0, 0.0]]"
    text = CASE.format(dt=dt, end=end, every=5, mesh=mesh, vx=vx, H=10.0, bulk=BULK,
                       initial="static", far='far = "far"',
                       bottom='bottom = { name = "bottom", alpha = 0.8 }')
    held = f'type = "velocity"\nvalue = {{ x = {vx}, y = 0.0 }}\n'
    text = text.replace(f'name = "face"\n{held}', f'name = "base"\n{held}')
    text = text.replace(f'[[boundary]]\nname = "outer"\n{held}', "")
    path = tmp_path / f"{name}.toml"
    path.write_text(text.replace("E = 3.0e10", "E = 1.0e9"))
    return path
