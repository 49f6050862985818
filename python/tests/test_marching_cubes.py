"""tmc.marching_cubes against skimage.measure.marching_cubes: the same
surface (vertex positions up to order), the same winding, normals that
point the same way, and a closed manifold where scikit-image's is not."""

from __future__ import annotations

import numpy as np
import pytest

import tmc
from conftest import SHARED_DATA, edge_counts, gyroid, is_closed_manifold, sphere

skimage_measure = pytest.importorskip("skimage.measure")
spatial = pytest.importorskip("scipy.spatial")


def nearest(points: np.ndarray, to: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance from each of `points` to the nearest of `to`, and its index."""
    return spatial.cKDTree(to).query(points)


def compare(volume, level, spacing=(1.0, 1.0, 1.0), method="lewiner", gradient_direction="descent"):
    """Both libraries on the same array; returns what the tests look at."""
    ours = tmc.marching_cubes(
        volume, level, spacing=spacing, method=method, gradient_direction=gradient_direction
    )
    theirs = skimage_measure.marching_cubes(
        volume, level, spacing=spacing, method=method, gradient_direction=gradient_direction
    )
    return ours, theirs


def winding(verts, faces, normals):
    """Mean sign of each face's right-hand normal against the vertex normals."""
    t = verts[faces]
    face_normal = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    return float(np.sign((face_normal * normals[faces].sum(axis=1)).sum(axis=1)).mean())


def angles_degrees(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    cos = (a * b).sum(axis=1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def central_difference_normals(volume, verts, spacing=(1.0, 1.0, 1.0)):
    """The definition of tmc's normals, computed here with numpy alone:
    np.gradient (central differences, one-sided at the border) at the
    samples, trilinearly interpolated to each vertex, in physical units,
    pointing toward lower values."""
    gradient = np.stack(np.gradient(volume.astype(np.float64), *spacing), axis=-1)
    position = verts.astype(np.float64) / np.asarray(spacing)
    shape = np.array(volume.shape)
    cell = np.clip(np.floor(position).astype(np.intp), 0, shape - 2)
    t = position - cell
    result = np.zeros_like(position)
    for corner in np.ndindex(2, 2, 2):
        weight = np.prod(np.where(corner, t, 1.0 - t), axis=1)
        index = tuple((cell + corner).T)
        result += weight[:, None] * gradient[index]
    return -result


def assert_normals_are_central_differences(volume, ours, spacing=(1.0, 1.0, 1.0)):
    v, _, n, _ = ours
    expected = central_difference_normals(volume, v, spacing)
    strong = np.linalg.norm(expected, axis=1) > 1e-3 * np.abs(expected).max()
    angle = angles_degrees(n[strong], expected[strong])
    assert strong.mean() > 0.99
    assert np.percentile(angle, 99.9) < 1.0, np.percentile(angle, 99.9)


def assert_same_surface(ours, theirs, exact_fraction=0.99):
    (v, f, n, values), (sv, sf, sn, _) = ours, theirs
    assert v.dtype == np.float32 and f.dtype == np.int32
    assert n.dtype == np.float32 and values.shape == (len(v),)
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-5)
    # Edge vertices are where both put them, but on edges that end at a
    # sample equal to the level (a tie), where scikit-image's vertex sits on
    # the sample and tmc's 2^-10 of the edge from it (unit spacing here);
    # TMC's extra interior vertices and Lewiner's are within a cell of the
    # other's.
    tie = 2.0**-10 + 1e-4
    distance, index = nearest(v, sv)
    assert (distance < tie).mean() >= exact_fraction, (distance < tie).mean()
    assert distance.max() < 1.0
    back, _ = nearest(sv, v)
    assert (back < tie).mean() >= exact_fraction
    # Normals point the same way where the vertices coincide; they are not
    # equal: scikit-image estimates the gradient inside each cube, tmc (as
    # VTK) by central differences at the samples (checked exactly below).
    same = distance < 1e-4
    angle = angles_degrees(n[same], sn[index[same]])
    assert np.median(angle) < 12.0 and (angle < 90.0).mean() > 0.99, (
        np.median(angle),
        (angle < 90.0).mean(),
    )
    # The faces are wound the same way relative to the normals (on noisy
    # CT a few per cent of the triangles disagree with any vertex normals).
    ours_winding, theirs_winding = winding(v, f, n), winding(sv, sf, sn)
    assert abs(ours_winding) > 0.9 and np.sign(ours_winding) == np.sign(theirs_winding)


@pytest.mark.parametrize("gradient_direction", ["descent", "ascent"])
def test_sphere(gradient_direction):
    volume = sphere()
    if gradient_direction == "ascent":
        volume = -volume
    ours, theirs = compare(volume, 0.0, gradient_direction=gradient_direction)
    assert_same_surface(ours, theirs, exact_fraction=1.0)
    assert_normals_are_central_differences(volume, ours)
    assert is_closed_manifold(ours[1])


def test_sphere_lorensen_is_plain_mc_and_spacing_scales_index_axes():
    volume = sphere(dtype=np.float64)
    ours, theirs = compare(volume, 0.0, spacing=(1.0, 1.0, 1.0), method="lorensen")
    assert_same_surface(ours, theirs, exact_fraction=1.0)
    scaled = tmc.marching_cubes(volume, 0.0, spacing=(0.5, 2.0, 3.0))[0]
    np.testing.assert_allclose(scaled, ours[0] * [0.5, 2.0, 3.0], rtol=1e-6)


def test_gyroid():
    volume = gyroid()
    ours, theirs = compare(volume, 0.0)
    assert_same_surface(ours, theirs)
    assert_normals_are_central_differences(volume, ours)
    spacing = (0.5, 1.0, 2.0)
    anisotropic = tmc.marching_cubes(volume, 0.0, spacing=spacing)
    assert_normals_are_central_differences(volume, anisotropic, spacing)
    assert edge_counts(ours[1])["non_manifold"] == 0


@pytest.mark.parametrize(
    "name, level",
    [("headsq_quarter.nrrd", 500.0), ("cthead.nrrd", 1600.0), ("engine.nrrd", 80.0)],
)
def test_real_ct(name, level):
    nrrd = pytest.importorskip("nrrd")
    path = SHARED_DATA / name
    if not path.exists():
        pytest.skip(f"{path} not present (../shared/data)")
    data, _ = nrrd.read(str(path), index_order="C")  # [z][y][x]
    ours, theirs = compare(data, level)
    assert_same_surface(ours, theirs)
    assert_normals_are_central_differences(data, ours)
    counts = edge_counts(ours[1])
    assert counts["non_manifold"] == 0 and counts["inconsistent"] == 0


def padded(interior: np.ndarray) -> np.ndarray:
    """`interior` inside a border of zeros: every surface is closed."""
    return np.pad(interior, 1)


def test_closed_manifold_where_scikit_image_is_not():
    """Ties on integer data (values 0, 1, 2 and level 1) and the case-4
    tunnel: tmc's surface is a closed oriented manifold, scikit-image's
    Lewiner surface of the same arrays is not."""
    rng = np.random.default_rng(3)
    ties = padded(rng.integers(0, 3, size=(14, 15, 16)).astype(np.int16))
    # Two diagonal corners of one cell inside, with a body saddle joining
    # them (the tunnel of MC case 4: the trilinear interpolant's surface is
    # one tube).
    tunnel = np.zeros((4, 4, 4), dtype=np.float32)
    tunnel[1:3, 1:3, 1:3] = -1.0
    tunnel[1, 1, 1] = tunnel[2, 2, 2] = 1.0
    tunnel[1, 2, 2] = tunnel[2, 1, 1] = -0.02
    skimage_failures = 0
    for volume, level in [(ties, 1.0), (tunnel, 0.0)]:
        v, f, n, _ = tmc.marching_cubes(volume, level)
        assert is_closed_manifold(f), edge_counts(f)
        _, sf, _, _ = skimage_measure.marching_cubes(volume, level)
        skimage_failures += not is_closed_manifold(sf)
    assert skimage_failures >= 1


def test_step_size_is_a_strided_view():
    volume = sphere()
    v, f, _, _ = tmc.marching_cubes(volume, 0.0, step_size=2)
    expected = tmc.marching_cubes(np.ascontiguousarray(volume[::2, ::2, ::2]), 0.0, spacing=(2, 2, 2))
    np.testing.assert_array_equal(v, expected[0])
    np.testing.assert_array_equal(f, expected[1])


def test_allow_degenerate_false_removes_nothing_even_on_ties():
    """Samples equal to the level (ties) no longer collapse triangles: with
    allow_degenerate=False (scikit-image's merge of equal positions) the
    mesh comes back unchanged, and no triangle has zero area in float32
    or float64 arithmetic, on labels, a checkerboard of ties and a CT."""
    blob = np.zeros((6, 6, 6), dtype=np.uint8)
    blob[2:4, 2:4, 2:4] = 2
    blob[3, 3, 3] = 1  # ties at the level
    checker = np.indices((7, 7, 7)).sum(axis=0) % 2 * 2  # 0 and 2
    checker[::3] = 1  # whole planes of ties
    both = ["descent", "ascent"]
    checker = np.pad(checker, 1)
    volumes = [
        (blob, 1.0, both),
        (checker, 1.0, both),
        (checker, 0.0, ["descent"]),
        (checker, 2.0, ["ascent"]),
    ]
    path = SHARED_DATA / "bonsai.nrrd"
    nrrd = pytest.importorskip("nrrd")
    if path.exists():
        data, _ = nrrd.read(str(path), index_order="C")
        volumes.append((data, 40.0, both))  # 71,270 samples at 40
    for volume, level, directions in volumes:
        for direction in directions:
            kept = tmc.marching_cubes(volume, level, gradient_direction=direction)
            merged = tmc.marching_cubes(
                volume, level, gradient_direction=direction, allow_degenerate=False
            )
            for a, b in zip(kept, merged):
                np.testing.assert_array_equal(a, b)
            v, f = kept[0], kept[1]
            assert len(f) > 0
            assert len(np.unique(v, axis=0)) == len(v)
            for dtype in [np.float32, np.float64]:
                t = v.astype(dtype)[f]
                cross = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
                assert (np.abs(cross).max(axis=1) > 0).all(), (level, direction, dtype)


def test_level_defaults_to_mid_range_and_errors_match_scikit_image():
    volume = sphere()
    v, _, _, _ = tmc.marching_cubes(volume)
    mid = 0.5 * (float(volume.min()) + float(volume.max()))
    np.testing.assert_array_equal(v, tmc.marching_cubes(volume, mid)[0])
    with pytest.raises(ValueError, match="within volume data range"):
        tmc.marching_cubes(volume, 1e6)
    with pytest.raises(RuntimeError, match="No surface found"):
        tmc.marching_cubes(np.zeros((4, 4, 4)), 0.0)
    with pytest.raises(ValueError, match="gradient_direction"):
        tmc.marching_cubes(volume, 0.0, gradient_direction="up")
    with pytest.raises(ValueError, match="step_size"):
        tmc.marching_cubes(volume, 0.0, step_size=0)
    with pytest.raises(ValueError, match="mask"):
        tmc.marching_cubes(volume, 0.0, mask=volume > 5)
    full = tmc.marching_cubes(volume, 0.0, mask=np.ones(volume.shape, bool))
    np.testing.assert_array_equal(full[0], tmc.marching_cubes(volume, 0.0)[0])


def test_values_are_the_largest_sample_of_each_vertex_element():
    """Computed here with numpy: per axis, a vertex index within 1e-4 of an
    integer is on that grid plane, else between its floor and the next; the
    value is the largest sample of that edge (or face, cell, sample)."""
    volume = gyroid(n=30).astype(np.float64)
    spacing = (0.5, 1.0, 2.0)
    v, _, _, values = tmc.marching_cubes(volume, 0.1, spacing=spacing)
    index = v.astype(np.float64) / spacing
    nearest = np.round(index)
    on_plane = np.abs(index - nearest) <= 1e-4
    low = np.where(on_plane, nearest, np.floor(index)).astype(np.intp)
    shape = np.array(volume.shape)
    low = np.clip(low, 0, np.where(on_plane, shape - 1, shape - 2))
    high = np.where(on_plane, low, np.minimum(low + 1, shape - 1))
    expected = np.full(len(v), -np.inf)
    for corner in np.ndindex(2, 2, 2):
        at = np.where(np.array(corner, bool), high, low)
        expected = np.maximum(expected, volume[tuple(at.T)])
    assert on_plane.sum(axis=1).min() >= 1  # every vertex is on a grid plane
    assert values.dtype == np.float32
    np.testing.assert_array_equal(values, expected.astype(np.float32))


def test_the_four_arrays_do_not_depend_on_the_threads():
    """The values are computed by whichever worker made each chunk, the
    rest streams through the one writing thread: every thread count gives
    the same arrays, bit for bit (u16 and f64 samples, both directions)."""
    for volume in (gyroid(n=40).astype(np.float64), (gyroid(n=33) * 1000 + 2000).astype(np.uint16)):
        level = float(np.median(volume))
        for direction in ("descent", "ascent"):
            first = tmc.marching_cubes(volume, level, gradient_direction=direction, threads=1)
            assert len(first[0]) > 1000
            for threads in (2, 3):
                again = tmc.marching_cubes(
                    volume, level, gradient_direction=direction, threads=threads
                )
                for a, b in zip(first, again):
                    assert a.dtype == b.dtype
                    np.testing.assert_array_equal(a, b)



def test_the_default_level_is_the_middle_of_the_finite_samples():
    """NaN samples are outside, so the default level is the middle of the
    finite samples' range (numpy's min and max of an array with a NaN are
    NaN, which gave a NaN level the caller never asked for); infinite
    samples are left out of the range too. No finite sample: a ValueError
    saying to give the level."""
    volume = sphere(shape=(12, 13, 14), center=(5.5, 6.2, 6.7), radius=4.0)
    for bad in (np.nan, np.inf, -np.inf):
        spoiled = volume.copy()
        spoiled[0, 0, 0] = bad
        finite = spoiled[np.isfinite(spoiled)]
        level = 0.5 * (float(finite.min()) + float(finite.max()))
        got = tmc.marching_cubes(spoiled)
        given = tmc.marching_cubes(spoiled, level)
        assert len(got[1]) > 0
        for a, b in zip(got, given):
            np.testing.assert_array_equal(a, b)
    with pytest.raises(ValueError, match="no finite sample"):
        tmc.marching_cubes(np.full((3, 3, 3), np.nan, dtype=np.float32))
