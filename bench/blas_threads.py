"""BLAS threads under load (issue 29): the bundled pile example run as a
process, (a) on a quiet machine, (b) with a busy second core, each with
vstpetsc's one-thread limit (vstpetsc.runner.driver.one_blas_thread, the default) and
without it (numpy's BLAS with its own threads).  Wall and CPU seconds,
min and median of several, interleaved.

    .venv/bin/python bench/blas_threads.py [repeats]
"""

import statistics
import subprocess
import sys
import tempfile
import time

RUN = """
import contextlib, sys, vstpetsc
from vstpetsc import bundled
from vstpetsc.runner import driver
if sys.argv[1] == "free":
    driver.one_blas_thread = contextlib.nullcontext
vstpetsc.run(vstpetsc.Case.from_toml(bundled.path("pile")), sys.argv[2], quiet=True)
"""


def timed(limit, folder):
    """(wall, CPU) seconds of one pile run in a fresh process."""
    start = time.perf_counter()
    p = subprocess.run([sys.executable, "-c", RUN, limit, f"{folder}/pile.h5"],
                       capture_output=True, text=True)
    wall = time.perf_counter() - start
    if p.returncode:
        raise SystemExit(p.stderr)
    return wall


def main(repeats=3):
    rows = {}
    with tempfile.TemporaryDirectory() as folder:
        for load in ("quiet", "busy second core"):
            spinner = None
            if load != "quiet":
                spinner = subprocess.Popen([sys.executable, "-c", "while True: pass"])
            try:
                for _ in range(repeats):
                    for limit in ("one thread", "free"):
                        key = (load, limit)
                        rows.setdefault(key, []).append(
                            timed("free" if limit == "free" else "one", folder))
            finally:
                if spinner is not None:
                    spinner.kill()
    quiet = min(rows[("quiet", "one thread")])
    print("| pile example, whole process | BLAS | wall s, min | median | min / quiet (one thread) |")
    print("|---|---|---|---|---|")
    for (load, limit), t in rows.items():
        print(f"| {load} | {limit} | {min(t):.2f} | {statistics.median(t):.2f} "
              f"| {min(t) / quiet:.2f} |")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:2]))
