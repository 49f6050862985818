"""Shared helpers of the Python package's tests: the repository's paths, the
CLI binary, and mesh readers and checks written here with numpy alone, so
that nothing the tests compare with comes from the code under test."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
SHARED_DATA = REPO.parent / "shared" / "data"


def tmc_binary() -> str:
    """The `tmc` CLI: $TMC_BIN (which must exist when set), else the
    release build of this checkout; the test is skipped, saying why, when
    there is neither."""
    given = os.environ.get("TMC_BIN")
    if given:
        assert Path(given).is_file(), f"TMC_BIN={given} does not exist"
        return given
    built = REPO / "target" / "release" / "tmc"
    if built.is_file():
        return str(built)
    found = shutil.which("tmc")
    if found:
        return found
    pytest.skip("no tmc binary: run `cargo build --release` or set TMC_BIN")


def run_cli(*args: str) -> subprocess.CompletedProcess:
    """Runs the CLI and fails the test with its stderr if it fails."""
    done = subprocess.run([tmc_binary(), *args], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done


def read_ply(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and triangles of a binary little-endian PLY with float x y z
    and a uchar/int list of vertex indices (what tmc writes), parsed with
    numpy from the header's declarations."""
    data = Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    assert header[0] == "ply" and header[1] == "format binary_little_endian 1.0", header[:2]
    elements = []
    for line in header:
        words = line.split()
        if words[0] == "element":
            elements.append([words[1], int(words[2]), []])
        elif words[0] == "property":
            elements[-1][2].append(words[1:])
    types = {"float": "<f4", "double": "<f8", "uchar": "u1", "uint8": "u1", "int": "<i4",
             "uint": "<u4", "int32": "<i4", "uint32": "<u4"}
    offset = end
    vertices = triangles = None
    for name, count, props in elements:
        if name == "vertex":
            dtype = np.dtype([(p[-1], types[p[0]]) for p in props])
            table = np.frombuffer(data, dtype, count, offset)
            offset += dtype.itemsize * count
            vertices = np.stack([table["x"], table["y"], table["z"]], axis=1).astype(np.float64)
        elif name == "face":
            (kind, count_type, index_type, _), = props
            assert kind == "list"
            dtype = np.dtype([("n", types[count_type]), ("i", types[index_type], 3)])
            table = np.frombuffer(data, dtype, count, offset)
            offset += dtype.itemsize * count
            assert (table["n"] == 3).all()
            triangles = table["i"].astype(np.int64)
    assert offset == len(data), "trailing bytes after the PLY body"
    return vertices, triangles


def edge_counts(faces: np.ndarray) -> dict:
    """Oriented-manifold facts of a triangle list, from the indices alone:
    boundary edges (one triangle), non-manifold edges (three or more), and
    inconsistent edges (two triangles that run the edge the same way)."""
    faces = np.asarray(faces, dtype=np.int64)
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    undirected = np.sort(directed, axis=1)
    _, inverse, counts = np.unique(undirected, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    _, directed_counts = np.unique(directed, axis=0, return_counts=True)
    return {
        "boundary": int((counts == 1).sum()),
        "non_manifold": int((counts > 2).sum()),
        "inconsistent": int((directed_counts > 1).sum()),
    }


def is_closed_manifold(faces: np.ndarray) -> bool:
    """Every edge in exactly two triangles, run in opposite directions."""
    counts = edge_counts(faces)
    return len(faces) > 0 and counts == {"boundary": 0, "non_manifold": 0, "inconsistent": 0}


def sphere(shape=(40, 44, 48), center=(19.5, 20.2, 23.7), radius=15.0, dtype=np.float32):
    """A field that is `radius` minus the distance to `center` (index space,
    positive inside)."""
    z, y, x = np.indices(shape, dtype=np.float64)
    d = np.sqrt((z - center[0]) ** 2 + (y - center[1]) ** 2 + (x - center[2]) ** 2)
    return (radius - d).astype(dtype)


def gyroid(n=48, period=16.0):
    """The gyroid sin x cos y + sin y cos z + sin z cos x on an n^3 grid."""
    z, y, x = np.indices((n, n, n), dtype=np.float64) * (2 * np.pi / period)
    return (np.sin(x) * np.cos(y) + np.sin(y) * np.cos(z) + np.sin(z) * np.cos(x)).astype(np.float32)


def _sigint_at_default() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def sigint_latency(setup: str, call: str, wait: float, within: float = 0.5) -> float:
    """Runs the Python `setup`, then `call` (one line), in a child, sends
    it SIGINT `wait` seconds after `call` began and returns the seconds
    from the signal to the KeyboardInterrupt (the test fails if the child
    was not interrupted): the least of up to three such runs, stopping at
    the first within `within` seconds. The suite runs beside the Rust
    tests on two cores, where one run's child can wait a scheduler slice
    or two for a core; the bound is about tmc, not about that."""
    best = float("inf")
    for _ in range(3):
        best = min(best, _one_sigint_latency(setup, call, wait))
        if best < within:
            break
    return best


def _one_sigint_latency(setup: str, call: str, wait: float, timeout: float = 120) -> float:
    """One run of [`sigint_latency`]; infinity when the child is still
    running `timeout` seconds after the signal (it is killed then)."""
    code = textwrap.dedent(setup) + textwrap.dedent(
        f"""
        import time
        print("start", flush=True)
        try:
            {call}
            print("finished", flush=True)
        except KeyboardInterrupt:
            print("interrupted", time.time(), flush=True)
        """
    )
    child = subprocess.Popen(
        [sys.executable, "-c", code],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        # SIGINT at its default in the child: a Python started with it
        # ignored (a suite run in the background, nohup) keeps it ignored
        # and would never raise KeyboardInterrupt.
        preexec_fn=_sigint_at_default,
    )
    assert child.stdout.readline().strip() == "start"
    time.sleep(wait)
    sent = time.time()
    child.send_signal(signal.SIGINT)
    try:
        out_text, err = child.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        child.kill()
        child.communicate()
        return float("inf")
    words = out_text.split()
    assert words and words[0] == "interrupted", (out_text, err)
    return float(words[1]) - sent


def traced_peak(extract, volume, iso):
    """``(peak bytes Python allocated, mesh)`` of ``extract(volume, iso)``,
    measured with tracemalloc (numpy's buffers included)."""
    import tracemalloc

    tracemalloc.start()
    try:
        mesh = extract(volume, iso)
        return tracemalloc.get_traced_memory()[1], mesh
    finally:
        tracemalloc.stop()
