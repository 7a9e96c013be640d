"""A rigid block on a horizontal Coulomb base shaken horizontally and
vertically (Newmark 1965's sliding block with a vertical acceleration):
the independent estimate the gravity-dam example is compared with.

The base accelerates a_h(t), a_v(t) (y up) under gravity g.  Pressed by
N = m (g + a_v) >= 0 (no tension: while g + a_v < 0 the block is taken as
free, N = 0, no friction), the block sticks while |a_h| <= mu (g + a_v)
and otherwise slides with the relative acceleration
-a_h - sign(s') mu (g + a_v), until its relative velocity s' returns to
zero.  Returned: the relative displacement s(t) of the block with
respect to the base (what vstpetsc's interface slip measures).  Explicit
steps on a fine grid with the sticking test done exactly at each step
(the relative velocity is clamped to 0 when friction would reverse it);
first order, converged by refining (tests check two step sizes)."""

import numpy as np


def rigid_block_slip(t, a_h, a_v, mu, g, step=1e-5):
    """s(t) at the times ``t`` for base accelerations sampled at ``t``
    (linear in between)."""
    grid = np.arange(t[0], t[-1] + step / 2, step)
    ah, av = np.interp(grid, t, a_h), np.interp(grid, t, a_v)
    s, v = np.zeros(grid.size), 0.0
    for k in range(grid.size - 1):
        press = max(g + av[k], 0.0)
        limit = mu * press
        if v == 0.0 and abs(ah[k]) <= limit:
            s[k + 1] = s[k]
            continue
        direction = np.sign(v) if v != 0.0 else -np.sign(ah[k])
        accel = -ah[k] - direction * limit
        new = v + accel * step
        if v != 0.0 and np.sign(new) != np.sign(v):      # friction stops it in the step
            new = 0.0
        s[k + 1] = s[k] + 0.5 * (v + new) * step
        v = new
    return np.interp(t, grid, s)
