"""What a geometry room gives the shared time loop for one case."""

from dataclasses import dataclass


@dataclass
class RunParts:
    """The model, its slab loads, its slab solver, its energy book, the
    run's SolverOptions and the static start (None: from rest)."""

    model: object
    loads: object
    solver: object
    energy: object
    options: object
    static: object = None
