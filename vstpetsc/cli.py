"""Command line: parse, validate, call the library, report.

Exit status: 0 success, 2 bad case or arguments (one line per problem on
stderr, no traceback), 3 failed solve (result file kept, status "failed").
"""

import os
import sys

USAGE = """usage: vstpetsc run CASE.toml [-o RESULT.h5] [--quiet] [PETSc options ...]
       vstpetsc --version"""

EXIT_BAD_INPUT = 2
EXIT_SOLVE_FAILED = 3


class UsageError(ValueError):
    pass


def split_args(argv):
    """Separate our options from PETSc's (single-dash options and their
    values, which may be negative numbers)."""
    ours, petsc = [], []
    i = 0
    while i < len(argv):
        tok = argv[i]
        if tok in ("-o", "--output"):
            if i + 1 >= len(argv):
                raise UsageError(f"{tok}: needs a file name")
            ours += [tok, argv[i + 1]]
            i += 2
        elif tok.startswith("--") or not tok.startswith("-") or tok == "-":
            ours.append(tok)
            i += 1
        else:
            petsc.append(tok)
            if i + 1 < len(argv) and _is_value(argv[i + 1]):
                petsc.append(argv[i + 1])
                i += 1
            i += 1
    return ours, petsc


def _is_value(tok):
    if not tok.startswith("-"):
        return True
    try:
        float(tok)
        return True
    except ValueError:
        return False


def parse_run(args):
    opts = {"case": None, "output": None, "quiet": False}
    it = iter(args)
    for tok in it:
        if tok in ("-o", "--output"):
            opts["output"] = next(it)
        elif tok == "--quiet":
            opts["quiet"] = True
        elif tok.startswith("--"):
            raise UsageError(f"{tok}: unknown option")
        elif opts["case"] is None:
            opts["case"] = tok
        else:
            raise UsageError(f"{tok}: unexpected argument (one case file per run)")
    if opts["case"] is None:
        raise UsageError("run: missing CASE.toml")
    return opts


def _fail(lines, code):
    for line in lines:
        sys.stderr.write(f"vstpetsc: error: {line}\n")
    return code


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv or argv[0] in ("-h", "--help", "help"):
        print(USAGE)
        return 0 if argv else EXIT_BAD_INPUT
    if argv[0] == "--version":
        from vstpetsc import __version__
        print(f"vstpetsc {__version__}")
        return 0
    command, rest = argv[0], argv[1:]
    if command != "run":
        return _fail([f"unknown command {command!r}", USAGE], EXIT_BAD_INPUT)
    try:
        ours, petsc_args = split_args(rest)
        opts = parse_run(ours)
    except UsageError as exc:
        return _fail([str(exc)], EXIT_BAD_INPUT)
    return _run(opts, petsc_args)


def _run(opts, petsc_args):
    from vstpetsc.case import CaseError, load_case

    # Validate before PETSc starts: every rank reads the same file and
    # reaches the same verdict, so no rank waits in a collective call.
    try:
        case = load_case(opts["case"])
    except CaseError as exc:
        return _fail(exc.problems, EXIT_BAD_INPUT)
    out_path = opts["output"] or case.output_path
    problem = _unwritable(out_path)
    if problem:
        return _fail([f"{'-o' if opts['output'] else 'output.path'}: {problem}"],
                     EXIT_BAD_INPUT)

    import petsc4py
    petsc4py.init([sys.argv[0]] + petsc_args)
    from vstpetsc.run import run
    from vstpetsc.solver import SolveFailed

    try:
        run(case, out_path, petsc_options=" ".join(petsc_args), quiet=opts["quiet"])
    except SolveFailed as exc:
        return _fail([f"{exc}; result kept in {out_path} (status \"failed\")"],
                     EXIT_SOLVE_FAILED)
    return 0


def _unwritable(path):
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        return f"folder {folder} does not exist"
    if os.path.isdir(path):
        return f"{path} is a folder"
    if not os.access(folder, os.W_OK) or (os.path.exists(path) and
                                           not os.access(path, os.W_OK)):
        return f"cannot write {path}"
    return None
