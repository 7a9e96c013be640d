"""The names of a plane-strain result file (interface.md, "Plane strain
(2-D)"); what a plane-strain model writes under them is
:mod:`vstpetsc.plane.layout`:

    /mesh/coordinates (nn, 2), /mesh/cells (ne, 4), /mesh/region (ne,) + attribute names
    /field/u, /field/v (nt, nn, 2), /field/stress (nt, ne, 3)
    /field/principal_max, principal_min (+ _time) (ne,) envelopes, rewritten with every block
    /gauge/<name>/u, v (ns + 1, 2)
    /interface/<name>/nodes, normal, tangent (m, 2), length (m,)
    /interface/<name>/gap, normal_force, shear_force, slip, stretch (nt, m)
    /water/<name>/nodes (m,), /water/<name>/pressure (nt, m), force (nt, 2)
    /energy/*, /solver/*, /time as in 1-D
"""


PAIR_SERIES = ("gap", "normal_force", "shear_force", "slip", "stretch")
# the components of a 2-D vector: a gauge's columns of u and v, a load's keys
COMPONENTS = ("x", "y")

MESH = "mesh"
FIELD = "field"
INTERFACE = "interface"      # /interface/<name>: a [[interface]]'s pairs
WATER = "water"              # /water/<name>: a [[water]]'s wetted nodes and loads
WATER_SERIES = ("pressure", "force")
DIMENSION = "dimension"
REQUIRED = ("time", MESH, FIELD, "energy", "solver")


def field_path(key):
    return f"{FIELD}/{key}"
