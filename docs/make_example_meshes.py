"""Writes the Gmsh meshes of the bundled examples (vstpetsc/examples/*.msh)
from vstpetsc's own generators, so that the examples show a mesh read from
a file as users give them.

    .venv/bin/python docs/make_example_meshes.py

dam-modes-section.msh: the triangular dam of dam-modes (height 40 m,
slopes 2 : 1 both sides, crest 0, rows 4 m apart: the dam region of
vstpetsc.plane.dam_mesh), its base curve "contact" and faces "faces".

rockfill-dam-section.msh: the zoned rockfill dam of the rockfill-dam
example on its foundation (vstpetsc.plane.rockfill_mesh with its default
parameters: height 40 m, crest 8 m, slopes 2 : 1 upstream and 1.8 : 1
downstream, a clay core 4 m wide at the crest whose faces slope 0.25 : 1,
the foundation 300 m x 30 m, cells of about h = 2 m: 2250 quadrilaterals
and 1724 triangles on 3260 nodes); regions "core", "upstream_shell",
"downstream_shell", "foundation"; curves "base", "left", "right",
"faces", "contact" (the dam's base) and "core_upstream", "core_downstream"
(the core's faces, inner curves to split as interfaces).

lamb-halfspace.msh: the half of a half-space beside the plane of symmetry
x = 0 of the lamb example: [0, 250] x [-150, 0] m in squares of 2.5 m;
curves "left" (the plane of symmetry), "right", "bottom", "top" (the free
surface) and "load" (the surface's first edge, 0 <= x <= 2.5 m, where the
line load is spread).

lamb-load.csv: the line load F(t) of the lamb example, a Ricker wavelet of
2 Hz peak frequency, 1e4 N/m, centred at 0.6 s, sampled every 1 ms to
1.6 s (time, force)."""

import os

import numpy as np

from vstpetsc.plane.dam_mesh import dam_mesh
from vstpetsc.plane.gmsh_file import write_gmsh22
from vstpetsc.plane.rockfill_mesh import rockfill_mesh

FOLDER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "vstpetsc", "examples")


LAMB = {"width": 250.0, "depth": 150.0, "h": 2.5}
LAMB_LOAD = {"frequency": 2.0, "amplitude": 1.0e4, "delay": 0.6, "end": 1.6, "step": 1e-3}


def lamb_halfspace(width=LAMB["width"], depth=LAMB["depth"], h=LAMB["h"]):
    from vstpetsc.plane.mesh import rectangle

    m = rectangle((0.0, width), (-depth, 0.0), int(round(width / h)), int(round(depth / h)))
    return m.split_curve("top", "load", lambda x, y: x <= h * (1 + 1e-9))


def ricker(t, frequency, amplitude, delay):
    """amplitude (1 - 2 a) exp(-a), a = (pi f (t - delay))^2 (Ricker 1953)."""
    a = (np.pi * frequency * (t - delay)) ** 2
    return amplitude * (1.0 - 2.0 * a) * np.exp(-a)


def write_lamb_load(path):
    p = LAMB_LOAD
    t = np.arange(0.0, p["end"] + p["step"] / 2, p["step"])
    f = ricker(t, p["frequency"], p["amplitude"], p["delay"])
    with open(path, "w") as out:
        out.write("time,force\n")
        out.writelines(f"{a:.4f},{b:.9e}\n" for a, b in zip(t, f))
    return path


def dam_section():
    return dam_mesh(40.0, 0.0, 2.0, 2.0, 10.0, 1000.0, 4.0).region_mesh("dam")


def rockfill_dam_section():
    return rockfill_mesh(h=2.0)


if __name__ == "__main__":
    for name, mesh in (("dam-modes-section.msh", dam_section()),
                       ("lamb-halfspace.msh", lamb_halfspace()),
                       ("rockfill-dam-section.msh", rockfill_dam_section())):
        print("wrote", os.path.normpath(str(write_gmsh22(os.path.join(FOLDER, name), mesh))))
    print("wrote", os.path.normpath(write_lamb_load(os.path.join(FOLDER, "lamb-load.csv"))))
