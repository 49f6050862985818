"""tmc.extract gives, vertex for vertex and triangle for triangle, the mesh
the CLI writes for the same .npy file: every dtype, both memory orders,
--inside low, --close and --method mc; and extract_to writes the CLI's bytes."""

from __future__ import annotations

import os

import numpy as np
import pytest

import tmc
from conftest import read_ply, run_cli

DTYPES = ["u1", "i1", "u2", "i2", "u4", "i4", "u8", "i8", "f2", "f4", "f8"]


def noise_volume(dtype: str, shape=(9, 10, 11), seed=7) -> np.ndarray:
    """Smooth-ish noise in each type's range, with many ties at the isovalue
    for the integer types (values 0..6, isovalue 3)."""
    rng = np.random.default_rng(seed)
    values = rng.integers(0, 7, size=shape)
    if dtype.startswith("f"):
        values = values + rng.random(shape) * 0.5
    if dtype.startswith("i"):
        values = values - 3
    return values.astype(dtype)


def iso_for(dtype: str) -> float:
    return 0.0 if dtype.startswith("i") else 3.0


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("order", ["C", "F"])
@pytest.mark.parametrize(
    "options",
    [{}, {"inside": "low"}, {"close": True}, {"method": "mc"}],
    ids=["default", "inside-low", "close", "mc"],
)
def test_same_mesh_as_the_cli(tmp_path, dtype, order, options):
    volume = np.asarray(noise_volume(dtype), order=order)
    assert volume.flags.f_contiguous == (order == "F")
    npy = tmp_path / "v.npy"
    np.save(npy, volume)
    iso = iso_for(dtype)
    args = ["extract", str(npy), "--iso", repr(iso), "-o", str(tmp_path / "cli.ply"), "--quiet"]
    if options.get("inside") == "low":
        args += ["--inside", "low"]
    if options.get("close"):
        args += ["--close"]
    if options.get("method") == "mc":
        args += ["--method", "mc"]
    run_cli(*args)
    vertices, triangles = read_ply(tmp_path / "cli.ply")
    assert len(triangles) > 0

    for given in (volume, str(npy)):  # the array in memory, and the file by path
        mesh = tmc.extract(given, iso, **options)
        assert mesh.vertices.dtype == np.float64 and mesh.vertices.shape[1] == 3
        assert mesh.triangles.dtype == np.uint32
        np.testing.assert_array_equal(mesh.vertices, vertices)
        np.testing.assert_array_equal(mesh.triangles, triangles)
        assert mesh.stats["triangles"] == len(triangles)
        assert mesh.stats["iso"] == iso
        assert mesh.stats["method"] == options.get("method", "tmc")
        assert mesh.stats["inside"] == options.get("inside", "high")


def test_views_and_memmaps_read_in_place_give_the_same_mesh(tmp_path):
    base = noise_volume("f4", shape=(12, 13, 14))
    expected = tmc.extract(np.ascontiguousarray(base[::-1, 2:, ::2]), 3.0)
    # A reversed, offset, strided view: read through its strides.
    view = base[::-1, 2:, ::2]
    assert not view.flags.c_contiguous
    got = tmc.extract(view, 3.0)
    np.testing.assert_array_equal(got.vertices, expected.vertices)
    np.testing.assert_array_equal(got.triangles, expected.triangles)
    # The same view of a memmap: tmc maps the file itself.
    path = tmp_path / "v.npy"
    np.save(path, base)
    mapped = np.load(path, mmap_mode="r")
    got = tmc.extract(mapped[::-1, 2:, ::2], 3.0)
    np.testing.assert_array_equal(got.vertices, expected.vertices)
    np.testing.assert_array_equal(got.triangles, expected.triangles)
    # A big-endian array and a bool mask.
    got = tmc.extract(view.astype(">f4"), 3.0)
    np.testing.assert_array_equal(got.triangles, expected.triangles)
    mask = base > 3.0
    np.testing.assert_array_equal(
        tmc.extract(mask, 0.5).triangles, tmc.extract(mask.astype(np.uint8), 0.5).triangles
    )


def test_spacing_and_origin_are_x_y_z(tmp_path):
    volume = noise_volume("u1")
    plain = tmc.extract(volume, 3.0)
    placed = tmc.extract(volume, 3.0, spacing=(0.5, 2.0, 3.0), origin=(10.0, -1.0, 4.0))
    np.testing.assert_allclose(
        placed.vertices, plain.vertices * [0.5, 2.0, 3.0] + [10.0, -1.0, 4.0], rtol=1e-6
    )
    np.testing.assert_array_equal(placed.triangles, plain.triangles)


@pytest.mark.parametrize("suffix", [".ply", ".tmesh", ".obj", ".off", ".stl"])
def test_extract_to_writes_what_the_cli_writes(tmp_path, suffix):
    volume = noise_volume("i2")
    npy = tmp_path / "v.npy"
    np.save(npy, volume)
    run_cli("extract", str(npy), "--iso", "0", "--close", "-o", str(tmp_path / f"cli{suffix}"), "--quiet")
    report = tmc.extract_to(npy, 0.0, tmp_path / f"py{suffix}", close=True)
    assert (tmp_path / f"py{suffix}").read_bytes() == (tmp_path / f"cli{suffix}").read_bytes()
    assert report["triangles"] > 0 and report["close"] is True
    # From the array in memory too.
    tmc.extract_to(volume, 0.0, tmp_path / f"array{suffix}", close=True)
    assert (tmp_path / f"array{suffix}").read_bytes() == (tmp_path / f"cli{suffix}").read_bytes()


@pytest.mark.parametrize("suffix", [".ply", ".tmesh", ".obj"])
def test_extract_to_with_normals_writes_what_the_cli_writes(tmp_path, suffix):
    # Integer noise with many ties at the isovalue: gradient normals and,
    # where the gradient vanishes, the triangles' normals.
    volume = noise_volume("u2")
    npy = tmp_path / "v.npy"
    np.save(npy, volume)
    cli = tmp_path / f"cli{suffix}"
    run_cli("extract", str(npy), "--iso", "3", "--normals", "-o", str(cli), "--quiet")
    tmc.extract_to(npy, 3.0, tmp_path / f"py{suffix}", normals=True)
    assert (tmp_path / f"py{suffix}").read_bytes() == cli.read_bytes()
    tmc.extract_to(volume, 3.0, tmp_path / f"array{suffix}", normals=True, threads=2)
    assert (tmp_path / f"array{suffix}").read_bytes() == cli.read_bytes()
    # Without normals, the file has none: the bytes of the CLI without
    # --normals, and different from the file with them.
    plain = tmp_path / f"plain{suffix}"
    tmc.extract_to(npy, 3.0, plain)
    run_cli("extract", str(npy), "--iso", "3", "-o", str(tmp_path / f"cli_plain{suffix}"), "--quiet")
    assert plain.read_bytes() == (tmp_path / f"cli_plain{suffix}").read_bytes()
    assert plain.read_bytes() != cli.read_bytes()
    if suffix == ".ply":
        # The normals in the file are those of tmc.extract(normals=True),
        # parsed from the PLY's declared layout with numpy.
        data = cli.read_bytes()
        end = data.index(b"end_header\n") + len(b"end_header\n")
        header = data[:end].decode("ascii")
        assert "property float nx" in header
        n = int(header.split("element vertex ")[1].split()[0])
        rows = np.frombuffer(data[end : end + n * 24], dtype="<f4").reshape(n, 6)
        mesh = tmc.extract(npy, 3.0, normals=True)
        np.testing.assert_array_equal(rows[:, 3:], mesh.normals)
        np.testing.assert_array_equal(rows[:, :3], mesh.vertices.astype(np.float32))


def test_write_read_and_check_round_trip(tmp_path):
    mesh = tmc.extract(noise_volume("u2"), 3.0, close=True)
    for suffix in (".ply", ".obj", ".off"):
        mesh.write(tmp_path / f"m{suffix}")
        back = tmc.read_mesh(tmp_path / f"m{suffix}")
        np.testing.assert_array_equal(back.triangles, mesh.triangles)
        np.testing.assert_allclose(back.vertices, mesh.vertices, rtol=1e-6)
    # A .tmesh file records the extraction (grid, chunks per plane): the
    # mesh of tmc.extract writes the bytes of extract_to; a mesh read from a
    # file, or one whose sizes changed, refuses, saying so.
    mesh.write(tmp_path / "m.tmesh")
    tmc.extract_to(noise_volume("u2"), 3.0, tmp_path / "streamed.tmesh", close=True)
    assert (tmp_path / "m.tmesh").read_bytes() == (tmp_path / "streamed.tmesh").read_bytes()
    back = tmc.read_mesh(tmp_path / "m.tmesh")
    np.testing.assert_array_equal(back.triangles, mesh.triangles)
    np.testing.assert_array_equal(back.vertices, mesh.vertices)
    with pytest.raises(ValueError, match="extract_to"):
        back.write(tmp_path / "again.tmesh")
    cut = tmc.Mesh(mesh.vertices, mesh.triangles[:-1])
    cut._record = mesh._record
    with pytest.raises(ValueError, match="chunks as made"):
        cut.write(tmp_path / "cut.tmesh")
    assert not (tmp_path / "again.tmesh").exists() and not (tmp_path / "cut.tmesh").exists()
    report = mesh.check()
    cli = __import__("json").loads(run_cli("check", str(tmp_path / "m.ply"), "--json").stdout)
    assert report == cli
    assert report["boundary_edges"] == 0 and report["non_manifold_edges"] == 0


@pytest.mark.parametrize("normals", [False, True])
def test_a_mesh_pickles_and_copies_with_its_record(tmp_path, normals):
    # A Mesh of tmc.extract sent to or from another process (pickle, as
    # multiprocessing does) or copied with copy.deepcopy keeps its arrays,
    # stats and the record that writes its .tmesh file; it raised
    # TypeError: cannot pickle 'tmc._tmc.Record' object.
    import copy
    import pickle

    volume = noise_volume("u2")
    mesh = tmc.extract(volume, 3.0, close=True, normals=normals, spacing=(0.5, 2.0, 1.5),
                       origin=(1.0, -2.0, 3.0), inside="low", method="mc")
    mesh.write(tmp_path / "m.tmesh")
    for protocol in range(2, pickle.HIGHEST_PROTOCOL + 1):
        for other in (pickle.loads(pickle.dumps(mesh, protocol)), copy.deepcopy(mesh), copy.copy(mesh)):
            np.testing.assert_array_equal(other.vertices, mesh.vertices)
            np.testing.assert_array_equal(other.triangles, mesh.triangles)
            if normals:
                np.testing.assert_array_equal(other.normals, mesh.normals)
            else:
                assert other.normals is None
            assert other.stats == mesh.stats
            other.write(tmp_path / "o.tmesh")
            assert (tmp_path / "o.tmesh").read_bytes() == (tmp_path / "m.tmesh").read_bytes()
    # A mesh read from a file (no record) pickles too, and still refuses .tmesh.
    mesh.write(tmp_path / "m.ply")
    back = pickle.loads(pickle.dumps(tmc.read_mesh(tmp_path / "m.ply")))
    np.testing.assert_array_equal(back.triangles, mesh.triangles)
    with pytest.raises(ValueError, match="extract_to"):
        back.write(tmp_path / "again.tmesh")


def test_info_is_the_cli_info(tmp_path):
    npy = tmp_path / "v.npy"
    np.save(npy, noise_volume("f4"))
    cli = __import__("json").loads(run_cli("info", str(npy), "--json").stdout)
    assert tmc.info(npy) == cli


def test_paths_may_be_bytes_as_open_takes_them(tmp_path):
    """str, bytes and os.PathLike name the same files, as in Python's own
    open: a bytes name (undecodable bytes included) reaches the file system
    as it is."""
    volume = noise_volume("i2")
    folder = tmp_path / "caf\xe9"  # written as UTF-8 by the file system encoding
    folder.mkdir()
    npy = folder / "v.npy"
    np.save(npy, volume)
    want = tmc.extract_to(npy, 0.0, tmp_path / "want.ply")
    raw = os.fsencode(tmp_path) + b"/odd\xff"  # not UTF-8
    os.mkdir(raw)
    got = tmc.extract_to(os.fsencode(npy), 0.0, raw + b"/got.ply")
    assert got["triangles"] == want["triangles"] > 0
    assert open(raw + b"/got.ply", "rb").read() == (tmp_path / "want.ply").read_bytes()
    mesh = tmc.read_mesh(raw + b"/got.ply")
    assert len(mesh.triangles) == got["triangles"]
    assert tmc.extract(os.fsencode(npy), 0.0).triangles.shape == mesh.triangles.shape
    mesh.write(raw + b"/again.ply")
    assert tmc.info(os.fsencode(npy))["dims"] == tmc.info(npy)["dims"]
    labels = (volume > 0).astype(np.uint8)
    np.save(folder / "l.npy", labels)
    tmc.extract_labels_to(os.fsencode(folder / "l.npy"), raw + b"/l_{label}.ply")
    assert os.path.exists(raw + b"/l_1.ply")
    with pytest.raises(TypeError):
        tmc.extract_to(npy, 0.0, 3)


def test_zero_pixdim_note_is_a_warning(tmp_path):
    """The note the CLI prints on stderr for a NIfTI whose pixdim[1] is 0
    (read as 1, as nibabel does) is a UserWarning in Python, for every
    call that reads a path; the mesh is the one the CLI writes."""
    from conftest import REPO

    data = bytearray((REPO / "tests" / "data" / "nifti1_u8.nii").read_bytes())
    data[252:256] = bytes(4)  # qform_code = sform_code = 0
    data[80:84] = np.float32(0).tobytes()  # pixdim[1] = 0
    path = tmp_path / "flat.nii"
    path.write_bytes(bytes(data))
    with pytest.warns(UserWarning, match=r"pixdim\[1\] = 0"):
        mesh = tmc.extract(path, 128)
    with pytest.warns(UserWarning, match=r"pixdim\[1\] = 0"):
        tmc.extract_to(path, 128, tmp_path / "py.ply")
    with pytest.warns(UserWarning, match=r"pixdim\[1\] = 0"):
        tmc.extract_labels(path, [255])
    out = run_cli("extract", str(path), "--iso", "128", "-o", str(tmp_path / "cli.ply"))
    assert "pixdim[1] = 0" in out.stderr
    vertices, _ = read_ply(tmp_path / "cli.ply")
    assert np.allclose(mesh.vertices, vertices)
