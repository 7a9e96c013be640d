"""The mesh split along an interface curve (vstpetsc.plane.interfaces):
every node of the curve doubled, the second side's cells on the new
nodes, the pairs' normals, tangents and tributary lengths, other curves
renumbered where they touch the interface, a crack's tip left single, a
curve on the boundary refused; tied back together, the split mesh's M and
K are the original's."""

import numpy as np
import pytest
import scipy.sparse as sp

from vstpetsc.plane import assembly
from vstpetsc.plane.dam_mesh import dam_mesh
from vstpetsc.plane.interfaces import split
from vstpetsc.plane.mesh import PlaneMesh, rectangle

LAM, MU, RHO = 1.0e8, 5.0e7, 2000.0


def with_joint(triangles, stop=None):
    """A 4 x 4 square of 4 x 4 cells with the inner line y = 2 (from x = 0
    to ``stop``, default the whole width) as curve "joint", left to right."""
    m = rectangle((0.0, 4.0), (0.0, 4.0), 4, 4, triangles)
    row = np.flatnonzero(np.isclose(m.coordinates[:, 1], 2.0))
    row = row[np.argsort(m.coordinates[row, 0])]
    if stop is not None:
        row = row[m.coordinates[row, 0] <= stop]
    curves = dict(m.curves, joint=np.column_stack([row[:-1], row[1:]]))
    return PlaneMesh(m.coordinates, m.cells, m.region, m.region_names, curves)


def tie(pairs, nnodes):
    """The (2 n_split, 2 n) matrix that gives both nodes of a pair the
    original node's dofs."""
    original = np.arange(nnodes + len(pairs.nodes))
    original[pairs.nodes[:, 1]] = pairs.nodes[:, 0]
    rows = np.arange(2 * original.size)
    cols = (2 * original[:, None] + np.arange(2)).ravel()
    return sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(rows.size, 2 * nnodes))


@pytest.mark.parametrize("triangles", [False, True], ids=["quadrilaterals", "triangles"])
def test_a_joint_across_a_square(triangles):
    m = with_joint(triangles)
    s, pairs = split(m, "joint")
    assert s.nnodes == m.nnodes + 5 and len(pairs.nodes) == 5
    first, second = pairs.nodes.T
    assert np.array_equal(s.coordinates[first], s.coordinates[second])
    assert np.allclose(pairs.normal, [0.0, 1.0]) and np.allclose(pairs.tangent, [1.0, 0.0])
    assert np.allclose(np.sort(pairs.length), [0.5, 0.5, 1.0, 1.0, 1.0])
    centre = s.coordinates[np.where(s.cells < 0, s.cells[:, [0]], s.cells)].mean(axis=1)[:, 1]
    above, below = s.cells[centre > 2.0], s.cells[centre < 2.0]
    assert not np.isin(first, above).any() and not np.isin(second, below).any()
    assert np.allclose(s.areas(), m.areas())
    # the sides' curves: "left" and "right" keep their edges, those above
    # the joint on the new end nodes
    for side in ("left", "right"):
        upper = s.curves[side][s.coordinates[s.curves[side]].mean(axis=1)[:, 1] > 2.0]
        assert np.isin(upper, second).any() and not np.isin(upper, first).any()
    # tied back together, the split mesh is the original
    P = tie(pairs, m.nnodes)
    for a, b in zip(assembly.matrices(s, LAM, MU, RHO), assembly.matrices(m, LAM, MU, RHO)):
        assert np.abs((P.T @ a @ P - b).toarray()).max() <= 1e-12 * np.abs(b).max()


def test_a_crack_tip_stays_single():
    m = with_joint(False, stop=2.0)           # the joint ends at (2, 2), inside
    s, pairs = split(m, "joint")
    assert len(pairs.nodes) == 2               # (0, 2) and (1, 2); the tip (2, 2) is welded
    assert np.allclose(s.coordinates[pairs.nodes[:, 0], 0], [0.0, 1.0])


def test_the_dam_contact_separates_dam_and_foundation():
    m = dam_mesh(20.0, 4.0, 2.0, 1.5, 12.0, 120.0, 4.0)
    s, pairs = split(m, "contact")
    dam, foundation = (np.unique(c[c >= 0]) for c in (s.cells[s.region == 0],
                                                     s.cells[s.region == 1]))
    assert not np.intersect1d(dam, foundation).size
    assert np.isin(pairs.nodes[:, 1], dam).all() and np.isin(pairs.nodes[:, 0], foundation).all()
    assert np.allclose(pairs.normal, [0.0, 1.0])
    base = 4.0 + (2.0 + 1.5) * 20.0
    assert pairs.length.sum() == pytest.approx(base, rel=1e-12)
    # "faces" at the dam's toes: its dam edges on the dam's nodes
    faces = s.curves["faces"]
    assert np.isin(faces, dam).all(axis=1).sum() + np.isin(faces, foundation).all(axis=1).sum() \
        == len(faces)


def test_a_curve_on_the_boundary_is_refused():
    m = rectangle((0.0, 4.0), (0.0, 4.0), 4, 4)
    with pytest.raises(ValueError, match="runs along the mesh's boundary"):
        split(m, "bottom")
    with pytest.raises(ValueError, match="no curve 'nowhere'"):
        split(m, "nowhere")


def test_stiff_springs_across_the_split_weld_it_back():
    """A closed, sticking interface's linear part: springs joining each
    pair (interfaces.spring_matrix) added to the split square's K. Its
    lowest natural frequencies approach the unsplit square's as the
    springs stiffen, the gap falling as 1 / stiffness (the springs'
    compliance); the springs strain nothing under rigid motions."""
    import scipy.linalg

    from vstpetsc.plane.interfaces import spring_matrix

    m = with_joint(False)
    s, pairs = split(m, "joint")
    held = lambda mesh: (2 * np.flatnonzero(np.isclose(mesh.coordinates[:, 1], 0.0))[:, None]
                         + np.arange(2)).ravel()

    def lowest(mesh, K_extra=None):
        M, K = (a.toarray() for a in assembly.matrices(mesh, LAM, MU, RHO))
        if K_extra is not None:
            K = K + K_extra.toarray()
        free = np.setdiff1d(np.arange(M.shape[0]), held(mesh))
        return scipy.linalg.eigh(K[np.ix_(free, free)], M[np.ix_(free, free)],
                                 eigvals_only=True)[:4]

    welded = lowest(m)
    gaps = []
    for k in (1e10, 1e11, 1e12):
        springs = spring_matrix(pairs, k, k, s.nnodes)
        rigid = np.zeros(2 * s.nnodes)
        rigid[0::2], rigid[1::2] = 1.0, 0.5                     # a translation
        assert np.abs(springs @ rigid).max() <= 1e-12 * k
        gaps.append(np.abs(lowest(s, springs) / welded - 1).max())
    print("springs across the joint: lowest four frequencies' gap", gaps)
    assert gaps[0] < 1e-2 and gaps[1] < gaps[0] / 5 and gaps[2] < gaps[1] / 5
