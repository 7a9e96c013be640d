"""The cells' parts of a plane mesh on several ranks
(vstpetsc.plane.solver.partition): the cells' graph joins cells that share
an edge and the cells of an interface pair's nodes; METIS's bisection
weighted by each cell's share of its nodes gives the ranks as many nodes
within a few per cent (DMPlex's own partitioner balances cells: the 1 m
rockfill dam's two ranks owned 6104 and 6838 nodes); a distributed dam on
three ranks owns its nodes so; a bad -vst_plane_partition is named."""

import sys

import numpy as np
import pytest

from test_parallel import mpirun
from vstpetsc.plane import mesh as plane_mesh
from vstpetsc.plane.dam_mesh import dam_mesh
from vstpetsc.plane.solver.partition import balanced_parts, cell_graph, node_shares

needs_metis = pytest.mark.skipif(balanced_parts(np.array([[0, 1, 2, -1]] * 3), 2) is None,
                                 reason="no libmetis.so.5")


def test_the_cells_graph_joins_neighbours_and_linked_cells():
    m = plane_mesh.rectangle((0.0, 4.0), (0.0, 3.0), 4, 3, False)
    indptr, indices = cell_graph(m.cells)
    degree = np.diff(indptr)
    # corners 2, sides 3, inside 4 neighbours; symmetric, no self loops
    assert sorted(np.bincount(degree)[2:]) == [2, 4, 6] and degree.max() == 4
    rows = np.repeat(np.arange(m.ncells), degree)
    pairs = set(zip(rows.tolist(), indices.tolist()))
    assert all((b, a) in pairs for a, b in pairs) and not any(a == b for a, b in pairs)
    # two squares apart, linked by a node pair: their cells join
    cells = np.concatenate([m.cells, m.cells + m.nnodes])
    alone = cell_graph(cells)
    linked = cell_graph(cells, np.array([[m.nnodes - 1, m.nnodes]]))
    assert linked[1].size == alone[1].size + 2


def test_a_cells_node_shares_add_up_to_the_nodes():
    m = dam_mesh(20.0, 4.0, 1.5, 1.5, 10.0, 80.0, 4.0)
    shares = node_shares(m.cells)
    assert set(np.unique((m.cells >= 0).sum(axis=1))) == {3, 4}       # mixed
    assert abs(shares.sum() / 60 - m.nnodes) <= 0.01 * m.nnodes


@needs_metis
@pytest.mark.parametrize("parts", [2, 3])
def test_metis_parts_hold_as_many_nodes(parts):
    m = dam_mesh(20.0, 4.0, 1.5, 1.5, 10.0, 80.0, 2.0)
    part = balanced_parts(m.cells, parts)
    assert np.array_equal(part, balanced_parts(m.cells.copy(), parts))   # repeatable
    weight = np.bincount(part, node_shares(m.cells), minlength=parts)
    assert weight.max() <= 1.03 * weight.mean(), weight
    cells = np.bincount(part, minlength=parts)
    assert cells.min() > 0


SCRIPT = r'''
import sys
import numpy as np
from petsc4py import PETSc
from vstpetsc.plane.dam_mesh import dam_mesh
from vstpetsc.plane.solver.distributed import distribute

comm = PETSc.COMM_WORLD
m = dam_mesh(20.0, 4.0, 1.5, 1.5, 10.0, 80.0, 0.5)
local = distribute(m if comm.getRank() == 0 else None, comm)
owned = comm.tompi4py().gather(local.stop - local.start, root=0)
if comm.getRank() == 0:
    np.save(sys.argv[1], np.array(owned))
'''


@needs_metis
@pytest.mark.parametrize("ranks", [3])
def test_a_distributed_dam_owns_as_many_nodes_a_rank(tmp_path, ranks):
    script, out = tmp_path / "owned.py", tmp_path / "owned.npy"
    script.write_text(SCRIPT)
    p = mpirun(out, n=ranks, program=f"{sys.executable} {script}")
    assert p.returncode == 0, p.stderr
    owned = np.load(out)
    assert owned.size == ranks and owned.max() <= 1.05 * owned.mean(), owned


def test_a_bad_partition_option_is_named(tmp_path):
    from test_plane_ranks import assert_bad_option_named

    assert_bad_option_named(tmp_path, "vst_plane_partition", "chaco")
