"""`array=`, `level=` and `dataset=`: the package's names for the CLI's
`--array`, `--level` and `--dataset`, in every function that reads a path
(extract, extract_to, extract_labels, extract_labels_to, info). Each must
read what the path forms (`STORE/ARRAY`, `FILE:/DATASET`) read, and that
must be the mesh of the same samples given as a numpy array (zarr-python
and h5py write the files; tmc's in-memory path shares no reader with the
Zarr and HDF5 ones)."""

import numpy as np
import pytest

import tmc

ISO = 50.0


def ball():
    z, y, x = np.mgrid[0:20, 0:22, 0:24]
    r = np.sqrt((x - 11.3) ** 2 + (y - 10.2) ** 2 + (z - 9.7) ** 2)
    return (100 - 8 * r).astype(np.float32)


def same_mesh(got, want):
    assert len(want.triangles) > 0
    np.testing.assert_array_equal(got.triangles, want.triangles)
    np.testing.assert_array_equal(got.vertices, want.vertices)


def test_a_zarr_array_in_a_group_is_named_by_array(tmp_path):
    zarr = pytest.importorskip("zarr", minversion="3")
    vol = ball()
    store = tmp_path / "g.zarr"
    group = zarr.open_group(str(store), mode="w")
    a = group.create_array("seg/volume", shape=vol.shape, dtype=vol.dtype, chunks=(5, 11, 24))
    a[...] = vol
    want = tmc.extract(vol, ISO)
    same_mesh(tmc.extract(store, ISO, array="seg/volume"), want)
    same_mesh(tmc.extract(store / "seg" / "volume", ISO), want)
    # The store alone is a group: the error says how to name the array.
    with pytest.raises(ValueError, match="--array"):
        tmc.extract(store, ISO)
    with pytest.raises(ValueError, match="nope"):
        tmc.extract(store, ISO, array="nope")
    # extract_to writes what extract holds; info describes that array.
    out = tmp_path / "out.ply"
    report = tmc.extract_to(store, ISO, out, array="seg/volume")
    assert report["triangles"] == len(want.triangles)
    same_mesh(tmc.read_mesh(out), tmc.Mesh(want.vertices.astype(np.float32).astype(np.float64),
                                            want.triangles))
    info = tmc.info(store, array="seg/volume")
    assert info["dims"] == [24, 22, 20]
    # A label map in the same group, by array, as its numpy array.
    labels = np.zeros(vol.shape, np.uint8)
    labels[vol > ISO] = 3
    labels[2:6, 3:9, 4:10] = 7
    m = group.create_array("seg/labels", shape=labels.shape, dtype=labels.dtype,
                           chunks=(7, 22, 24))
    m[...] = labels
    got = tmc.extract_labels(store, array="seg/labels")
    want_labels = tmc.extract_labels(labels)
    assert sorted(got) == sorted(want_labels) == [3, 7]
    for label in got:
        same_mesh(got[label], want_labels[label])
    written = tmc.extract_labels_to(store, tmp_path / "{label}.ply", array="seg/labels")
    assert [entry["label"] for entry in written["labels"]] == [3, 7]


def test_an_ome_zarr_level_is_named_by_level(tmp_path):
    zarr = pytest.importorskip("zarr", minversion="3")
    vol = ball()
    half = np.ascontiguousarray(vol[::2, ::2, ::2])
    store = tmp_path / "image.zarr"
    group = zarr.open_group(str(store), mode="w", zarr_format=2)
    for path, data in (("0", vol), ("1", half)):
        a = group.create_array(path, shape=data.shape, dtype=data.dtype, chunks=(8, 8, 8))
        a[...] = data
    axes = [{"name": n, "type": "space", "unit": "millimeter"} for n in "zyx"]
    group.attrs["multiscales"] = [{"version": "0.4", "axes": axes, "datasets": [
        {"path": "0", "coordinateTransformations": [{"type": "scale", "scale": [0.5] * 3}]},
        {"path": "1", "coordinateTransformations": [{"type": "scale", "scale": [1.0] * 3}]},
    ]}]
    same_mesh(tmc.extract(store, ISO), tmc.extract(vol, ISO, spacing=(0.5, 0.5, 0.5)))
    want = tmc.extract(half, ISO)
    same_mesh(tmc.extract(store, ISO, level=1), want)
    same_mesh(tmc.extract(store / "1", ISO), want)
    assert tmc.info(store, level=1)["dims"] == [12, 11, 10]
    with pytest.raises(ValueError, match="2 levels"):
        tmc.extract(store, ISO, level=2)
    with pytest.raises(ValueError, match="not both"):
        tmc.extract(store, ISO, level=1, array="1")
    with pytest.raises(ValueError, match="0 or more"):
        tmc.extract(store, ISO, level=-1)
    with pytest.raises(TypeError, match="level"):
        tmc.extract(store, ISO, level=1.5)


def test_an_hdf5_dataset_is_named_by_dataset(tmp_path):
    h5py = pytest.importorskip("h5py")
    vol = ball()
    path = tmp_path / "scan.h5"
    with h5py.File(path, "w") as f:
        f.create_dataset("grp/vol", data=vol, chunks=(4, 11, 12), compression="gzip")
        f.create_dataset("other", data=vol[:10])
    want = tmc.extract(vol, ISO)
    same_mesh(tmc.extract(path, ISO, dataset="/grp/vol"), want)
    same_mesh(tmc.extract(path, ISO, dataset="grp/vol"), want)
    same_mesh(tmc.extract(f"{path}:/grp/vol", ISO), want)
    same_mesh(tmc.extract(path, ISO, dataset="other"), tmc.extract(vol[:10], ISO))
    assert tmc.info(path, dataset="other")["dims"] == [24, 22, 10]
    # Two datasets: without a name the error lists them.
    with pytest.raises(ValueError, match="/grp/vol, /other"):
        tmc.extract(path, ISO)
    with pytest.raises(ValueError, match="no dataset"):
        tmc.extract(path, ISO, dataset="nope")
    # The Zarr names on an HDF5 file, and the HDF5 name on an array, are refused.
    with pytest.raises(ValueError, match="Zarr"):
        tmc.extract(path, ISO, array="grp/vol")
    with pytest.raises(ValueError, match="not of an array"):
        tmc.extract(vol, ISO, dataset="grp/vol")
    with pytest.raises(TypeError, match="dataset"):
        tmc.extract(path, ISO, dataset=3)
