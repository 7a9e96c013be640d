"""What every law at a body end shares: the end's node and a header line."""

from vstpetsc.line.laws.base import Law


class EndLaw(Law):
    """A law at one end of a body (``spec``: a case's [[bc]] entry, its
    ``body`` a body of the mesh: a shear twin for a shear bc)."""

    def __init__(self, spec, index, case, mesh):
        self.spec, self.index = spec, index
        self.node = mesh.end_node(spec.body, spec.end)
        self.element = mesh.end_element(spec.body, spec.end)
        self.body_name = mesh.names[spec.body]

    def describe(self):
        return f"bc: {self.body_name} {self.spec.end} end {self.spec.type}"
