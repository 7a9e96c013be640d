"""The 1-D room: bodies on a line, the laws of their ends, block bands, the
shear component, the static start and the 1-D slab solver.  It never
imports vstpetsc.plane."""
