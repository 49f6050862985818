"""Lazy arrays (a ``dask.array``, an ``xarray.DataArray`` backed by dask,
a Zarr array in memory, an HDF5 dataset tmc's readers cannot open) passed
as the volume are read a slice of planes at a time, each slice computed by
the array's own library, instead of whole through ``numpy.asarray``: an
array larger than memory extracts in bounded memory. Every mesh is
compared with the mesh of the numpy array of the same samples."""

import os

import numpy as np
import pytest

import tmc
from conftest import traced_peak

da = pytest.importorskip("dask.array")
xr = pytest.importorskip("xarray")
zarr = pytest.importorskip("zarr", minversion="3")
h5py = pytest.importorskip("h5py")


def ball(shape=(37, 29, 33), scale=60.0, dtype=np.int16):
    """A noisy ball."""
    rng = np.random.default_rng(7)
    z, y, x = np.mgrid[0 : shape[0], 0 : shape[1], 0 : shape[2]]
    c = [(n - 1) / 2 + 0.3 for n in shape]
    r = np.sqrt((x - c[2]) ** 2 + (y - c[1]) ** 2 + (z - c[0]) ** 2)
    return (1000 - scale * r + rng.integers(0, 40, r.shape)).astype(dtype)


def assert_same(got, want):
    assert len(want.triangles) > 0
    np.testing.assert_array_equal(got.triangles, want.triangles)
    np.testing.assert_array_equal(got.vertices, want.vertices)
    if want.normals is not None:
        np.testing.assert_array_equal(got.normals, want.normals)


def lazy(data):
    """(name, lazy array of ``data``) for each kind the package slices."""
    memory = zarr.create_array(store=zarr.storage.MemoryStore(), shape=data.shape,
                               dtype=data.dtype, chunks=(6, 10, 11))
    memory[...] = data
    core = h5py.File(f"lazy-{id(data)}.h5", "w", driver="core", backing_store=False)
    return [
        ("dask", da.from_array(data, chunks=(5, 29, 33))),
        ("dask, chunks of one plane", da.from_array(data, chunks=(1, 15, 33))),
        ("dask, (1, z, y, x)", da.from_array(data[np.newaxis], chunks=(1, 8, 29, 33))),
        ("xarray of dask", xr.DataArray(da.from_array(data, chunks=(9, 29, 33)),
                                        dims=("z", "y", "x"))),
        ("zarr in memory", memory),
        ("h5py in memory", core.create_dataset("v", data=data, chunks=(4, 29, 33))),
    ]


@pytest.mark.parametrize("dtype", [np.int16, np.float32, np.dtype(">u2"), np.bool_])
def test_lazy_arrays_give_the_numpy_arrays_meshes(tmp_path, dtype):
    data = ball().astype(dtype) if dtype is not np.bool_ else ball() > 700
    iso = 0.5 if dtype is np.bool_ else 700.5
    grid = dict(spacing=(0.5, 2.0, 1.25), origin=(-3.0, 4.0, 10.0))
    for name, obj in lazy(data):
        assert tmc._stored.sliced_array(obj, (None,) * 7) is not None, name
        assert_same(tmc.extract(obj, iso), tmc.extract(data, iso))
        assert_same(tmc.extract(obj, iso, normals=True, close=True, **grid),
                    tmc.extract(data, iso, normals=True, close=True, **grid))
        assert_same(tmc.extract(obj, iso, method="mc", inside="low"),
                    tmc.extract(data, iso, method="mc", inside="low"))
        tmc.extract_to(obj, iso, tmp_path / "lazy.tmesh", **grid)
        tmc.extract_to(data, iso, tmp_path / "numpy.tmesh", **grid)
        got, want = (tmp_path / "lazy.tmesh").read_bytes(), (tmp_path / "numpy.tmesh").read_bytes()
        assert got == want, name


def test_lazy_label_maps_give_the_numpy_maps_labels():
    labels = (ball() // 150).astype(np.uint16)
    want = tmc.extract_labels(labels, close=True)
    assert len(want) >= 3
    for name, obj in lazy(labels):
        got = tmc.extract_labels(obj, close=True)
        assert sorted(got) == sorted(want), name
        for label in want:
            assert_same(got[label], want[label])


def test_each_chunk_is_computed_once_a_pass():
    data = ball(shape=(60, 29, 33))
    computed = []

    def count(block, block_info=None):
        if block_info is not None and block.size:
            computed.append(block_info[0]["chunk-location"])
        return block

    for chunks, layers in (((7, 29, 33), 9), ((60, 29, 33), 1), ((5, 15, 17), 12)):
        computed.clear()
        obj = da.from_array(data, chunks=chunks).map_blocks(count, dtype=data.dtype)
        assert_same(tmc.extract(obj, 700.5, threads=2), tmc.extract(data, 700.5))
        blocks = layers * len(obj.chunks[1]) * len(obj.chunks[2])
        assert len(computed) == blocks, (chunks, len(computed), blocks)
        assert len(set(computed)) == blocks


def test_a_lazy_array_is_never_read_whole(monkeypatch):
    """Python's allocations while a 4.2 MB dask array (made chunk by chunk,
    never whole) is extracted stay under a quarter of its size; read
    through numpy (slicing switched off), they reach its size, which shows
    that the measure sees a whole read."""
    shape = (96, 100, 110)

    def make(block_info=None):
        (z0, z1), (y0, y1), (x0, x1) = block_info[None]["array-location"]
        z = np.arange(z0, z1, dtype=np.float32)[:, None, None] - np.float32(48.1)
        y = np.arange(y0, y1, dtype=np.float32)[None, :, None] - np.float32(50.2)
        x = np.arange(x0, x1, dtype=np.float32)[None, None, :] - np.float32(55.3)
        r = (z * z + y * y) + x * x
        np.sqrt(r, out=r)
        r *= np.float32(-25.0)
        r += np.float32(1000.0)
        return r

    obj = da.map_blocks(make, chunks=((4,) * 24, (100,), (110,)), dtype=np.float32)
    nbytes = int(np.prod(shape)) * 4
    want = tmc.extract(obj.compute(), 500.5)
    monkeypatch.setattr(tmc._stored, "LAYER_BYTES", 256 << 10)

    used, mesh = traced_peak(tmc.extract, obj, 500.5)
    assert_same(mesh, want)
    assert used < nbytes / 4, (used, nbytes)
    monkeypatch.setattr(tmc._stored, "sliced_array", lambda volume, select: None)
    used, mesh = traced_peak(tmc.extract, obj, 500.5)
    assert_same(mesh, want)
    assert used >= nbytes, (used, nbytes)


def test_the_arrays_own_exception_is_raised_and_nothing_is_written(tmp_path):
    data = ball()

    def fail(block, block_info=None):
        if block_info is not None and block_info[0]["chunk-location"][0] == 3:
            raise RuntimeError("chunk 3 could not be fetched")
        return block

    obj = da.from_array(data, chunks=(5, 29, 33)).map_blocks(fail, dtype=data.dtype)
    with pytest.raises(RuntimeError, match="chunk 3 could not be fetched"):
        tmc.extract(obj, 700.5)
    out = tmp_path / "m.ply"
    with pytest.raises(RuntimeError, match="chunk 3 could not be fetched"):
        tmc.extract_to(obj, 700.5, out)
    assert os.listdir(tmp_path) == []
    with pytest.raises(RuntimeError, match="chunk 3"):
        tmc.extract_labels(obj > 700)


def test_a_slice_of_the_wrong_shape_or_dtype_is_refused(tmp_path):
    """A buggy ``map_blocks`` whose blocks are not what the array says
    (another dtype, or the y and x axes swapped: the same bytes) raises,
    naming the planes, what came back and what the array declares, with
    nothing written: it was cast or reshaped into a mesh of other samples
    (float64 blocks of a float32 array meshed as float32, fractions of a
    uint8 array truncated, the swapped axes read as rows)."""
    data = ball(dtype=np.float32)
    obj = da.from_array(data, chunks=(5, 29, 33))
    wrong = [
        (obj.map_blocks(lambda b: b.astype(np.float64), dtype=np.float32),
         TypeError, r"float64.*float32"),
        ((obj / 1000).map_blocks(lambda b: b * 255.5, dtype=np.uint8),
         TypeError, r"float\d+.*uint8"),
        (obj.map_blocks(lambda b: np.ascontiguousarray(b.transpose(0, 2, 1)), dtype=obj.dtype),
         ValueError, r"\(\d+, 33, 29\).*\(\d+, 29, 33\)"),
    ]
    for bad, error, message in wrong:
        with pytest.raises(error, match=message):
            tmc.extract(bad, 700.5)
        with pytest.raises(error, match=r"planes \d+\.\.\d+"):
            tmc.extract_to(bad, 700.5, tmp_path / "m.ply")
        assert os.listdir(tmp_path) == []
    # The same byte order or another is the same dtype.
    swapped = da.from_array(data.astype(">f4"), chunks=(5, 29, 33))
    assert_same(tmc.extract(swapped.map_blocks(lambda b: b.astype("<f4"), dtype=">f4"), 700.5),
                tmc.extract(data, 700.5))


def test_what_is_not_sliced_is_read_as_before():
    data = ball()
    # Already in memory: read in place.
    in_memory = xr.DataArray(data, dims=("z", "y", "x"))
    assert tmc._stored.sliced_array(in_memory, (None,) * 7) is None
    assert_same(tmc.extract(in_memory, 700.5), tmc.extract(data, 700.5))
    # Not a volume of a type tmc reads: numpy's errors, as before.
    two = da.from_array(np.stack([data, data]), chunks=(1, 5, 29, 33))
    assert tmc._stored.sliced_array(two, (None,) * 7) is None
    with pytest.raises(ValueError, match="shape"):
        tmc.extract(two, 700.5)
    complex_array = da.from_array(data.astype(np.complex64), chunks=(5, 29, 33))
    assert tmc._stored.sliced_array(complex_array, (None,) * 7) is None
    with pytest.raises(TypeError, match="dtype"):
        tmc.extract(complex_array, 700.5)
    empty = da.zeros((0, 4, 4), chunks=(1, 4, 4))
    assert tmc._stored.sliced_array(empty, (None,) * 7) is None


def test_layers_are_whole_chunks_within_the_bound():
    depth = tmc._stored.layer_depth
    plane = 1 << 20  # 1 MiB planes: 32 fit in a layer
    assert depth(da.zeros((100, 8, 8), chunks=(10, 8, 8)), 100, plane) == 30
    assert depth(da.zeros((100, 8, 8), chunks=(64, 8, 8)), 100, plane) == 32
    assert depth(da.zeros((100, 8, 8), chunks=(1, 8, 8)), 100, plane) == 32
    assert depth(da.zeros((20, 8, 8), chunks=(1, 8, 8)), 20, plane) == 20
    assert depth(object(), 100, plane) == 32
    assert depth(object(), 100, 1 << 30) == 1
