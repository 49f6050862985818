"""HDF5 datasets written by h5py at test time (contiguous, chunked with gzip
and shuffle, big-endian, half floats, in a group) give the mesh of the same
samples as a numpy array, and a bool dataset (an enumeration to HDF5) that
of its 0/1 mask; `element_size_um` gives the spacing; a damaged chunk and a
missing dataset raise."""

import numpy as np
import pytest

import tmc

h5py = pytest.importorskip("h5py")


def volume():
    """A noisy torus around the z axis, 19 x 24 x 29 samples (z, y, x)."""
    rng = np.random.default_rng(5)
    z, y, x = np.mgrid[0:19, 0:24, 0:29].astype(float)
    ring = np.hypot(np.hypot(x - 14.1, y - 11.6) - 7.3, z - 9.2)
    return (1100 - 150 * ring + rng.integers(0, 30, ring.shape)).astype(np.int16)


CASES = {
    "contiguous": dict(dtype="<i2", kw={}),
    "gzip_shuffle": dict(dtype="<u2", kw=dict(chunks=(5, 7, 8), compression="gzip", shuffle=True)),
    "gzip_f4_whole_planes": dict(dtype="<f4", kw=dict(chunks=(3, 24, 29), compression="gzip",
                                                      compression_opts=9, shuffle=True)),
    "gzip_big_endian_i4": dict(dtype=">i4", kw=dict(chunks=(4, 4, 4), compression="gzip")),
    # Half floats hold the torus's integers (all below 2048) exactly.
    "gzip_f2": dict(dtype="<f2", kw=dict(chunks=(5, 7, 8), compression="gzip", shuffle=True)),
    "big_endian_f2": dict(dtype=">f2", kw={}),
    "f8_latest": dict(dtype="<f8", kw=dict(chunks=(6, 9, 10), compression="gzip", shuffle=True,
                                           maxshape=(None, None, None)), libver="latest"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_hdf5_gives_the_mesh_of_the_array(tmp_path, case):
    c = CASES[case]
    data = volume().clip(0).astype(c["dtype"])
    path = tmp_path / f"{case}.h5"
    with h5py.File(path, "w", libver=c.get("libver", "earliest")) as f:
        f.create_dataset("exchange/data", data=data, **c["kw"])
    for iso in (300.5, 700.5):
        got = tmc.extract(f"{path}:/exchange/data", iso)
        want = tmc.extract(data.astype(np.float64), iso)
        assert len(want.triangles) > 0
        np.testing.assert_array_equal(got.triangles, want.triangles)
        np.testing.assert_array_equal(got.vertices, want.vertices)


def test_a_bool_dataset_is_its_mask(tmp_path):
    """h5py stores a bool array as an enumeration of int8 (FALSE 0, TRUE 1):
    read as those integers, a mask's surface at 0.5."""
    mask = volume() > 700
    path = tmp_path / "mask.h5"
    with h5py.File(path, "w") as f:
        f.create_dataset("mask", data=mask, chunks=(5, 7, 8), compression="gzip")
        assert h5py.check_enum_dtype(f["mask"].dtype) is not None or f["mask"].dtype == bool
    got = tmc.extract(f"{path}:/mask", 0.5)
    want = tmc.extract(mask.astype(np.uint8), 0.5)
    assert len(want.triangles) > 0
    np.testing.assert_array_equal(got.triangles, want.triangles)
    np.testing.assert_array_equal(got.vertices, want.vertices)


def test_element_size_um_is_the_spacing(tmp_path):
    data = volume()
    path = tmp_path / "scan.h5"
    with h5py.File(path, "w") as f:
        d = f.create_dataset("data", data=data, chunks=(7, 13, 16), compression="gzip")
        d.attrs["element_size_um"] = [4.0, 2.0, 1.0]  # z, y, x
    got = tmc.extract(f"{path}:/data", 500.5)
    want = tmc.extract(data, 500.5, spacing=(0.001, 0.002, 0.004))
    np.testing.assert_array_equal(got.triangles, want.triangles)
    np.testing.assert_allclose(got.vertices, want.vertices, rtol=0, atol=1e-9)


def test_a_damaged_chunk_or_a_missing_dataset_raises(tmp_path):
    data = volume()
    path = tmp_path / "bad.h5"
    with h5py.File(path, "w") as f:
        f.create_dataset("data", data=data, chunks=(7, 13, 16), compression="gzip")
    with pytest.raises(Exception, match="no dataset '/nope'"):
        tmc.extract(f"{path}:/nope", 500.5)
    with h5py.File(path, "r") as f:
        info = f["data"].id.get_chunk_info(5)
    raw = bytearray(path.read_bytes())
    raw[info.byte_offset:info.byte_offset + info.size] = b"\xff" * info.size
    path.write_bytes(bytes(raw))
    with pytest.raises(Exception, match="bad.h5"):
        tmc.extract(f"{path}:/data", 500.5)


@pytest.mark.parametrize("chunks", [None, (5, 7, 8, 3), (4, 6, 5, 1)])
def test_a_channel_axis_last_is_picked_with_at(tmp_path, chunks):
    """A (z, y, x, c) dataset with three channels (ilastik writes zyxc), the
    channels interleaved, contiguous or chunked with all channels or one a
    chunk: ``at={3: c}`` gives the mesh of channel c as a numpy array,
    extract_labels and info too; without a pick the error says how to pick
    the last axis."""
    base = volume().clip(0).astype(np.float32)
    data = np.stack([base, 1500 - base, base[::-1]], axis=-1)
    path = tmp_path / "zyxc.h5"
    with h5py.File(path, "w") as f:
        f.create_dataset("exported_data", data=data, chunks=chunks,
                         compression="gzip" if chunks else None)
    for c in range(3):
        got = tmc.extract(str(path), 700.5, dataset="/exported_data", at={3: c})
        want = tmc.extract(data[..., c].astype(np.float64), 700.5)
        assert len(want.triangles) > 0
        np.testing.assert_array_equal(got.triangles, want.triangles)
        np.testing.assert_array_equal(got.vertices, want.vertices)
    facts = tmc.info(f"{path}:/exported_data", at={"3": 1})
    assert facts["dims"] == [29, 24, 19]
    assert facts["max"] == float((1500 - base).max())
    seg = (data[..., 0] > 700).astype(np.uint8) + (data[..., 0] > 900)
    with h5py.File(tmp_path / "seg.h5", "w") as f:
        f.create_dataset("s", data=np.stack([seg, seg * 0], axis=-1), chunks=chunks and (5, 7, 8, 2))
    labelled = tmc.extract_labels(f"{tmp_path / 'seg.h5'}:/s", at={3: 0})
    want_labels = tmc.extract_labels(seg)
    assert sorted(labelled) == sorted(want_labels) == [1, 2]
    for label in want_labels:
        np.testing.assert_array_equal(labelled[label].triangles, want_labels[label].triangles)
    with pytest.raises(ValueError, match=r"--at 3=I"):
        tmc.extract(f"{path}:/exported_data", 700.5)
    with pytest.raises(ValueError, match=r"axis '3' has 3 entries \(0 to 2\)"):
        tmc.extract(f"{path}:/exported_data", 700.5, at={3: 3})
