"""What the package promises beyond the mesh: a memmap far larger than the
memory it may use extracts in bounded memory, the GIL is released while it
works, `threads` does not change the output, and Ctrl-C stops an extraction
within half a second with KeyboardInterrupt and nothing written."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import tmc
from conftest import _one_sigint_latency, sigint_latency, sphere


def run_python(code: str, timeout: float = 600) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def test_a_4_gib_memmap_extracts_in_bounded_memory(tmp_path):
    """A 4 GiB uint8 memmap (2048 x 2048 x 1024, a ball in the middle): the
    extraction's peak resident memory (VmHWM, which counts mapped file
    pages too) stays far below the file's size."""
    path = tmp_path / "big.u8"
    shape = (1024, 2048, 2048)
    volume = np.memmap(path, dtype=np.uint8, mode="w+", shape=shape)
    z, y, x = np.ogrid[448:576, 960:1088, 960:1088]
    volume[448:576, 960:1088, 960:1088] = (
        ((z - 512.0) ** 2 + (y - 1024.0) ** 2 + (x - 1024.0) ** 2) < 60.0**2
    ) * 200
    volume.flush()
    del volume
    assert path.stat().st_size == 4 << 30
    done = run_python(
        f"""
        import numpy as np, resource, tmc
        volume = np.memmap({str(path)!r}, dtype=np.uint8, mode="r", shape={shape!r})
        mesh = tmc.extract(volume, 100.0)
        peak = int(open("/proc/self/status").read().split("VmHWM:")[1].split()[0]) * 1024
        print(len(mesh.triangles), peak)
        """
    )
    assert done.returncode == 0, done.stderr
    triangles, peak = map(int, done.stdout.split())
    assert triangles > 10_000
    print(f"4 GiB memmap: {triangles} triangles, peak resident {peak / 2**20:.0f} MiB")
    assert peak < 1 << 30, f"peak resident memory {peak / 2**20:.0f} MiB"


def test_strided_planes_are_not_copied(tmp_path):
    """A view whose planes are not contiguous (every other sample of a
    memmap along x) is read a band of rows at a time, not gathered into
    whole planes of float64: the extraction's anonymous memory grows by
    far less than two planes of 6144^2 float64 (576 MiB) from planes of
    2048^2 to planes of 6144^2."""
    grown = []
    for n in (2048, 6144):
        path = tmp_path / f"wide{n}.u16"
        shape = (6, n, 2 * n)
        volume = np.memmap(path, dtype=np.uint16, mode="w+", shape=shape)
        c = n // 2
        z, y, x = np.ogrid[0:6, c - 24 : c + 24, 2 * c - 48 : 2 * c + 48 : 2]
        ball = ((z - 3.0) ** 2 + (y - c) ** 2 + (x / 2.0 - c) ** 2) < 20.0**2
        volume[:, c - 24 : c + 24, 2 * c - 48 : 2 * c + 48 : 2] = ball * 2000
        volume.flush()
        del volume
        done = run_python(
            f"""
            import threading, time
            import numpy as np, tmc
            wide = np.memmap({str(path)!r}, dtype=np.uint16, mode="r", shape={shape!r})
            view = wide[:, :, ::2]
            def anon():
                status = open("/proc/self/status").read()
                return int(status.split("RssAnon:")[1].split()[0]) * 1024
            peak, done = [0], [False]
            def sample():
                while not done[0]:
                    peak[0] = max(peak[0], anon())
                    time.sleep(0.002)
            base = anon()
            sampler = threading.Thread(target=sample)
            sampler.start()
            mesh = tmc.extract(view, 1000.0, threads=2)
            done[0] = True
            sampler.join()
            print(len(mesh.triangles), peak[0] - base)
            """
        )
        assert done.returncode == 0, done.stderr
        triangles, growth = map(int, done.stdout.split())
        assert triangles > 1000
        grown.append(growth)
        path.unlink()
    print(f"anonymous memory grown: {grown[0] / 2**20:.1f} MiB at 2048^2, "
          f"{grown[1] / 2**20:.1f} MiB at 6144^2")
    assert grown[1] - grown[0] < 96 << 20, f"{(grown[1] - grown[0]) / 2**20:.1f} MiB more"


def test_threads_do_not_change_the_mesh():
    volume = sphere(shape=(60, 61, 62), radius=25.0)
    one = tmc.extract(volume, 0.0, threads=1)
    two = tmc.extract(volume, 0.0, threads=2)
    np.testing.assert_array_equal(one.vertices, two.vertices)
    np.testing.assert_array_equal(one.triangles, two.triangles)


def test_the_gil_is_released_while_extracting():
    """Python code in another thread keeps running during an extraction
    (with the GIL held it could not run at all until the call returned)."""
    rng = np.random.default_rng(0)
    volume = rng.random((200, 200, 200), dtype=np.float32)
    ticks = []
    finished = threading.Event()

    def count():
        while not finished.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    time.sleep(0.05)
    start = time.perf_counter()
    tmc.extract(volume, 0.5, threads=1)
    end = time.perf_counter()
    finished.set()
    counter.join()
    during = [t for t in ticks if start < t < end]
    assert end - start > 0.2, "the extraction was too short to tell"
    # With the GIL held, no tick could fall inside the call.
    assert len(during) > 10, (len(during), end - start)


def test_two_threads_extract_at_once_and_agree():
    volume = sphere(shape=(80, 81, 82), radius=35.0)
    expected = tmc.extract(volume, 0.0, threads=1)
    results = [None, None]

    def work(i):
        results[i] = tmc.extract(volume, 0.0, threads=1)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for mesh in results:
        np.testing.assert_array_equal(mesh.triangles, expected.triangles)


@pytest.mark.parametrize("call", ["extract", "extract_to"])
def test_ctrl_c_stops_within_half_a_second(tmp_path, call):
    out = tmp_path / "out.ply"
    target = f"tmc.extract_to(volume, 0.5, {str(out)!r})" if call == "extract_to" else "tmc.extract(volume, 0.5)"
    setup = """
        import numpy as np, tmc
        volume = np.random.default_rng(1).random((400, 400, 400), dtype=np.float32)
        """
    latency = sigint_latency(setup, target, 1.0)
    print(f"{call}: KeyboardInterrupt {latency * 1000:.0f} ms after SIGINT")
    assert latency < 0.5
    assert list(tmp_path.iterdir()) == []


def test_ctrl_c_stops_within_a_huge_plane():
    """Ctrl-C stops an extraction whose planes are huge: a broadcast array
    of 10^5 x 10^5 x 10^5 samples (no memory: every stride is 0), each
    plane 10^10 samples, which `Plane::load` classifies in bands, asking
    between them whether the run was interrupted (before, it classified the
    whole plane first: minutes). The child is killed if it is still
    running 8 s after SIGINT."""
    setup = """
        import numpy as np, tmc
        volume = np.broadcast_to(np.float32(1), (10**5,) * 3)
        """
    latency = _one_sigint_latency(setup, "tmc.extract(volume, 9)", 1.0, timeout=8)
    print(f"KeyboardInterrupt {latency * 1000:.0f} ms after SIGINT")
    assert latency < 2, "still running 2 s after SIGINT"
