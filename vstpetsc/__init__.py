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

import importlib
import importlib.util

from vstpetsc.errors import CaseError, InputError, Interrupted, SolveFailed
# here, not on demand: the package has a function named sweep (the module
# is vstpetsc.runner.sweep)
from vstpetsc.runner.sweep import sweep
from vstpetsc.version import __version__

# The other public names and their modules, imported when first asked for
# (PEP 562): `import vstpetsc` loads numpy and no more (issue 29: it loaded
# every module of the package, h5py and scipy included, which `vstpetsc
# --help` and every tool that only imports the package paid); the first
# ``vstpetsc.run`` loads what a run needs, once per process.
_PUBLIC = {"Case": "vstpetsc.input.case", "RunInfo": "vstpetsc.runner.driver",
           "run": "vstpetsc.runner.driver",
           "Result": "vstpetsc.results.reader", "response_spectrum": "vstpetsc.results.spectrum",
           "transfer_function": "vstpetsc.results.spectrum"}

__all__ = ["Case", "CaseError", "InputError", "Interrupted", "Result", "RunInfo",
           "SolveFailed", "response_spectrum", "run", "sweep", "transfer_function",
           "__version__"]


def __getattr__(name):
    """A public name (imported now, then kept), or a submodule."""
    if name in _PUBLIC:
        value = getattr(importlib.import_module(_PUBLIC[name]), name)
        globals()[name] = value
        return value
    if not name.startswith("__") and importlib.util.find_spec(f"{__name__}.{name}"):
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_PUBLIC))
