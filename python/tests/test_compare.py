"""``tmc.compare`` gives the figures of ``tmc compare --json`` (the CLI
run on the same file) but the times, for a file and for an array; its
topology is the checker's of ``extract``'s meshes; ``topology_memory``
leaves it out and says so; bad ``runs`` raise."""

import json

import numpy as np
import pytest

import tmc
from conftest import REPO, run_cli

HEAD = REPO / "data" / "headsq_quarter.nrrd"
TIMES = ("seconds", "median_seconds", "min_seconds", "max_seconds")


def without_times(report):
    """The report without what changes from run to run."""
    out = {k: v for k, v in report.items()
           if k not in ("ratio", "peak_rss_anon_bytes", "input", "runs")}
    for side in ("tmc", "mc"):
        out[side] = {k: v for k, v in report[side].items() if k not in TIMES}
    return out


def test_the_figures_are_the_clis(tmp_path):
    rng = np.random.default_rng(3)
    noise = rng.integers(0, 5, (14, 15, 16)).astype(np.uint8)
    np.save(tmp_path / "noise.npy", noise)
    for volume, path, iso in ((HEAD, HEAD, 500), (noise, tmp_path / "noise.npy", 2)):
        ours = tmc.compare(volume, iso, runs=3)
        cli = json.loads(run_cli("compare", str(path), "--iso", str(iso), "--runs", "3",
                                 "--json", "-q").stdout)
        assert without_times(ours) == without_times(cli)
        assert ours["input"] == (None if isinstance(volume, np.ndarray) else str(HEAD))
        for side in ("tmc", "mc"):
            assert len(ours[side]["seconds"]) == 3
            assert ours[side]["min_seconds"] <= ours[side]["median_seconds"]
        r = ours["ratio"]
        assert r["low"] <= r["median"] <= r["high"]
    # Noise has cells where TMC and MC differ, and the counts are the
    # meshes' own.
    assert ours["differing_cells"]["cells"] > 0
    for method in ("tmc", "mc"):
        mesh = tmc.extract(noise, 2, method=method)
        assert ours[method]["triangles"] == len(mesh.triangles)
        checked = mesh.check()
        assert ours[method]["components"] == checked["components"]
        assert ours[method]["euler"] == checked["euler"]


def test_topology_beyond_its_memory_is_left_out_and_said():
    report = tmc.compare(HEAD, 500, runs=1, topology_memory=1000)
    assert report["tmc"]["components"] is None and report["mc"]["genus"] is None
    assert "left out" in report["topology_note"]
    assert tmc.compare(HEAD, 500, runs=1)["topology_note"] is None


def test_bad_arguments_raise():
    with pytest.raises(ValueError, match="runs"):
        tmc.compare(HEAD, 500, runs=0)
    with pytest.raises(TypeError, match="runs"):
        tmc.compare(HEAD, 500, runs=1.5)
    with pytest.raises(ValueError, match="topology_memory"):
        tmc.compare(HEAD, 500, topology_memory=-1)
    with pytest.raises(ValueError, match="inside"):
        tmc.compare(HEAD, 500, inside="middle")
