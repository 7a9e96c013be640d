"""Running a case: the time loop (solve the slab, update the laws, record),
progress, signals and restarts.  :func:`run` is the library's entry point;
the command line is a thin shell over it.  Collective over ``comm``."""

import contextlib
import json
import signal
import sys
import threading
import time

import numpy as np
from dataclasses import dataclass

from vstpetsc import geometry
from vstpetsc.errors import InputError, Interrupted, SolveFailed
from vstpetsc.runner.recorder import Recorder, load_restart
from vstpetsc.results.files import foreign, path_problem, same_file
from vstpetsc.results.reader import Result


@dataclass
class RunInfo:
    """What one call of :func:`run` did."""

    slabs: int          # slabs computed by this call
    wall: float         # seconds, set-up included


def run(case, output=None, options=(), quiet=False, comm=None, restart=False,
        out=None, err=None):
    """Solve ``case`` and write its result file.

    Parameters
    ----------
    case : vstpetsc.Case
    output : str, optional
        The result file; default ``case.output_file``.  With ``restart``, the
        file to continue (appended to).
    options : sequence of str, optional
        PETSc options for this run's solvers, written as on a command line
        (``["-ksp_type", "gmres", "-snes_monitor"]``); see docs/solver.md.
    quiet : bool
        No header and no progress line.
    comm : PETSc or mpi4py communicator, optional
        Default PETSc.COMM_WORLD (every rank of an mpirun).
    restart : bool
        Continue the run stored in ``output`` from its last row.
    out, err : text streams, optional
        Where the header and the progress line go (stdout, stderr).

    Returns
    -------
    vstpetsc.Result
        The result file, with ``.run`` a :class:`RunInfo`.

    Raises
    ------
    vstpetsc.InputError
        An option or the output cannot be used (nothing written).
    vstpetsc.SolveFailed
        A slab could not be solved, or the file could not be written: the
        file keeps every slab before it, with status "failed".
    vstpetsc.Interrupted
        SIGTERM or SIGINT: the file keeps every slab so far, status
        "interrupted"; continue with ``restart=True``.
    """
    from vstpetsc import petsc
    from vstpetsc.petsc.options import scoped, translate

    output = case.output_file if output is None else str(output)
    check_output(case, output)
    petsc.initialize(translate(options))
    comm = petsc.communicator(comm)
    # Values near overflow make numpy warn, many times over, before the run
    # reports them in one line: a solution that is not finite (exit 3), or
    # energies that are not (Recorder.record).  The warnings add nothing.
    with scoped(options), np.errstate(all="ignore"), one_blas_thread():
        petsc.release(comm, collect=False)      # what an earlier run let go
        loop = TimeLoop(case, output, comm, quiet, out or sys.stdout, err or sys.stderr)
        info = loop.execute(restart, " ".join(map(str, options)))
        del loop
        petsc.release(comm)         # this run's matrices and solvers
    comm.barrier()
    result = Result(output)
    result.run = info
    return result


_BLAS = []          # the process's ThreadpoolController (None: no threadpoolctl)


def one_blas_thread():
    """A context in which numpy's BLAS runs on one thread: vstpetsc's dense
    algebra is on tiny matrices, where BLAS threads only spin, and on a
    busy machine a run took 5-6 times as long with them (issue 29;
    bench/blas_threads.py).  The user's setting comes back on leaving;
    without threadpoolctl nothing changes.  The libraries are looked up
    once per process (a lookup costs milliseconds: every run would pay
    them)."""
    if not _BLAS:
        try:
            from threadpoolctl import ThreadpoolController
        except ImportError:
            _BLAS.append(None)
        else:
            _BLAS.append(ThreadpoolController())
    controller = _BLAS[0]
    if controller is None:
        return contextlib.nullcontext()
    return controller.limit(limits=1, user_api="blas")


def check_output(case, output):
    """InputError if ``output`` cannot be written or is one of the case's
    own files."""
    problem = path_problem(output)
    if problem:
        raise InputError(f"output: {problem}")
    for source in case.inputs():
        if same_file(output, source):
            raise InputError(f"output: {output} is the case's input file {source}; "
                             "choose another result file")
    if foreign(output):
        raise InputError(f"output: {output} exists and is not a vstpetsc result file; "
                         "remove it or choose another result file")


class TimeLoop:
    """One run: the model, its solver, its recorder and the loop over slabs."""

    def __init__(self, case, output, comm, quiet, out, err):
        from vstpetsc.petsc.failures import setup_error

        self.case, self.output, self.comm = case, output, comm
        self.talk = comm.getRank() == 0 and not quiet
        self.out, self.err = out, err
        self.start = time.perf_counter()
        try:
            parts = geometry.room(case).run_parts(case, comm)
        except Exception as exc:
            error = setup_error(exc)
            if error is None:
                raise
            raise error from None
        self.model, self.loads, self.solver = parts.model, parts.loads, parts.solver
        self.energy, self.static = parts.energy, parts.static
        self.setup_time = time.perf_counter() - self.start
        self.space = self.solver.space
        self.recorder = Recorder(output, self.model, self.solver, comm,
                                 parts.options.flush_interval, self.energy)

    def execute(self, restart, petsc_options):
        """Solve every slab; return a RunInfo."""
        case, model = self.case, self.model
        if restart:
            self.recorder.lock_existing()
            try:
                k0, u, v, rhs, envelopes = load_restart(self.output, case, model, self.energy)
            except InputError:
                self.recorder.release()
                raise
        else:
            k0, rhs, envelopes = 0, None, None
            u, v = model.initial_state()
            if self.static is not None:
                u, v = u + self.static.u, v + self.static.v
            self.energy.start(u, v)
        self.solver.set_state(u, v, envelopes)
        if rhs is not None:
            self.solver.restart.restore(rhs)
        if self.talk:
            self.out.write(header(case, model, self.output, self.solver, self.comm.getSize()))
            if restart:
                self.out.write(f"  restart from slab {k0} (t = {k0 * case.dt:g})\n")
            self.out.flush()
        # from the first byte written: stop after a slab; a signal while the
        # completed run closes its file is too late to stop anything
        with StopSignals() as stop:
            self.recorder.open(restart, self._attrs(petsc_options), u, v)
            self._loop(k0, stop)
            self.recorder.close("completed", case.nslabs, snapshot=True,
                                wall_time=time.perf_counter() - self.start,
                                setup_time=self.setup_time)
        return RunInfo(case.nslabs - k0, time.perf_counter() - self.start)

    def _attrs(self, petsc_options):
        """The root attributes of the result file."""
        case, lay = self.case, geometry.layout(self.model)
        return {"case": case.text, "case_folder": case.folder,
                "input_digests": json.dumps(case.input_digests, sort_keys=True),
                "petsc_options": petsc_options,
                "mpi_size": self.comm.getSize(),
                "formulation": lay.formulation(self.model), **lay.root_attrs(),
                "dt": case.dt, "slabs": case.nslabs, "every": case.every,
                **{f"unit_{k}": v for k, v in case.units.items()},
                "solver": self.solver.describe()}

    def _loop(self, k0, stop):
        """Slabs k0+1 .. n."""
        case, solver = self.case, self.solver
        n, dt = case.nslabs, case.dt
        progress = Progress(n - k0, self.err if self.talk else None)
        k = k0
        gauges = len(self.recorder.gauges) > 0
        try:
            for k in range(k0 + 1, n + 1):
                t0, t1 = (k - 1) * dt, k * dt
                solver.rhs(*self.loads.slab(k))
                its = solver.solve(k)
                solver.laws.finish_slab(t0, dt)
                solver.advance()
                if gauges:
                    self.recorder.gauge_row()
                signum = self.space.max_over_ranks(stop.signum)
                if k % case.every == 0 or k == n or signum:
                    self.recorder.record(k, its)
                progress.update(k - k0, t1, force=k == n)
                if signum:
                    raise Interrupted(signum, f"stopped by {signal.Signals(signum).name} "
                                      f"after slab {k} (t = {t1:g}); continue with --restart")
        except Exception as exc:
            progress.done()
            self._stop(exc, k)
        progress.done()

    def _stop(self, exc, k):
        """End a run that stopped inside the loop: close the file with the
        right status and raise the error the caller reports."""
        from vstpetsc.petsc.failures import slab_error

        exc = slab_error(exc, k)
        if not isinstance(exc, (SolveFailed, Interrupted)):
            raise exc
        interrupted = isinstance(exc, Interrupted)
        try:
            self.recorder.close("interrupted" if interrupted else "failed",
                                k if interrupted else k - 1, snapshot=interrupted,
                                message=str(exc))
        except SolveFailed as failed:          # the file cannot be written either
            exc = failed
        # mpirun ends the job as soon as one rank exits with an error:
        # no rank leaves before rank 0 has closed the file
        self.comm.barrier()
        raise exc from None


def header(case, model, output, solver, size):
    """The run header: the model, then the solver."""
    return (f"{describe_model(case, model, output)}\n  solver: {solver.describe()} on "
            f"{size} rank{'s' if size > 1 else ''}\n")


def describe_model(case, model, output):
    """The model summary of the case's room."""
    return geometry.room(case).describe(case, model, output)


class Progress:
    """A progress line on a stream, rewritten at most twice a second."""

    def __init__(self, total, stream):
        self.total, self.stream = total, stream
        self.start = time.perf_counter()
        self.last = -1.0

    def update(self, k, t, force=False):
        if self.stream is None:
            return
        now = time.perf_counter()
        if not force and now - self.last < 0.5:
            return
        self.last = now
        el = now - self.start
        eta = el / k * (self.total - k) if k else float("nan")
        self.stream.write(f"\rslab {k}/{self.total}  t = {t:.6g}  elapsed {el:.1f} s"
                          f"  ETA {eta:.1f} s   ")
        self.stream.flush()

    def done(self):
        if self.stream is not None:
            self.stream.write("\n")
            self.stream.flush()
            self.stream = None


class StopSignals:
    """Turns SIGTERM, SIGINT and SIGUSR1 into a flag that the time loop reads
    after each slab (the slab in progress is finished and written).  Under
    mpirun, SIGUSR1 is the signal to use: Open MPI forwards it to every rank,
    while it answers SIGTERM itself (exit status 1, SIGKILL to the ranks one
    second later).  Handlers are installed only where Python allows it (the
    main thread)."""

    def __init__(self):
        self.signum = 0

    def __enter__(self):
        self.previous = {}
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGUSR1):
                self.previous[sig] = signal.signal(sig, self._catch)
        return self

    def _catch(self, signum, frame):
        self.signum = signum

    def __exit__(self, *exc):
        for sig, handler in self.previous.items():
            signal.signal(sig, handler)

