"""What a run keeps: the result file on rank 0 (opened, appended in blocks
with the restart state, closed with a status) and the restart from it.
Every rank calls these methods; rank 0's verdicts reach every rank."""

import time

import numpy as np

from vstpetsc.errors import InputError
from vstpetsc.results import layout


class Recorder:
    """The result file of one run (``writer`` on rank 0, None elsewhere)."""

    def __init__(self, output, model, solver, comm, interval):
        self.output, self.model, self.solver = output, model, solver
        self.space = solver.space
        self.rank0 = comm.getRank() == 0
        self.size = comm.getSize()
        self.interval = interval
        self.writer, self.lock = None, None
        self.start = time.perf_counter()

    def _agree(self, action):
        """Run ``action`` on rank 0; its InputError stops every rank."""
        error = None
        if self.rank0:
            try:
                action()
            except InputError as exc:
                error = str(exc)
            except OSError as exc:
                error = f"{self.output}: {exc.strerror}"
        error = self.space.from_rank0(error)
        if error:
            raise InputError(error)

    def lock_existing(self):
        """Lock the file to continue (a restart) before it is read."""
        from vstpetsc.results.files import OutputLock

        def take():
            self.lock = OutputLock(self.output)
            self.lock.existing()
        self._agree(take)

    def release(self):
        if self.lock is not None:
            self.lock.release()
            self.lock = None

    def open(self, restart, attrs, u, v):
        """The writer on rank 0: a new file with the row of t = 0, or the
        locked file of a restart."""
        from vstpetsc.results.writer import ResultWriter

        model, dt = self.model, model_dt(self.model)

        def create():
            if restart:
                self.writer = ResultWriter.reopen(self.lock, attrs, self.interval)
                return
            first = layout.row(model, 0, dt, u, v, (0, 0), 0.0)
            self.writer = ResultWriter.create(
                self.output, layout.series(model), layout.statics(model),
                layout.group_attrs(model), attrs, first, self.interval)
        self._agree(create)

    def record(self, k, its):
        """Keep slab k: its row on rank 0, a block to the file when due;
        returns the row's kinetic + strain energy (rank 0)."""
        state = self.solver.gather_state()
        energy = None
        if self.rank0:
            u, v = state
            row = layout.row(self.model, k, model_dt(self.model), u, v, its,
                             time.perf_counter() - self.start)
            self.writer.append(row)
            energy = row["energy/kinetic"] + row["energy/strain"]
        if self.space.max_over_ranks(int(self.rank0 and self.writer.due())):
            self.flush(k)
        return energy

    def flush(self, k):
        """Write the buffered rows with the restart state of slab k."""
        from vstpetsc.results.writer import OutputFailed

        rhs = self.solver.rhs_state()          # collective
        error = None
        if self.rank0:
            try:
                self.writer.flush({layout.RHS_STATE: rhs}, k)
            except OutputFailed as exc:
                error = str(exc)
        error = self.space.from_rank0(error)
        if error:
            raise OutputFailed(error)

    def close(self, status, slab, snapshot, **attrs):
        """Close the file with ``status`` (collective when ``snapshot``)."""
        rhs = self.solver.rhs_state() if snapshot else None
        if self.writer:
            writer, self.writer = self.writer, None
            writer.close(status, {layout.RHS_STATE: rhs} if snapshot else None, slab,
                         slabs_done=slab, **attrs)


def model_dt(model):
    return model.case.dt


def load_restart(path, case, model):
    """(slab, u, v, initial energy, running right-hand side or None) of the
    last row of result file ``path``, after checking that it continues
    ``case``; its laws take their running totals back."""
    import h5py


    try:
        f = h5py.File(path, "r", locking=False)
    except OSError:
        raise InputError(f"--restart: cannot open {path} as an HDF5 file") from None
    with f:
        if "solver/slab" not in f or "case" not in f.attrs:
            raise InputError(f"--restart: {path} has no restart data (not a vstpetsc result)")
        _check_continues(f, path, case)
        k0, u, v, values = layout.last_state(f, model)
        if k0 >= case.nslabs:
            raise InputError(f"--restart: {path} already reaches slab {k0} (t = "
                             f"{f['time'][-1]:g}); raise time.end to continue it")
        for law in model.recorded:
            law.restore(values[law.group])
        energy0 = float(f["energy/kinetic"][0] + f["energy/strain"][0])
        rhs = f.get(layout.RHS_STATE)
        # kept with every block; after a failed solve the last rows have
        # none and the solver starts again from (u, v), equal up to rounding
        rhs = rhs[...] if rhs is not None and int(rhs.attrs["slab"]) == k0 else None
    return k0, np.asarray(u), np.asarray(v), energy0, rhs


def _check_continues(f, path, case):
    from vstpetsc.case import Case

    if Case.from_text(f.attrs["case"]).restart_key() != case.restart_key():
        raise InputError(f"--restart: the case differs from the one stored in {path} "
                         "in more than time.end (and output.path)")
    every = int(f.attrs.get("every", 1))
    if every != case.every:
        raise InputError(f"--restart: {path} keeps every {every} slabs; continuing with "
                         f"every {case.every} would mix two samplings (give --every {every})")
