"""A run and many: the time loop both geometries share, the recorder, the
energy book, sweeps over ranks."""
