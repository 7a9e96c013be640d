"""The Python API in a dozen lines: build the bar-wall case without a case
file, sweep the impact velocity, compare the contact force with Z v0.

    python examples/api.py [FOLDER]      # result files go to FOLDER (default: a temporary one)

A steel bar thrown at a rigid wall presses on it with Z v0 (Z = rho c A) for
2L/c (formulation.md section 7).
"""

import os
import sys
import tempfile

import numpy as np

import vstpetsc

E, RHO, AREA, L = 2.0e11, 7850.0, 1.0, 1.0
Z = RHO * np.sqrt(E / RHO) * AREA


def bar_wall():
    """The bundled bar-wall case, as Python data."""
    return vstpetsc.Case.from_dict({
        "time": {"dt": 2.0e-6, "end": 1.0e-3},
        "body": [{"name": "bar", "x": [0.0, L], "elements": 100, "E": E, "rho": RHO,
                  "area": AREA, "v0": 1.0}],
        "contact": [{"pair": ["bar", "wall"], "wall": L + 1.0e-4}],
    })


def main(folder):
    case = bar_wall()
    print(f"{'v0 [m/s]':>9} {'peak force [N]':>15} {'mean force [N]':>15} {'Z v0 [N]':>12} "
          f"{'mean / Z v0':>12}")
    for v0 in (0.5, 1.0, 2.0):
        result = vstpetsc.run(case.with_value("body.bar.v0", v0),
                              output=os.path.join(folder, f"v0-{v0:g}.h5"), quiet=True)
        pair = result.contact(0)
        mean = pair.impulse_total[-1] / pair.contact_time[-1]
        print(f"{v0:9.3g} {pair.force.max():15.6g} {mean:15.6g} {Z * v0:12.6g} "
              f"{mean / (Z * v0):12.4f}")
    return 0


if __name__ == "__main__":
    if len(sys.argv) > 1:
        sys.exit(main(sys.argv[1]))
    with tempfile.TemporaryDirectory() as tmp:
        sys.exit(main(tmp))
