"""A case document's validation (docs/case-file.md): ``read(doc)`` turns a
TOML document (nested dicts and lists) into the typed parts of a
:class:`vstpetsc.input.case.Case`, or raises :class:`CaseError` with every
problem of the document.  The tables every case has are
:mod:`vstpetsc.input.tables`; the rest are its geometry's
(``vstpetsc.geometry.schema``: :mod:`vstpetsc.line.schema`,
:mod:`vstpetsc.plane.schema`).  Nothing here imports PETSc."""

from vstpetsc import geometry
from vstpetsc.errors import CaseError
from vstpetsc.input.checker import Checker
from vstpetsc.input.tables import read_output, read_time, read_units


def read(doc, folder=None):
    """The typed parts of a case document: a dict of Case fields (relative
    file names refer to ``folder``)."""
    chk = Checker(folder)
    room = geometry.schema(doc)
    parts = room.read_start(chk, doc)
    parts.update(read_time(chk, chk.table(doc, "time", "time", required=True)))
    parts.update(read_output(chk, chk.table(doc, "output", "output", required=False)))
    parts["units"] = read_units(chk, chk.table(doc, "units", "units", required=False))
    room.read_rest(chk, doc, parts)
    if chk.problems:
        raise CaseError(chk.problems)
    parts["input_files"] = chk.inputs
    return parts
