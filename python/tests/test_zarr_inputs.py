"""Zarr arrays written by zarr-python 3 at test time (v2 and v3; blosc,
zstd, sharding; a missing chunk) give the mesh of the same samples as a
numpy array, and an OME-Zarr image its physical coordinates."""

import numpy as np
import pytest

import tmc

zarr = pytest.importorskip("zarr", minversion="3")
from zarr.codecs import BloscCodec, ZstdCodec  # noqa: E402
import numcodecs  # noqa: E402


def volume():
    rng = np.random.default_rng(29)
    z, y, x = np.mgrid[0:21, 0:26, 0:31]
    r = np.sqrt((x - 15.2) ** 2 + (y - 12.7) ** 2 + (z - 10.1) ** 2)
    return (1000 - 60 * r + rng.integers(0, 40, r.shape)).astype(np.int16)


CASES = {
    "v3_zstd": dict(chunks=(5, 7, 8), compressors=ZstdCodec(level=3)),
    "v3_blosc": dict(chunks=(4, 26, 9), compressors=BloscCodec(cname="lz4hc", shuffle="shuffle")),
    "v3_shards": dict(chunks=(3, 5, 7), shards=(6, 10, 14), compressors=ZstdCodec(level=1)),
    "v2_blosc": dict(chunks=(8, 8, 8), zarr_format=2,
                     compressors=numcodecs.Blosc(cname="zstd", shuffle=numcodecs.Blosc.BITSHUFFLE)),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_zarr_gives_the_mesh_of_the_array(tmp_path, case):
    data = volume()
    path = tmp_path / f"{case}.zarr"
    a = zarr.create_array(store=str(path), shape=data.shape, dtype=data.dtype, **CASES[case])
    a[...] = data
    for iso in (300.5, 700.5):
        got = tmc.extract(str(path), iso)
        want = tmc.extract(data, iso)
        assert len(want.triangles) > 0
        np.testing.assert_array_equal(got.triangles, want.triangles)
        np.testing.assert_array_equal(got.vertices, want.vertices)


def test_missing_chunks_are_the_fill_value(tmp_path):
    data = volume()
    path = tmp_path / "holes.zarr"
    a = zarr.create_array(store=str(path), shape=data.shape, dtype=data.dtype,
                          chunks=(7, 13, 31), fill_value=900, compressors=ZstdCodec(level=3))
    a[7:14] = data[7:14]
    expected = zarr.open_array(str(path))[...]
    assert (expected[:7] == 900).all()
    got = tmc.extract(str(path), 500.5)
    want = tmc.extract(expected, 500.5)
    np.testing.assert_array_equal(got.triangles, want.triangles)
    np.testing.assert_array_equal(got.vertices, want.vertices)


def test_ome_zarr_scale_and_translation(tmp_path):
    data = volume()
    path = tmp_path / "image.zarr"
    g = zarr.open_group(str(path), mode="w", zarr_format=3)
    a = g.create_array("0", shape=(1,) + data.shape, dtype=data.dtype, chunks=(1, 7, 13, 16))
    a[...] = data[None]
    axes = [{"name": "c", "type": "channel"}] + [
        {"name": n, "type": "space", "unit": "micrometer"} for n in "zyx"]
    g.attrs["ome"] = {"version": "0.5", "multiscales": [{
        "axes": axes,
        "datasets": [{"path": "0", "coordinateTransformations": [
            {"type": "scale", "scale": [1.0, 4.0, 2.0, 1.0]},
            {"type": "translation", "translation": [0.0, 100.0, 200.0, 300.0]}]}]}]}
    got = tmc.extract(str(path), 500.5)
    # micrometres in millimetres; spacing and origin are x, y, z
    want = tmc.extract(data, 500.5, spacing=(0.001, 0.002, 0.004), origin=(0.3, 0.2, 0.1))
    np.testing.assert_array_equal(got.triangles, want.triangles)
    np.testing.assert_allclose(got.vertices, want.vertices, rtol=0, atol=1e-9)
