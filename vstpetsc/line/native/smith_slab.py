"""A slab of laws with Smith soil nodes among them in compiled code
(smith_slab.c), on one rank: the Newton of
:class:`vstpetsc.line.reduced_newton.ReducedNewton` on the laws' coordinates,
its products with S and its steps by the block Thomas algorithm on the slab
matrix's bands instead of a dense S (docs/pile-driving.md).  The Smith
nodes are evaluated in C; any other law (the cushion, a pair) through a
callback to its ``force``.  ``-vst_native 0`` runs the Python path, the
checked reference.
"""

import ctypes

import numpy as np

from vstpetsc.native import bind
from vstpetsc.line.reduced_newton import not_converged

_P = ctypes.c_void_p
_OTHERS = ctypes.CFUNCTYPE(ctypes.c_int)


class _Nodes(ctypes.Structure):
    """The C struct SmithNodes of smith_slab.c, field for field."""

    _fields_ = [("count", ctypes.c_int)] + [(name, _P) for name in (
        "law", "uidx", "sign", "Ru", "k", "J", "toe", "wn", "p", "out", "hit", "table",
        "impulse")] + [("tables", ctypes.c_int), ("tally", _P)]


class _Cushions(ctypes.Structure):
    """The C struct Cushions of smith_slab.c, field for field."""

    _fields_ = [("count", ctypes.c_int)] + [(name, _P) for name in (
        "law", "uidx", "g0", "k", "ku", "gn", "M", "out", "spans", "nspans", "hit")]


SPANS = 8                       # smith_slab.c's SPANS


class _Slab(ctypes.Structure):
    """The C struct SmithSlab of smith_slab.c, field for field."""

    _fields_ = [("laws", ctypes.c_int), ("N", ctypes.c_long), ("max_it", ctypes.c_int),
                ("rtol", ctypes.c_double), ("atol", ctypes.c_double), ("dt", ctypes.c_double)] + \
        [(name, _P) for name in (
            "A", "Ainv", "ACp", "S", "M", "B", "Binv", "BCp", "g", "sol", "V", "W", "lnode",
            "lsign", "X", "b", "CW", "u", "f_prev", "y0", "y", "trial", "r", "d", "sf", "f",
            "tan", "work", "key", "key_work")] + \
        [(name, ctypes.c_int) for name in ("nkeys", "nu", "nheads")] + \
        [(name, _P) for name in ("unode", "head_law", "head_node", "head_sign")] + \
        [("soil", _Nodes), ("cushions", _Cushions), ("others", _OTHERS), ("yeval", _P),
         ("acted", ctypes.c_int), ("ran", ctypes.c_int), ("iterations", ctypes.c_int),
         ("norm", ctypes.c_double)]


def banded(lawset):
    """Whether every law's nodes are neighbours (A + the tangents keep A's
    block bands): a pair between two bodies numbered one after the other."""
    return all(law.nodes.size == 1 or abs(int(law.nodes[1]) - int(law.nodes[0])) == 1
               for law in lawset.laws)


class SmithSlab:
    """The slab's laws in one compiled Newton; after :meth:`run` the
    LawSet's ``f``, ``work`` and the Smith nodes' outputs are the slab's."""

    def __init__(self, lib, lawset, solver, f_prev, keys, heads, S=None, rtol=1e-12,
                 atol=1e-50, max_it=30):
        """``keys``: each law's energy term; ``heads``: [(law, sign, node
        among the LawSet's)] whose work on that node is reported; ``S``:
        the condensed matrix, to use it instead of A's bands (``dense``: the
        caller then puts the laws' terms into the solution)."""
        _declare(lib)
        self.bank = soil = SmithBank(lawset)
        self.lib, self.lawset, self.laws = lib, lawset, lawset.laws
        self.max_it = max_it
        self.dense = S is not None
        self.keys = list(dict.fromkeys(keys))
        self.a = arrays = _arrays(lawset, solver, f_prev, keys, self.keys, heads, S)
        L, N = len(self.laws), arrays["A"].shape[0]
        lib.vst_smith_factor_a(arrays["A"].ctypes.data, N, arrays["Ainv"].ctypes.data,
                               arrays["ACp"].ctypes.data)
        self.cushions = CushionBank(lawset)
        compiled = {id(law) for law in soil.laws + self.cushions.laws}
        self.others = [j for j, law in enumerate(self.laws) if id(law) not in compiled]
        self.other_laws = [(j, self.laws[j]) for j in self.others]
        self.callback = _OTHERS(self._evaluate_others) if self.others else _OTHERS()
        self.ctx = _Slab(laws=L, N=N, max_it=max_it, rtol=rtol, atol=atol, dt=self.laws[0].dt,
                         nkeys=len(self.keys), nu=lawset.nodes.size, nheads=len(heads),
                         soil=soil.struct(), cushions=self.cushions.struct(),
                         others=self.callback)
        bind(self.ctx, arrays)
        self.ref = ctypes.addressof(self.ctx)
        self.synced = False
        self.f, self.y = lawset.f, arrays["y"]
        self.iterations = 0

    def _evaluate_others(self):
        """The other laws at ``yeval`` into f and tan (the callback)."""
        y, f, tan = self.a["yeval"], self.a["f"], self.a["tan"]
        any_acts = 0
        for j, law in self.other_laws:
            out = law.force(float(y[2 * j]), float(y[2 * j + 1]))
            if out is None:
                f[2 * j] = f[2 * j + 1] = 0.0
                tan[4 * j:4 * j + 4] = 0.0
            else:
                f[2 * j], f[2 * j + 1] = out[0], out[1]
                tan[4 * j:4 * j + 4] = out[2:6]
                any_acts = 1
        return any_acts

    def run(self, acted, dt, t0, slab_index):
        """The slab from the law-free solution (the solver's array, updated
        in place) and the terms ``f_prev`` of the previous slab, the Smith
        nodes' and the cushions' finish included: whether a law acts."""
        if not self.synced:
            self.bank.sync()
            self.cushions.sync()
            self.synced = True
        self.ctx.acted = acted
        if self.others:
            code = self._run_with_others(acted, dt, t0)
        else:
            code = self.lib.vst_smith_slab(self.ref)
        self.cushions.after()
        if code != 0:
            raise not_converged(slab_index, self.max_it, self.ctx.norm)
        self.iterations = self.ctx.iterations
        return bool(self.ctx.ran)

    def _run_with_others(self, acted, dt, t0):
        """run() with laws evaluated in Python: their start and test
        between the compiled start and solve."""
        ran = self.lib.vst_smith_start(self.ref)
        y0 = self.a["y0"].tolist()
        for j, law in self.other_laws:
            law.start_slab(self.lawset.u[self.lawset.node_index[j]], dt)
            law.start_time(t0)
        if not ran:
            ran = any(law.acts(y0[2 * j], y0[2 * j + 1]) for j, law in self.other_laws)
        if not ran and acted:         # their last evaluation: nothing in this slab
            self.a["yeval"][:] = self.a["y0"]
            self._evaluate_others()
        self.ctx.ran = int(bool(ran))
        return self.lib.vst_smith_solve(self.ref)

    def advance(self, acted):
        """LawSolver.advance: the laws' displacements; after an acting slab
        its terms into the running right-hand side; the marked laws' work
        on their node (0 when none)."""
        return self.lib.vst_smith_advance(self.ref, acted)

    def work_terms(self):
        """[(energy term, the slab's work)]."""
        return zip(self.keys, self.a["key_work"].tolist())


def _declare(lib):
    """The compiled slab's signatures."""
    for name in ("vst_smith_start", "vst_smith_solve", "vst_smith_slab"):
        getattr(lib, name).argtypes = [_P]
        getattr(lib, name).restype = ctypes.c_int
    lib.vst_smith_advance.argtypes = [_P, ctypes.c_int]
    lib.vst_smith_advance.restype = ctypes.c_double
    lib.vst_smith_factor_a.argtypes = [_P, ctypes.c_long, _P, _P]
    lib.vst_smith_factor_a.restype = None


def _arrays(lawset, solver, f_prev, keys, key_names, heads, S):
    """{field of the C struct SmithSlab: array}: the solver's and the
    LawSet's own arrays (read and written in place), the laws' nodes and
    signs, the energy terms, the marked laws, and the workspaces."""
    L = len(lawset.laws)
    A = np.ascontiguousarray(solver.matrix_blocks())
    N = A.shape[0]
    a = {"A": A, "V": np.ascontiguousarray(solver.V), "W": np.ascontiguousarray(solver.W),
         "X": solver.x, "b": solver.br, "CW": np.ascontiguousarray(solver.carry @ solver.W),
         "u": lawset.u, "f_prev": f_prev, "f": lawset.f,
         "lnode": np.full(2 * L, -1, dtype=np.int64), "lsign": np.zeros(2 * L),
         "key": np.array([key_names.index(k) for k in keys], dtype=np.intc),
         "key_work": np.zeros(len(key_names)),
         "unode": np.ascontiguousarray(lawset.nodes, dtype=np.int64),
         "head_law": np.array([h[0] for h in heads], dtype=np.intc),
         "head_sign": np.array([h[1] for h in heads], dtype=float),
         "head_node": np.array([lawset.nodes[h[2]] for h in heads], dtype=np.int64),
         "B": np.zeros_like(A), "tan": np.zeros(4 * L), "work": np.zeros(L)}
    if S is not None:
        a["S"] = np.ascontiguousarray(S, dtype=float)
        a["M"] = np.zeros_like(a["S"])
    for name in ("Ainv", "ACp", "Binv", "BCp"):
        a[name] = np.zeros(4 * N)
    for name in ("g", "sol"):
        a[name] = np.zeros(2 * N)
    for name in ("y0", "y", "trial", "r", "d", "sf", "yeval"):
        a[name] = np.zeros(2 * L)
    for j, law in enumerate(lawset.laws):
        a["lnode"][2 * j:2 * j + law.nodes.size] = law.nodes
        a["lsign"][2 * j:2 * j + law.nodes.size] = law.signs
    return a


class SmithBank:
    """The Smith nodes' state as arrays for the compiled slab, which starts
    and finishes them (their ``start_slab`` and ``finish_slab``); the slips,
    impulses and the tables' work go back to the laws and reports when a
    report reads them."""

    def __init__(self, lawset):
        from vstpetsc.line.laws.soil import SoilNode

        js = [j for j, law in enumerate(lawset.laws) if type(law) is SoilNode]
        self.laws = laws = [lawset.laws[j] for j in js]
        reports = list({id(law.report): law.report for law in laws}.values())
        self.reports = reports
        n = len(laws)
        self.a = {"law": np.array(js, dtype=np.intc),
                  "uidx": np.array([int(lawset.node_index[j][0]) for j in js], dtype=np.int64),
                  "sign": np.array([law.signs[0] for law in laws], dtype=float),
                  "Ru": np.array([law.Ru for law in laws]), "k": np.array([law.k for law in laws]),
                  "J": np.array([law.J for law in laws]),
                  "toe": np.array([law.toe for law in laws], dtype=np.intc),
                  "wn": np.zeros(n), "p": np.zeros(n), "out": np.zeros(7 * n),
                  "hit": np.zeros(n, dtype=np.intc),
                  "table": np.array([reports.index(law.report) for law in laws], dtype=np.intc),
                  "impulse": np.zeros(n), "tally": np.zeros(len(reports))}
        for report in reports:
            report.before_read = self.write_back
        self.synced = False

    def struct(self):
        return bind(_Nodes(count=len(self.laws), tables=len(self.reports)), self.a)

    def sync(self):
        """The slips and the tables' work from the laws, at the first slab
        (after a restart has set them)."""
        self.a["p"][:] = [law.p for law in self.laws]
        self.a["tally"][:] = [report.tally[0] for report in self.reports]
        self.synced = True

    def write_back(self):
        """The slips, impulses and the tables' work into the laws and
        reports (before a report reads them)."""
        if self.synced:
            for law, p, i in zip(self.laws, self.a["p"].tolist(), self.a["impulse"].tolist()):
                law.p, law.impulse = p, i
            for report, tally in zip(self.reports, self.a["tally"].tolist()):
                report.tally[0] = tally


class CushionBank:
    """The cushions' state as arrays for the compiled slab, which starts
    them and moves their M on: their M in at the first slab; their gap, M
    and last integrals out after every slab (their own ``finish_slab``
    then runs)."""

    def __init__(self, lawset):
        from vstpetsc.line.laws.cushion import Cushion

        js = [j for j, law in enumerate(lawset.laws) if type(law) is Cushion]
        self.laws = laws = [lawset.laws[j] for j in js]
        n = len(laws)
        uidx = np.full((n, 2), -1, dtype=np.int64)
        for i, j in enumerate(js):
            idx = lawset.node_index[j]
            uidx[i, :idx.size] = idx
        self.a = {"law": np.array(js, dtype=np.intc), "uidx": uidx,
                  "g0": np.array([law.g0 for law in laws], dtype=float),
                  "k": np.array([law.k for law in laws], dtype=float),
                  "ku": np.array([law.ku for law in laws], dtype=float),
                  "gn": np.zeros(n), "M": np.zeros(n), "out": np.zeros(7 * n),
                  "spans": np.zeros(2 * SPANS * n), "nspans": np.zeros(n, dtype=np.intc),
                  "hit": np.zeros(n, dtype=np.intc)}

    def struct(self):
        return bind(_Cushions(count=len(self.laws)), self.a)

    def sync(self):
        """Their M from the laws, at the first slab (after a restart)."""
        self.a["M"][:] = [law.M for law in self.laws]

    def after(self):
        """What Cushion.start_slab and force leave on the laws (their M
        moves on in C as in their finish_slab)."""
        if not self.laws:
            return
        a = self.a
        gn, M, hit = a["gn"].tolist(), a["M"].tolist(), a["hit"].tolist()
        for i, law in enumerate(self.laws):
            law.gn, law.M = gn[i], M[i]
            if not hit[i]:
                law.last = None
                continue
            out = a["out"][7 * i:7 * i + 7].tolist()
            spans = a["spans"][2 * SPANS * i:2 * SPANS * i + 2 * a["nspans"][i]].tolist()
            law.last = (*out, list(zip(spans[::2], spans[1::2])))


def dense_is_cheaper(laws, nodes):
    """Whether a step with the dense S (O((2 laws)^3)) costs less than one
    on A's bands (some 100 flops a node)."""
    return (2 * laws) ** 3 / 3 < 100 * nodes


def takes(lawset, comm_size):
    """Whether the compiled slab runs these laws: Smith nodes among them,
    one rank, A + the tangents within A's bands, no law whose work splits
    into several energy terms (friction)."""
    from vstpetsc.line.laws.soil import SoilNode

    return (comm_size == 1 and any(type(law) is SoilNode for law in lawset.laws)
            and banded(lawset)
            and not any(getattr(law, "work_terms", None) for law in lawset.laws))


def node_integrals(lib, wn, p, y1, y2, dt, k, Ru, J, toe):
    """The compiled :func:`vstpetsc.kernels.smith.smith_integrals` of one node
    (for tests): its 7 outputs, or None."""
    lib.vst_smith_node.argtypes = [_P, _P]
    lib.vst_smith_node.restype = ctypes.c_int
    args = np.array([wn, p, y1, y2, dt, k, Ru, J, float(toe)])
    out = np.zeros(7)
    return tuple(out.tolist()) if lib.vst_smith_node(args.ctypes.data, out.ctypes.data) else None


def cushion_integrals(lib, gn, d1, d2, dt, k, ku, M):
    """The compiled :func:`vstpetsc.line.laws.cushion.cushion_integrals` (for
    tests): (7 outputs, the spans), or None."""
    lib.vst_cushion_integrals.argtypes = [_P, _P, _P, _P]
    lib.vst_cushion_integrals.restype = ctypes.c_int
    args = np.array([gn, d1, d2, dt, k, ku, M])
    out, spans, count = np.zeros(7), np.zeros(2 * SPANS), np.zeros(1, dtype=np.intc)
    if not lib.vst_cushion_integrals(args.ctypes.data, out.ctypes.data, spans.ctypes.data,
                                     count.ctypes.data):
        return None
    return (*out.tolist(), [tuple(p) for p in spans.reshape(-1, 2)[:count[0]].tolist()])
