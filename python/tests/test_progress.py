"""``progress=`` of extract, extract_to, extract_labels and
extract_labels_to: called on the calling thread as ``progress(done,
total)`` in cell layers, never decreasing, ending at ``(total, total)``
with ``total`` the volume's cell layers; an exception it raises stops the
run with nothing written; anything but a callable is a ``TypeError``."""

import threading

import numpy as np
import pytest

import tmc
from conftest import REPO

HEAD = REPO / "data" / "headsq_quarter.nrrd"


def recorder():
    calls = []
    caller = threading.get_ident()

    def progress(done, total):
        assert threading.get_ident() == caller
        calls.append((done, total))

    return calls, progress


def check(calls, layers):
    assert calls, "never called"
    assert all(total == layers for _, total in calls), calls
    dones = [done for done, _ in calls]
    assert dones == sorted(dones) and len(set(calls)) == len(calls), calls
    assert calls[-1] == (layers, layers)


def test_every_call_reports_cell_layers_and_ends_at_the_total(tmp_path):
    nz = int(tmc.info(HEAD)["dims"][2])
    calls, progress = recorder()
    tmc.extract(HEAD, 500, progress=progress)
    check(calls, nz - 1)
    calls, progress = recorder()
    tmc.extract_to(HEAD, 500, tmp_path / "m.tmesh", progress=progress, threads=1)
    check(calls, nz - 1)
    seg = (np.arange(30 * 20 * 10).reshape(30, 20, 10) // 1500).astype(np.uint8)
    calls, progress = recorder()
    meshes = tmc.extract_labels(seg, progress=progress)
    assert meshes
    check(calls, 29)
    calls, progress = recorder()
    tmc.extract_labels_to(seg, tmp_path / "{label}.ply", progress=progress)
    check(calls, 29)


def test_a_progress_that_raises_stops_the_run_and_writes_nothing(tmp_path):
    rng = np.random.default_rng(5)
    noise = rng.standard_normal((200, 160, 160)).astype(np.float32)
    calls = []

    def stop(done, total):
        calls.append(done)
        raise RuntimeError("stopped by the progress callback")

    output = tmp_path / "noise.tmesh"
    with pytest.raises(RuntimeError, match="stopped by the progress callback"):
        tmc.extract_to(noise, 0.0, output, progress=stop, threads=1)
    assert len(calls) == 1 and calls[0] < 199, calls
    assert list(tmp_path.iterdir()) == []


def test_progress_must_be_callable():
    for bad in (1, "bar", [print]):
        with pytest.raises(TypeError, match="progress"):
            tmc.extract(np.zeros((3, 3, 3)), 0.5, progress=bad)
