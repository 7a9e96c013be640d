"""The default stiffnesses of a contact pair and of its stick spring,
from the stiffnesses of what meets at the pair: one rule for both
geometries (a 1-D pair between bar ends, a 2-D interface's pairs per unit
length)."""

# the default penalty as a multiple of the bodies' largest E A / h (in
# series for "power", the stiffer one's for "seed"; default_penalty): soft
# for "power" (the force then follows the arriving wave; docs/accuracy.md),
# the seed's old value for "seed" (its results kept bit for bit)
DEFAULT_BETA = {"power": 0.5, "seed": 50.0}

# the tangential stiffness k_t = STICK_BETA times the shear stiffnesses G A / h of
# the pair's end elements in series (the normal penalty's rule with G for
# E, default_penalty).  Stiff, unlike the normal default (0.5): the
# force is capped at mu N, so a stiff stick spring cannot overshoot as an
# impact does, and its compliance mu N / k_t is elastic slip that delays
# every stop.  A flexible column on a Coulomb base, 16 / 32 / 64 elements,
# final slip against tests/references/coulomb_column.py on the same mesh: 3.6 / 2.0 /
# 1.0 % off at 0.5, 0.20 / 0.065 / 0.013 % at 32; 256 gains little more
# and costs twice the time (docs/shear.md)
STICK_BETA = 32.0


def default_penalty(formulation, stiffnesses, dt, beta=None):
    """Penalty used when the case gives none, from the largest E A / h of
    each body at the pair (one for a wall pair).

    "power": k = beta K with K the bodies' stiffnesses in series (a wall
    is rigid): the spring then loads the impedance it sees, the bodies' in
    series, with the same rise time Z / k whether it meets a wall or another
    body (two equal bars: K = E A / 2h, the peak force as on a wall;
    docs/accuracy.md).  "seed": eps = 2 k / dt with k = beta times the
    stiffer body's K, the seed's penalty with that slab-mean force per unit
    penetration (its residual weight I_a carries one more power of time, so
    eps has units of force / (length time)).  formulation.md section 4 once
    suggested ``beta (E A / h) / dt^2``, which is not dimensionally
    consistent (the contact stiffness would change with the unit of time),
    so 1/dt.
    """
    beta = DEFAULT_BETA[formulation] if beta is None else beta
    if formulation == "power":
        return beta / sum(1.0 / k for k in stiffnesses)
    return 2.0 * beta * max(stiffnesses) / dt
