"""Multi-page TIFFs of 64-bit integers and half floats, written by tifffile
at test time (plain and compressed pages), give the mesh of the same
samples as a numpy array: each plane is converted to f64 as it is read,
as for `.npy`."""

import numpy as np
import pytest

import tmc

tifffile = pytest.importorskip("tifffile")


def volume():
    """A noisy ball, 17 x 20 x 23 samples (z, y, x), values 0..~1000."""
    rng = np.random.default_rng(9)
    z, y, x = np.mgrid[0:17, 0:20, 0:23].astype(float)
    r = np.sqrt((x - 11.3) ** 2 + (y - 9.1) ** 2 + (z - 8.2) ** 2)
    return (1000 - 90 * r + rng.integers(0, 40, r.shape)).clip(0).round()


CASES = {
    # Beyond 32 bits: the samples sit 2^40 up, exact in an f64.
    "u64": ("<u8", 2**40, None),
    "i64_negative": ("<i8", -(2**40), None),
    "i64_zlib": ("<i8", 2**35, "zlib"),
    # The ball's integers (below 2048) are exact half floats.
    "f16": ("<f2", 0, None),
    "f16_zlib_big_endian": (">f2", 0, "zlib"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_wide_pages_give_the_mesh_of_the_array(tmp_path, case):
    dtype, shift, compression = CASES[case]
    data = (volume() + shift).astype(dtype)
    path = tmp_path / f"{case}.tif"
    tifffile.imwrite(path, data, compression=compression, byteorder=dtype[0])
    with tifffile.TiffFile(path) as tif:
        assert len(tif.pages) == data.shape[0]
        assert tif.pages[0].dtype == np.dtype(dtype).newbyteorder("=")
    for iso in (300.5, 700.5):
        got = tmc.extract(str(path), shift + iso)
        want = tmc.extract(data.astype(np.float64), shift + iso)
        assert len(want.triangles) > 0
        np.testing.assert_array_equal(got.triangles, want.triangles)
        np.testing.assert_array_equal(got.vertices, want.vertices)
