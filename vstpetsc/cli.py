"""Command line: parse, call the library, report.

Exit status: 0 success, 2 bad case or arguments (one line per problem on
stderr, no traceback), 3 failed solve (result file kept, status "failed"),
128 + signal number when stopped by SIGTERM or SIGINT.
"""

import os
import shutil
import sys

from vstpetsc.input.checker import INT64

USAGE = """usage: vstpetsc run CASE.toml [-o RESULT.h5] [--every K] [--quiet] [--dry-run]
                    [--restart RESULT.h5] [PETSc options ...]
       vstpetsc example [NAME [-o CASE.toml]]   list the bundled cases, or write one
       vstpetsc info RESULT.h5                   one-screen summary of a result
       vstpetsc plot RESULT.h5 [-o FIGURE.png] [--times T1,T2]
                    [--color speed|sxx|syy|sxy|strain_max|principal_max|principal_min]
                                                 velocity map and what the case has; 2-D: the
                                                 deformed mesh by speed at T1, T2, gauges, energy,
                                                 each interface's slip and opening
       vstpetsc sweep CASE.toml --set KEY=V1,V2,... [--set ...] [-o DIR] [--quiet]
                    [--ranks-per-run K] [PETSc options ...]   a run per combination, DIR/summary.csv
       vstpetsc plot DIR/summary.csv [--x KEY] [--y QUANTITY] [-o FIGURE.png]
       vstpetsc export RESULT.h5 [--csv DIR] [--xdmf]
                                                 time series as CSV files in DIR; RESULT.xdmf
                                                 (u, v, stress over time, 1-D or 2-D; a 2-D
                                                 result's interfaces) for ParaView
       vstpetsc spectrum RESULT.h5 --gauge NAME [--component shear|axial|x|y] [--damping 0.05]
                    [--periods A:B:N] [--csv FILE] [-o FIGURE.png]   response spectrum
       vstpetsc transfer RESULT.h5 --from NAME --to NAME [--component shear|axial|x|y]
                    [--smooth B] [--csv FILE] [-o FIGURE.png]   Fourier amplitude ratio
                                                 (x|y: a 2-D result's gauges, x by default)
       vstpetsc --version"""

EXIT_BAD_INPUT = 2
MAX_LINES = 50          # problems printed at most
EXIT_SOLVE_FAILED = 3
# our options that take a value; every other single-dash option is PETSc's
VALUED = ("-o", "--output", "--every", "--restart", "--set", "--x", "--y", "--ranks-per-run")
FLAGS = ("--quiet", "--dry-run")


class UsageError(ValueError):
    pass


def split_args(argv):
    """Separate our options from PETSc's (single-dash options and their
    values, which may be negative numbers)."""
    from vstpetsc.petsc.options import is_value

    ours, petsc = [], []
    i = 0
    while i < len(argv):
        tok = argv[i]
        if tok in VALUED:
            if i + 1 >= len(argv):
                raise UsageError(f"{tok}: needs a value")
            ours += [tok, argv[i + 1]]
            i += 2
        elif tok.startswith("--") or not tok.startswith("-") or tok == "-":
            ours.append(tok)
            i += 1
        else:
            petsc.append(tok)
            if i + 1 < len(argv) and is_value(argv[i + 1]):
                petsc.append(argv[i + 1])
                i += 1
            i += 1
    return ours, petsc


def parse_options(args, positional, flags=(), valued=("-o", "--output")):
    """Options of one command: up to ``len(positional)`` positional names."""
    key = lambda tok: "output" if tok in ("-o", "--output") else tok.lstrip("-")
    opts = {name: None for name in positional}
    opts.update({f: False for f in flags})
    opts.update({key(v): None for v in valued})
    it = iter(args)
    names = list(positional)
    for tok in it:
        if tok in valued:
            value = next(it, None)
            if value is None:
                raise UsageError(f"{tok}: needs a value")
            opts[key(tok)] = value
        elif tok in flags:
            opts[tok] = True
        elif tok.startswith("-"):
            raise UsageError(f"{tok}: unknown option")
        elif names:
            opts[names.pop(0)] = tok
        else:
            raise UsageError(f"{tok}: unexpected argument")
    return opts


def _rank():
    from vstpetsc.petsc import rank
    return rank()


def _fail(lines, code, kind="error: "):
    if _rank() == 0:
        for line in lines:
            sys.stderr.write(f"vstpetsc: {kind}{line}\n")
        sys.stderr.flush()
    return code


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv or argv[0] in ("-h", "--help", "help"):
        print(USAGE)
        return 0 if argv else EXIT_BAD_INPUT
    if argv[0] == "--version":
        from vstpetsc.version import __version__
        print(f"vstpetsc {__version__}")
        return 0
    command, rest = argv[0], argv[1:]
    commands = {"run": _run, "example": _example, "info": _info, "plot": _plot,
                "export": _export, "sweep": _sweep, "spectrum": _spectrum,
                "transfer": _transfer}
    if command not in commands:
        return _fail([f"unknown command {command!r} (commands: {', '.join(commands)})"],
                     EXIT_BAD_INPUT)
    if "--help" in rest or "-h" in rest:
        print(USAGE)
        return 0
    code = _command(commands[command], rest)
    writer = sys.modules.get("vstpetsc.results.writer")
    if writer is not None and writer.unclosable():   # closing that file would crash
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    return code


def _exit_on_stop_signals():
    """Outside the time loop (which finishes its slab and writes it: driver.
    StopSignals) SIGTERM, SIGINT and SIGUSR1 end the process at once with
    128 + the signal: before the result file has its name there is nothing
    to keep, and after the run completed its file is closed (exit 143, not
    a traceback or Python's default -15)."""
    import signal

    def stop(signum, frame):
        sys.stdout.flush()
        os._exit(128 + signum)

    for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGUSR1):
        signal.signal(sig, stop)


def _command(command, rest):
    """Run one command; exceptions become messages and exit statuses."""
    from vstpetsc.errors import CaseError, InputError, Interrupted, SolveFailed

    try:
        return command(rest)
    except CaseError as exc:
        shown = exc.problems[:MAX_LINES]
        more = len(exc.problems) - len(shown)
        return _fail(shown + ([f"... and {more} more problems"] if more else []),
                     EXIT_BAD_INPUT)
    except (UsageError, InputError) as exc:
        return _fail([str(exc)], EXIT_BAD_INPUT)
    except Interrupted as exc:
        return _fail([str(exc)], 128 + exc.signum, kind="")
    except SolveFailed as exc:
        return _fail([str(exc)], EXIT_SOLVE_FAILED)
    except KeyboardInterrupt:           # Ctrl-C before the time loop started
        return 128 + 2
    except BrokenPipeError:             # e.g. `vstpetsc info R.h5 | head`
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


def _run(rest):
    from vstpetsc.input.case import Case
    from vstpetsc.results.files import path_problem as output_problem

    ours, petsc_args = split_args(rest)
    opts = parse_options(ours, ["case"], FLAGS, VALUED)
    if opts["case"] is None:
        raise UsageError("run: missing CASE.toml")
    # Validate before PETSc starts: every rank reads the same file and
    # reaches the same verdict, so no rank waits in a collective call.
    case = Case.from_toml(opts["case"])
    if opts["every"] is not None:
        if not opts["every"].isdigit() or not 1 <= int(opts["every"]) <= INT64:
            raise UsageError(f"--every: must be a whole number in 1 .. {INT64}, "
                             f"got {opts['every']!r}")
        case.every = int(opts["every"])
    out_path = opts["output"] or case.output_file
    if opts["restart"]:
        if opts["output"] and os.path.abspath(opts["output"]) != os.path.abspath(opts["restart"]):
            raise UsageError("--restart appends to its file; give no other -o")
        out_path = opts["restart"]
        if not os.path.isfile(out_path):
            raise UsageError(f"--restart: {out_path}: no such file")
    if opts["--dry-run"]:
        if _rank() == 0:
            print(_dry_run(case, out_path))
        return 0
    problem = output_problem(out_path)
    if problem:
        raise UsageError(f"{'-o' if opts['output'] else 'output.path'}: {problem}")
    return _solve(case, out_path, petsc_args, opts)


def _dry_run(case, out_path):
    """The model summary of ``case`` without solving anything."""
    from vstpetsc import geometry
    return geometry.room(case).dry_run(case, out_path)


def _solve(case, out_path, petsc_args, opts):
    from vstpetsc import petsc, run
    from vstpetsc.errors import Interrupted, SolveFailed
    from vstpetsc.petsc.options import translate
    from vstpetsc.results.writer import OutputFailed

    _exit_on_stop_signals()
    petsc.initialize(translate(petsc_args))
    try:
        result = run(case, out_path, options=petsc_args, quiet=opts["--quiet"],
                     restart=bool(opts["restart"]))
    except Interrupted as exc:
        raise Interrupted(exc.signum, f"{exc}; result kept in {out_path} "
                          "(status \"interrupted\")") from None
    except OutputFailed:
        raise
    except SolveFailed as exc:
        raise SolveFailed(f"{exc}; result kept in {out_path} (status \"failed\")") from None
    from vstpetsc.results.summary import energy_line, energy_totals

    info = result.run
    if _rank() == 0:
        # from the file, as `info` reads it: the same numbers, over every
        # kept row of a restarted run too
        energy = energy_line(energy_totals({key: result.energy[key] for key in result.energy}))
        print(f"completed {info.slabs} slabs in {info.wall:.2f} s "
              f"({1e3 * info.wall / max(info.slabs, 1):.3f} ms/slab); "
              f"energy {energy}; result: {out_path}", flush=True)
    return 0


def _example(rest):
    from vstpetsc import bundled
    from vstpetsc.results.files import path_problem as output_problem

    opts = parse_options(rest, ["name"])
    if opts["name"] is None:
        if opts["output"]:
            raise UsageError("example: -o needs a NAME")
        width = max(map(len, bundled.names()))
        for name in bundled.names():
            print(f"{name:<{width}}  {bundled.description(name)}")
        return 0
    try:
        text = bundled.text(opts["name"])
    except KeyError:
        raise UsageError(f"example: unknown name {opts['name']!r} (bundled: "
                         f"{', '.join(bundled.names())})") from None
    out = opts["output"] or f"{opts['name']}.toml"
    folder = os.path.dirname(os.path.abspath(out))
    extra = [(p, os.path.join(folder, os.path.basename(p))) for p in bundled.companions(opts["name"])]
    if opts["output"] is None:
        for target in [out] + [t for _, t in extra]:
            if os.path.exists(target):
                raise UsageError(f"example: {target} exists; give -o {out} to overwrite it")
    problem = output_problem(out)
    if problem:
        raise UsageError(f"-o: {problem}")
    with open(out, "w") as f:
        f.write(text)
    for source, target in extra:
        shutil.copyfile(source, target)
    also = "".join(f" and {os.path.basename(t)}" for _, t in extra)
    print(f"wrote {out}{also}; run it with: vstpetsc run {out}")
    return 0


def _result(opts, command):
    from vstpetsc.results.reader import Result

    if opts["result"] is None:
        raise UsageError(f"{command}: missing RESULT.h5")
    return Result(opts["result"])


def _info(rest):
    from vstpetsc.results.summary import format_summary

    opts = parse_options(rest, ["result"], valued=())
    result = _result(opts, "info")
    print(format_summary(result.summary(), result.path))
    return 0


def _figure(opts, source):
    """The figure's path: -o, else ``source`` with .png; UsageError if it
    cannot be written."""
    from vstpetsc.results.files import path_problem

    out = opts["output"] or os.path.splitext(source)[0] + ".png"
    problem = path_problem(out)
    if problem:
        raise UsageError(f"-o: {problem}")
    return out


def _plot(rest):
    if any(tok.endswith(".csv") for tok in rest if not tok.startswith("-")):
        return _plot_sweep(rest)
    opts = parse_options(rest, ["result"], valued=("-o", "--output", "--times", "--color"))
    result = _result(opts, "plot")
    times = _plot_times(opts["times"], result)
    colour = _plot_colour(opts["color"], result)
    out = _figure(opts, result.path)
    from vstpetsc.results.plot import plot_result
    plot_result(result, out, times=times, colour=colour)
    print(f"wrote {out}")
    return 0


def _plot_colour(text, result):
    """--color: what a 2-D result's mesh panels show (None when not given)."""
    from vstpetsc.results.plane_plot import COLOURS

    if text is None:
        return None
    if result.dimension != 2:
        raise UsageError("--color: only for a 2-D result's mesh panels")
    if text not in COLOURS:
        raise UsageError(f"--color: one of {', '.join(COLOURS)}, got {text!r}")
    return text


def _plot_times(text, result):
    """--times T1,T2,...: the kept times of a 2-D result's mesh panels
    (None when not given)."""
    import numpy as np

    from vstpetsc.results.plane_plot import times_problem

    if text is None:
        return None
    if result.dimension != 2:
        raise UsageError("--times: only for a 2-D result (a 1-D figure shows every time)")
    try:
        times = [float(word) for word in text.split(",")]
    except ValueError:
        times = [np.nan]
    if not np.all(np.isfinite(times)):
        raise UsageError(f"--times: numbers separated by commas, got {text!r}")
    why = times_problem(result.time, times)
    if why:
        raise UsageError(f"--times: {why}")
    return times


def _export(rest):
    opts = parse_options(rest, ["result"], flags=("--xdmf",), valued=("--csv",))
    if opts["csv"] is None and not opts["--xdmf"]:
        raise UsageError("export: give --csv DIR, --xdmf or both")
    result = _result(opts, "export")
    if opts["csv"] is not None:
        folder = opts["csv"]
        if any(not c.isprintable() for c in folder):
            raise UsageError("--csv: the path contains a control character")
        if os.path.exists(folder) and not os.path.isdir(folder):
            raise UsageError(f"--csv: {folder} exists and is not a folder")
        try:
            written = result.to_csv(folder)
        except OSError as exc:
            raise UsageError(f"--csv: cannot write {folder}: {exc.strerror}") from None
        print(f"wrote {len(written)} CSV files to {folder}: "
              + ", ".join(os.path.basename(p) for p in written))
    if opts["--xdmf"]:
        try:
            print(f"wrote {result.to_xdmf()}")
        except OSError as exc:
            raise UsageError(f"--xdmf: cannot write beside {result.path}: "
                             f"{exc.strerror}") from None
    return 0


def _sweep(rest):
    import vstpetsc
    from vstpetsc.runner.sweep import parse_setting

    ours, petsc_args = split_args(rest)
    settings, others = {}, []
    it = iter(ours)
    for tok in it:
        if tok == "--set":
            key, values = parse_setting(next(it))
            if key in settings:
                raise UsageError(f"--set {key}: given twice")
            settings[key] = values
        else:
            others.append(tok)
    opts = parse_options(others, ["case"], flags=("--quiet",),
                         valued=("-o", "--output", "--ranks-per-run"))
    if opts["case"] is None or not settings:
        raise UsageError("sweep: give CASE.toml and at least one --set KEY=V1,V2,...")
    case = vstpetsc.Case.from_toml(opts["case"])
    folder = opts["output"] or os.path.splitext(opts["case"])[0] + "-sweep"
    per = opts["ranks-per-run"] or "1"
    if not per.isdigit():
        raise UsageError(f"--ranks-per-run: a positive whole number, got {per!r}")
    rows = vstpetsc.sweep(case, settings, folder, options=petsc_args, ranks_per_run=int(per))
    failed = [r for r in rows if r["status"] != "completed"]
    if _rank() == 0 and not opts["--quiet"]:
        for r in rows:
            values = ", ".join(f"{k}={r[k]}" for k in settings)
            print(f"{r['file']}  {values}: {r['status']} ({r['wall_time']:.2f} s)"
                  + (f": {r['message']}" if r.get("message") else ""))
    if _rank() == 0:
        print(f"sweep: {len(rows)} runs, {len(rows) - len(failed)} completed, "
              f"{len(failed)} failed; summary: {os.path.join(folder, 'summary.csv')}")
    return EXIT_SOLVE_FAILED if failed else 0


def _plot_sweep(rest):
    from vstpetsc.results.plot import plot_sweep

    opts = parse_options(rest, ["summary"], valued=("-o", "--output", "--x", "--y"))
    path = opts["summary"]
    if not os.path.isfile(path):
        raise UsageError(f"{path}: no such file")
    out = _figure(opts, path)
    print(f"wrote {plot_sweep(path, out, opts['x'], opts['y'])}")
    return 0


# spectrum and transfer (docs/seismic-outputs.md)
SEISMIC = ("-o", "--output", "--csv", "--component")
MAX_PERIODS = 100_000         # --periods A:B:N: a bound on N (the work grows with it)


def _gauge(result, opts, key):
    """The gauge named by option --``key``."""
    name = opts[key]
    known = f"(gauges: {', '.join(result.gauges) or 'none'})"
    if name is None:
        raise UsageError(f"--{key}: give a gauge name {known}")
    if name not in result.gauges:
        raise UsageError(f"--{key}: no gauge {name!r} in {result.path} {known}")
    return result.gauge(name)


def _component(opts, gauges, result):
    """--component: x or y on a 2-D result (x by default); shear or axial
    on a 1-D one, by default shear when every gauge's body has one."""
    from vstpetsc.results import seismic

    if result.dimension == 2:
        return _plane_component(opts["component"])
    everywhere = all(seismic.has_shear(g) for g in gauges)
    component = opts["component"] or ("shear" if everywhere else "axial")
    if component not in seismic.COMPONENTS:
        plane = " (x and y name a 2-D result's components)" \
            if component in seismic.PLANE_COMPONENTS else ""
        raise UsageError(f"--component: shear or axial, got {component!r}{plane}")
    for g in gauges:
        if component == "shear" and not seismic.has_shear(g):
            raise UsageError(f"--component: gauge {g.name!r} has no shear component (its "
                             f"body {g.attrs['body']!r} has no G or Vs)")
    return component


def _plane_component(component):
    """--component of a plane-strain gauge: the column of its (v_x, v_y)."""
    from vstpetsc.results import seismic

    component = component or seismic.PLANE_COMPONENTS[0]
    if component not in seismic.PLANE_COMPONENTS:
        raise UsageError(f"--component: x or y for a 2-D result, got {component!r}")
    return component


def _number(opts, key, problem, default=None):
    """Option --``key`` as a float, ``problem(value)`` None for a good one."""
    text = opts[key]
    if text is None:
        return default
    try:
        value = float(text)
    except ValueError:
        value = text
    why = problem(value)
    if why:
        raise UsageError(f"--{key}: {why}")
    return value


def _periods(text):
    """--periods A:B:N: N periods log-spaced from A to B, both included."""
    import numpy as np

    if text is None:
        return None
    parts = text.split(":")
    try:
        lo, hi, n = float(parts[0]), float(parts[1]), parts[2]
        good = (len(parts) == 3 and n.isdigit() and 0 < lo < hi < np.inf
                and 2 <= int(n) <= MAX_PERIODS)
    except (ValueError, IndexError):
        good = False
    if not good:
        raise UsageError(f"--periods: A:B:N with 0 < A < B and a whole N in 2 .. "
                         f"{MAX_PERIODS}, got {text!r}")
    return np.geomspace(lo, hi, int(n))


def _outputs(opts):
    """The --csv and -o paths given (None when not), checked writable."""
    from vstpetsc.results.files import path_problem

    for key, flag in (("csv", "--csv"), ("output", "-o")):
        problem = opts[key] and path_problem(opts[key])
        if problem:
            raise UsageError(f"{flag}: {problem}")
    return opts["csv"], opts["output"]


def _report(opts, columns, draw, lines):
    """Write the CSV and the figure asked for, else print ``lines``."""
    from vstpetsc.results.export import _write_csv

    csv, figure = _outputs(opts)
    if csv:
        print(f"wrote {_write_csv(csv, columns)}")
    if figure:
        print(f"wrote {draw(figure)}")
    if not (csv or figure):
        print("\n".join(lines))
    return 0


def _spectrum(rest):
    from vstpetsc.results import plot, seismic
    from vstpetsc.results.spectrum import damping_problem, response_spectrum

    opts = parse_options(rest, ["result"], valued=SEISMIC + ("--gauge", "--damping", "--periods"))
    result = _result(opts, "spectrum")
    gauge = _gauge(result, opts, "gauge")
    component = _component(opts, [gauge], result)
    damping = _number(opts, "damping", damping_problem, 0.05)
    periods = _periods(opts["periods"])
    acc = seismic.gauge_acceleration(gauge, component)
    spec = response_spectrum(acc, gauge.dt, periods, damping)
    title = f"gauge {opts['gauge']}, {component} acceleration, damping {damping:g}"
    lines = [f"response spectrum of {title}"] + seismic.spectrum_summary(
        spec, acc, gauge.dt, plot.units(result.attrs))
    return _report(opts, spec, lambda out: plot.plot_spectrum(spec, out, result, title), lines)


def _transfer(rest):
    from vstpetsc.results import plot, seismic
    from vstpetsc.results.spectrum import bandwidth_problem, fourier_amplitude, transfer_function

    opts = parse_options(rest, ["result"], valued=SEISMIC + ("--from", "--to", "--smooth"))
    result = _result(opts, "transfer")
    lower, upper = _gauge(result, opts, "from"), _gauge(result, opts, "to")
    component = _component(opts, [lower, upper], result)
    smooth = _number(opts, "smooth", bandwidth_problem)
    records = [seismic.gauge_acceleration(g, component) for g in (lower, upper)]
    freq, amp = transfer_function(*records, lower.dt, smooth)
    title = (f"{opts['to']} / {opts['from']}, {component} acceleration"
             + (f", Konno-Ohmachi b = {smooth:g}" if smooth else ""))
    lines = [f"transfer function {title}"] + seismic.transfer_summary(
        freq, amp, fourier_amplitude(records[0], lower.dt)[1], plot.units(result.attrs))
    return _report(opts, {"frequency": freq, "amplitude": amp},
                   lambda out: plot.plot_transfer(freq, amp, out, result, title), lines)
