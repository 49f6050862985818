"""tmc.marching_cubes against the Rust library's extraction of the same
array, side by side in one process (issue 27's "within 1.2x"): medians of 7
interleaved runs at 1 and 2 threads of the library without and with normals
(examples/time_extract --serve on the same .npy), tmc.extract without and
with normals, and tmc.marching_cubes (normals and values too).

Usage: python scripts/bench_marching_cubes.py NAME ISO [SHARED] [TIME_EXTRACT]
  NAME: a volume of ../shared/data (NAME.nrrd), converted to float32 .npy
  in target/bench-marching-cubes/; needs numpy, pynrrd and the tmc package.
"""
import json
import os
import subprocess
import sys
import time

import nrrd
import numpy as np
import tmc

name, iso = sys.argv[1], float(sys.argv[2])
shared = sys.argv[3] if len(sys.argv) > 3 else "../shared/data"
te = sys.argv[4] if len(sys.argv) > 4 else "target/release/examples/time_extract"
cache = "target/bench-marching-cubes"
os.makedirs(cache, exist_ok=True)
vol, _ = nrrd.read(f"{shared}/{name}.nrrd", index_order="C")
vol = np.ascontiguousarray(vol.astype(np.float32))
npy = f"{cache}/{name}.npy"
np.save(npy, vol)
srv = {
    n: subprocess.Popen([te, npy, "--iso", repr(iso), "--serve"] + (["--normals"] if n else []),
                        stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    for n in (0, 1)
}
for p in srv.values():
    p.stdout.readline()  # {"ready": ...}


def ask(n, t):
    p = srv[n]
    p.stdin.write(f"tmc {t}\n")
    p.stdin.flush()
    return json.loads(p.stdout.readline())["seconds"]


def py(f):
    s = time.perf_counter()
    f()
    return time.perf_counter() - s


res = {}
for rep in range(8):  # the first is a warm-up
    for t in (1, 2):
        for k, f in [("rust", lambda: ask(0, t)), ("rust+n", lambda: ask(1, t)),
                     ("py.extract", lambda: py(lambda: tmc.extract(vol, iso, threads=t))),
                     ("py.extract+n", lambda: py(lambda: tmc.extract(vol, iso, threads=t, normals=True))),
                     ("py.mc", lambda: py(lambda: tmc.marching_cubes(vol, iso, threads=t)))]:
            v = f()
            if rep:
                res.setdefault((k, t), []).append(v)
for t in (1, 2):
    m = {k: np.median(res[(k, t)]) for k in ["rust", "rust+n", "py.extract", "py.extract+n", "py.mc"]}
    print(f"{name}@{iso:g} {t}T " + " ".join(f"{k}={v * 1e3:.1f}ms" for k, v in m.items())
          + f" py.extract/rust={m['py.extract'] / m['rust']:.2f} py.mc/rust+n={m['py.mc'] / m['rust+n']:.2f}")
for p in srv.values():
    p.stdin.close()
    p.wait()
