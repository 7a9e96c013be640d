"""The package's version, in a module of its own: the result writer stamps
it on every file, and taking it from ``vstpetsc`` itself would make the
writer import the package's ``__init__``, which imports vstpetsc.runner.sweep,
which runs cases through the writer (an import cycle)."""

__version__ = "0.2.0"
