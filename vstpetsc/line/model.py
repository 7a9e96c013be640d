"""A case in mesh terms: nodes and elements of all bodies, per-element
material, the tridiagonal bands of M, C and K, and the case's laws.

One global node numbering, left to right; bodies never share a node, so an
element never joins two bodies and the nodes of a contact pair between two
bodies are neighbours.  Pure numpy.
"""

from dataclasses import dataclass, field

import numpy as np

from vstpetsc import materials
from vstpetsc.line.laws import build_laws
from vstpetsc.line.schema import MASSES
from vstpetsc.line.shear import field_bodies


@dataclass
class Mesh:
    """Nodes and elements of all bodies.

    Attributes
    ----------
    x : (N,) reference node coordinates.
    first : (nb + 1,) first node of each body; body ``b`` owns nodes
        ``first[b]:first[b+1]`` and elements ``first[b]-b:first[b+1]-b-1``.
    elem_node : (ne,) left node of each element (its right node is +1).
    elem_body : (ne,) body of each element.
    h, E, A, rho : (ne,) element length and material (tables evaluated at
        element midpoints).
    alpha, beta : (ne,) Rayleigh coefficients of the element's body.
    kf, cf : (ne,) foundation stiffness and damping per length.
    mass_off : (ne,) the off-diagonal o of the element mass matrix
        rho A h / 12 [[6 - o, o], [o, 6 - o]] (2: consistent, 1: averaged,
        0: lumped).
    names : the bodies' names (a shear twin's is "<name>/shear").
    axial_nodes : the nodes of the axial field, 0 .. axial_nodes - 1; the
        shear twins' follow (vstpetsc.line.shear).
    twins : {axial body: the body that carries its shear motion}.
    """

    x: np.ndarray
    first: np.ndarray
    elem_node: np.ndarray
    elem_body: np.ndarray
    h: np.ndarray
    E: np.ndarray
    A: np.ndarray
    rho: np.ndarray
    alpha: np.ndarray
    beta: np.ndarray
    kf: np.ndarray
    cf: np.ndarray
    mass_off: np.ndarray
    names: tuple = ()
    axial_nodes: int = 0
    twins: dict = field(default_factory=dict)

    @property
    def nnodes(self):
        return self.x.size

    def nodes(self, body):
        return slice(int(self.first[body]), int(self.first[body + 1]))

    def elements(self, body):
        return slice(int(self.first[body]) - body, int(self.first[body + 1]) - body - 1)

    def left_node(self, body):
        return int(self.first[body])

    def right_node(self, body):
        return int(self.first[body + 1] - 1)

    def end_node(self, body, end):
        return self.left_node(body) if end == "left" else self.right_node(body)

    def end_element(self, body, end):
        el = self.elements(body)
        return el.start if end == "left" else el.stop - 1

    def element_stiffness(self):
        """E A / h of every element, rounded, each to a multiple of the
        unit in the last place of twice the node sums ke_{e-1} + ke_e it
        enters (a change of at most about 2e-16 of that sum), so that every
        such sum is exact and K's rows sum to zero exactly, as the bars' own
        stiffness does: with the plain sums a body moving as a whole felt
        springs to the ground of that rounding (k_ii + k_ij != 0), whose
        energy no term of the balance holds (docs/loads.md section 4).  An
        element never rounds to zero stiffness (at least one unit).  The
        slab matrix and the hysteretic soil's linear part both take it."""
        ke = self.E * self.A / self.h
        shared = self.elem_body[1:] == self.elem_body[:-1]       # elements e, e+1 share a node
        unit = np.where(shared, np.spacing(2.0 * (ke[:-1] + ke[1:])), 0.0)
        q = np.zeros_like(ke)                 # the coarser grid of the two sums of each element
        q[:-1] = unit
        q[1:] = np.maximum(q[1:], unit)
        # q is a power of 2: ke / q and the product below are exact
        rounded = np.maximum(np.round(ke / np.where(q > 0, q, 1.0)), 1.0) * q
        return np.where(q > 0, rounded, ke)

    def body_stiffness(self, body):
        """The largest E A / h of the body's elements."""
        el = self.elements(body)
        return float((self.E[el] * self.A[el] / self.h[el]).max())


@dataclass
class Operators:
    """The symmetric tridiagonal spatial matrices as diagonals (N,) and the
    entries (i, i+1) = (i+1, i) (N - 1,), zero between two bodies:
    M (masses, support masses included), C (every dashpot), K (the bars'
    own stiffness) and S (springs to the ground: foundation, supports)."""

    m_diag: np.ndarray
    m_off: np.ndarray
    c_diag: np.ndarray
    c_off: np.ndarray
    k_diag: np.ndarray
    k_off: np.ndarray
    s_diag: np.ndarray
    s_off: np.ndarray

    def add_node(self, which, node, value):
        """Add ``value`` to the diagonal of matrix ``which`` ("m", "c", "s")."""
        getattr(self, f"{which}_diag")[node] += value

    @property
    def damped(self):
        return bool(np.any(self.c_diag) or np.any(self.c_off))

    @property
    def sprung(self):
        return bool(np.any(self.s_diag) or np.any(self.s_off))


@dataclass
class Model:
    """A case in mesh terms, with its laws (:mod:`vstpetsc.line.laws`);
    ``bodies``: the mesh's bodies, the case's then their shear twins."""

    case: object
    mesh: Mesh
    ops: Operators
    laws: list
    bodies: list
    soil: object = None        # the shear field's hysteretic law (vstpetsc.materials)

    @property
    def nonlinear(self):
        return [law for law in self.laws if law.nodes.size]

    @property
    def recorded(self):
        return [law for law in self.laws if law.group is not None]

    def initial_state(self):
        """Nodal u0 and v0 (:func:`initial_state`), as a plane-strain model
        gives its own."""
        return initial_state(self)


def build_model(case):
    """Mesh the bodies, assemble M and K, build the laws and let them add
    their linear terms."""
    bodies, twins = field_bodies(case.bodies)
    mesh = build_mesh(bodies, len(case.bodies), twins)
    ops = element_operators(mesh)
    laws = build_laws(case, mesh)
    for law in laws:
        law.add_operators(ops)
    return Model(case, mesh, ops, laws, bodies, materials.build(case.bodies, mesh))


def build_mesh(bodies, axial=None, twins=None):
    """Every body meshed with its own number of linear elements, equal
    ones or each layer's (Body.node_x); material tables evaluated at the
    element midpoints.  The first
    ``axial`` bodies (default all) are the axial field; ``twins`` maps
    them to their shear twins among the others."""
    counts = np.array([b.elements + 1 for b in bodies])
    first = np.concatenate(([0], np.cumsum(counts)))
    x = np.concatenate([b.node_x() for b in bodies])
    elem_body = np.repeat(np.arange(len(bodies)), [b.elements for b in bodies])
    elem_node = np.concatenate([np.arange(first[i], first[i + 1] - 1)
                                for i in range(len(bodies))])
    h = x[elem_node + 1] - x[elem_node]
    mid = 0.5 * (x[elem_node] + x[elem_node + 1])
    profile = lambda key: np.concatenate(
        [getattr(b, key)(mid[elem_body == i]) for i, b in enumerate(bodies)])
    constant = lambda values: np.array(values, dtype=float)[elem_body]
    axial = len(bodies) if axial is None else axial
    return Mesh(x, first, elem_node, elem_body, h, profile("E"), profile("area"),
                profile("rho"), constant([b.damping[0] for b in bodies]),
                constant([b.damping[1] for b in bodies]),
                constant([b.foundation[0] for b in bodies]),
                constant([b.foundation[1] for b in bodies]),
                constant([MASSES[b.mass] for b in bodies]),
                tuple(b.name for b in bodies), int(first[axial]), dict(twins or {}))


def element_operators(mesh):
    """Mass M_e = rho A h / 12 [[6 - o, o], [o, 6 - o]] (o = 2: consistent,
    rho A h / 6 [[2, 1], [1, 2]], bit for bit; 1: averaged; 0: lumped), stiffness
    K_e = E A / h [[1, -1], [-1, 1]], Rayleigh and foundation dashpots
    C_e = alpha M_e + beta K_e + c_f h / 6 [[2, 1], [1, 2]] and foundation
    springs S_e = k_f h / 6 [[2, 1], [1, 2]], assembled."""
    twelfth = mesh.rho * mesh.A * mesh.h / 12.0
    md, mo = twelfth * (6.0 - mesh.mass_off), twelfth * mesh.mass_off
    ke = mesh.element_stiffness()
    ce = mesh.cf * mesh.h / 6.0
    se = mesh.kf * mesh.h / 6.0
    return Operators(*assemble(mesh, md, mo),
                     *assemble(mesh, mesh.alpha * md + mesh.beta * ke + 2 * ce,
                               mesh.alpha * mo - mesh.beta * ke + ce),
                     *assemble(mesh, ke, -ke), *assemble(mesh, 2 * se, se))


def assemble(mesh, diag_e, off_e):
    """Bands of sum_e [[d, o], [o, d]] over the elements."""
    n = mesh.nnodes
    diag, off = np.zeros(n), np.zeros(max(n - 1, 0))
    # Each node is the left node of at most one element and the right node of
    # at most one, so the fancy-indexed += below never repeats an index.
    diag[mesh.elem_node] += diag_e
    diag[mesh.elem_node + 1] += diag_e
    off[mesh.elem_node] = off_e
    return diag, off


def band_mult(diag, off, u):
    """Product of the symmetric tridiagonal matrix (diag, off) with ``u``."""
    y = diag * u
    y[:-1] += off * u[1:]
    y[1:] += off * u[:-1]
    return y


def kinetic_energy(ops, v):
    """1/2 v^T M v (support masses included)."""
    return 0.5 * float(v @ band_mult(ops.m_diag, ops.m_off, v))


def strain_energy(ops, u):
    """1/2 u^T K u: the bars' own."""
    return 0.5 * float(u @ band_mult(ops.k_diag, ops.k_off, u))


def spring_energy(ops, u):
    """1/2 u^T S u: foundation and support springs."""
    return 0.5 * float(u @ band_mult(ops.s_diag, ops.s_off, u)) if ops.sprung else 0.0


def initial_state(model):
    """Nodal u0 and v0 from the bodies' profiles."""
    mesh = model.mesh
    u, v = np.zeros(mesh.nnodes), np.zeros(mesh.nnodes)
    for b, body in enumerate(model.bodies):
        sl = mesh.nodes(b)
        u[sl], v[sl] = body.u0(mesh.x[sl]), body.v0(mesh.x[sl])
    return u, v


def dense(ops, which="mk"):
    """Dense matrices named by ``which`` (default M and K; "mcks" for all
    four), for checks on small meshes."""
    return tuple(np.diag(getattr(ops, f"{w}_diag")) + np.diag(getattr(ops, f"{w}_off"), 1)
                 + np.diag(getattr(ops, f"{w}_off"), -1) for w in which)


def modes(ops, fixed_nodes=()):
    """Eigenpairs of (K + S) phi = w^2 M phi with the given nodes fixed (dense; for
    checks on small meshes).  Returns (w2, Phi, free) with Phi M-orthonormal
    over the free nodes."""
    import scipy.linalg

    M, K, S = dense(ops, "mks")
    K = K + S
    free = np.setdiff1d(np.arange(M.shape[0]), np.asarray(fixed_nodes, dtype=int))
    w2, phi = scipy.linalg.eigh(K[np.ix_(free, free)], M[np.ix_(free, free)])
    return np.maximum(w2, 0.0), phi, free
