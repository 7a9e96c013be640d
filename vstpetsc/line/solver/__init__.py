"""The 1-D slab solver on PETSc: a DMDA over the nodes, the slab's linear
solve, the laws' and the soil's Newton, the end of a slab, restarts."""
