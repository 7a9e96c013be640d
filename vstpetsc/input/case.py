"""A case: what `vstpetsc run` solves, read from TOML or built in Python.

    case = Case.from_toml("bar-wall.toml")
    case = Case.from_dict({"time": {"dt": 2e-6, "end": 2e-3}, "body": [...]})
    faster = case.with_value("body.bar.v0", 2.0)
    text = case.to_toml()                  # Case.from_text(text) == case

A case keeps its document (the TOML tables as nested dicts and lists) and
the typed view that the solver reads (:mod:`vstpetsc.input.schema`).  Invalid
input raises :class:`vstpetsc.CaseError` with one line per problem.
"""

import copy
import hashlib
import numbers
import os
import tomllib

from vstpetsc.input import schema, toml_text
from vstpetsc.errors import CaseError

# the arrays of tables a dotted path enters by a name (the key given) or
# by an index ([[interface]] and [[water]] were missing: a 2-D sweep's
# interface.<name>.friction was "not a table", and water.0.level in a
# case without water was taken as a table and every run failed)
ARRAYS = {"body": "name", "contact": None, "bc": None, "soil": None, "gauge": "name",
          "region": "name", "boundary": "name", "interface": "name", "water": "name"}


class Case:
    """A validated case.

    Attributes
    ----------
    dt : float
        Slab length.
    nslabs : int
        Number of slabs, ``round(time.end / dt)``.
    every : int
        Keep every k-th slab end in the result file.
    output_path : str
        ``output.path`` as given; :attr:`output_file` resolves it.
    bodies, contacts, bcs : lists of Body, ContactSpec, BoundarySpec
    plane : vstpetsc.plane.schema.PlaneSpec or None
        A plane-strain case's [mesh], [[region]] and [[boundary]] tables
        (None: a 1-D case; its bodies, contacts and bcs are then empty).
    gravity : GravitySpec or None
    gauges : list of GaugeSpec
        The [[gauge]] points, recorded every slab.
    units : dict
        Unit names for plot labels.
    text : str
        The TOML text (the file's own text for :meth:`from_toml`).
    source : str
        Where the case came from (a path, or "<dict>").
    input_digests : dict
        {history file as named from :attr:`folder`: SHA-256 of its contents
        when the case was read}: what the case reads besides its text.
    folder : str
        The folder relative paths in the case refer to.
    """

    def __init__(self, doc, text=None, source="<dict>", folder=None):
        try:
            self.doc = _plain(doc)
        except RecursionError:
            raise CaseError([f"{source}: nested too deeply"]) from None
        if not isinstance(self.doc, dict):
            raise CaseError([f"{source}: a case is a table (dict), got {type(doc).__name__}"])
        self.folder = os.path.abspath(folder or os.getcwd())
        for key, value in schema.read(self.doc, self.folder).items():
            setattr(self, key, value)
        self.input_digests = _digests(self.input_files, self.folder)
        self.text = toml_text.dumps(self.doc) if text is None else text
        self.source = source

    @classmethod
    def from_toml(cls, path):
        """Read and validate the case file at ``path``."""
        try:
            with open(path, "rb") as f:
                raw = f.read()
        except OSError as exc:
            raise CaseError([f"{path}: cannot read case file ({exc.strerror})"]) from None
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            raise CaseError([f"{path}: not a UTF-8 text file"]) from None
        return cls.from_text(text, source=str(path),
                             folder=os.path.dirname(os.path.abspath(path)))

    @classmethod
    def from_text(cls, text, source="<text>", folder=None):
        """Validate the TOML ``text`` of a case."""
        try:
            doc = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise CaseError([f"{source}: TOML syntax error: {exc}"]) from None
        except RecursionError:
            raise CaseError([f"{source}: TOML nested too deeply"]) from None
        return cls(doc, text=text, source=source, folder=folder)

    @classmethod
    def from_dict(cls, doc, folder=None):
        """Validate a case given as nested dicts and lists (the TOML tables:
        ``{"time": {...}, "body": [{...}, ...], ...}``); relative paths refer
        to ``folder`` (default: the current folder)."""
        return cls(doc, folder=folder)

    def to_dict(self):
        """A deep copy of the case's tables."""
        return copy.deepcopy(self.doc)

    def to_toml(self):
        """TOML text that :meth:`from_text` reads back to an equal case."""
        return toml_text.dumps(self.doc)

    def with_value(self, path, value):
        """A validated copy with one value changed.

        ``path`` is dotted: ``time.dt``, ``output.every``, ``body.<name>.<key>``,
        ``contact.<k>.<key>``, ``bc.<k>.<key>``, ``soil.<k>.<key>`` (k counts
        from 0 in case order); in 2-D ``region``, ``boundary``,
        ``interface`` and ``water`` by name (or index); deeper keys
        (``body.bar.damping.alpha``, ``boundary.base.incident.x.scale``) too.
        """
        doc, created = self.to_dict(), []
        table, key = _locate(doc, path, created)
        # what the path adds to the case: if the one build below finds one of
        # them unknown, the error names the path (as check_path does)
        added = [] if key in table and not created else created + [key]
        table[key] = value
        try:
            return Case(doc, source=self.source, folder=self.folder)
        except CaseError as exc:
            _raise_unknown(path, exc.problems, added, key)
            raise

    def check_path(self, path):
        """CaseError unless ``path`` can name a value (see :meth:`with_value`):
        its tables exist and its key is one the table allows (a misspelled
        key is named with the closest allowed one, whatever the value)."""
        doc, created = self.to_dict(), []
        table, key = _locate(doc, path, created)
        if key in table and not created:
            return
        table[key] = 0          # any value: only whether the key is allowed counts
        try:
            Case(doc, source=self.source, folder=self.folder)
        except CaseError as exc:
            _raise_unknown(path, exc.problems, created + [key], key)

    @property
    def output_file(self):
        """``output.path`` resolved against :attr:`folder`."""
        return self.resolve(self.output_path)

    def resolve(self, path):
        """``path`` relative to the case's folder (absolute paths unchanged)."""
        return os.path.join(self.folder, os.path.expanduser(path))

    def inputs(self):
        """The files the case was read from: its own and the history files
        it names (a result must not overwrite them)."""
        return ([self.source] if os.path.isfile(self.source) else []) + list(self.input_files)

    def restart_key(self):
        """What must match for a restart: the case without time.end and
        output.path (a run may be extended and its file moved)."""
        return restart_key(self.doc)

    def __eq__(self, other):
        return isinstance(other, Case) and self.doc == other.doc

    def __repr__(self):
        if self.plane is not None:
            return f"<Case {self.source}: plane strain, {len(self.plane.regions)} regions, " \
                f"{self.nslabs} slabs>"
        names = ", ".join(b.name for b in self.bodies)
        return f"<Case {self.source}: {len(self.bodies)} bodies ({names}), {self.nslabs} slabs>"


def restart_key(doc):
    """:meth:`Case.restart_key` of a case document, e.g. the TOML text a
    result file keeps, compared without validating it: its history files
    are relative to a folder that the text does not say."""
    doc = _plain(doc)                    # new tables: the caller's are not changed
    if isinstance(doc.get("time"), dict):
        doc["time"].pop("end", None)
    if isinstance(doc.get("output"), dict):
        doc["output"].pop("path", None)
    return doc


def _digests(paths, folder):
    """{path relative to ``folder``: hex SHA-256 of the file} ("" for a file
    that vanished since it was read)."""
    out = {}
    for path in paths:
        try:
            with open(path, "rb") as f:
                digest = hashlib.file_digest(f, "sha256").hexdigest()
        except OSError:
            digest = ""
        out[os.path.relpath(path, folder)] = digest
    return out


def _raise_unknown(path, problems, added, key):
    """CaseError naming ``path`` alone if ``problems`` (of the case with a
    value at ``path``) say that one of ``added``, the tables and the key
    that ``path`` adds to the case, is unknown; ``key``: the last."""
    for new in added:
        unknown = _unknown_key(problems, new)
        if unknown is not None:
            what = "unknown key" if new == key else f"unknown key {new!r}"
            raise CaseError([f"{path}: {what}{unknown}"]) from None


def _unknown_key(problems, key):
    """The hint of the checker's "unknown key" line about ``key`` (what
    follows "unknown key"), or None if no problem says ``key`` is unknown.
    Only that key's line counts: a placeholder value may make other keys
    of its table unknown (a missing ``formulation`` set to 0)."""
    for problem in problems:
        name, _, what = problem.partition(": ")
        if (name == key or name.endswith(f".{key}")) and what.startswith("unknown key"):
            return what[len("unknown key"):]
    return None


def _locate(doc, path, created=None):
    """The table holding the last key of dotted ``path``, and that key;
    tables the path names that are missing are made (their names appended
    to ``created``)."""
    parts = str(path).split(".")
    if len(parts) < 2 or "" in parts:
        raise CaseError([f"{path}: a path is table.key, e.g. time.dt or body.<name>.v0"])
    node, i = doc, 0
    while i < len(parts) - 1:
        part = parts[i]
        if isinstance(node, dict) and part in ARRAYS and isinstance(node.get(part), list):
            node, i = _element(node[part], parts, i + 1, path, ARRAYS[part])
            continue
        nxt = node.get(part) if isinstance(node, dict) else None
        if nxt is None and isinstance(node, dict) and part not in ARRAYS:
            nxt = node[part] = {}
            if created is not None:
                created.append(part)
        if not isinstance(nxt, dict):
            raise CaseError([f"{path}: {'.'.join(parts[:i + 1])} is not a table"])
        node, i = nxt, i + 1
    if not isinstance(node, dict):
        raise CaseError([f"{path}: {'.'.join(parts[:-1])} is not a table"])
    return node, parts[-1]


def _element(items, parts, i, path, key):
    """The element of an array of tables named by parts[i:] (a name, which
    may contain dots, or a 0-based index) and the index of the next part."""
    if key is not None:
        for j in range(len(parts) - 1, i, -1):
            name = ".".join(parts[i:j])
            match = [t for t in items if isinstance(t, dict) and t.get(key) == name]
            if match:
                return match[0], j
    if parts[i].isdigit() and int(parts[i]) < len(items):
        return items[int(parts[i])], i + 1
    what = f"{key} or index" if key else "index"
    raise CaseError([f"{path}: no {parts[i - 1]} with {what} {parts[i]!r} "
                     f"(there are {len(items)})"])


def _plain(obj):
    """``obj`` with numpy scalars and arrays, tuples and other sequences made
    plain Python (what TOML holds); anything else is left for validation."""
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if hasattr(obj, "tolist") and not isinstance(obj, (str, bytes)):
        return _plain(obj.tolist())
    if isinstance(obj, bool) or obj is None or isinstance(obj, str):
        return obj
    if isinstance(obj, numbers.Integral):
        return int(obj)
    if isinstance(obj, numbers.Real):
        return float(obj)
    return obj
