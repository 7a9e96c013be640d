"""Gmsh meshes through PETSc's DMPlex (vstpetsc.plane.solver.dmplex): a file
written here in Gmsh's 2.2 ASCII format (and in 4.1, read alike) from a mesh of our own generator
(mixed: quadrilaterals below, triangles above, two physical surfaces, two
physical curves, some cells written clockwise) reads back as the same
geometry: its cells' areas, regions and curves, and the same assembled
matrices; a column one cell wide from a file is the 1-D bar."""

import numpy as np
import pytest

from test_plane_matrices import LAM, MU, RHO, one_d_operators, tie
from vstpetsc.plane import assembly, mesh as plane_mesh
from vstpetsc.plane.solver.dmplex import read_gmsh
from vstpetsc.plane.gmsh_file import write_gmsh22


def mixed(width=2.0, height=3.0, nx=2, ny=6):
    """Quadrilaterals in the lower half ("rock"), triangles above ("soil")."""
    quads = plane_mesh.rectangle((0.0, width), (0.0, height), nx, ny)
    tris = plane_mesh.rectangle((0.0, width), (0.0, height), nx, ny, triangles=True)
    lower = quads.coordinates[quads.cells[:, :4]].mean(axis=1)[:, 1] < height / 2
    upper = tris.coordinates[tris.cells[:, :3]].mean(axis=1)[:, 1] > height / 2
    cells = np.concatenate([quads.cells[lower], tris.cells[upper]])
    region = np.concatenate([np.zeros(lower.sum(), int), np.ones(upper.sum(), int)])
    return plane_mesh.PlaneMesh(quads.coordinates, cells, region, ("rock", "soil"),
                                {"base": quads.curves["bottom"], "top": quads.curves["top"]})


def write_gmsh41(path, m):
    """``m`` as a Gmsh 4.1 ASCII file: an entity per physical curve and per
    region, every node classified on the first surface."""
    curves, regions = list(m.curves), list(m.region_names)
    lines = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames",
             str(len(curves) + len(regions))]
    lines += [f'1 {i + 1} "{n}"' for i, n in enumerate(curves)]
    lines += [f'2 {len(curves) + i + 1} "{n}"' for i, n in enumerate(regions)]
    lines += ["$EndPhysicalNames", "$Entities", f"0 {len(curves)} {len(regions)} 0"]
    box = "0 0 0 0 0 0"
    lines += [f"{i + 1} {box} 1 {i + 1} 0" for i in range(len(curves))]
    lines += [f"{i + 1} {box} 1 {len(curves) + i + 1} 0" for i in range(len(regions))]
    lines += ["$EndEntities", "$Nodes", f"1 {m.nnodes} 1 {m.nnodes}", f"2 1 0 {m.nnodes}"]
    lines += [str(i + 1) for i in range(m.nnodes)]
    lines += [f"{x!r} {y!r} 0" for x, y in m.coordinates]
    lines += ["$EndNodes"]
    blocks = [(1, i + 1, 1, [e for e in m.curves[c]]) for i, c in enumerate(curves)]
    for r in range(len(regions)):
        for kind, corners in ((2, 3), (3, 4)):
            cells = [c[:corners] for c, g in zip(m.cells, m.region)
                     if g == r and (c >= 0).sum() == corners]
            if cells:
                blocks.append((2, r + 1, kind, cells))
    total = sum(len(b[3]) for b in blocks)
    lines += ["$Elements", f"{len(blocks)} {total} 1 {total}"]
    tag = 0
    for dim, entity, kind, rows in blocks:
        lines.append(f"{dim} {entity} {kind} {len(rows)}")
        for row in rows:
            tag += 1
            lines.append(f"{tag} " + " ".join(str(n + 1) for n in row))
    lines += ["$EndElements"]
    path.write_text("\n".join(lines) + "\n")
    return path


def canonical(m):
    """Cells as sorted tuples of node sets with their region, in sorted
    order (a reader may renumber cells and rotate their corners)."""
    return sorted((tuple(sorted(c[c >= 0])), m.region_names[r]) for c, r in zip(m.cells, m.region))


def test_a_mixed_mesh_reads_back_as_written(tmp_path):
    m = mixed()
    read = read_gmsh(write_gmsh22(tmp_path / "mixed.msh", m, clockwise={0, 13}))
    assert np.array_equal(read.coordinates, m.coordinates)
    assert canonical(read) == canonical(m)
    assert np.all(read.areas() > 0)
    assert read.areas().sum() == pytest.approx(6.0, rel=1e-14)
    for name in ("base", "top"):
        assert sorted(map(sorted, read.curves[name].tolist())) == \
            sorted(map(sorted, m.curves[name].tolist()))
    mine = [A.toarray() for A in assembly.matrices(m, LAM, MU, RHO, "consistent")]
    theirs = [A.toarray() for A in assembly.matrices(read, LAM, MU, RHO, "consistent")]
    for a, b in zip(mine, theirs):
        assert np.allclose(a, b, rtol=0, atol=1e-13 * np.abs(a).max())


def test_gmsh_41_reads_as_22(tmp_path):
    m = mixed()
    old = read_gmsh(write_gmsh22(tmp_path / "m22.msh", m))
    new = read_gmsh(write_gmsh41(tmp_path / "m41.msh", m))
    assert np.array_equal(old.coordinates, new.coordinates)
    assert canonical(old) == canonical(new)
    assert {k: sorted(map(sorted, v.tolist())) for k, v in old.curves.items()} == \
        {k: sorted(map(sorted, v.tolist())) for k, v in new.curves.items()}


@pytest.mark.parametrize("triangles", [False, True], ids=["quadrilaterals", "triangles"])
def test_a_column_from_a_file_is_the_1d_bar(tmp_path, triangles):
    m = plane_mesh.rectangle((0.0, 0.5), (0.0, 3.0), 1, 6, triangles)
    read = read_gmsh(write_gmsh22(tmp_path / "column.msh", m))
    M, K = (A.toarray() for A in assembly.matrices(read, LAM, MU, RHO, "averaged"))
    Px, Py = tie(read)
    for P, E1 in ((Px, MU), (Py, LAM + 2 * MU)):
        M1, K1 = one_d_operators(E1, "averaged")
        assert np.allclose(P.T @ K @ P, K1, rtol=1e-12, atol=1e-12 * np.abs(K1).max())
        assert np.allclose(P.T @ M @ P, M1, rtol=1e-12, atol=1e-12 * np.abs(M1).max())


def test_a_cell_in_no_region_is_refused(tmp_path):
    m = mixed()
    path = write_gmsh22(tmp_path / "m.msh", m)
    text = path.read_text().splitlines()
    # the last cell's physical (and elementary) tag to one no name is given
    fields = text[-2].split()
    fields[3] = fields[4] = "99"
    text[-2] = " ".join(fields)
    path.write_text("\n".join(text) + "\n")
    with pytest.raises(ValueError, match="in no physical surface"):
        read_gmsh(path)
