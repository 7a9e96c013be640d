"""Sections of bench/README.md written by the benchmarks that run after
bench/run.py (which rewrites the file)."""

import os


def write_section(path, title, text):
    """Replace (or append) the section that starts with the line ``title``
    in README.md ``path``, leaving the rest."""
    old = open(path).read() if os.path.exists(path) else ""
    start = old.find(title)
    if start < 0:
        new = old.rstrip("\n") + "\n\n" + text
    else:
        rest = old.find("\n## ", start + len(title))
        new = old[:start] + text + ("" if rest < 0 else "\n" + old[rest + 1:])
    with open(path, "w") as f:
        f.write(new)
