#!/usr/bin/env python3
"""Make a realistic segmentation label map from a CT for the --labels benchmark.

The CT (a raw, uncompressed NRRD such as cthead.nrrd) is resampled
trilinearly to SIZE^3 samples, its intensity split into tissue classes by
thresholds (below the first is background, label 0), and the volume into a
coarse grid of BLOCKS^3 blocks; each (class, block) pair present is one
label, numbered from 1. The labels touch each other and the volume border
and have the irregular shapes of real tissue, as in an organ atlas.

    make-label-map.py CT.nrrd OUT.nrrd [--size 512] [--blocks 5]
                      [--thresholds 400,1100,1800]

Writes a raw uint16 NRRD (SIZE^3 x 2 bytes) and prints the number of
labels. Needs: python3 -m pip install numpy
"""

import argparse
import sys

import numpy as np

TYPES = {"uint8": "u1", "uint16": "u2", "int16": "i2", "float": "f4", "short": "i2"}


def read_nrrd(path):
    """The samples of a raw NRRD as a (z, y, x) array."""
    with open(path, "rb") as f:
        header = {}
        while True:
            line = f.readline()
            if line in (b"\n", b"\r\n", b""):
                break
            text = line.decode("ascii", "replace").strip()
            if ":" in text and not text.startswith("#"):
                key, value = text.split(":", 1)
                header[key.strip()] = value.strip()
        if header.get("encoding") != "raw":
            sys.exit(f"{path}: only raw NRRD is read here")
        sizes = [int(s) for s in header["sizes"].split()]
        kind = TYPES[header["type"]]
        endian = "<" if header.get("endian", "little") == "little" else ">"
        data = np.frombuffer(f.read(), dtype=endian + kind, count=int(np.prod(sizes)))
    return data.reshape(sizes[::-1]).astype(np.float32)


def resample_axis(a, axis, n):
    """Linear interpolation of `a` to `n` samples along `axis` (ends kept)."""
    m = a.shape[axis]
    t = np.linspace(0, m - 1, n, dtype=np.float64)
    i = np.minimum(t.astype(int), m - 2)
    w = (t - i).astype(np.float32)
    shape = [1] * a.ndim
    shape[axis] = n
    w = w.reshape(shape)
    return np.take(a, i, axis=axis) * (1 - w) + np.take(a, i + 1, axis=axis) * w


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("ct")
    p.add_argument("out")
    p.add_argument("--size", type=int, default=512)
    p.add_argument("--blocks", type=int, default=5)
    p.add_argument("--thresholds", default="400,1100,1800")
    args = p.parse_args()
    thresholds = np.array([float(t) for t in args.thresholds.split(",")], dtype=np.float32)
    ct = read_nrrd(args.ct)
    n, b = args.size, args.blocks
    # x and y first (small), then z one output plane at a time.
    xy = resample_axis(resample_axis(ct, 2, n), 1, n)
    block = (np.arange(n) * b // n).astype(np.int64)
    by, bx = np.meshgrid(block, block, indexing="ij")
    # The (class, block) key of a sample is at most `keys - 1`: small enough
    # for a presence table and a lookup table, so that neither a sort of all
    # the samples (np.unique) nor an int64 copy of the volume is needed.
    keys = len(thresholds) * b * b * b + 1
    if keys > 65536:
        sys.exit("too many classes and blocks for uint16 labels")
    t = np.linspace(0, xy.shape[0] - 1, n)
    classes = np.empty((n, n, n), dtype=np.uint16)
    present = np.zeros(keys, dtype=bool)
    for z in range(n):
        i = min(int(t[z]), xy.shape[0] - 2)
        w = np.float32(t[z] - i)
        plane = xy[i] * (1 - w) + xy[i + 1] * w
        c = np.searchsorted(thresholds, plane, side="right")  # 0 = background
        key = ((c - 1) * b + block[z]) * b * b + by * b + bx + 1
        classes[z] = np.where(c > 0, key, 0)
        present |= np.bincount(classes[z].ravel(), minlength=keys) > 0
    # Consecutive labels 1..L in the order of the keys (0 stays background).
    present[0] = True
    lookup = (np.cumsum(present) - 1).astype(np.uint16)
    labels = lookup[classes]
    count = int(present.sum()) - 1
    with open(args.out, "wb") as f:
        f.write(
            (
                "NRRD0004\ntype: uint16\ndimension: 3\n"
                f"sizes: {n} {n} {n}\nspacing: 1 1 1\nendian: little\nencoding: raw\n\n"
            ).encode()
        )
        f.write(labels.astype("<u2", copy=False).tobytes())
    print(count)


if __name__ == "__main__":
    main()
