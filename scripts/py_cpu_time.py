"""CPU time per call of tmc.marching_cubes or tmc.extract at one thread.

Usage: python scripts/py_cpu_time.py VOLUME.npy ISO {mc,ext} CALLS

Loads the .npy (as scikit-image would get it), makes one untimed call, then
CALLS timed ones, and prints the median CPU time (time.process_time, every
thread of the process) and the median wall time, in milliseconds. CPU time
is what to compare on a machine busy with other work, where wall clock is
not (docs/performance.md, "In-process from Python").
"""

import statistics
import sys
import time

import numpy as np

import tmc


def main() -> None:
    path, iso, what, calls = sys.argv[1], float(sys.argv[2]), sys.argv[3], int(sys.argv[4])
    vol = np.load(path)

    def call() -> None:
        if what == "mc":
            tmc.marching_cubes(vol, iso, threads=1)
        elif what == "ext":
            tmc.extract(vol, iso, threads=1)
        else:
            raise SystemExit(f"unknown {what!r} (expected mc or ext)")

    call()
    cpu, wall = [], []
    for _ in range(calls):
        c, w = time.process_time(), time.perf_counter()
        call()
        wall.append(time.perf_counter() - w)
        cpu.append(time.process_time() - c)
    print(f"{statistics.median(cpu) * 1000:.1f} {statistics.median(wall) * 1000:.1f}")


if __name__ == "__main__":
    main()
