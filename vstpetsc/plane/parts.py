"""What the plane-strain room gives the shared run (vstpetsc.geometry): a
case's model, loads, slab solver and energy book; its summary."""

from vstpetsc.runner.parts import RunParts


def run_parts(case, comm):
    """The RunParts of a plane-strain case on ``comm`` (collective)."""
    from vstpetsc.petsc.options import SolverOptions
    from vstpetsc.plane.energy import RunEnergyBook
    from vstpetsc.plane.loads import plane_loads
    from vstpetsc.plane.model import PlaneModel
    from vstpetsc.plane.solver.slab_solver import PlaneSolver

    model = PlaneModel(case, comm)
    static, extra = None, ()
    if case.gravity is not None and case.gravity.initial == "static":
        from vstpetsc.plane.confinement import confined, confined_static
        from vstpetsc.plane.loads import gravity_pattern
        from vstpetsc.plane.solver.static import static_state

        static = confined_static(model) if confined(case) else \
            static_state(model, gravity_pattern(model))
        extra = (static.reactions,)
    loads = plane_loads(model, case.dt, extra)
    solver = PlaneSolver(model, case.dt, comm, loads)
    energy = RunEnergyBook(model, solver)
    options = SolverOptions.read(model.nnodes, comm.getSize())
    return RunParts(model, loads, solver, energy, options, static)


def describe(case, model, output):
    """The model summary (printed on rank 0, which holds the whole mesh)."""
    from vstpetsc.plane.model import summary
    return summary(case, output, model.mesh, model.infos, getattr(model, "factors", None))


def dry_run(case, output):
    """The model summary without a solver."""
    from vstpetsc.plane.model import summary
    return summary(case, output)
