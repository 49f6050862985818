#!/usr/bin/env python3
"""Writes a large chunked zstd Zarr v3 array of a synthetic CT-like head,
layer of chunks by layer of chunks (never the whole volume in memory), for
the larger-than-memory test of issue 29: by default 2048 x 2048 x 4096 u16
samples (32 GiB uncompressed), chunks of 8 x 512 x 512 (z, y, x; a layer
of chunks is 64 MiB, and tmc holds a few layers per worker). The
samples are smooth shells plus a little noise, so the chunks compress to a
small fraction (check the size with `du` before and `df` first).

    python3 -m pip install 'zarr>=3' numpy
    python3 scripts/make-big-zarr.py OUT.zarr [NX NY NZ] [--nrrd RAW.nrrd]
    tmc info OUT.zarr
    tmc extract OUT.zarr --iso 1300 -o head.tmesh --threads 2 --json
    # --json reports peak_rss_anon_bytes; the chunk layers held are a few
    # per worker (docs/formats.md). Each stored chunk file is opened once
    # per pass: count them with strace -f -e trace=openat.

With `--nrrd RAW.nrrd` the same samples are also written as a raw NRRD (for
timing the Zarr against the volume memory-mapped raw: scripts/bench-big-volume
takes either).
"""
import sys

import numpy as np
import zarr
from zarr.codecs import ZstdCodec


def layer(z0, depth, nx, ny, nz, rng, rxy):
    """Samples of planes z0 .. z0 + depth: nested ellipsoidal shells (tested
    on the squared radius, `rxy` holding its x and y part), plus noise."""
    z = np.arange(z0, z0 + depth, dtype=np.float32)
    rz = ((z - nz / 2) / (0.48 * nz)) ** 2
    r2 = rxy[None, :, :] + rz[:, None, None]
    v = rng.integers(0, 8, r2.shape, dtype=np.uint16)
    v += np.where(r2 < 1.0, np.uint16(1000), np.uint16(0))
    v += np.where(r2 < 0.93 ** 2, np.uint16(600), np.uint16(0))
    v -= np.where(r2 < 0.85 ** 2, np.uint16(500), np.uint16(0))
    return v


def main():
    args = sys.argv[1:]
    raw = None
    if "--nrrd" in args:
        at = args.index("--nrrd")
        raw = args[at + 1]
        del args[at:at + 2]
    out = args[0]
    nx, ny, nz = (int(a) for a in args[1:4]) if len(args) > 3 else (2048, 2048, 4096)
    chunks = (8, 512, 512)
    a = zarr.create_array(store=out, shape=(nz, ny, nx), dtype=np.uint16,
                          chunks=chunks, compressors=ZstdCodec(level=3))
    rng = np.random.default_rng(29)
    y, x = np.mgrid[0:ny, 0:nx].astype(np.float32)
    rxy = ((x - nx / 2) / (0.42 * nx)) ** 2 + ((y - ny / 2) / (0.45 * ny)) ** 2
    nrrd = None
    if raw is not None:
        nrrd = open(raw, "wb")
        nrrd.write((f"NRRD0004\ntype: uint16\ndimension: 3\nsizes: {nx} {ny} {nz}\n"
                    "encoding: raw\nendian: little\n\n").encode())
    for z0 in range(0, nz, chunks[0]):
        depth = min(chunks[0], nz - z0)
        samples = layer(z0, depth, nx, ny, nz, rng, rxy)
        a[z0:z0 + depth] = samples
        if nrrd is not None:
            nrrd.write(samples.astype("<u2").tobytes())
        print(f"\r{z0 + depth}/{nz} planes", end="", file=sys.stderr)
    print(file=sys.stderr)
    if nrrd is not None:
        nrrd.close()


if __name__ == "__main__":
    main()
