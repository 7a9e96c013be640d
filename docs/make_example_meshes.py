"""Writes the Gmsh meshes of the bundled examples (vstpetsc/examples/*.msh)
from vstpetsc's own generators, so that the examples show a mesh read from
a file as users give them.

    .venv/bin/python docs/make_example_meshes.py

dam-modes-section.msh: the triangular dam of dam-modes (height 40 m,
slopes 2 : 1 both sides, crest 0, rows 4 m apart: the dam region of
vstpetsc.plane.dam_mesh), its base curve "contact" and faces "faces"."""

import os

from vstpetsc.plane.dam_mesh import dam_mesh
from vstpetsc.plane.gmsh_file import write_gmsh22

FOLDER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "vstpetsc", "examples")


def dam_section():
    return dam_mesh(40.0, 0.0, 2.0, 2.0, 10.0, 1000.0, 4.0).region_mesh("dam")


if __name__ == "__main__":
    path = write_gmsh22(os.path.join(FOLDER, "dam-modes-section.msh"), dam_section())
    print("wrote", os.path.normpath(str(path)))
