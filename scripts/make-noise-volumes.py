#!/usr/bin/env python3
"""Writes the noise volumes of docs/performance-log.md (needs numpy).

Usage: scripts/make-noise-volumes.py DIR

* uniform64.npy: 64^3 f64, uniform in [-1, 1] (seed 7); surface at 0;
* smooth64.npy: the same after one 3x3x3 box filter (edges repeated);
* uniform_f32.npy: 96x128x128 float32, uniform in [0, 1] (seed 11);
  isovalues 0.5 and 0.1.

Nearly every cell of the uniform volumes is ambiguous, so they show what
the kernel costs; the fixed seeds make them the same on every machine.
"""
import sys
from pathlib import Path

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    uniform = np.random.default_rng(7).uniform(-1, 1, (64, 64, 64))
    np.save(out / "uniform64.npy", uniform)
    padded = np.pad(uniform, 1, mode="edge")
    smooth = sliding_window_view(padded, (3, 3, 3)).mean(axis=(-1, -2, -3))
    np.save(out / "smooth64.npy", smooth)
    f32 = np.random.default_rng(11).uniform(0, 1, (96, 128, 128)).astype(np.float32)
    np.save(out / "uniform_f32.npy", f32)


if __name__ == "__main__":
    main()
