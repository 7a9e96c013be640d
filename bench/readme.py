"""Sections of bench/README.md written by the benchmarks that run after
bench/run.py (which rewrites the whole file)."""

import os


def write_readme(path, text):
    """Replace (or append) the section that ``text`` is (its first line,
    "## Title", names it) in README.md, leaving the rest."""
    title = text.split("\n", 1)[0]
    old = open(path).read() if os.path.exists(path) else ""
    start = old.find(title)
    if start < 0:
        new = old.rstrip("\n") + "\n\n" + text
    else:
        rest = old.find("\n## ", start + len(title))
        new = old[:start] + text + ("" if rest < 0 else "\n" + old[rest + 1:])
    with open(path, "w") as f:
        f.write(new)
