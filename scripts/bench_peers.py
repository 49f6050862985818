"""Side-by-side timing of tmc and its peers on the same volumes.

Run by scripts/bench-peers inside its virtual environment (.venv-bench: vtk,
scikit-image, PyMCubes, pynrrd from PyPI); see that script for the set-up.

Every tool starts from the same float32 samples already in memory and leaves
its mesh in memory, so the figures compare the extraction itself:

* tmc 1T / 2T, mc 1T / 2T: tmc::extract with --method tmc or mc and 1 or 2
  threads, timed inside the example `time_extract` (which holds the volume as
  float32, like the peers), driven over a pipe; tmc+n 1T / 2T: the same with
  vertex normals (`time_extract --normals`), the library's part of
  tmc.marching_cubes;
* pass 1T / 2T: no extraction, one pass over the same samples (their maximum),
  the memory-bandwidth floor a sparse surface is compared with;
* FE 1T / 2T: VTK vtkFlyingEdges3D (normals, gradients and scalars off), with
  the STDThread SMP backend initialised to 1 or 2 threads (the PyPI wheel's
  default backend is Sequential, i.e. one thread);
* MC33: the MC33 C library (Vega et al. 2019), create_MC33 +
  calculate_isosurface, timed in the C driver bench_peers_mc33.c (MC33 always
  computes vertex normals too);
* skimage: skimage.measure.marching_cubes, method 'lewiner' (also computes
  normals and values);
* PyMCubes: mcubes.marching_cubes.

Triangle counts agree up to the ambiguous cells, except MC33's on integer
volumes at an integer isovalue (cthead, bonsai, engine): samples equal to the
isovalue are handled differently there (tmc counts them as outside; MC33's
count at 80 on engine matches neither 79.5 nor 80.5).

Separately, "cmd 1T / 2T" is the wall clock of the whole command
`tmc extract VOL --iso V -o OUT.ply --threads N` (read the .npy, extract, write
binary PLY).

Runs are interleaved to spread the machine's noise over all tools: one
untimed warm-up round, then `for run in range(N): for tool in tools`. The
table gives medians; results.json also has every run, the best run and the
triangle counts.
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np


# (name, how to make it, isovalue). "lib" volumes are tmc::synth::gyroid(n,
# periods) and tmc::synth::noise(n, seed, smoothing passes) written by the
# example bench_volume (4.5 periods give the issue's ~2.9M triangles at 258^3;
# the noise is the one of benches/tmc_vs_mc.rs); "synth" volumes come from
# `tmc synth`; "nrrd" ones from ../shared/data (skipped when absent).
FULL_VOLUMES = [
    ("gyroid 258^3", ("lib", "gyroid", 258, "4.5"), 0.0),
    ("noise 258^3", ("lib", "noise", 258, "7", "1"), 0.0),
    ("sphere 512^3", ("synth", "sphere", 512, "f32"), 0.0),
    ("head phantom 512^3", ("synth", "head", 512, "f32"), 500.0),
    ("cthead", ("nrrd", "cthead.nrrd"), 550.0),
    ("cthead", ("nrrd", "cthead.nrrd"), 1600.0),
    ("bonsai", ("nrrd", "bonsai.nrrd"), 40.0),
    ("engine", ("nrrd", "engine.nrrd"), 80.0),
]

QUICK_VOLUMES = [
    ("gyroid 64^3", ("lib", "gyroid", 64, "4.5"), 0.0),
    ("noise 64^3", ("lib", "noise", 64, "7", "1"), 0.0),
    ("sphere 64^3", ("synth", "sphere", 64, "f32"), 0.0),
    ("head phantom 64^3", ("synth", "head", 64, "f32"), 500.0),
    ("engine", ("nrrd", "engine.nrrd"), 80.0),
]


def log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def volume_file(spec, args) -> Path | None:
    """The float32 .npy of a volume in the cache, written on first use."""
    vols = args.cache / "volumes"
    vols.mkdir(parents=True, exist_ok=True)
    if spec[0] == "lib":
        _, kind, n, *params = spec
        path = vols / f"lib_{kind}_{n}_{'_'.join(params)}_f32.npy"
        if not path.exists():
            log(f"writing {path}")
            subprocess.run([str(args.bench_volume), kind, str(n), *params, str(path)],
                           check=True)
        return path
    if spec[0] == "synth":
        _, kind, n, dtype = spec
        path = vols / f"{kind}_{n}_{dtype}.npy"
        if not path.exists():
            log(f"writing {path}")
            subprocess.run(
                [str(args.tmc), "synth", kind, "--dims", f"{n},{n},{n}", "--dtype", dtype,
                 "-o", str(path), "--quiet"],
                check=True,
            )
        return path
    _, name = spec
    src = args.shared / name
    path = vols / (Path(name).stem + "_f32.npy")
    if path.exists():
        return path
    if not src.exists():
        log(f"skipping {name}: {src} not found")
        return None
    import nrrd  # pynrrd

    log(f"converting {src} to {path} (float32, unit spacing)")
    data, _ = nrrd.read(str(src), index_order="C")  # shape (z, y, x)
    tmp = path.with_suffix(".tmp.npy")
    np.save(tmp, np.ascontiguousarray(data, dtype=np.float32))
    os.replace(tmp, path)
    return path


class Server:
    """A timing process that loads the volume once and answers one request
    line with one JSON line (time_extract --serve, bench_peers_mc33)."""

    def __init__(self, argv: list[str]):
        self.proc = subprocess.Popen(
            argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1
        )
        ready = self._read()
        if not ready.get("ready"):
            raise RuntimeError(f"{argv[0]} did not start: {ready}")

    def _read(self) -> dict:
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError(f"timing process exited with {self.proc.wait()}")
        return json.loads(line)

    def ask(self, request: str) -> tuple[float, int]:
        self.proc.stdin.write(request + "\n")
        self.proc.stdin.flush()
        answer = self._read()
        return answer["seconds"], answer["triangles"]

    def close(self) -> None:
        self.proc.stdin.close()
        self.proc.wait()


def make_tools(vol: np.ndarray, path: Path, iso: float, args) -> tuple[dict, list]:
    """name -> callable returning (seconds, triangles); and things to close."""
    tools: dict = {}
    closers: list = []

    tmc_server = Server([str(args.time_extract), str(path), "--iso", repr(iso), "--serve"])
    closers.append(tmc_server.close)
    for method in ("tmc", "mc", "pass"):
        for threads in (1, 2):
            tools[f"{method} {threads}T"] = (
                lambda m=method, t=threads: tmc_server.ask(f"{m} {t}")
            )
    # The same extraction with vertex normals: the library's share of
    # tmc.marching_cubes, which returns normals.
    normals_server = Server([str(args.time_extract), str(path), "--iso", repr(iso), "--serve",
                             "--normals"])
    closers.append(normals_server.close)
    for threads in (1, 2):
        tools[f"tmc+n {threads}T"] = lambda t=threads: normals_server.ask(f"tmc {t}")

    try:
        from vtkmodules.util.numpy_support import numpy_to_vtk
        from vtkmodules.vtkCommonCore import vtkSMPTools
        from vtkmodules.vtkCommonDataModel import vtkImageData
        from vtkmodules.vtkFiltersCore import vtkFlyingEdges3D

        vtkSMPTools.SetBackend("STDThread")
        nz, ny, nx = vol.shape
        image = vtkImageData()
        image.SetDimensions(nx, ny, nz)
        flat = vol.reshape(-1)  # a view: numpy_to_vtk shares it
        scalars = numpy_to_vtk(flat, deep=False)
        image.GetPointData().SetScalars(scalars)
        fe = vtkFlyingEdges3D()
        fe.SetInputData(image)
        fe.SetValue(0, iso)
        fe.ComputeNormalsOff()
        fe.ComputeGradientsOff()
        fe.ComputeScalarsOff()

        def flying_edges(threads: int, fe=fe, keep=(flat, scalars, image)):
            vtkSMPTools.Initialize(threads)
            fe.Modified()
            start = time.perf_counter()
            fe.Update()
            seconds = time.perf_counter() - start
            return seconds, fe.GetOutput().GetNumberOfCells()

        tools["FE 1T"] = lambda: flying_edges(1)
        tools["FE 2T"] = lambda: flying_edges(2)
    except ImportError as e:
        log(f"skipping VTK: {e}")

    if args.mc33:
        mc33 = Server([str(args.mc33), str(path), repr(iso)])
        closers.append(mc33.close)
        tools["MC33"] = lambda: mc33.ask("run")

    try:
        import tmc as tmc_py  # the Python package (python/), in-process

        def tmc_marching_cubes(threads: int):
            start = time.perf_counter()
            _, faces, _, _ = tmc_py.marching_cubes(vol, iso, threads=threads)
            return time.perf_counter() - start, len(faces)

        def tmc_extract(threads: int):
            start = time.perf_counter()
            mesh = tmc_py.extract(vol, iso, threads=threads)
            return time.perf_counter() - start, len(mesh.triangles)

        for threads in (1, 2):
            tools[f"py.mc {threads}T"] = lambda t=threads: tmc_marching_cubes(t)
            tools[f"py.extract {threads}T"] = lambda t=threads: tmc_extract(t)
    except ImportError as e:
        log(f"skipping the tmc Python package: {e}")

    try:
        from skimage import measure

        def skimage_mc():
            start = time.perf_counter()
            _, faces, _, _ = measure.marching_cubes(vol, level=iso, method="lewiner")
            return time.perf_counter() - start, len(faces)

        tools["skimage"] = skimage_mc
    except ImportError as e:
        log(f"skipping scikit-image: {e}")

    try:
        import mcubes

        def pymcubes():
            start = time.perf_counter()
            _, triangles = mcubes.marching_cubes(vol, iso)
            return time.perf_counter() - start, len(triangles)

        tools["PyMCubes"] = pymcubes
    except ImportError as e:
        log(f"skipping PyMCubes: {e}")

    out = args.cache / "out.ply"
    for threads in (1, 2):
        def command(t=threads):
            argv = [str(args.tmc), "extract", str(path), "--iso", repr(iso), "-o", str(out),
                    "--threads", str(t), "--quiet"]
            start = time.perf_counter()
            subprocess.run(argv, check=True)
            return time.perf_counter() - start, None

        tools[f"cmd {threads}T"] = command
    return tools, closers


def bench_volume(name: str, path: Path, iso: float, args) -> dict:
    vol = np.load(path)
    log(f"{name} @ {iso}: {'x'.join(map(str, vol.shape[::-1]))} {vol.dtype}, {args.runs} runs")
    tools, closers = make_tools(vol, path, iso, args)
    times = {t: [] for t in tools}
    triangles = {}
    try:
        for run in range(args.runs + 1):  # run 0 is the untimed warm-up
            for tool, fn in tools.items():
                gc.collect()
                seconds, tris = fn()
                if run > 0:
                    times[tool].append(seconds)
                if tris is not None:
                    triangles[tool] = int(tris)
    finally:
        for close in closers:
            close()
    return {
        "volume": name,
        "file": str(path),
        "iso": iso,
        "dims": list(vol.shape[::-1]),
        "runs": times,
        "median": {t: statistics.median(v) for t, v in times.items()},
        "best": {t: min(v) for t, v in times.items()},
        "triangles": triangles,
    }


def fmt_s(x) -> str:
    return "—" if x is None else f"{x:.3f}"


def fmt_ratio(a, b) -> str:
    return "—" if a is None or b is None else f"{a / b:.2f}"


def tables(results: list[dict], args) -> str:
    out = []
    out.append(
        f"Median seconds of {args.runs} interleaved runs, extraction only (volume in memory, "
        "mesh left in memory); 'cmd' = whole `tmc extract ... -o out.ply` (read, extract, "
        "write PLY). Ratios are tmc / peer (below 1: tmc faster)."
    )
    out.append("")
    cols = ["tmc 1T", "tmc 2T", "FE 1T", "FE 2T", "MC33", "skimage", "PyMCubes",
            "cmd 1T", "cmd 2T"]
    ratios = [("tmc 1T", "FE 1T"), ("tmc 2T", "FE 2T"), ("tmc 1T", "MC33"),
              ("tmc 1T", "skimage"), ("tmc 1T", "PyMCubes")]
    head = ["volume", "iso", "triangles (tmc)"] + cols + [
        f"{a.replace(' ', '')}/{b.replace(' ', '')}" for a, b in ratios
    ]
    out.append("| " + " | ".join(head) + " |")
    out.append("|" + "---|" * len(head))
    for r in results:
        m = r["median"]
        row = [r["volume"], f"{r['iso']:g}", f"{r['triangles'].get('tmc 1T', 0):,}"]
        row += [fmt_s(m.get(c)) for c in cols]
        row += [fmt_ratio(m.get(a), m.get(b)) for a, b in ratios]
        out.append("| " + " | ".join(row) + " |")
    out.append("")
    out.append("Triangles per tool (the same surface should give similar counts):")
    out.append("")
    tcols = ["tmc 1T", "mc 1T", "FE 1T", "MC33", "skimage", "PyMCubes"]
    out.append("| volume | iso | " + " | ".join(tcols) + " |")
    out.append("|" + "---|" * (len(tcols) + 2))
    for r in results:
        t = r["triangles"]
        out.append(f"| {r['volume']} | {r['iso']:g} | "
                   + " | ".join(f"{t[c]:,}" if c in t else "—" for c in tcols) + " |")
    out.append("")
    out.append("The bandwidth floor: 'pass' = one pass over the samples in memory (their "
               "maximum, time_extract --method pass), same threads; tmc / pass:")
    out.append("")
    out.append("| volume | pass 1T | pass 2T | tmc/pass 1T | tmc/pass 2T |")
    out.append("|---|---|---|---|---|")
    for r in results:
        m = r["median"]
        out.append(f"| {r['volume']} | {fmt_s(m.get('pass 1T'))} | {fmt_s(m.get('pass 2T'))} | "
                   f"{fmt_ratio(m.get('tmc 1T'), m.get('pass 1T'))} | "
                   f"{fmt_ratio(m.get('tmc 2T'), m.get('pass 2T'))} |")
    out.append("")
    out.append("In-process from Python, on the same numpy arrays: `tmc.extract` (the mesh "
               "only: the work of 'tmc' above) and `tmc.marching_cubes` (scikit-image's "
               "return values: also normals and values); median seconds, and ratios: "
               "extract / the Rust library's extraction (the binding's cost; target at "
               "most 1.2), marching_cubes / the library's extraction with normals "
               "('tmc+n', the same work) and without, scikit-image / marching_cubes "
               "(target at least 5), and the peers / marching_cubes at 1 thread:")
    out.append("")
    out.append("| volume | tmc+n 1T | tmc+n 2T | py.extract 1T | py.extract 2T | py.mc 1T "
               "| py.mc 2T | py.extract/tmc 1T | py.extract/tmc 2T | py.mc/tmc+n 1T "
               "| py.mc/tmc+n 2T | py.mc/tmc 1T "
               "| skimage/py.mc 1T | skimage/py.mc 2T | FE 1T/py.mc 1T | PyMCubes/py.mc 1T |")
    out.append("|" + "---|" * 16)
    for r in results:
        m = r["median"]
        out.append(
            f"| {r['volume']} | {fmt_s(m.get('tmc+n 1T'))} | {fmt_s(m.get('tmc+n 2T'))} | "
            f"{fmt_s(m.get('py.extract 1T'))} | "
            f"{fmt_s(m.get('py.extract 2T'))} | {fmt_s(m.get('py.mc 1T'))} | "
            f"{fmt_s(m.get('py.mc 2T'))} | "
            f"{fmt_ratio(m.get('py.extract 1T'), m.get('tmc 1T'))} | "
            f"{fmt_ratio(m.get('py.extract 2T'), m.get('tmc 2T'))} | "
            f"{fmt_ratio(m.get('py.mc 1T'), m.get('tmc+n 1T'))} | "
            f"{fmt_ratio(m.get('py.mc 2T'), m.get('tmc+n 2T'))} | "
            f"{fmt_ratio(m.get('py.mc 1T'), m.get('tmc 1T'))} | "
            f"{fmt_ratio(m.get('skimage'), m.get('py.mc 1T'))} | "
            f"{fmt_ratio(m.get('skimage'), m.get('py.mc 2T'))} | "
            f"{fmt_ratio(m.get('FE 1T'), m.get('py.mc 1T'))} | "
            f"{fmt_ratio(m.get('PyMCubes'), m.get('py.mc 1T'))} |"
        )
    out.append("")
    out.append("TMC against standard MC (tmc --method mc), same code path, median seconds:")
    out.append("")
    out.append("| volume | iso | tmc 1T | mc 1T | tmc/mc 1T | tmc 2T | mc 2T | tmc/mc 2T "
               "| triangles tmc | triangles mc |")
    out.append("|" + "---|" * 10)
    for r in results:
        m, t = r["median"], r["triangles"]
        out.append(
            f"| {r['volume']} | {r['iso']:g} | {fmt_s(m.get('tmc 1T'))} | "
            f"{fmt_s(m.get('mc 1T'))} | {fmt_ratio(m.get('tmc 1T'), m.get('mc 1T'))} | "
            f"{fmt_s(m.get('tmc 2T'))} | {fmt_s(m.get('mc 2T'))} | "
            f"{fmt_ratio(m.get('tmc 2T'), m.get('mc 2T'))} | "
            f"{t.get('tmc 1T', 0):,} | {t.get('mc 1T', 0):,} |"
        )
    return "\n".join(out)


def versions() -> dict:
    found = {"python": sys.version.split()[0], "numpy": np.__version__}
    for module, attr in (("vtk", "__version__"), ("skimage", "__version__"),
                         ("mcubes", "__version__")):
        try:
            found[module] = getattr(__import__(module), attr, "?")
        except ImportError:
            pass
    return found


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--runs", type=int, default=5)
    p.add_argument("--quick", action="store_true", help="small volumes, a smoke test")
    p.add_argument("--tmc", type=Path, required=True, help="the tmc binary")
    p.add_argument("--time-extract", type=Path, required=True, help="examples/time_extract")
    p.add_argument("--bench-volume", type=Path, required=True, help="examples/bench_volume")
    p.add_argument("--mc33", type=Path, help="the MC33 timing driver (skipped if absent)")
    p.add_argument("--cache", type=Path, required=True, help="volumes and results go here")
    p.add_argument("--shared", type=Path, required=True, help="../shared/data")
    p.add_argument("--only", help="run only volumes whose name contains this")
    args = p.parse_args()
    if args.runs < 1:
        p.error("--runs must be at least 1")

    results = []
    for name, spec, iso in QUICK_VOLUMES if args.quick else FULL_VOLUMES:
        if args.only and args.only not in name:
            continue
        path = volume_file(spec, args)
        if path is None:
            continue
        results.append(bench_volume(name, path, iso, args))

    report = tables(results, args)
    print(report)
    args.cache.mkdir(parents=True, exist_ok=True)
    out = args.cache / ("results-quick.json" if args.quick else "results.json")
    out.write_text(json.dumps({
        "runs": args.runs,
        "quick": args.quick,
        "cpus": os.cpu_count(),
        "versions": versions(),
        "mc33": str(args.mc33) if args.mc33 else None,
        "results": results,
    }, indent=1))
    log(f"wrote {out}")


if __name__ == "__main__":
    main()
