"""Coulomb friction of a contact pair ([[contact]] ``friction = mu``): a law
on the shear field's end nodes of the pair (vstpetsc.line.shear), whose limit
mu N(theta) follows the pair's normal force inside the slab (docs/shear.md).

The pair's relative shear velocity s = w(second) - w(first) (a wall moves
with ``wall_shear_velocity``, sampled at the slab ends and linear in
between, as a prescribed velocity) enters an elastic-perfectly-plastic
tangential spring whose slab integrals kernels/coulomb.py gives exactly, the
stick/slip switches inside the slab included.  The friction force T on the
second side is the kernel's; the law's reduced coordinate is
y = sum c_k w_k = -s - c_wall v_wall (c_k as the pair: +1 left, -1 right),
so its terms are f_a = F_a and df/dy = -dF/ds.

Coulomb friction does not act back on the normal force (no dilatancy), so
the pair's Newton coordinates converge on their own, and this law, which
comes after its pair in the law list, reads the pair's N(theta) of the
same evaluation (``PenaltyContact.normal_force``).

Energy (docs/shear.md): the law takes w = f . y from the bodies; of it the
dissipation D goes to /energy/friction, the change of the spring's energy
k_t e^2 / 2 to /energy/contact, and the wall's work c_wall (F_1 v_w^1 +
F_2 v_w^2) is external: w = D + dE - W_wall.
"""

import numpy as np

from vstpetsc.line.laws.base import Law
from vstpetsc.kernels.coulomb import friction_integrals
from vstpetsc.kernels.stiffness import STICK_BETA, default_penalty

SERIES = ("shear_force", "slip", "shear_stretch")
# slabs whose wall velocities one call of the wall's history gives (a call
# per slab cost more than the compiled slab's friction)
WALL_CHUNK = 512


class CoulombFriction(Law):
    """Friction of pair ``index`` (``pair``: its normal law)."""

    energy_key = "friction"
    energy_keys = ("friction", "wall", "contact")      # work_terms' keys
    series = SERIES

    def __init__(self, spec, index, case, mesh, pair):
        nodes, signs, twins = [], [], mesh.twins
        if spec.left is not None:
            nodes.append(mesh.right_node(twins[spec.left]))
            signs.append(1.0)
        if spec.right is not None:
            nodes.append(mesh.left_node(twins[spec.right]))
            signs.append(-1.0)
        self.nodes, self.signs = np.array(nodes), np.array(signs)
        self.pair, self.index, self.group = pair, index, f"contact/{index}"
        self.mu, self.dt = spec.friction, case.dt
        self.wall = spec.wall_shear_velocity
        # the wall as a node of the pair: +1 on the left of the gap, -1 on the right
        self.wall_sign = 1.0 if spec.left is None else -1.0 if spec.right is None else 0.0
        # the default normal penalty's rule with G for E (docs/shear.md)
        self.stiffness = default_penalty(
            "power", [mesh.body_stiffness(twins[b]) for b in (spec.left, spec.right)
                      if b is not None], case.dt, STICK_BETA)
        self.stretch = self.slip = self.mean_force = 0.0
        self.wall_v = (0.0, 0.0)
        self.wall_times = []    # slab start times of the wall velocities at hand ...
        self.wall_ends = ([], [])   # ... and the velocities at those slabs' two ends
        self.wall_next = 0      # where the next slab's start time is looked for
        self.last = None        # the FrictionSlab of the last force()

    def start_slab(self, u, dt):
        """Nothing: the stretch carries the spring's state across slabs."""

    def start_time(self, t0):
        """The wall's velocities at the slab's ends t0 and t0 + dt (from
        those of the slabs ahead, evaluated at once)."""
        if self.wall is None:
            return
        i = self.wall_next
        if i >= len(self.wall_times) or self.wall_times[i] != t0:
            i = self._wall_ahead(t0)
        self.wall_v = (self.wall_ends[0][i], self.wall_ends[1][i])
        self.wall_next = i + 1

    def _wall_ahead(self, t0):
        """The wall's velocities of WALL_CHUNK slabs from t0, the k-th at
        t0 = k dt and t0 + dt as the driver and this law compute them
        (elementwise the same operations as one slab's: the same values);
        a t0 off that grid alone.  Returns t0's index."""
        k = round(t0 / self.dt)
        times = np.arange(k, k + WALL_CHUNK) * self.dt
        if times[0] != t0:
            times = np.array([t0])
        self.wall_times = times.tolist()
        self.wall_ends = (np.asarray(self.wall(times), dtype=float).tolist(),
                          np.asarray(self.wall(times + self.dt), dtype=float).tolist())
        return 0

    def acts(self, y1, y2):
        """Never on its own: it acts only where its pair does, and then
        Newton runs for every law."""
        return False

    def force(self, y1, y2):
        normal = self.pair.normal_force()
        if normal is None:
            self.last = None
            return None
        coefficients, pieces = normal
        c, (v1, v2) = self.wall_sign, self.wall_v
        slab = friction_integrals(self.stretch, -(y1 + c * v1), -(y2 + c * v2), self.dt,
                                  self.stiffness, self.mu, coefficients, pieces)
        self.last = slab
        return (slab.f1, slab.f2, -slab.d11, -slab.d12, -slab.d21, -slab.d22)

    def work_terms(self, work):
        """((energy key, value), ...) of the slab's work f . y."""
        if self.last is None:
            return (("contact", work),)
        slab = self.last
        c, (v1, v2) = self.wall_sign, self.wall_v
        wall = c * (slab.f1 * v1 + slab.f2 * v2)
        # a start stretch beyond the limit (the seed's slab-mean N jumps
        # between slabs) releases its excess: dissipated, not stored
        dissipated = slab.dissipation + slab.released
        return (("friction", dissipated), ("wall", wall),
                ("contact", work - dissipated + wall))

    def finish_slab(self, t0, dt):
        if self.last is None:
            self.stretch = self.mean_force = 0.0
            return
        slab = self.last
        self.stretch = slab.stretch
        self.slip += slab.slip
        self.mean_force = (slab.f1 + slab.f2) / dt

    def values(self, u):
        return {"shear_force": self.mean_force, "slip": self.slip,
                "shear_stretch": self.stretch}

    def restore(self, values):
        self.stretch = float(values["shear_stretch"])
        self.slip = float(values["slip"])
        self.mean_force = float(values["shear_force"])

    def stored_energy(self, u):
        return 0.5 * self.stiffness * self.stretch ** 2

    def attrs(self):
        return {"friction": self.mu, "shear_stiffness": self.stiffness}

    def final_attrs(self):
        return {"permanent_slip": self.slip}

    def describe(self):
        wall = "" if self.wall is None or self.wall.is_zero else ", the wall shakes"
        return (f"friction[{self.index}]: Coulomb mu = {self.mu:g}, tangential stiffness "
                f"{self.stiffness:.6g}{wall}")


def build(spec, index, case, mesh, pair):
    return CoulombFriction(spec, index, case, mesh, pair)
