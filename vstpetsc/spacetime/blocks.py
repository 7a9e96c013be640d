"""Per-slab arrays evaluated for a block of slabs at a time: a history's
exact slab integrals cost one numpy call for a thousand slabs as for one."""

BLOCK = 1024          # slabs evaluated at a time


class Blocks:
    """Per-slab arrays evaluated BLOCK slabs at a time by ``evaluate(k0,
    k1)`` (slabs k0+1 .. k1): :meth:`at` gives the block holding slab k and
    k's row in it."""

    def __init__(self, evaluate):
        self.evaluate = evaluate
        self.block = (0, 0, None)          # (first slab - 1, last slab, arrays)

    def at(self, k):
        k0, k1, arrays = self.block
        if not k0 < k <= k1:
            k0, k1 = k - 1, k - 1 + BLOCK
            arrays = self.evaluate(k0, k1)
            self.block = (k0, k1, arrays)
        return arrays, k - k0 - 1
