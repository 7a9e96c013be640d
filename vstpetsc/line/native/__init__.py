"""The Python twins of the 1-D compiled kernels (the library is
vstpetsc.native's)."""
