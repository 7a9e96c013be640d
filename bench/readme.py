"""bench/README.md in sections: bench/run.py writes the head and its own
sections, the benchmarks that run after it (`make bench`) each replace or
add their own."""

import os


def bench_arguments(name, here):
    """The options of a bench that measures in a worker and keeps its
    results in NAME.json: --quick, --worker, --readme-only, --out."""
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--readme-only", action="store_true",
                    help=f"rewrite the README section from bench/{name}.json")
    ap.add_argument("--out", default=here)
    return ap


def results_and_section(out, name, readme_only, measure, section, title):
    """A bench's results: measured (``measure()``) and kept in
    OUT/NAME.json, or read back from it (``readme_only``); then its section
    ``title`` of OUT/README.md written from them (``section(results)``)."""
    import json

    json_path = os.path.join(out, f"{name}.json")
    if readme_only:
        with open(json_path) as f:
            res = json.load(f)
    else:
        res = measure()
        os.makedirs(out, exist_ok=True)
        with open(json_path, "w") as f:
            json.dump(res, f, indent=1)
    write_readme(os.path.join(out, "README.md"), section(res))
    print(f"wrote {json_path} and the section {title!r} of README.md")
    return res


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
