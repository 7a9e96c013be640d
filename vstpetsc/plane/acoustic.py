"""The acoustic reservoir (interface.md, "Water against a dam (2-D)",
``hydrodynamic = "acoustic"``; docs/water.md, section 4): the water is a
region of the mesh whose unknown at each node is its velocity
potential's rate scaled to a velocity,

    w = psi_t / c = -p / (rho c),

(the particle velocity of a plane wave of pressure p), in the x slot of
the node's two; the y slot is held at zero.  With psi = c int w dt the
wave equation psi_tt = c^2 lap(psi) times c and rho reads, in weak form,

    rho M_w w_t + bulk K_w (int w dt) + rho c L^T v = 0,

M_w and K_w the scalar mass and Laplacian of the water's cells, so that
the water enters the slab algebra as a solid does: mass density rho,
modulus bulk, its energy 1/2 rho w^2 + 1/2 bulk |grad int w|^2 (the
pressure's p^2 / (2 rho c^2) and the flow's 1/2 rho |grad psi|^2).  On a
wetted face the solid feels -p n = rho c w n and the water the solid's
normal velocity: the two couplings are -rho c L and +rho c L^T, a skew
block of C that does no work.  Far end: plane-wave absorption
dpsi/dn = -psi_t / c, a dashpot rho c on w; bottom: Fenves and Chopra's
(1983) dp/dn = -q p_t with q c = (1 - alpha) / (1 + alpha), a dashpot
rho c (1 - alpha) / (1 + alpha); free surface p = 0: w held at zero.

The face couplings and the dashpots are per node (tributary lengths: the
interfaces' node pairs of the mesh split along the faces), exact for a
face that moves as a rigid body.  Pure numpy."""

from dataclasses import dataclass

import numpy as np

from vstpetsc.plane import elements
from vstpetsc.plane.boundaries import edge_frames

LEVEL = 1e-9        # the free surface's nodes: within this of the water's height


def element_stiffness(xy, bulk):
    """(n, 2k, 2k) bulk int grad N . grad N of cells with corners xy
    (n, k, 2) (k = 3: linear triangles, exact; 4: bilinear quadrilaterals,
    2 x 2 Gauss points) in the x slots, zeros in the y slots."""
    n, k = xy.shape[:2]
    if k == 3:
        dN, area = elements.triangle_gradients(xy, area=True)
        lap = area[:, None, None] * (dN @ dN.transpose(0, 2, 1))
    else:
        lap = np.zeros((n, 4, 4))
        for xi, eta in elements.POINTS:
            _, dN, det = elements.quadrilateral_gradients(xy, xi, eta)
            lap += det[:, None, None] * (dN @ dN.transpose(0, 2, 1))
    out = np.zeros((n, 2 * k, 2 * k))
    out[:, 0::2, 0::2] = np.asarray(bulk, float)[:, None, None] * lap
    return out


def water_nodes(mesh, region_index):
    """Boolean (nn,): the nodes of the cells of the regions ``region_index``."""
    out = np.zeros(mesh.nnodes, dtype=bool)
    cells = mesh.cells[np.isin(mesh.region, region_index)]
    out[cells[cells >= 0]] = True
    return out


def surface_tolerance(level):
    """How near the level a node of the free surface lies (every rank the same)."""
    return LEVEL * max(1.0, abs(level))


def held_nodes(mesh, specs):
    """(the free surfaces' nodes, every water node) of ``mesh``'s acoustic
    waters: the nodes whose w and whose y slot are held at zero."""
    surface, every = [], []
    for spec in specs:
        # every rank's mesh names every region (distributed: the names broadcast)
        nodes = np.flatnonzero(water_nodes(mesh, [mesh.region_names.index(spec.acoustic.region)]))
        top = mesh.coordinates[nodes, 1] >= spec.level - surface_tolerance(spec.level)
        surface.append(nodes[top])
        every.append(nodes)
    join = lambda parts: np.unique(np.concatenate(parts)) if parts else np.zeros(0, dtype=int)
    return join(surface), join(every)


@dataclass
class FaceCoupling:
    """The node pairs of a wetted face: the ``solid`` node and the
    ``water`` node at each (m,), ``push`` (m, 2) = rho c L n, n the solid's
    outward normal and L the pair's tributary length: the solid's force is
    push w, the water's flux push . v."""

    solid: np.ndarray
    water: np.ndarray
    push: np.ndarray


def face_coupling(pairs, wet, rho, c):
    """The FaceCoupling of a face's NodePairs (vstpetsc.plane.interfaces),
    ``wet`` the split mesh's water nodes (boolean)."""
    first_wet = wet[pairs.nodes[:, 0]]
    solid = np.where(first_wet, pairs.nodes[:, 1], pairs.nodes[:, 0])
    water = np.where(first_wet, pairs.nodes[:, 0], pairs.nodes[:, 1])
    # the pairs' normal points from the first side to the second
    outward = np.where(first_wet[:, None], -pairs.normal, pairs.normal)
    return FaceCoupling(solid, water, rho * c * pairs.length[:, None] * outward)


def coupling_entries(face):
    """(rows, columns, values): the skew block of C, -push on the solid's
    rows at the water's w and +push on the water's row at the solid's
    (v_x, v_y), in the dofs of the nodes' numbers."""
    s, w, push = face.solid, face.water, face.push
    solid_dofs = 2 * s[:, None] + np.arange(2)
    water_dof = np.repeat(2 * w[:, None], 2, axis=1)
    rows = np.concatenate([solid_dofs.ravel(), water_dof.ravel()])
    cols = np.concatenate([water_dof.ravel(), solid_dofs.ravel()])
    return rows, cols, np.concatenate([-push.ravel(), push.ravel()])


def edge_dashpots(mesh, edges, coefficient):
    """(dofs, values): a dashpot ``coefficient`` per unit length on the w
    of each node of ``edges`` (m, 2), by tributary length."""
    if not len(edges):
        return np.zeros(0, dtype=int), np.zeros(0)
    length, _, _ = edge_frames(mesh, edges)
    return 2 * edges.ravel(), coefficient * np.repeat(0.5 * length, 2)


def dynamic_pressure(impedance, w):
    """p = -rho c w of the water's ``impedance`` rho c (0.0, not -0.0,
    where w is 0)."""
    return -impedance * w + 0.0
