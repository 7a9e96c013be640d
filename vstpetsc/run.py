"""Running a case: the model in mesh terms, the time loop, progress and the
result file.  Collective over the ranks of ``comm``."""

import signal
import sys
import threading
import time
from dataclasses import dataclass

import h5py
import numpy as np
from petsc4py import PETSc

from vstpetsc import mesh
from vstpetsc.case import restart_key
from vstpetsc.contact import ContactPair, default_penalty
from vstpetsc.output import CONTACT_TOTALS, ResultWriter
from vstpetsc.solver import SlabSolver, SolveFailed


class BadOption(ValueError):
    """A vstpetsc option on the command line that cannot be used."""


def ownership_option(nnodes, size):
    """Node counts per rank from -vst_ownership n0,n1,... (None if absent):
    forces the DMDA layout, e.g. to put a contact pair across two ranks."""
    opts = PETSc.Options()
    if not opts.hasName("vst_ownership"):
        return None
    text = opts.getString("vst_ownership")
    try:
        counts = [int(c) for c in text.split(",")]
    except ValueError:
        raise BadOption(f"-vst_ownership: node counts separated by commas, got {text!r}") from None
    if len(counts) != size or sum(counts) != nnodes or min(counts) < 1:
        raise BadOption(f"-vst_ownership: needs {size} positive counts summing to the "
                        f"{nnodes} nodes, got {text!r}")
    return counts


@dataclass
class Model:
    """A case in mesh terms."""

    case: object
    layout: mesh.Layout
    pairs: list
    dirichlet: list      # (dofs (2,), History or None for fixed)
    tractions: list      # (dof pair (2,), History, area)

    @property
    def dirichlet_dofs(self):
        return np.concatenate([d for d, _ in self.dirichlet]) if self.dirichlet else \
            np.zeros(0, dtype=int)


def build_model(case):
    """Mesh the bodies and translate contacts and boundary conditions."""
    layout = mesh.build_layout(case.bodies)
    stiff = layout.E * layout.A / layout.h
    body_stiff = np.array([stiff[layout.elem_body == b].max()
                           for b in range(len(case.bodies))])
    pairs = []
    for c in case.contacts:
        nodes, signs, ks = [], [], []
        if c.left is not None:
            nodes.append(layout.right_node(c.left))
            signs.append(1.0)
            ks.append(body_stiff[c.left])
        if c.right is not None:
            nodes.append(layout.left_node(c.right))
            signs.append(-1.0)
            ks.append(body_stiff[c.right])
        if c.left is None:
            g0 = case.bodies[c.right].x[0] - c.wall
        elif c.right is None:
            g0 = c.wall - case.bodies[c.left].x[1]
        else:
            g0 = case.bodies[c.right].x[0] - case.bodies[c.left].x[1]
        k = max(ks)
        pen = c.penalty if c.penalty is not None else \
            default_penalty(c.formulation, k, case.dt)
        pairs.append(ContactPair(tuple(nodes), tuple(signs), g0, pen, c.formulation, k))
    dirichlet, tractions = [], []
    for bc in case.bcs:
        node = layout.end_node(bc.body, bc.end)
        dofs = np.array([2 * node, 2 * node + 1])
        if bc.type == "fixed":
            dirichlet.append((dofs, None))
        elif bc.type == "velocity":
            dirichlet.append((dofs, bc.value))
        else:
            tractions.append((dofs, bc.value, case.bodies[bc.body].area))
    return Model(case, layout, pairs, dirichlet, tractions)


def initial_state(model):
    """Nodal u0 and v0 from the bodies' profiles."""
    lay = model.layout
    u, v = np.zeros(lay.nnodes), np.zeros(lay.nnodes)
    for b, body in enumerate(model.case.bodies):
        sl = slice(lay.first[b], lay.first[b + 1])
        u[sl], v[sl] = body.u0(lay.x[sl]), body.v0(lay.x[sl])
    return u, v


class SlabLoads:
    """((force dofs, values), (Dirichlet dofs, values)) of a slab (t0, t1]:
    ``SlabLoads(model)(t0, t1)``.  The dofs never change, so they are
    gathered once; fixed ends give the same zero values every slab."""

    def __init__(self, model):
        self.tractions, self.dirichlet = model.tractions, model.dirichlet
        self.fd = _cat([d for d, _, _ in self.tractions]).astype(int)
        self.dd = _cat([d for d, _ in self.dirichlet]).astype(int)
        self.fixed = all(h is None for _, h in self.dirichlet)
        self.no_force, self.zero = np.zeros(0), np.zeros(self.dd.size)

    def __call__(self, t0, t1):
        fv = _cat([area * h.hat_integrals(t0, t1) for _, h, area in self.tractions]) \
            if self.tractions else self.no_force
        dv = self.zero if self.fixed else _cat(
            [np.zeros(2) if h is None else h(np.array([t0, t1])) for _, h in self.dirichlet])
        return (self.fd, fv), (self.dd, dv)


def _cat(parts):
    return np.concatenate(parts) if parts else np.zeros(0)


def pair_gaps(model, u):
    """Gap of every pair for nodal displacements u."""
    return np.array([p.g0 - sum(s * u[n] for n, s in zip(p.nodes, p.signs))
                     for p in model.pairs])


def pair_meta(model):
    names = [b.name for b in model.case.bodies]
    out = []
    for c, p in zip(model.case.contacts, model.pairs):
        left = "wall" if c.left is None else names[c.left]
        right = "wall" if c.right is None else names[c.right]
        out.append({"pair": f"{left},{right}", "formulation": p.formulation,
                    "penalty": p.penalty, "initial_gap": p.g0,
                    "wall": np.nan if c.wall is None else c.wall})
    return out


def formulation_attr(model):
    forms = sorted({p.formulation for p in model.pairs})
    return ",".join(forms) if forms else "none"


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


@dataclass
class RunResult:
    status: str
    slabs: int
    wall: float
    energy0: float
    energy1: float


class Interrupted(RuntimeError):
    """The run stopped on SIGTERM or SIGINT after finishing a slab."""

    def __init__(self, signum, message):
        super().__init__(message)
        self.signum = signum


class _StopSignals:
    """Turns SIGTERM and SIGINT into a flag that the time loop reads after
    each slab (the slab in progress is finished and written)."""

    def __init__(self):
        self.signum = 0

    def __enter__(self):
        self.previous = {}
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGTERM, signal.SIGINT):
                self.previous[sig] = signal.signal(sig, self._catch)
        return self

    def _catch(self, signum, frame):
        self.signum = signum

    def __exit__(self, *exc):
        for sig, handler in self.previous.items():
            signal.signal(sig, handler)


def load_restart(path, case, model):
    """State of the last row of result file ``path`` (read on every rank):
    (slab index, u, v, totals, initial energy, running right-hand side or
    None).  BadOption if it cannot continue ``case``."""
    try:
        f = h5py.File(path, "r")
    except OSError:
        raise BadOption(f"--restart: cannot open {path} as an HDF5 file") from None
    with f:
        if "solver/slab" not in f or "case" not in f.attrs:
            raise BadOption(f"--restart: {path} has no restart data (not a vstpetsc result)")
        stored = f.attrs["case"]
        if restart_key(stored) != restart_key(case.text):
            raise BadOption(f"--restart: the case differs from the one stored in {path} "
                            "in more than time.end (and output.path)")
        k0 = int(f["solver/slab"][-1])
        if k0 >= case.nslabs:
            raise BadOption(f"--restart: {path} already reaches slab {k0} (t = "
                            f"{f['time'][-1]:g}); raise time.end to continue it")
        u = np.concatenate([f[f"body/{b.name}/u"][-1] for b in case.bodies])
        v = np.concatenate([f[f"body/{b.name}/v"][-1] for b in case.bodies])
        totals = ContactTotals(len(model.pairs))
        for p in range(len(model.pairs)):
            g = f[f"contact/{p}"]
            for key in CONTACT_TOTALS:
                getattr(totals, key)[p] = g[key][-1]
            totals.on[p] = g["impulse"][-1] > 0
        energy0 = float(f["energy/kinetic"][0] + f["energy/strain"][0])
        rhs = f.get("solver/rhs_state")
        # kept when the run stopped cleanly; after a failure or a kill the
        # solver starts again from (u, v), equal up to rounding
        rhs = rhs[...] if rhs is not None and int(rhs.attrs["slab"]) == k0 else None
    return k0, u, v, totals, energy0, rhs


def run(case, output_path, petsc_options="", quiet=False, comm=None, ownership=None,
        out=sys.stdout, err=sys.stderr, restart=False):
    """Solve ``case`` and write the result file.

    With ``restart``, continue the run stored in ``output_path`` from its
    last row and append to it.  Raises :class:`vstpetsc.solver.SolveFailed`
    (file closed with status "failed") when a slab cannot be solved, and
    :class:`Interrupted` (status "interrupted") on SIGTERM or SIGINT; every
    slab computed so far is in the file either way.
    """
    comm = comm or PETSc.COMM_WORLD
    rank0 = comm.getRank() == 0
    model = build_model(case)
    lay = model.layout
    if ownership is None:
        ownership = ownership_option(lay.nnodes, comm.getSize())
    npairs = len(model.pairs)
    if restart:
        k0, u, v, totals, energy0, rhs = load_restart(output_path, case, model)
    else:
        k0, (u, v), totals, rhs = 0, initial_state(model), ContactTotals(npairs), None
        energy0 = mesh.kinetic_energy(lay, v) + mesh.strain_energy(lay, u)
    t_start = time.perf_counter()
    try:
        solver = SlabSolver(lay, case.dt, model.dirichlet_dofs, model.pairs, comm=comm,
                            ownership=ownership)
    except ValueError as exc:
        raise BadOption(str(exc)) from None
    except PETSc.Error as exc:     # e.g. a solver type that does not exist or fit
        raise BadOption("PETSc could not set up the solver with these options "
                        f"(error {exc.ierr}: {_petsc_message(exc)})") from None
    setup_time = time.perf_counter() - t_start
    solver.set_state(u, v)
    if rhs is not None:
        solver.set_rhs_state(rhs)
    talk = rank0 and not quiet
    if talk:
        _header(out, case, model, solver, comm.getSize(), output_path)
        if restart:
            out.write(f"  restart from slab {k0} (t = {k0 * case.dt:g})\n")
    writer = None
    if rank0:
        attrs = {"case": case.text, "petsc_options": petsc_options,
                 "mpi_size": comm.getSize(), "formulation": formulation_attr(model),
                 "dt": case.dt, "slabs": case.nslabs, "every": case.every,
                 **{f"unit_{k}": v for k, v in case.units.items()},
                 "solver": solver.describe()}
        if restart:
            writer = ResultWriter.reopen(output_path, attrs)
        else:
            bodies = [(b.name, lay.x[lay.first[i]:lay.first[i + 1]], b.elements)
                      for i, b in enumerate(case.bodies)]
            writer = ResultWriter(output_path, bodies, pair_meta(model), attrs)
            _record(writer, model, 0, u, v, np.zeros(npairs), totals, (0, 0), case.dt, 0.0)
    progress = Progress(case.nslabs - k0, err if talk else None)
    loads = SlabLoads(model)
    n = case.nslabs
    energy1, k = energy0, k0
    with _StopSignals() as stop:
        try:
            for k in range(k0 + 1, n + 1):
                t0, t1 = (k - 1) * case.dt, k * case.dt
                forces, dirichlet = loads(t0, t1)
                solver.rhs(forces, dirichlet)
                its = solver.solve(k)
                totals.add(solver.impulse, t0, case.dt)
                solver.advance()
                signum = stop.signum
                if comm.getSize() > 1:      # every rank stops after the same slab
                    signum = comm.tompi4py().allreduce(signum, op=_mpi_max())
                if k % case.every == 0 or k == n or signum:
                    state = solver.gather_state()
                    if rank0:
                        u, v = state
                        energy1 = mesh.kinetic_energy(lay, v) + mesh.strain_energy(lay, u)
                        _record(writer, model, k, u, v, solver.impulse, totals, its,
                                case.dt, time.perf_counter() - t_start)
                progress.update(k - k0, t1, force=k == n)
                if signum:
                    name = signal.Signals(signum).name
                    raise Interrupted(signum, f"stopped by {name} after slab {k} (t = "
                                      f"{t1:g}); continue with --restart")
        except (SolveFailed, PETSc.Error, Interrupted) as exc:
            status = "interrupted" if isinstance(exc, Interrupted) else "failed"
            done = k if status == "interrupted" else k - 1
            if isinstance(exc, PETSc.Error):   # e.g. an option that breaks a solver
                exc = SolveFailed(f"slab {k}: PETSc error {exc.ierr}: {_petsc_message(exc)}")
            if talk:
                progress.done()
            rhs = solver.rhs_state() if status == "interrupted" else None  # collective
            if writer:
                if rhs is not None:
                    writer.save_rhs_state(rhs, k)
                writer.close(status, message=str(exc), slabs_done=done)
            raise exc from None
    wall = time.perf_counter() - t_start
    if talk:
        progress.done()
    rhs = solver.rhs_state()        # collective
    if writer:
        writer.save_rhs_state(rhs, n)
        writer.close("completed", slabs_done=n, wall_time=wall, setup_time=setup_time)
    result = RunResult("completed", n - k0, wall, energy0, energy1)
    if rank0:
        rel = (energy1 - energy0) / energy0 if energy0 else float("nan")
        out.write(f"completed {n - k0} slabs in {wall:.2f} s "
                  f"({1e3 * wall / max(n - k0, 1):.3f} ms/slab); "
                  f"energy {energy0:.6g} -> {energy1:.6g} ({100 * rel:+.3f} %); "
                  f"result: {output_path}\n")
        out.flush()
    return result


def _petsc_message(exc):
    """The most specific line of a petsc4py error's traceback."""
    lines = [l.split("]", 1)[-1].strip() for l in str(exc).strip().splitlines()]
    text = [l for l in lines if l and "() at " not in l and not l.startswith("error code")]
    return "; ".join(reversed(text[-2:])) if text else lines[-1]   # most specific first


def _mpi_max():
    from mpi4py import MPI
    return MPI.MAX


class ContactTotals:
    """Running totals per pair over every slab."""

    def __init__(self, npairs):
        z = np.zeros(npairs)
        self.impulse_total, self.contact_time, self.force_peak = z.copy(), z.copy(), z.copy()
        self.episodes = z.copy()
        self.first_contact = np.full(npairs, np.nan)
        self.on = np.zeros(npairs, dtype=bool)

    def add(self, impulse, t0, dt):
        if not impulse.size:
            return
        on = impulse > 0
        if not on.any() and not self.on.any():      # nothing changes (most slabs)
            return
        self.episodes += on & ~self.on
        self.on = on
        self.impulse_total += impulse
        self.contact_time += dt * on
        self.force_peak = np.maximum(self.force_peak, impulse / dt)
        self.first_contact = np.where(np.isnan(self.first_contact) & on, t0,
                                      self.first_contact)


def _record(writer, model, k, u, v, impulses, totals, its, dt, wall):
    if writer is None:
        return
    lay = model.layout
    row = {"time": k * dt, "solver/slab": k, "energy/kinetic": mesh.kinetic_energy(lay, v),
           "energy/strain": mesh.strain_energy(lay, u),
           "solver/newton_iterations": its[0], "solver/linear_iterations": its[1],
           "solver/wall_time": wall}
    stress = mesh.element_stress(lay, u)
    for b, body in enumerate(model.case.bodies):
        sl = slice(lay.first[b], lay.first[b + 1])
        row[f"body/{body.name}/u"] = u[sl]
        row[f"body/{body.name}/v"] = v[sl]
        row[f"body/{body.name}/stress"] = stress[lay.elem_body == b]
    gaps = pair_gaps(model, u)
    for p in range(len(model.pairs)):
        row[f"contact/{p}/gap"] = gaps[p]
        row[f"contact/{p}/impulse"] = impulses[p]
        row[f"contact/{p}/force"] = impulses[p] / dt
        for key in CONTACT_TOTALS:
            row[f"contact/{p}/{key}"] = getattr(totals, key)[p]
    writer.append(row)


def describe_model(case, model, output_path):
    """The model summary: bodies, nodes, slabs, pairs and their penalties."""
    lay = model.layout
    lines = [f"vstpetsc: {case.source}",
             f"  {len(case.bodies)} bodies, {lay.nnodes} nodes, {lay.elem_node.size} "
             f"elements; dt = {case.dt:g}, {case.nslabs} slabs to t = "
             f"{case.nslabs * case.dt:g}; keep every {case.every}; result: {output_path}"]
    for b in case.bodies:
        c = np.sqrt(b.E / b.rho)
        h = (b.x[1] - b.x[0]) / b.elements
        lines.append(f"  body {b.name}: x = [{b.x[0]:g}, {b.x[1]:g}], {b.elements} elements,"
                     f" c = {c:.6g}, c dt / h = {c * case.dt / h:.3g}")
    names = [b.name for b in case.bodies]
    for k, (c, p) in enumerate(zip(case.contacts, model.pairs)):
        left = "wall" if c.left is None else names[c.left]
        right = "wall" if c.right is None else names[c.right]
        given = "given" if c.penalty is not None else "default"
        lines.append(f"  contact[{k}] {left} | {right}: gap {p.g0:g}, {p.formulation} "
                     f"penalty {p.penalty:.6g} ({given})")
    for bc in case.bcs:
        lines.append(f"  bc: {names[bc.body]} {bc.end} end {bc.type}")
    return "\n".join(lines)


def _header(out, case, model, solver, size, output_path):
    text = describe_model(case, model, output_path)
    out.write(f"{text}\n  solver: {solver.describe()} on {size} "
              f"rank{'s' if size > 1 else ''}\n")
    out.flush()
