"""The plane-strain room (docs/plane-strain.md): what is 2-D of a case
whose domain is a cross-section, beside the 1-D room of bodies on a line.

What both geometries share stays where it is (the time algebra in
vstpetsc.slab, the histories, the laws' slab kernels, the time loop, the
results, the CLI); this package holds only the 2-D mesh (``mesh``), the
element matrices of plane-strain cells vectorised over every cell
(``elements``) and their assembly into sparse matrices (``assembly``).
Nothing here imports PETSc but ``assembly``'s PETSc conversion.
"""
