"""vstpetsc: velocity-based space-time FEM (v-ST/FEM) for 1-D elastic bars with
penalty contact, on PETSc.

The numerical kernels (:mod:`vstpetsc.slab`, :mod:`vstpetsc.contact`,
:mod:`vstpetsc.mesh`, :mod:`vstpetsc.history`) are plain numpy; petsc4py is
confined to :mod:`vstpetsc.solver` and :mod:`vstpetsc.run`.
"""

__version__ = "0.1.0"
