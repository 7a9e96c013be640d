"""The 2-D room's PETSc side: Gmsh through DMPlex, the DMPlex distribution,
PETSc matrices, the slab solver and its linear solver, the interface
pairs' Newton, the static solve."""
