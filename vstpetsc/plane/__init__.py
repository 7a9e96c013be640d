"""The plane-strain room (docs/plane-strain.md): what is 2-D of a case
whose domain is a cross-section, beside the 1-D room of bodies on a line.

What both geometries share stays where it is (the time algebra in
vstpetsc.spacetime.slab, the histories, the time loop in vstpetsc.runner.driver, the
recorder, the writer, the energy book, the CLI); this package holds the
2-D tables (``schema``), the mesh and its sources (``mesh``, ``dam_mesh``,
``rockfill_mesh``, ``solver.dmplex``, ``gmsh_file``), the element matrices vectorised over
every cell (``elements``, ``assembly``), the distribution (``solver.distributed``), the
model, its boundaries and loads (``model``, ``curves``, ``boundaries``,
``loads``, ``solver.static``), the slab solver (``solver.slab_solver``,
``solver.stepper``), gauges and energy (``gauges``, ``energy``), interfaces
(``interfaces``: the mesh split; the laws are issue 38's) and what a run
asks of the room (``parts``, ``layout``).  ``schema``, ``mesh``,
``dam_mesh``, ``rockfill_mesh``, ``elements``, ``boundaries``, ``curves``, ``gauges`` and
``interfaces`` import no PETSc.
"""
