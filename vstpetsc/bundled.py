"""The example cases shipped with the package (vstpetsc/examples/*.toml).

The first line of each file is ``# NAME: one-line description``; the comment
block under it tells the physical story.
"""

import os
import re

FOLDER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "examples")


def names():
    """Sorted names of the bundled examples."""
    return sorted(f[:-5] for f in os.listdir(FOLDER) if f.endswith(".toml"))


def path(name):
    """Path of a bundled example; KeyError for an unknown name."""
    if name not in names():
        raise KeyError(name)
    return os.path.join(FOLDER, name + ".toml")


def text(name):
    with open(path(name)) as f:
        return f.read()


def companions(name):
    """Paths of the files a bundled case reads (``NAME-*.csv`` records and
    ``NAME-*.msh`` meshes beside it, and those of another example it names,
    e.g. rockfill-dam-mkz reads rockfill-dam's mesh and records)."""
    named = set(re.findall(r'"([\w.-]+\.(?:csv|msh))"', text(name)))
    return sorted(os.path.join(FOLDER, f) for f in os.listdir(FOLDER)
                  if f.endswith((".csv", ".msh")) and (f.startswith(name + "-") or f in named))


def description(name):
    """The one-line description from the file's first line."""
    first = text(name).splitlines()[0]
    return first.split(":", 1)[1].strip() if ":" in first else ""
