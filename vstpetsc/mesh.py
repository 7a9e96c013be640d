"""The spatial mesh of all bodies: one global node numbering, left to right,
with bodies never sharing a node, and the tridiagonal bands of the consistent
mass and stiffness matrices.  Pure numpy."""

from dataclasses import dataclass

import numpy as np


@dataclass
class Layout:
    """Nodes and elements of all bodies.

    Attributes
    ----------
    x : (N,) reference node coordinates.
    first : (nb + 1,) first node of each body; body ``b`` owns nodes
        ``first[b]:first[b+1]``.
    elem_node : (ne,) left node of each element (its right node is +1).
    elem_body : (ne,) body of each element.
    h, E, A, rho : (ne,) element length and material.
    m_diag, k_diag : (N,) diagonals of M and K.
    m_off, k_off : (N - 1,) entries (i, i+1) = (i+1, i) of M and K; zero
        between two bodies.
    """

    x: np.ndarray
    first: np.ndarray
    elem_node: np.ndarray
    elem_body: np.ndarray
    h: np.ndarray
    E: np.ndarray
    A: np.ndarray
    rho: np.ndarray
    m_diag: np.ndarray
    m_off: np.ndarray
    k_diag: np.ndarray
    k_off: np.ndarray

    @property
    def nnodes(self):
        return self.x.size

    def left_node(self, body):
        return int(self.first[body])

    def right_node(self, body):
        return int(self.first[body + 1] - 1)

    def end_node(self, body, end):
        return self.left_node(body) if end == "left" else self.right_node(body)


def build_layout(bodies):
    """Mesh every body with its own number of equal linear elements."""
    counts = np.array([b.elements + 1 for b in bodies])
    first = np.concatenate(([0], np.cumsum(counts)))
    x = np.concatenate([np.linspace(b.x[0], b.x[1], b.elements + 1) for b in bodies])
    elem_body = np.repeat(np.arange(len(bodies)), [b.elements for b in bodies])
    elem_node = np.concatenate([np.arange(first[i], first[i + 1] - 1)
                                for i in range(len(bodies))])
    h = x[elem_node + 1] - x[elem_node]
    E = np.array([b.E for b in bodies])[elem_body]
    A = np.array([b.area for b in bodies])[elem_body]
    rho = np.array([b.rho for b in bodies])[elem_body]
    n = x.size
    me = rho * A * h / 6.0          # M_e = me [[2, 1], [1, 2]]
    ke = E * A / h                  # K_e = ke [[1, -1], [-1, 1]]
    m_diag, k_diag = np.zeros(n), np.zeros(n)
    m_off, k_off = np.zeros(max(n - 1, 0)), np.zeros(max(n - 1, 0))
    # Each node is the left node of at most one element and the right node of
    # at most one, so the fancy-indexed += below never repeats an index.
    m_diag[elem_node] += 2 * me
    m_diag[elem_node + 1] += 2 * me
    k_diag[elem_node] += ke
    k_diag[elem_node + 1] += ke
    m_off[elem_node] = me
    k_off[elem_node] = -ke
    return Layout(x, first, elem_node, elem_body, h, E, A, rho,
                  m_diag, m_off, k_diag, k_off)


def band_mult(diag, off, u):
    """Product of the symmetric tridiagonal matrix (diag, off) with ``u``."""
    y = diag * u
    y[:-1] += off * u[1:]
    y[1:] += off * u[:-1]
    return y


def kinetic_energy(layout, v):
    """1/2 v^T M v."""
    return 0.5 * float(v @ band_mult(layout.m_diag, layout.m_off, v))


def strain_energy(layout, u):
    """1/2 u^T K u."""
    return 0.5 * float(u @ band_mult(layout.k_diag, layout.k_off, u))


def element_stress(layout, u):
    """E du/dx per element."""
    n = layout.elem_node
    return layout.E * (u[n + 1] - u[n]) / layout.h


def modes(layout, fixed_nodes=()):
    """Eigenpairs of K phi = w^2 M phi with the given nodes fixed (dense; for
    checks on small meshes).  Returns (w2, Phi, free) with Phi M-orthonormal
    over the free nodes."""
    import scipy.linalg

    n = layout.nnodes
    M = np.diag(layout.m_diag) + np.diag(layout.m_off, 1) + np.diag(layout.m_off, -1)
    K = np.diag(layout.k_diag) + np.diag(layout.k_off, 1) + np.diag(layout.k_off, -1)
    free = np.setdiff1d(np.arange(n), np.asarray(fixed_nodes, dtype=int))
    w2, phi = scipy.linalg.eigh(K[np.ix_(free, free)], M[np.ix_(free, free)])
    return np.maximum(w2, 0.0), phi, free
