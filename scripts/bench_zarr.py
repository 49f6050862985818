"""The driver of scripts/bench-zarr (see there): writes the Zarr copies,
runs time_extract on each store of each volume in turn (interleaved, so a
busy machine slows all alike), and prints medians and Zarr / raw ratios."""

import argparse
import json
import statistics
import subprocess
from pathlib import Path

import nrrd
import numpy as np
import zarr
from zarr.codecs import BloscCodec, BloscShuffle, ZstdCodec

# (name, NRRD in ../shared/data or None for the phantom, isovalue)
VOLUMES = [
    ("cthead", "cthead.nrrd", 1600.0),
    ("bonsai", "bonsai.nrrd", 40.0),
    ("lidc_chest_ct", "lidc_chest_ct.nrrd", 114.0),
    ("head phantom 256^3 u16", None, 1500.0),
]

CODECS = {
    "zstd 0": lambda: ZstdCodec(level=0),
    "zstd 3": lambda: ZstdCodec(level=3),
    "blosc zstd shuffle": lambda: BloscCodec(cname="zstd", clevel=5, shuffle=BloscShuffle.shuffle),
}


def raw_volume(args, name, source):
    """The volume's raw NRRD (memory-mapped by tmc) and its samples."""
    if source is None:
        path = args.cache / "head256.nrrd"
        if not path.exists():
            subprocess.run([str(args.release / "tmc"), "synth", "head", "--dims", "256,256,256",
                            "--dtype", "u16", "-o", str(path)], check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    else:
        path = args.shared / source
        if not path.exists():
            return None, None
    samples, header = nrrd.read(str(path), index_order="C")
    if header.get("encoding", "raw") != "raw":
        raise SystemExit(f"{path}: not a raw NRRD")
    return path, np.ascontiguousarray(samples)


def zarr_copy(args, name, codec, samples):
    """The Zarr v3 copy of `samples` with `codec`, written once."""
    path = args.cache / f"{name.split()[0]}-{codec.replace(' ', '-')}.zarr"
    if not (path / "zarr.json").exists():
        array = zarr.create_array(str(path), shape=samples.shape, dtype=samples.dtype,
                                  chunks=args.chunks, compressors=CODECS[codec](),
                                  overwrite=True)
        array[:] = samples
    return path


def run(args, path, iso):
    out = subprocess.run([str(args.release / "examples" / "time_extract"), str(path), "--iso",
                          repr(iso), "--threads", str(args.threads), "--opened", "--runs", "1"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])["seconds"]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--release", type=Path, required=True)
    p.add_argument("--cache", type=Path, required=True)
    p.add_argument("--shared", type=Path, required=True)
    p.add_argument("--runs", type=int, default=7)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--chunks", default="16,128,128")
    args = p.parse_args()
    args.chunks = tuple(int(c) for c in args.chunks.split(","))
    args.cache.mkdir(parents=True, exist_ok=True)
    print(f"time_extract --opened --threads {args.threads}, medians of {args.runs} interleaved "
          f"runs; Zarr v3 written by zarr-python {zarr.__version__}, chunks {args.chunks} (z,y,x); "
          f"ratio = Zarr / raw NRRD (memory-mapped)\n")
    print("| volume | raw NRRD s | " + " | ".join(f"{c} s (ratio, MB on disk)" for c in CODECS) + " |")
    print("|---" * (2 + len(CODECS)) + "|")
    for name, source, iso in VOLUMES:
        raw, samples = raw_volume(args, name, source)
        if raw is None:
            print(f"| {name} | skipped: {source} not found |")
            continue
        stores = {c: zarr_copy(args, name, c, samples) for c in CODECS}
        times = {k: [] for k in ["raw", *CODECS]}
        for k, path in [("raw", raw), *stores.items()]:
            run(args, path, iso)  # warm-up: page cache and allocator
        for _ in range(args.runs):
            for k, path in [("raw", raw), *stores.items()]:
                times[k].append(run(args, path, iso))
        base = statistics.median(times["raw"])
        cells = []
        for c in CODECS:
            m = statistics.median(times[c])
            size = sum(f.stat().st_size for f in stores[c].rglob("*") if f.is_file()) / 1e6
            cells.append(f"{m:.3f} ({m / base:.2f}x, {size:.1f})")
        print(f"| {name} ({samples.dtype}, {samples.nbytes / 1e6:.0f} MB) @ {iso:g} | {base:.3f} | "
              + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
