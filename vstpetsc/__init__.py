"""vstpetsc: velocity-based space-time FEM (v-ST/FEM) for 1-D elastic bars
with penalty contact, on PETSc.

The Python API (the command line is a thin shell over it)::

    import vstpetsc
    case = vstpetsc.Case.from_toml("bar-wall.toml")     # or Case.from_dict({...})
    result = vstpetsc.run(case.with_value("body.bar.v0", 2.0), output="run.h5")
    result.contact(0).force.max(), result.body("bar").u, result.energy["kinetic"]
    rows = vstpetsc.sweep(case, {"body.bar.v0": [0.5, 1.0, 2.0]}, "sweep-out")
    vstpetsc.response_spectrum(result.gauge("top").acceleration, case.dt)

``import vstpetsc`` does not start PETSc; :func:`run` does.
"""

__version__ = "0.2.0"

from vstpetsc.case import Case                                   # noqa: E402
from vstpetsc.driver import RunInfo, run                         # noqa: E402
from vstpetsc.errors import (CaseError, InputError, Interrupted,  # noqa: E402
                             SolveFailed)
from vstpetsc.results.reader import Result                       # noqa: E402
from vstpetsc.spectrum import response_spectrum, transfer_function  # noqa: E402
from vstpetsc.sweep import sweep                                 # noqa: E402

__all__ = ["Case", "CaseError", "InputError", "Interrupted", "Result", "RunInfo",
           "SolveFailed", "response_spectrum", "run", "sweep", "transfer_function",
           "__version__"]
