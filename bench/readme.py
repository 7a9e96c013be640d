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


def sections(text):
    """{"## Title" line: the section's text} of a README, in order."""
    parts = ("\n" + text).split("\n## ")[1:]
    return {"## " + p.split("\n", 1)[0]: ("## " + p).rstrip("\n") + "\n" for p in parts}


def keep_others(path, text):
    """``text`` (a whole README that bench/run.py writes) followed by the
    sections of the README at ``path`` that ``text`` has not: those the
    benchmarks after bench/run.py wrote (OpenSees, sweeps, ...)."""
    old = open(path).read() if os.path.exists(path) else ""
    own = sections(text)
    kept = [body for title, body in sections(old).items() if title not in own]
    return "\n".join([text.rstrip("\n") + "\n"] + kept)
