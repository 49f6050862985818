"""`tmc extract --at AXIS=I`: one volume of an OME-Zarr image of several
channels and time points, or of an HDF5 dataset of several volumes, read
in place. Each pick must give the mesh of that entry's samples as a numpy
array (zarr-python and h5py write the files; the expected mesh comes from
tmc's in-memory path on the numpy slice, which shares no reader with the
Zarr and HDF5 ones)."""

import numpy as np
import pytest

import tmc
from conftest import read_ply, tmc_binary

import subprocess


def volumes(shape):
    """A stack of different volumes: a noisy ball whose centre and radius
    change with the leading indices."""
    rng = np.random.default_rng(7)
    z, y, x = np.mgrid[0:13, 0:17, 0:19]
    out = np.empty(shape + z.shape, np.int16)
    for k, index in enumerate(np.ndindex(*shape)):
        r = np.sqrt((x - 9.1 - k % 3) ** 2 + (y - 8.4) ** 2 + (z - 6.2 + k % 2) ** 2)
        out[index] = 1000 - (50 + 7 * k) * r + rng.integers(0, 30, r.shape)
    return out


def cli(*args):
    return subprocess.run([tmc_binary(), *args], capture_output=True, text=True)


def same_as_slice(path, at, samples, tmp_path):
    out = tmp_path / f"at_{at.replace(',', '_').replace('=', '')}.ply"
    done = cli("extract", str(path), "--iso", "500.5", "--at", at, "-o", str(out), "-q")
    assert done.returncode == 0, done.stderr
    vertices, triangles = read_ply(out)
    want = tmc.extract(np.ascontiguousarray(samples), 500.5)
    assert len(want.triangles) > 0
    np.testing.assert_array_equal(triangles, want.triangles)
    np.testing.assert_array_equal(vertices, want.vertices.astype(np.float32))


def test_ome_zarr_channels_and_times_are_picked(tmp_path):
    zarr = pytest.importorskip("zarr", minversion="3")
    data = volumes((2, 3))
    path = tmp_path / "image.zarr"
    g = zarr.open_group(str(path), mode="w", zarr_format=2)
    # Two channels a chunk: the third channel's chunk is a partial one,
    # and channel 1 starts inside its chunk.
    a = g.create_array("0", shape=data.shape, dtype=data.dtype, chunks=(1, 2, 5, 17, 8))
    a[...] = data
    axes = [{"name": "t", "type": "time"}, {"name": "c", "type": "channel"}] + [
        {"name": n, "type": "space"} for n in "zyx"]
    g.attrs["multiscales"] = [{"version": "0.4", "axes": axes, "datasets": [
        {"path": "0", "coordinateTransformations": [{"type": "scale", "scale": [1.0] * 5}]}]}]
    for t in range(2):
        for c in range(3):
            same_as_slice(path, f"c={c},t={t}", data[t, c], tmp_path)
    # By position, as for any array.
    same_as_slice(path, "0=1,1=2", data[1, 2], tmp_path)
    # Without a pick: one line saying how to give it, no output.
    out = tmp_path / "none.ply"
    done = cli("extract", str(path), "--iso", "500.5", "-o", str(out))
    assert done.returncode != 0
    assert "pick one with --at t=I (I from 0 to 1)" in done.stderr, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert not out.exists()
    done = cli("extract", str(path), "--iso", "500.5", "--at", "c=3,t=0", "-o", str(out))
    assert done.returncode != 0 and "axis 'c' has 3 entries (0 to 2)" in done.stderr
    assert not out.exists()


def test_hdf5_volumes_are_picked_by_position(tmp_path):
    h5py = pytest.importorskip("h5py")
    data = volumes((3,))
    path = tmp_path / "stack.h5"
    with h5py.File(path, "w") as f:
        f.create_dataset("scans", data=data, chunks=(2, 5, 7, 8), compression="gzip")
    for k in range(3):
        same_as_slice(f"{path}:/scans", f"0={k}", data[k], tmp_path)
    done = cli("extract", f"{path}:/scans", "--iso", "500.5", "-o", str(tmp_path / "x.ply"))
    assert done.returncode != 0 and "pick one with --at 0=I (I from 0 to 2)" in done.stderr


def test_the_python_functions_take_at(tmp_path):
    zarr = pytest.importorskip("zarr", minversion="3")
    data = volumes((2, 3))
    path = tmp_path / "plain.zarr"
    a = zarr.create_array(store=str(path), shape=data.shape, dtype=data.dtype,
                          chunks=(1, 2, 5, 17, 8))
    a[...] = data
    for at in ({0: 1, 1: 2}, {"0": 1, "1": 2}):
        got = tmc.extract(str(path), 500.5, at=at)
        want = tmc.extract(np.ascontiguousarray(data[1, 2]), 500.5)
        np.testing.assert_array_equal(got.triangles, want.triangles)
        np.testing.assert_array_equal(got.vertices, want.vertices)
    report = tmc.extract_to(str(path), 500.5, tmp_path / "x.tmesh", at={0: 0, 1: 1})
    assert report["triangles"] == len(tmc.extract(np.ascontiguousarray(data[0, 1]), 500.5).triangles)
    info = tmc.info(str(path), at={0: 1, 1: 0})
    assert info["max"] == float(data[1, 0].max())
    labels = (data[1, 1] > 700).astype(np.uint8) + (data[1, 1] > 900)
    lpath = tmp_path / "labels.zarr"
    la = zarr.create_array(store=str(lpath), shape=(2,) + labels.shape, dtype=np.uint8,
                           chunks=(1,) + labels.shape)
    la[1] = labels
    by_at = tmc.extract_labels(str(lpath), at={0: 1})
    want = tmc.extract_labels(labels)
    assert sorted(by_at) == sorted(want) == [1, 2]
    for k in want:
        np.testing.assert_array_equal(by_at[k].triangles, want[k].triangles)
    out = tmc.extract_labels_to(str(lpath), tmp_path / "{label}.ply", at={0: 1})
    assert len(out["labels"]) == 2
    with pytest.raises(ValueError, match="pick one with --at 0=I"):
        tmc.extract(str(path), 500.5)
    with pytest.raises(ValueError, match="not of an array"):
        tmc.extract(data[0, 0], 500.5, at={0: 0})
    with pytest.raises(TypeError, match="mapping"):
        tmc.extract(str(path), 500.5, at=[("0", 1)])
    with pytest.raises(TypeError):
        tmc.extract(str(path), 500.5, at={0: 1.5, 1: 0})
    with pytest.raises(ValueError, match="0 or more"):
        tmc.extract(str(path), 500.5, at={0: -1, 1: 0})


@pytest.mark.parametrize("zarr_format", [2, 3])
def test_a_zarr_channel_axis_last_is_picked(tmp_path, zarr_format):
    """A plain Zarr array of (z, y, x, c), channels interleaved, two of the
    three a chunk (channel 2's chunk a partial one), and its (z, y, x, 1)
    sibling: `--at 3=C` reads channel C, the sibling reads without a pick,
    and without one the error says how to pick the last axis."""
    zarr = pytest.importorskip("zarr", minversion="3")
    data = np.moveaxis(volumes((3,)), 0, -1)
    path = tmp_path / f"zyxc_v{zarr_format}.zarr"
    a = zarr.create_array(str(path), shape=data.shape, dtype=data.dtype, chunks=(5, 6, 8, 2),
                          zarr_format=zarr_format)
    a[...] = data
    for c in range(3):
        same_as_slice(path, f"3={c}", data[..., c], tmp_path)
    one = tmp_path / f"zyx1_v{zarr_format}.zarr"
    b = zarr.create_array(str(one), shape=data.shape[:3] + (1,), dtype=data.dtype,
                          chunks=(4, 17, 19, 1), zarr_format=zarr_format)
    b[...] = data[..., 1:2]
    got = tmc.extract(str(one), 500.5)
    want = tmc.extract(np.ascontiguousarray(data[..., 1]), 500.5)
    np.testing.assert_array_equal(got.triangles, want.triangles)
    np.testing.assert_array_equal(got.vertices, want.vertices)
    done = cli("extract", str(path), "--iso", "500.5", "-o", str(tmp_path / "x.ply"))
    assert done.returncode != 0 and "--at 3=I" in done.stderr, done.stderr
    assert not (tmp_path / "x.ply").exists()
