"""A ``zarr.Array`` (local directory store) or ``h5py.Dataset`` (file on
disk) passed as the volume is streamed from its store plane by plane, as
its path would be, instead of being read whole through ``numpy.asarray``
(which it was: a volume larger than memory could not be passed as the
object). It keeps an array's meaning: spacing 1 and origin 0 unless given,
not the file's, and no warning. Objects tmc's readers cannot open (a
filter they do not read, a store in memory) are read a slice at a time
through their own library (test_lazy_arrays.py).
Every mesh is compared with the mesh of the numpy array of the same
samples (written and read by zarr-python and h5py)."""

import warnings

import numpy as np
import pytest

import tmc
from tmc import _tmc
from conftest import traced_peak

zarr = pytest.importorskip("zarr", minversion="3")
h5py = pytest.importorskip("h5py")
numcodecs = pytest.importorskip("numcodecs")
from zarr.codecs import ZstdCodec  # noqa: E402


def volume(shape=(21, 26, 31), radius_scale=60.0):
    """A noisy ball, int16."""
    rng = np.random.default_rng(41)
    z, y, x = np.mgrid[0 : shape[0], 0 : shape[1], 0 : shape[2]]
    c = [(n - 1) / 2 + 0.3 for n in shape]
    r = np.sqrt((x - c[2]) ** 2 + (y - c[1]) ** 2 + (z - c[0]) ** 2)
    return (1000 - radius_scale * r + rng.integers(0, 40, r.shape)).astype(np.int16)


def assert_same(got, want):
    assert len(want.triangles) > 0
    np.testing.assert_array_equal(got.triangles, want.triangles)
    np.testing.assert_array_equal(got.vertices, want.vertices)


def stored(tmp_path, data):
    """(name, object, whether tmc streams it) for each kind of store."""
    root = zarr.create_array(store=str(tmp_path / "root.zarr"), shape=data.shape,
                             dtype=data.dtype, chunks=(5, 7, 8), compressors=ZstdCodec(level=3))
    root[...] = data
    group = zarr.open_group(str(tmp_path / "group.zarr"), mode="w")
    inner = group.create_array("scans/a", shape=data.shape, dtype=data.dtype, chunks=(4, 26, 9))
    inner[...] = data
    v2 = zarr.create_array(store=str(tmp_path / "v2.zarr"), shape=data.shape, dtype=data.dtype,
                           chunks=(8, 8, 8), zarr_format=2)
    v2[...] = data
    with h5py.File(tmp_path / "d.h5", "w") as h5:
        h5.create_dataset("ct/chunked", data=data, chunks=(4, 9, 10), compression="gzip")
        h5.create_dataset("contiguous", data=data)
    h5 = h5py.File(tmp_path / "d.h5", "r")
    chunked, contiguous = h5["ct/chunked"], h5["contiguous"]
    return [
        ("zarr root array", zarr.open_array(str(tmp_path / "root.zarr"), mode="r")),
        ("zarr array in a group", zarr.open_group(str(tmp_path / "group.zarr"))["scans/a"]),
        ("zarr v2 format", zarr.open_array(str(tmp_path / "v2.zarr"))),
        ("hdf5 chunked, gzip", chunked),
        ("hdf5 contiguous", contiguous),
    ]


def test_an_array_object_is_streamed_with_the_numpy_arrays_mesh(tmp_path):
    data = volume()
    for name, obj in stored(tmp_path, data):
        path, chosen = tmc._stored.stored_array(obj, (None,) * 7)
        assert _tmc.stored_shape(path, chosen) == list(data.shape), name
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            for iso in (300.5, 700.5):
                assert_same(tmc.extract(obj, iso), tmc.extract(data, iso))
            kw = dict(spacing=(0.5, 0.75, 2.0), origin=(-3.0, 4.0, 5.5))
            assert_same(tmc.extract(obj, 500.5, **kw), tmc.extract(data, 500.5, **kw))
            got = tmc.extract(obj, 500.5, normals=True, close=True)
            want = tmc.extract(data, 500.5, normals=True, close=True)
            np.testing.assert_array_equal(got.normals, want.normals)
            a, b = tmp_path / "a.ply", tmp_path / "b.ply"
            tmc.extract_to(obj, 600.5, a, **kw)
            tmc.extract_to(data, 600.5, b, **kw)
            assert a.read_bytes() == b.read_bytes(), name
        streamed = tmc.extract_labels(obj, [int(data[10, 13, 15])])
        whole = tmc.extract_labels(data, [int(data[10, 13, 15])])
        assert list(streamed) == list(whole), name
        for label in whole:
            assert_same(streamed[label], whole[label])


def test_streaming_does_not_read_the_array_whole(tmp_path, monkeypatch):
    """Python's allocations while extracting stay far below the array's
    size when streamed; read through numpy (streaming switched off) they
    reach it, which shows the measure sees a whole read."""
    data = volume((96, 100, 110), radius_scale=25.0).astype(np.float32)
    z = zarr.create_array(store=str(tmp_path / "big.zarr"), shape=data.shape, dtype=data.dtype,
                          chunks=(8, 100, 110))
    z[...] = data
    with h5py.File(tmp_path / "big.h5", "w") as f:
        f.create_dataset("v", data=data, chunks=(8, 50, 110))
    h5 = h5py.File(tmp_path / "big.h5", "r")
    objects = [zarr.open_array(str(tmp_path / "big.zarr"), mode="r"), h5["v"]]
    want = tmc.extract(data, 500.5)

    for obj in objects:
        used, mesh = traced_peak(tmc.extract, obj, 500.5)
        assert_same(mesh, want)
        assert used < data.nbytes / 8, (type(obj), used, data.nbytes)
    # Read whole through numpy when neither streamed nor sliced: the
    # measure sees a whole read.
    monkeypatch.setattr(tmc._stored, "stored_array", lambda volume, select: None)
    monkeypatch.setattr(tmc._stored, "sliced_array", lambda volume, select: None)
    for obj in objects:
        used, mesh = traced_peak(tmc.extract, obj, 500.5)
        assert_same(mesh, want)
        assert used >= data.nbytes, (type(obj), used, data.nbytes)
    h5.close()


def test_objects_tmc_cannot_open_are_read_a_slice_at_a_time(tmp_path):
    data = volume()
    delta = zarr.create_array(store=str(tmp_path / "delta.zarr"), shape=data.shape,
                              dtype=data.dtype, chunks=(8, 8, 8), zarr_format=2,
                              filters=[numcodecs.Delta(dtype="i2")])
    delta[...] = data
    memory = zarr.create_array(store=zarr.storage.MemoryStore(), shape=data.shape,
                               dtype=data.dtype, chunks=(8, 8, 8))
    memory[...] = data
    core = h5py.File("in-memory.h5", "w", driver="core", backing_store=False)
    in_memory = core.create_dataset("v", data=data)
    # A file h5py holds open for writing is locked against other readers.
    writing = h5py.File(tmp_path / "open.h5", "w")
    unclosed = writing.create_dataset("v", data=data, chunks=(8, 8, 8))
    # Stores in memory have no path; the delta filter and the lock are
    # found by tmc's readers refusing them.
    assert tmc._stored.zarr_location(memory) is None and tmc._stored.h5py_location(in_memory) is None
    for obj, (path, array, dataset) in ((delta, tmc._stored.zarr_location(delta)),
                                        (unclosed, tmc._stored.h5py_location(unclosed))):
        assert _tmc.stored_shape(path, (None, None, None, array, None, dataset, True)) is None
    for obj in (delta, memory, in_memory, unclosed):
        assert tmc._stored.stored_array(obj, (None,) * 7) is None
        assert tmc._stored.sliced_array(obj, (None,) * 7) is not None
        assert_same(tmc.extract(obj, 500.5), tmc.extract(data, 500.5))
    core.close()
    writing.close()


def test_an_ome_image_level_passed_as_an_array_keeps_an_arrays_grid(tmp_path):
    """The level array of an OME-Zarr image, passed as the object, is an
    array (spacing 1, origin 0, as numpy would give it): the image's scale
    and translation apply to its path only."""
    data = volume()
    path = tmp_path / "image.zarr"
    g = zarr.open_group(str(path), mode="w", zarr_format=3)
    a = g.create_array("0", shape=data.shape, dtype=data.dtype, chunks=(7, 13, 16))
    a[...] = data
    g.attrs["ome"] = {"version": "0.5", "multiscales": [{
        "axes": [{"name": n, "type": "space", "unit": "millimeter"} for n in "zyx"],
        "datasets": [{"path": "0", "coordinateTransformations": [
            {"type": "scale", "scale": [4.0, 2.0, 1.5]},
            {"type": "translation", "translation": [10.0, 20.0, 30.0]}]}]}]}
    level = zarr.open_group(str(path), mode="r")["0"]
    assert tmc._stored.stored_array(level, (None,) * 7) is not None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert_same(tmc.extract(level, 500.5), tmc.extract(data, 500.5))
    scaled = tmc.extract(str(path), 500.5)
    assert_same(scaled, tmc.extract(data, 500.5, spacing=(1.5, 2.0, 4.0),
                                    origin=(30.0, 20.0, 10.0)))


def test_shapes_and_choices_are_those_of_an_array(tmp_path):
    """Axes of size 1 before z, y, x are taken as by a numpy array; other
    shapes and a series/at/dataset choice with an object are refused with
    the numpy array's words."""
    data = volume()
    one = zarr.create_array(store=str(tmp_path / "one.zarr"), shape=(1,) + data.shape,
                            dtype=data.dtype, chunks=(1, 8, 8, 8))
    one[...] = data[None]
    assert_same(tmc.extract(one, 500.5), tmc.extract(data, 500.5))
    two = zarr.create_array(store=str(tmp_path / "two.zarr"), shape=(2,) + data.shape,
                            dtype=data.dtype, chunks=(1, 8, 8, 8))
    two[...] = np.stack([data, data])
    with pytest.raises(ValueError) as streamed:
        tmc.extract(two, 500.5)
    with pytest.raises(ValueError) as whole:
        tmc.extract(two[...], 500.5)
    assert str(streamed.value) == str(whole.value)
    with pytest.raises(ValueError, match="not of an array"):
        tmc.extract(one, 500.5, at={0: 0})
