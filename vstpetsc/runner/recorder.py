"""What a run keeps: the result file on rank 0 (opened, appended in blocks
with the restart state, closed with a status) and the restart from it.
Every rank calls these methods; rank 0's verdicts reach every rank."""

import math
import os
import time

import numpy as np

from vstpetsc.runner.energy import BALANCE, largest_term
from vstpetsc.errors import InputError, SolveFailed
from vstpetsc import geometry
from vstpetsc.results import layout


class Recorder:
    """The result file of one run (``writer`` on rank 0, None elsewhere)."""

    def __init__(self, output, model, solver, comm, interval, energy):
        self.output, self.model, self.solver = output, model, solver
        self.energy = energy
        self.space = solver.space
        self.rank0 = comm.getRank() == 0
        self.size = comm.getSize()
        self.interval = interval
        self.writer, self.lock = None, None
        self.layout = geometry.layout(model)
        self.rows = self.layout.RowFiller(model)
        self.event_sets = self.layout.event_sets(model)
        if self.rank0 and solver.serial and solver.native:
            from vstpetsc.native.rows import RowCopier

            self.rows.offload(solver.u, solver.v, solver.elongation(), RowCopier.of)
        self.gauges = self.layout.gauges(model)
        self.start = time.perf_counter()
        if len(self.gauges):
            self.probe = solver.probe(self.gauges.nodes)
            self.gauge_values = np.zeros(4 * len(self.gauges))

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

        model = self.model
        snapshots = self._snapshots(rhs=False)          # collective
        # the restart state the blocks write: its datasets are made before
        # the file goes into SWMR mode (Snapshots.reserve)
        state = self.solver.restart.saved()             # collective
        case = model.case
        # the rows this run writes at most: a tiny run's buffers are small
        expected = (case.nslabs // case.every + 2, case.nslabs + 2)

        def create():
            if restart:
                # events of slabs after the last row (a block killed midway)
                events = {name: law.totals["event_count"] for law, name in self.event_sets}
                self.writer = ResultWriter.reopen(self.lock, attrs, self.interval, expected,
                                                  state, events)
                return
            first = self.rows.row(0, u, v, (0, 0), 0.0, self.energy.row(u, v, {}))
            if len(self.gauges):
                self.gauges.fill(u[self.gauges.nodes], v[self.gauges.nodes], self.gauge_values)
                first.update((name, self.gauge_values[j]) for name, j in self.gauges.series())
            self.writer = ResultWriter.create(
                self.output, self.layout.series(model), self.layout.statics(model),
                self.layout.group_attrs(model), attrs, first, self.interval, snapshots,
                [name for _, name in self.event_sets], expected, state)
        self._agree(create)
        self.compiled_gauges = None
        if self.writer and self.writer.gauges:
            column = dict(self.gauges.series())
            # a series of several values (a 2-D gauge's x, y) takes as many columns
            self.gauge_order = np.concatenate([np.atleast_1d(column[n])
                                               for n in self.writer.gauges.names])
            self.compiled_gauges = self.layout.compiled_gauges(self.gauges, self.solver,
                                                               self.gauge_order)

    def _snapshots(self, rhs=True):
        """The state a restart needs, on rank 0: the envelopes and (``rhs``)
        the running right-hand side, Newton's start and the energy sums
        (collective)."""
        lo_hi = self.solver.envelopes(self.layout.envelope_count(self.model))
        saved = self.solver.restart.saved() if rhs else None
        if not self.rank0:
            return None
        out = self.layout.envelope_snapshots(self.model, *lo_hi)
        if rhs:
            out.update(saved)
        return out

    def gauge_row(self):
        """The gauges' row of the slab just solved (every slab); when the
        buffer is full it goes to the file alone (collective)."""
        if self.compiled_gauges is not None:           # one rank
            self.compiled_gauges(self.writer.gauges.slot())
            if self.writer.gauges.full():
                self.flush(None)
            return
        uv = self.probe()
        full = False
        if self.rank0:
            self.gauges.fill(*uv, self.gauge_values)
            np.take(self.gauge_values, self.gauge_order, out=self.writer.gauges.slot())
            full = self.writer.gauges.full()
        if self.space.max_over_ranks(int(full)):
            self.flush(None)

    def record(self, k, its):
        """Keep slab k: its row on rank 0, a block to the file when due;
        returns the row's energies (rank 0)."""
        state = self.solver.gather_state()
        totals = self.solver.totals()
        energy, problem = None, None
        if self.rank0:
            u, v = state
            d = self.solver.elongation()
            energy = self.energy.row(u, v, totals, d, self.solver.state_energies())
            problem = self._problem(energy, k)
        # a row beyond the range of doubles, or with a negative balance, is
        # not kept: the run fails on it
        problem = self.space.from_rank0(problem)
        if problem:
            raise SolveFailed(problem)
        if self.rank0:
            buffers, i = self.writer.slot()
            self.rows.fill(buffers, i, k, u, v, its, time.perf_counter() - self.start, energy, d)
        self._take_events()
        if self.space.max_over_ranks(int(self.rank0 and self.writer.due())):
            self.flush(k)
        return energy

    def _problem(self, energy, k):
        """Why slab k's energies cannot be kept, or None (rank 0)."""
        if not _finite(energy):
            return f"slab {k}: the energies are not finite (values beyond the range of a double)"
        return self.energy.balance_problem(energy, k)

    def _take_events(self):
        """The pairs' events since the last kept row (every rank), to the
        writer's next block (rank 0)."""
        for law, name in self.event_sets:
            if law.events:
                rows = law.take_events()
                if self.rank0:
                    self.writer.events.add(name, rows)

    def flush(self, k):
        """Write the buffered rows with the restart state of slab k (k
        None: the gauge rows alone, nothing else)."""
        from vstpetsc.results.writer import OutputFailed

        snapshots = self._snapshots() if k is not None else None     # collective
        error = None
        if self.rank0:
            try:
                self.writer.flush(snapshots, k, gauges_only=k is None)
            except OutputFailed as exc:
                error = str(exc)
        error = self.space.from_rank0(error)
        if error:
            raise OutputFailed(error)

    def close(self, status, slab, snapshot, **attrs):
        """Close the file with ``status`` (collective); the running
        right-hand side goes with it when ``snapshot`` (the envelopes
        always)."""
        snapshots = self._snapshots(rhs=snapshot)
        if self.writer:
            writer, self.writer = self.writer, None
            groups = layout.by_group([law for law in self.model.recorded
                                      if hasattr(law, "final_attrs")],
                                     lambda law: law.final_attrs())
            writer.close(status, snapshots, slab, groups=groups, slabs_done=slab, **attrs)


def _finite(energy):
    """Whether every energy is finite (each value: a sum of two large
    finite ones may overflow)."""
    return all(map(math.isfinite, energy.values()))


def load_restart(path, case, model, energy):
    """(slab, u, v, solver state {name: array} or None, envelopes or
    None) of the last row of result file ``path``, after checking that it continues
    ``case``; its laws and ``energy`` (an EnergyBook) take their running
    sums back."""
    from vstpetsc.results.hdf5 import open_to_read
    try:
        f = open_to_read(path)
    except OSError:
        raise InputError(f"--restart: cannot open {path} as an HDF5 file") from None
    with f:
        if "solver/slab" not in f or "case" not in f.attrs:
            raise InputError(f"--restart: {path} has no restart data (not a vstpetsc result)")
        _check_continues(f, path, case)
        lay = geometry.layout(model)
        missing = [name for name, _ in lay.series(model) if name not in f] + \
            [name for _, name in lay.event_sets(model) if name not in f]
        if missing:
            raise InputError(f"--restart: {path} has no {missing[0]} (written by another "
                             "vstpetsc version); run the case again")
        k0, u, v, values, first, last = lay.last_state(f, model)
        if k0 >= case.nslabs:
            raise InputError(f"--restart: {path} already reaches slab {k0} (t = "
                             f"{f['time'][-1]:g}); raise time.end to continue it")
        for law in model.recorded:
            law.restore(values[law.group])
        # kept with every block; after a failed solve the last rows have
        # none and the solver starts again from (u, v), equal up to rounding
        state = {name: f[name][...] for name in layout.RESTART_STATE
                 if name in f and int(f[name].attrs["slab"]) == k0}
        if model.soil is not None and layout.SOIL_STATE not in state:
            # the soil's reversal points and loops are not in (u, v)
            raise InputError(f"--restart: {path} keeps no soil state at its last row (slab "
                             f"{k0}: the run failed there); run the case again")
        energy.restore(first, last, continued=layout.ENERGY_STATE in state,
                       largest=largest_term({key: f[f"energy/{key}"][...] for key in BALANCE
                                             if f"energy/{key}" in f}))
        envelopes = lay.read_envelopes(f, model)
    return k0, np.asarray(u), np.asarray(v), state or None, envelopes


def _changed_inputs(f, case):
    """The files the case reads whose contents differ from those the run
    started with (files of earlier versions keep no digests: none)."""
    import json

    if "input_digests" not in f.attrs:
        return []
    try:
        stored = dict(json.loads(f.attrs["input_digests"]))
    except (TypeError, ValueError):
        raise InputError("--restart: the file's input_digests attribute is damaged (not a "
                         "vstpetsc result?)") from None
    return [name for name, digest in case.input_digests.items()
            if name in stored and stored[name] != digest]


def _check_continues(f, path, case):
    import tomllib

    from vstpetsc.input.case import restart_key

    try:
        stored = tomllib.loads(f.attrs["case"])
    except tomllib.TOMLDecodeError:
        raise InputError(f"--restart: {path} keeps a case that is not TOML (not a vstpetsc "
                         "result)") from None
    if restart_key(stored) != case.restart_key():
        raise InputError(f"--restart: the case differs from the one stored in {path} "
                         "in more than time.end (and output.path)")
    changed = _changed_inputs(f, case)
    if changed:
        mesh = case.plane.mesh.file if case.plane is not None else None
        kind = "mesh file" if mesh and os.path.samefile(case.resolve(changed[0]), mesh) \
            else "history file"
        raise InputError(f"--restart: the {kind} {changed[0]} changed since {path} "
                         "was started; continuing would mix two inputs (start a new run)")
    every = int(f.attrs.get("every", 1))
    if every != case.every:
        raise InputError(f"--restart: {path} keeps every {every} slabs; continuing with "
                         f"every {case.every} would mix two samplings (give --every {every})")
