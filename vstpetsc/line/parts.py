"""What the 1-D room gives the shared run (vstpetsc.geometry): a case's
model, loads, slab solver and energy book; its summary; the moduli of a
result's elements."""

import numpy as np

from vstpetsc.line import model as model_mod
from vstpetsc.line.shear import is_twin
from vstpetsc.runner.parts import RunParts


def run_parts(case, comm):
    """The RunParts of a 1-D case on ``comm`` (collective)."""
    from vstpetsc.line.energy import LineEnergyBook
    from vstpetsc.line.loading import SlabLoads
    from vstpetsc.line.solver.slab_solver import SlabSolver
    from vstpetsc.petsc.options import SolverOptions

    model = model_mod.build_model(case)
    static = None
    if case.gravity is not None and case.gravity.initial == "static":
        from vstpetsc.line.static import static_state       # scipy: only here
        static = static_state(model, case.dt)
        model.laws.append(static.reactions)
    options = SolverOptions.read(model.mesh.nnodes, comm.getSize())
    loads = SlabLoads(model.laws, case.dt)
    solver = SlabSolver(model, case.dt, comm, options, loads)
    return RunParts(model, loads, solver, LineEnergyBook(model), options, static)


def describe(case, model, output):
    """The model summary: bodies, nodes, slabs, and a line per law."""
    mesh = model.mesh
    lines = [f"vstpetsc: {case.source}",
             f"  {len(case.bodies)} bodies, {mesh.nnodes} nodes, {mesh.elem_node.size} "
             f"elements; dt = {case.dt:g}, {case.nslabs} slabs to t = "
             f"{case.nslabs * case.dt:g}; keep every {case.every}; result: {output}"]
    for i, b in enumerate(model.bodies):
        el = mesh.elements(i)
        c = np.sqrt(mesh.E[el] / mesh.rho[el])
        courant = (c * case.dt / mesh.h[el]).max()
        speed = f"{c[0]:.6g}" if np.ptp(c) == 0 else f"{c.min():.6g} .. {c.max():.6g}"
        lines.append(f"  body {b.name}: x = [{b.x[0]:g}, {b.x[1]:g}], {b.elements} elements,"
                     f" {'Vs' if is_twin(b.name) else 'c'} = {speed}, c dt / h = {courant:.3g}")
    lines += [f"  {law.describe()}" for law in model.laws if law.describe()]
    return "\n".join(lines)


def dry_run(case, output):
    """The model summary without a solver."""
    return describe(case, model_mod.build_model(case), output)


def element_modulus(case, body, shear):
    """E (or G with ``shear``) of each element of ``body`` as the run meshed
    it."""
    from vstpetsc.line.shear import field_bodies

    bodies, twins = field_bodies(case.bodies)
    mesh = model_mod.build_mesh(bodies, len(case.bodies), twins)
    b = [c.name for c in case.bodies].index(body)
    return mesh.E[mesh.elements(twins[b] if shear else b)]
