"""The layout module of a model's geometry: :mod:`vstpetsc.results.layout`
for bodies on a line, :mod:`vstpetsc.results.plane_layout` for a
plane-strain mesh; both give the recorder, the writer and the restart the
same functions."""

from vstpetsc.results import layout, plane_layout


def of(model):
    return plane_layout if getattr(model, "dimension", 1) == 2 else layout
