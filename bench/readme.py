"""bench/README.md in sections: bench/run.py writes the head and its own
sections, the benchmarks that run after it (`make bench`) each replace or
add their own."""

import os


def write_readme(path, text):
    """Replace (or append) the section that ``text`` is (its first line,
    "## Title", names it) in README.md, leaving the rest."""
    title = text.split("\n", 1)[0]
    old = _read(path)
    start = old.find(title)
    if start < 0:
        new = old.rstrip("\n") + "\n\n" + text
    else:
        rest = old.find("\n## ", start + len(title))
        new = old[:start] + text + ("" if rest < 0 else "\n" + old[rest + 1:])
    with open(path, "w") as f:
        f.write(new)


def with_other_sections(path, text):
    """``text`` (the README as bench/run.py makes it) followed by the
    sections of the README at ``path`` that ``text`` has no section of:
    those of the benchmarks run after it, which `run.py --readme-only`
    must keep."""
    own = set(sections(text))
    others = [body for title, body in sections(_read(path)).items() if title not in own]
    return "\n\n".join([text.rstrip("\n")] + [body.rstrip("\n") for body in others]) + "\n"


def sections(text):
    """{"## Title": the section's text, title line included}, in order."""
    out = {}
    for part in ("\n" + text).split("\n## ")[1:]:
        out["## " + part.split("\n", 1)[0]] = "## " + part
    return out


def _read(path):
    return open(path).read() if os.path.exists(path) else ""
