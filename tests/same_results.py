"""Every bundled example and the demo run by one checkout, and their result
files compared dataset by dataset with another checkout's: a move of
modules (issue 45) must leave every number bit for bit as it was.

    python tests/same_results.py run OUT          # this checkout's package: OUT/<example>.h5
    python tests/same_results.py compare A B      # every dataset and attribute of A/*.h5 and B/*.h5

Run the first with PYTHONPATH naming the other checkout to make its files.
Bit equality is what both are built to give: the same arithmetic in the
same order, on the same machine.  The wall time and the version are not
compared (they change from run to run), nor the folder the case was read
from (each checkout's own)."""

import io
import os
import sys

import h5py
import numpy as np

SKIPPED = ("solver/wall_time",)
SKIPPED_ATTRS = ("wall_time", "setup_time", "version", "case_folder")


def run_all(out):
    """Every bundled example (and the demo, bar-wall) into ``out``."""
    import vstpetsc
    from vstpetsc import bundled

    os.makedirs(out, exist_ok=True)
    for name in bundled.names():
        case = vstpetsc.Case.from_toml(bundled.path(name))
        vstpetsc.run(case, output=os.path.join(out, name + ".h5"), quiet=True, out=io.StringIO())
        print(name, flush=True)


def contents(path):
    """({dataset: array}, {object: {attribute: value}}) of a result file."""
    data, attrs = {}, {}

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset) and name not in SKIPPED:
            data[name] = obj[()]
        attrs[name] = {k: v for k, v in obj.attrs.items() if k not in SKIPPED_ATTRS}

    with h5py.File(path, "r") as f:
        f.visititems(visit)
        attrs["/"] = {k: v for k, v in f.attrs.items() if k not in SKIPPED_ATTRS}
    return data, attrs


def same(a, b):
    """The same bits (nan included)."""
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype.kind == "O" or b.dtype.kind == "O":
        return a.shape == b.shape and all(x == y for x, y in zip(a.ravel(), b.ravel()))
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def differences(first, second):
    """Lines naming every dataset or attribute that differs."""
    (da, aa), (db, ab) = contents(first), contents(second)
    out = [f"dataset {k}: only in one" for k in sorted(set(da) ^ set(db))]
    out += [f"dataset {k} differs" for k in sorted(set(da) & set(db)) if not same(da[k], db[k])]
    for obj in sorted(set(aa) | set(ab)):
        x, y = aa.get(obj, {}), ab.get(obj, {})
        out += [f"attribute {obj}:{k} differs" for k in sorted(set(x) | set(y))
                if k not in x or k not in y or not same(x[k], y[k])]
    return out


def compare(a, b):
    names = sorted(f for f in os.listdir(a) if f.endswith(".h5"))
    missing = sorted(set(names) ^ {f for f in os.listdir(b) if f.endswith(".h5")})
    bad = [f"{m}: in one folder only" for m in missing]
    for name in names:
        if name not in missing:
            bad += [f"{name}: {line}" for line in differences(os.path.join(a, name),
                                                              os.path.join(b, name))]
    print("\n".join(bad) if bad else f"{len(names)} result files the same bit for bit")
    return 1 if bad else 0


if __name__ == "__main__":
    if sys.argv[1:2] == ["run"] and len(sys.argv) == 3:
        run_all(sys.argv[2])
    elif sys.argv[1:2] == ["compare"] and len(sys.argv) == 4:
        sys.exit(compare(sys.argv[2], sys.argv[3]))
    else:
        sys.exit(__doc__)
