"""The suite as other x86-64 CPUs run it (``make test-portable``).

A test that leans on one CPU's rounding passes where it was written and
fails elsewhere.  This runs the whole suite under settings that change
every arithmetic path a CPU picks at run time, on this machine:

- numpy's SIMD dispatch narrowed (``NPY_DISABLE_CPU_FEATURES``): its
  transcendentals, sums and comparisons then run the kernels of an older
  CPU;
- OpenBLAS's kernel of an older CPU (``OPENBLAS_CORETYPE``), with fused
  multiply-adds (Haswell) or without (Prescott);
- the C kernels (vstpetsc/native) built for the baseline x86-64 and for
  this CPU's widest vectors (``VSTPETSC_NATIVE_LIB``): their vectorised
  reductions then sum in another order.

Only features this CPU has are switched off, and only kernels it can run
are asked for.  Usage: ``python tests/portable.py [pytest args ...]``;
exit status 0 when every setting passes.
"""

import os
import subprocess
import sys

import numpy.core._multiarray_umath as umath

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
NATIVE = os.path.join(ROOT, "vstpetsc", "native")
BUILD = os.path.join(ROOT, "build", "portable")
AVX512 = [f for f in umath.__cpu_dispatch__ if f.startswith("AVX512")]
AVX = AVX512 + ["AVX2", "FMA3", "F16C", "AVX"]


def has(feature):
    return bool(umath.__cpu_features__.get(feature))


def settings():
    """(name, numpy features off, OpenBLAS core, gcc -march) to run; each
    one only narrows what this CPU has."""
    out = []
    if has("AVX512F"):
        out.append(("no AVX-512, C for this CPU", AVX512, "Haswell", "native"))
    if has("AVX2") and has("FMA3"):
        out.append(("SSE only, C for the baseline", AVX, "Prescott", "x86-64"))
    else:
        out.append(("as is, C for the baseline", [], None, "x86-64"))
    return out


def build(march):
    """The C kernels built for ``-march=march``; the path of the library."""
    folder = os.path.join(BUILD, march)
    os.makedirs(folder, exist_ok=True)
    lib = os.path.join(folder, "libvstnative.so")
    sources = sorted(os.path.join(NATIVE, n) for n in os.listdir(NATIVE) if n.endswith(".c"))
    # the Makefile's flags, the target CPU aside
    subprocess.run(["gcc", "-O3", f"-march={march}", "-fopenmp-simd", "-fPIC", "-shared",
                    "-ffp-contract=off", "-Wall", "-Wextra", "-o", lib, *sources, "-lm"],
                   check=True)
    return lib


def environment(off, core, lib):
    env = dict(os.environ, VSTPETSC_NATIVE_LIB=lib)
    env["NPY_DISABLE_CPU_FEATURES"] = " ".join(f for f in off if has(f))
    if core:
        env["OPENBLAS_CORETYPE"] = core
    return env


def main(args):
    failed = []
    for name, off, core, march in settings():
        env = environment(off, core, build(march))
        print(f"== {name}: NPY_DISABLE_CPU_FEATURES={env['NPY_DISABLE_CPU_FEATURES']!r} "
              f"OPENBLAS_CORETYPE={core} -march={march}", flush=True)
        p = subprocess.run([sys.executable, "-m", "pytest", *(args or ["-q", "-n", "2",
                            "--dist", "loadgroup", "tests"])], cwd=ROOT, env=env)
        if p.returncode:
            failed.append(name)
    print("portable: " + (f"failed under {failed}" if failed else "every setting passed"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
