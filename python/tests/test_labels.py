"""tmc.extract_labels and tmc.extract_labels_to: every label of a label map
in one pass. Each label's mesh is compared with what the package's
single-isovalue extraction gives for that label's 0/1 indicator at 0.5
(np.array_equal, normals bit for bit), its closed surfaces with
scipy.ndimage's count of the indicator's 6-connected components, the
files with a numpy parser of binary PLY (conftest.read_ply and the parser
here), and the frog's labels with the CLI's files."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import tmc
from conftest import SHARED_DATA, read_ply, run_cli, sigint_latency

ndimage = pytest.importorskip("scipy.ndimage")

# scipy's 6-connectivity (faces only).
SIX = ndimage.generate_binary_structure(3, 1)


def label_map() -> np.ndarray:
    """A 14x16x18 map ([z][y][x]) of labels that touch each other and the
    volume's border, one-voxel labels, a label with a tunnel, a label of
    two components, and labels that touch only along an edge or a corner
    (not 6-connected: two components each)."""
    seg = np.zeros((14, 16, 18), dtype=np.int32)
    seg[0:6, 0:7, 0:8] = 1  # touches three faces of the volume
    seg[0:6, 0:7, 8:13] = 2  # touches 1 face to face
    seg[6:10, 2:9, 3:11] = 3  # on top of 1 and 2
    seg[13, 15, 17] = 4  # one voxel in the far corner
    seg[8, 12, 15] = 5  # one voxel inside
    seg[7, 13, 2] = 6  # one voxel beside another label (7)
    seg[7, 13, 3:6] = 7
    # A square ring (genus 1) of thickness 2 around a hole of 2x2.
    seg[10:12, 10:16, 11:17] = 8
    seg[10:12, 12:14, 13:15] = 0
    # Two boxes apart: two components.
    seg[1:3, 10:12, 1:3] = 9
    seg[4:6, 12:14, 4:6] = 9
    # Voxels meeting along an edge only, and at a corner only.
    seg[11, 2, 2] = 10
    seg[12, 3, 2] = 10
    seg[11, 5, 5] = 11
    seg[12, 6, 6] = 11
    return seg


def assert_same_mesh(got: tmc.Mesh, want: tmc.Mesh) -> None:
    """Same vertex and triangle arrays, and the same normals bits."""
    assert got.vertices.dtype == want.vertices.dtype == np.float64
    assert got.triangles.dtype == want.triangles.dtype == np.uint32
    assert np.array_equal(got.vertices, want.vertices)
    assert np.array_equal(got.triangles, want.triangles)
    if want.normals is None:
        assert got.normals is None
    else:
        assert got.normals is not None
        assert np.array_equal(got.normals.view(np.uint32), want.normals.view(np.uint32))


def indicator(seg: np.ndarray, label) -> np.ndarray:
    return (np.asarray(seg) == label).astype(np.uint8)


def assert_each_label_is_its_indicator(seg, meshes, **options) -> None:
    """Every label present (but 0) has a mesh, equal to the extraction of
    its indicator with the same options."""
    present = sorted(set(np.unique(seg).tolist()) - {0})
    assert sorted(meshes) == present
    assert list(meshes) == present, "'all' gives the labels ascending"
    for label, mesh in meshes.items():
        assert isinstance(label, int)
        want = tmc.extract(indicator(seg, label), 0.5, **options)
        assert len(want.triangles) > 0
        assert_same_mesh(mesh, want)


@pytest.mark.parametrize(
    "options",
    [{}, {"close": True}, {"normals": True}, {"close": True, "normals": True, "threads": 3}],
    ids=["open", "close", "normals", "close-normals-3-threads"],
)
def test_each_label_is_its_indicator_extraction(options):
    seg = label_map()
    meshes = tmc.extract_labels(seg, **options)
    assert_each_label_is_its_indicator(seg, meshes, **options)


def oracle_components(mask: np.ndarray) -> int:
    """Components of the closed surface of `mask`'s indicator: its
    6-connected components. Valid because a tie (0.5 on a face between two
    label samples that meet along an edge) is outside, so samples that meet
    along an edge or at a corner only are apart, and because no component
    encloses a cavity (a cavity would add an inner surface): that is
    asserted here, the cavities being what binary_fill_holes fills."""
    assert np.array_equal(ndimage.binary_fill_holes(mask), mask), "the oracle needs no cavity"
    return int(ndimage.label(mask, structure=SIX)[1])


def test_closed_surfaces_have_the_oracle_components():
    seg = label_map()
    meshes = tmc.extract_labels(seg, close=True)
    expected = {1: 1, 2: 1, 3: 1, 4: 1, 5: 1, 6: 1, 7: 1, 8: 1, 9: 2, 10: 2, 11: 2}
    for label, mesh in meshes.items():
        report = mesh.check()
        assert report["boundary_edges"] == 0 and report["non_manifold_edges"] == 0, label
        assert report["non_manifold_vertices"] == 0 and report["inconsistent_edges"] == 0, label
        assert report["components"] == oracle_components(seg == label), label
        assert report["components"] == expected[label], label
        genus = sum(c["genus"] for c in report["per_component"])
        assert genus == (1 if label == 8 else 0), label


def voronoi_map(count=300, shape=(20, 22, 24), seed=3) -> np.ndarray:
    """`count` labels (1..count): each sample takes the label of its
    nearest seed, so the labels tile the volume, touching each other and
    the border."""
    rng = np.random.default_rng(seed)
    seeds = rng.random((count, 3)) * np.array(shape)
    points = np.indices(shape).reshape(3, -1).T + 0.5
    nearest = np.empty(len(points), dtype=np.int64)
    for start in range(0, len(points), 2048):
        d = ((points[start:start + 2048, None, :] - seeds[None]) ** 2).sum(axis=2)
        nearest[start:start + 2048] = d.argmin(axis=1)
    return (nearest.reshape(shape) + 1).astype(np.uint16)


def test_three_hundred_labels():
    seg = voronoi_map()
    assert len(np.unique(seg)) == 300
    meshes = tmc.extract_labels(seg, close=True, threads=2)
    assert_each_label_is_its_indicator(seg, meshes, close=True)
    for label, mesh in meshes.items():
        report = mesh.check()
        assert report["boundary_edges"] == 0 and report["non_manifold_edges"] == 0, label
        assert report["components"] == oracle_components(seg == label), label


# Label values per dtype: negative ones where the type has them, and
# values at the type's ends.
DTYPE_LABELS = {
    "i1": [-128, -3, 1, 2, 127, 5, 6, 7, 8, 9, 10, 11],
    "u2": [65535, 1, 2, 300, 4, 5, 6, 7, 8, 9, 10, 11],
    "i4": [-(2**31), -1, 2, 3, 2**31 - 1, 5, 6, 7, 8, 9, 10, 11],
    "i8": [-(2**40) - 3, -1, 2**33, 3, 4, 5, 6, 7, 8, 9, 10, 2**52],
    "u8": [2**53 - 1, 2**40 + 1, 2**33, 3, 4, 5, 6, 7, 8, 9, 10, 11],
    "f2": [-2048.0, -1.0, 2048.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0],
    "f4": [-1e6, -2.0, 3.0, 4.0, 16777216.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0],
}


@pytest.mark.parametrize("dtype", sorted(DTYPE_LABELS))
def test_dtypes_and_negative_labels(dtype):
    base = label_map()
    values = np.array([0] + DTYPE_LABELS[dtype][:11], dtype=dtype)
    seg = values[base]
    assert seg.dtype == np.dtype(dtype)
    meshes = tmc.extract_labels(seg, close=True)
    assert sorted(meshes) == sorted(int(v) for v in values[1:])
    for label, mesh in meshes.items():
        assert_same_mesh(mesh, tmc.extract(indicator(seg, label), 0.5, close=True))


def test_a_64_bit_label_beyond_2_53_is_refused_with_its_position():
    """64-bit labels are read in place (no copy to float64); one that a
    float64 does not hold exactly is refused, naming its sample."""
    seg = label_map().astype(np.uint64)
    seg[2, 3, 4] = 2**53 + 2
    with pytest.raises(ValueError, match=r"sample \(x 4, y 3, z 2\) is .*beyond ±2\^53"):
        tmc.extract_labels(seg)


def test_background_and_chosen_labels():
    seg = label_map()
    meshes = tmc.extract_labels(seg, labels=[8, 3, 42], normals=True)
    assert list(meshes) == [8, 3, 42], "the order asked for"
    assert len(meshes[42].triangles) == 0, "an absent label has an empty mesh"
    for label in (8, 3):
        assert_same_mesh(meshes[label], tmc.extract(indicator(seg, label), 0.5, normals=True))
    # With background 1, "all" is every other value, 0 included.
    meshes = tmc.extract_labels(seg, background=1)
    assert list(meshes) == [0, *range(2, 12)]
    assert_same_mesh(meshes[0], tmc.extract(indicator(seg, 0), 0.5))


def test_fortran_order_and_strided_views():
    seg = label_map()
    fortran = np.asfortranarray(seg)
    assert fortran.flags.f_contiguous and not fortran.flags.c_contiguous
    big = np.zeros((30, 40, 40), dtype=np.int32)
    big[::2, 1:33:2, ::-2][:14, :16, :18] = seg
    view = big[::2, 1:33:2, ::-2][:14, :16, :18]
    assert not view.flags.c_contiguous and not view.flags.f_contiguous
    assert np.array_equal(view, seg)
    want = tmc.extract_labels(seg, close=True)
    for volume in (fortran, view):
        meshes = tmc.extract_labels(volume, close=True)
        assert list(meshes) == list(want)
        for label, mesh in meshes.items():
            assert_same_mesh(mesh, want[label])
            # and the indicator of the view itself (a C-ordered copy)
            assert_same_mesh(mesh, tmc.extract(indicator(volume, label), 0.5, close=True))


def test_a_fraction_is_refused_with_its_position(tmp_path):
    seg = label_map().astype(np.float32)
    whole = tmc.extract_labels(seg)
    assert sorted(whole) == list(range(1, 12)), "whole floats are labels"
    seg[5, 3, 7] = 2.5
    seg[9, 1, 1] = np.nan  # later in the file's order: not the one named
    with pytest.raises(ValueError, match=r"sample \(x 7, y 3, z 5\) is 2\.5, not a whole number"):
        tmc.extract_labels(seg)
    out = tmp_path / "out"
    out.mkdir()
    with pytest.raises(ValueError, match=r"\(x 7, y 3, z 5\)"):
        tmc.extract_labels_to(seg, out / "{label}.ply")
    assert list(out.iterdir()) == [], "nothing left behind"


def test_an_output_that_cannot_be_written_is_refused_before_the_map_is_read(tmp_path):
    """A missing directory or an unknown format of a label file is refused
    before the first reading of the volume: a map that reading refuses (a
    sample 2.5) gets the output's error (it got the map's, after reading
    all of it)."""
    seg = label_map().astype(np.float32)
    seg[5, 3, 7] = 2.5
    with pytest.raises(FileNotFoundError, match="does not exist"):
        tmc.extract_labels_to(seg, tmp_path / "missing" / "{label}.ply")
    with pytest.raises(ValueError, match="unknown output format"):
        tmc.extract_labels_to(seg, tmp_path / "{label}.xyz")
    assert list(tmp_path.iterdir()) == []


def test_bad_arguments_are_python_errors(tmp_path):
    seg = label_map()
    with pytest.raises(ValueError, match="'all' or a sequence"):
        tmc.extract_labels(seg, labels="some")
    with pytest.raises(TypeError, match="'all' or a sequence"):
        tmc.extract_labels(seg, labels=[1.5])
    # A bool is no label (True was taken as label 1).
    for flag in (True, [True], [2, np.True_], np.False_):
        with pytest.raises(TypeError, match="'all' or a sequence"):
            tmc.extract_labels(seg, labels=flag)
    with pytest.raises(ValueError, match="empty"):
        tmc.extract_labels(seg, labels=[])
    with pytest.raises(ValueError, match="label 3 is asked for twice"):
        tmc.extract_labels(seg, labels=[3, 1, 3])
    with pytest.raises(ValueError, match="no label but the background 0"):
        tmc.extract_labels(np.zeros((3, 3, 3), np.uint8))
    with pytest.raises(ValueError, match=r"must contain \{label\}"):
        tmc.extract_labels_to(seg, tmp_path / "all.obj")
    with pytest.raises(ValueError, match="does not fit the uint32"):
        tmc.extract_labels_to(seg, tmp_path / "all.ply", labels=[-1, 3])
    # A placeholder the call does not fill in stayed in the names
    # ('{stem}_3.ply'): refused, naming it.
    for template in ("{stem}_{label}.ply", "{label}_{part}.tmesh", "{Label}.ply"):
        with pytest.raises(ValueError, match=r"unknown placeholder \{\w+\} in output; it may use \{label\}"):
            tmc.extract_labels_to(seg, tmp_path / template)
    with pytest.raises(FileNotFoundError):
        tmc.extract_labels(tmp_path / "missing.nrrd")
    assert list(tmp_path.iterdir()) == []


def read_ply_table(path: Path):
    """The vertex table (a structured array) and the faces of a binary PLY
    whose faces are a uchar count, three uint/int indices and optionally a
    uint label; parsed with numpy from the header alone."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    lines = data[:end].decode("ascii").splitlines()
    assert lines[1] == "format binary_little_endian 1.0"
    types = {"float": "<f4", "uchar": "u1", "int": "<i4", "uint": "<u4"}
    elements = []
    for line in lines:
        words = line.split()
        if words[0] == "element":
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property":
            elements[-1][2].append(words[1:])
    (_, nv, vprops), (_, nf, fprops) = elements
    vtype = np.dtype([(p[1], types[p[0]]) for p in vprops])
    vertices = np.frombuffer(data, vtype, nv, end)
    fields = [("n", types[fprops[0][1]]), ("i", types[fprops[0][2]], 3)]
    fields += [(p[1], types[p[0]]) for p in fprops[1:]]
    faces = np.frombuffer(data, np.dtype(fields), nf, end + vtype.itemsize * nv)
    assert end + vtype.itemsize * nv + faces.dtype.itemsize * nf == len(data)
    assert (faces["n"] == 3).all()
    return vertices, faces


@pytest.mark.parametrize("normals", [False, True])
def test_files_per_label_hold_the_meshes(tmp_path, normals):
    seg = label_map()
    meshes = tmc.extract_labels(seg, close=True, normals=normals)
    report = tmc.extract_labels_to(seg, tmp_path / "l{label}.ply", close=True, normals=normals)
    assert report["input"] == "array" and report["close"] is True and report["background"] == 0
    assert [r["label"] for r in report["labels"]] == list(meshes)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(f"l{l}.ply" for l in meshes)
    for entry in report["labels"]:
        label, mesh = entry["label"], meshes[entry["label"]]
        path = tmp_path / f"l{label}.ply"
        assert entry["output"] == str(path)
        assert entry["triangles"] == len(mesh.triangles)
        assert entry["vertices"] == len(mesh.vertices)
        assert entry["samples"] == int((seg == label).sum()) == entry["voxel_volume"]
        vertices, triangles = read_ply(path)
        assert np.array_equal(vertices, mesh.vertices)
        assert np.array_equal(triangles, mesh.triangles)
        table, _ = read_ply_table(path)
        if normals:
            got = np.stack([table["nx"], table["ny"], table["nz"]], axis=1)
            assert np.array_equal(got.view(np.uint32), mesh.normals.view(np.uint32))
        else:
            assert "nx" not in table.dtype.names


def test_one_file_holds_every_label_with_its_faces_labelled(tmp_path):
    seg = label_map()
    meshes = tmc.extract_labels(seg, close=True)
    report = tmc.extract_labels_to(seg, tmp_path / "all.ply", close=True)
    assert [p.name for p in tmp_path.iterdir()] == ["all.ply"], "no spool left behind"
    assert {r["output"] for r in report["labels"]} == {str(tmp_path / "all.ply")}
    table, faces = read_ply_table(tmp_path / "all.ply")
    vertices = np.stack([table["x"], table["y"], table["z"]], axis=1).astype(np.float64)
    assert len(vertices) == sum(len(m.vertices) for m in meshes.values())
    assert len(faces) == sum(len(m.triangles) for m in meshes.values())
    assert set(np.unique(faces["label"]).tolist()) == set(meshes)
    for label, mesh in meshes.items():
        # A label's vertices keep their order in the union: those its faces
        # use, ascending, renumbered from 0, are its mesh.
        own = faces["i"][faces["label"] == label].astype(np.int64)
        used = np.unique(own)
        assert np.array_equal(vertices[used], mesh.vertices), label
        assert np.array_equal(np.searchsorted(used, own), mesh.triangles), label
    # The .tmesh of every label is the same union.
    tmc.extract_labels_to(seg, tmp_path / "all.tmesh", close=True)
    union = tmc.read_mesh(tmp_path / "all.tmesh")
    assert np.array_equal(union.vertices, vertices)
    assert np.array_equal(union.triangles, faces["i"])


@pytest.mark.parametrize("template", ["{label}.ply", "{label}.obj", "{label}.tmesh", "all.ply"])
def test_files_are_the_cli_bytes(tmp_path, template):
    seg = label_map()
    npy = tmp_path / "seg.npy"
    np.save(npy, seg)
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    run_cli("extract", str(npy), "--labels", "all", "--close", "--normals", "--quiet",
            "-o", str(tmp_path / "cli" / template))
    for volume in (seg, npy):
        report = tmc.extract_labels_to(volume, tmp_path / "py" / template, close=True, normals=True)
        cli = sorted((tmp_path / "cli").iterdir())
        py = sorted((tmp_path / "py").iterdir())
        assert [p.name for p in py] == [p.name for p in cli]
        for a, b in zip(py, cli):
            assert a.read_bytes() == b.read_bytes(), a.name
        assert report["input"] == ("array" if volume is seg else str(npy))


def test_the_frogs_tissues_are_the_cli_files(tmp_path):
    frog = SHARED_DATA / "frog_tissues.nrrd"
    if not frog.is_file():
        pytest.skip(f"{frog} is absent (the shared test data)")
    run_cli("extract", str(frog), "--labels", "all", "--quiet",
            "-o", str(tmp_path / "{label}.tmesh"))
    meshes = tmc.extract_labels(frog)
    files = sorted(tmp_path.iterdir(), key=lambda p: int(p.stem))
    assert [int(p.stem) for p in files] == list(meshes)
    assert len(meshes) >= 5
    for path in files:
        from_cli = tmc.read_mesh(path)
        mesh = meshes[int(path.stem)]
        assert len(mesh.triangles) > 0
        assert np.array_equal(mesh.vertices, from_cli.vertices), path.name
        assert np.array_equal(mesh.triangles, from_cli.triangles), path.name


def test_a_zarr_path_gives_the_meshes_of_the_array(tmp_path):
    zarr = pytest.importorskip("zarr", minversion="3")
    seg = label_map().astype(np.int16)
    path = tmp_path / "seg.zarr"
    stored = zarr.create_array(store=str(path), shape=seg.shape, dtype=seg.dtype, chunks=(5, 6, 7))
    stored[...] = seg
    want = tmc.extract_labels(seg, close=True)
    got = tmc.extract_labels(str(path), close=True)
    assert list(got) == list(want)
    for label, mesh in got.items():
        assert_same_mesh(mesh, want[label])


def test_a_nifti_path_gives_each_indicator_files_mesh(tmp_path):
    nib = pytest.importorskip("nibabel")
    seg = label_map().astype(np.int16)
    affine = np.array([[-0.8, 0, 0, 30.0], [0, 0.9, 0, -12.0], [0, 0, 1.5, 4.0], [0, 0, 0, 1]])

    def save(volume, name):
        path = tmp_path / name
        # nibabel's arrays are indexed [x][y][z].
        nib.save(nib.Nifti1Image(np.ascontiguousarray(volume.transpose(2, 1, 0)), affine), path)
        return path

    got = tmc.extract_labels(save(seg, "seg.nii.gz"), labels=[3, 8, 9], normals=True)
    for label, mesh in got.items():
        want = tmc.extract(save(indicator(seg, label), f"{label}.nii.gz"), 0.5, normals=True)
        assert len(want.triangles) > 0
        assert_same_mesh(mesh, want)


@pytest.mark.parametrize(
    "call",
    ["tmc.extract_labels(seg)", "tmc.extract_labels_to(seg, OUT + '/{label}.ply')",
     "tmc.extract_labels_to(seg, OUT + '/all.ply')"],
    ids=["in-memory", "file-per-label", "one-file"],
)
def test_ctrl_c_stops_the_pass_and_leaves_no_file(tmp_path, call):
    """SIGINT during the pass: KeyboardInterrupt within half a second (the
    GIL is released and the signal seen), and no label file behind."""
    setup = f"""
        import numpy as np, tmc
        OUT = {str(tmp_path)!r}
        # Noise of 60 labels: every label's window is every slab, so the
        # pass is about 60 extractions of the volume (seconds).
        seg = np.random.default_rng(1).integers(0, 61, (300, 300, 300), dtype=np.uint8)
        """
    latency = sigint_latency(setup, call, 1.5)
    assert latency < 0.5
    assert list(tmp_path.iterdir()) == []


# The figures `extract_labels_to(..., stats=True)` adds to each label.
FIGURES = ("components", "genus", "closed", "area", "enclosed_volume")


def same_figures(got: dict, want: dict) -> None:
    """The same per-label figures, each given by both or by neither;
    floats bit for bit."""
    for key in FIGURES:
        assert (key in got) == (key in want), (got["label"], key)
        if key not in want:
            continue
        a, b = got[key], want[key]
        if isinstance(b, float):
            assert isinstance(a, float) and a.hex() == b.hex(), (got["label"], key, a, b)
        else:
            assert type(a) is type(b) and a == b, (got["label"], key, a, b)


def test_stats_are_off_by_default(tmp_path):
    report = tmc.extract_labels_to(label_map(), tmp_path / "{label}.tmesh", close=True)
    for entry in report["labels"]:
        assert not set(FIGURES) & set(entry), entry


@pytest.mark.parametrize("template", ["{label}.tmesh", "{label}.ply", "all.ply"])
@pytest.mark.parametrize("close", [True, False], ids=["close", "open"])
def test_stats_are_the_cli_json_figures(tmp_path, template, close):
    """Each label's figures are those of `tmc extract --labels --json` for
    the same map (the same code counts them: this holds the package to
    calling it, on every label, with the CLI's options)."""
    seg = label_map()
    npy = tmp_path / "seg.npy"
    np.save(npy, seg)
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    flags = ["--close"] if close else []
    done = run_cli("extract", str(npy), "--labels", "all", *flags, "--json", "--quiet",
                   "-o", str(tmp_path / "cli" / template))
    cli = json.loads(done.stdout)
    for volume in (seg, npy):
        py = tmc.extract_labels_to(volume, tmp_path / "py" / template, close=close, stats=True)
        assert [e["label"] for e in py["labels"]] == [e["label"] for e in cli["labels"]]
        for got, want in zip(py["labels"], cli["labels"]):
            same_figures(got, want)
            rest = lambda e: {k: v for k, v in e.items() if k != "output"}  # noqa: E731
            assert rest(got) == rest(want)
    # Open, the labels on the volume's border have a boundary.
    assert {e["closed"] for e in cli["labels"]} == ({True} if close else {True, False})


def test_the_frogs_stats_are_the_cli_json_figures(tmp_path):
    frog = SHARED_DATA / "frog_tissues.nrrd"
    if not frog.is_file():
        pytest.skip(f"{frog} is absent (the shared test data)")
    done = run_cli("extract", str(frog), "--labels", "all", "--close", "--json", "--quiet",
                   "-o", str(tmp_path / "cli{label}.tmesh"))
    cli = json.loads(done.stdout)["labels"]
    py = tmc.extract_labels_to(frog, tmp_path / "py{label}.tmesh", close=True, stats=True)
    assert len(cli) >= 5 and len(py["labels"]) == len(cli)
    assert any(e["genus"] > 0 for e in cli) and any(e["components"] > 1 for e in cli)
    for got, want in zip(py["labels"], cli):
        assert got["label"] == want["label"]
        same_figures(got, want)


def file_figures(path: Path) -> dict:
    """Components, genus, area and enclosed volume of the mesh in `path` (a
    PLY tmc wrote), computed here: components of the vertex graph
    (scipy.sparse.csgraph), genus `(2C - χ - b) / 2` from `χ = V - E + F`
    over the distinct edges and `b`, the components of the graph of the
    edges of one triangle; area and volume summed in float64 in the order
    of the file's triangles from its float32 vertices, `|u x v| / 2` and
    `a . (b x c) / 6` (np.cumsum adds one term after the other)."""
    csgraph = pytest.importorskip("scipy.sparse.csgraph")
    sparse = pytest.importorskip("scipy.sparse")
    vertices, triangles = read_ply(path)
    t = triangles.astype(np.int64)
    n = len(vertices)
    assert len(t) > 0
    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    distinct, uses = np.unique(edges, axis=0, return_counts=True)
    assert uses.max() <= 2, "no edge of three triangles"

    def components(pairs: np.ndarray, nodes: np.ndarray) -> int:
        graph = sparse.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), (n, n))
        labels = csgraph.connected_components(graph, directed=False)[1]
        return len(np.unique(labels[nodes]))

    used = np.unique(t)
    assert len(used) == n, "every vertex used"
    count = components(distinct, used)
    boundary = distinct[uses == 1]
    loops = components(boundary, np.unique(boundary)) if len(boundary) else 0
    euler = n - len(distinct) + len(t)
    assert (2 * count - euler - loops) % 2 == 0
    a, b, c = (vertices[t[:, k]].astype(np.float64) for k in range(3))

    def cross(u, v):
        return np.stack([u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1],
                         u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2],
                         u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]], axis=1)

    normal = cross(b - a, c - a)
    area = np.sqrt(normal[:, 0] * normal[:, 0] + normal[:, 1] * normal[:, 1]
                   + normal[:, 2] * normal[:, 2]) / 2.0
    bc = cross(b, c)
    volume = (a[:, 0] * bc[:, 0] + a[:, 1] * bc[:, 1] + a[:, 2] * bc[:, 2]) / 6.0
    total = lambda x: float(np.cumsum(x)[-1]) if len(x) else 0.0  # noqa: E731
    figures = {"components": count, "genus": (2 * count - euler - loops) // 2,
               "closed": len(boundary) == 0, "area": total(area)}
    # Only a closed surface encloses a volume (an open one's sum moves with
    # the origin): reported for closed ones only.
    if figures["closed"]:
        figures["enclosed_volume"] = total(volume)
    return figures


# Generated maps and the genus of each label's closed surface by
# construction: label_map's ring (8) has one tunnel; Voronoi cells are
# convex, so none has.
MAPS = {"labels": (label_map, {8: 1}), "300-labels": (voronoi_map, {})}


@pytest.mark.parametrize("close", [True, False], ids=["close", "open"])
@pytest.mark.parametrize("name", sorted(MAPS))
def test_stats_match_an_independent_count(tmp_path, name, close):
    """Each label's figures against its file, counted here (file_figures),
    floats bit for bit; with close, the components are scipy.ndimage's
    6-connected components of the indicator (none has a cavity) and the
    genus is that of the map's shapes (MAPS)."""
    make, genus = MAPS[name]
    seg = make()
    spacing, origin = (0.5, 1.25, 2.0), (3.0, -1.0, 0.25)
    report = tmc.extract_labels_to(seg, tmp_path / "{label}.ply", close=close, stats=True,
                                   spacing=spacing, origin=origin, threads=2)
    assert len(report["labels"]) == len(np.unique(seg)) - (0 in seg)
    for entry in report["labels"]:
        label = entry["label"]
        want = file_figures(tmp_path / f"{label}.ply")
        want["label"] = label
        same_figures(entry, want)
        if close:
            assert entry["closed"] is True
            assert entry["components"] == oracle_components(seg == label), label
            assert entry["genus"] == genus.get(label, 0), label
            assert entry["enclosed_volume"] > 0, "outward triangles"
