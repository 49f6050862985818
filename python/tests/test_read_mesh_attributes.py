"""tmc.read_mesh keeps what a mesh file says beyond its positions and
triangles: the vertex normals (a .tmesh written with normals, PLY ``nx ny
nz``, NOFF, OBJ ``vn`` given one per vertex) and the per-triangle labels of
a label map's one-file output (PLY's ``label`` face property, .tmesh's labels
attribute). The files are written by numpy and by hand here (independent
writers: other property orders, big-endian, ASCII, polygons) as well as by
tmc, and each label's triangles are compared with the separate extraction
of that label."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest

import tmc


def ball(n: int = 16) -> np.ndarray:
    """A distance field whose 0.5 level is a sphere inside the volume."""
    z, y, x = np.mgrid[0:n, 0:n, 0:n].astype(np.float64)
    c = (n - 1) / 2
    return np.sqrt((x - c) ** 2 + (y - c) ** 2 + (z - c) ** 2) / (0.6 * n)


def write_binary_ply(path: Path, vertex_fields, vertices, face_fields, faces, big: bool) -> None:
    """A binary PLY written with numpy: ``vertex_fields`` and
    ``face_fields`` are (name, PLY type, numpy type) triples in file order,
    ``vertices`` and ``faces`` their columns by name; the face list is
    ``uchar int``."""
    order = ">" if big else "<"
    nv, nf = len(vertices["x"]), len(faces["vertex_indices"])
    lines = ["ply", f"format binary_{'big' if big else 'little'}_endian 1.0",
             "comment written by numpy for a test", f"element vertex {nv}"]
    lines += [f"property {ply} {name}" for name, ply, _ in vertex_fields]
    lines.append(f"element face {nf}")
    for name, ply, _ in face_fields:
        lines.append("property list uchar int vertex_indices" if name == "vertex_indices"
                     else f"property {ply} {name}")
    lines.append("end_header")
    vdtype = np.dtype([(name, order + np_type) for name, _, np_type in vertex_fields])
    face_dtype = []
    for name, _, np_type in face_fields:
        if name == "vertex_indices":
            face_dtype += [("n", "u1"), (name, order + "i4", (3,))]
        else:
            face_dtype.append((name, order + np_type))
    fdtype = np.dtype(face_dtype)
    vtable = np.zeros(nv, vdtype)
    for name in vdtype.names:
        vtable[name] = vertices[name]
    ftable = np.zeros(nf, fdtype)
    ftable["n"] = 3
    for name, _, _ in face_fields:
        ftable[name] = faces[name]
    path.write_bytes(("\n".join(lines) + "\n").encode() + vtable.tobytes() + ftable.tobytes())


def test_normals_come_back_from_every_format_that_holds_them(tmp_path: Path) -> None:
    mesh = tmc.extract(ball(), 0.5, normals=True)
    assert mesh.normals is not None and len(mesh.normals) > 100
    for name in ["m.ply", "m.obj"]:
        mesh.write(tmp_path / name)
        back = tmc.read_mesh(tmp_path / name)
        assert back.normals is not None, name
        assert back.normals.dtype == np.float32
        assert np.array_equal(back.normals, mesh.normals), name
        assert np.array_equal(back.triangles, mesh.triangles), name
        assert back.labels is None
    tmc.extract_to(ball(), 0.5, tmp_path / "m.tmesh", normals=True)
    back = tmc.read_mesh(tmp_path / "m.tmesh")
    assert np.array_equal(back.normals, mesh.normals)
    assert np.array_equal(back.vertices, mesh.vertices)
    # Without normals, none come back.
    plain = tmc.extract(ball(), 0.5)
    plain.write(tmp_path / "p.ply")
    plain.write(tmp_path / "p.obj")
    tmc.extract_to(ball(), 0.5, tmp_path / "p.tmesh")
    for name in ["p.ply", "p.obj", "p.tmesh"]:
        assert tmc.read_mesh(tmp_path / name).normals is None, name


@pytest.mark.parametrize("big", [False, True])
def test_a_foreign_ply_gives_its_normals_and_labels(tmp_path: Path, big: bool) -> None:
    """Properties in another order, with others between them, doubles,
    a quad (two triangles of one face, both with its label)."""
    rng = np.random.default_rng(7)
    n = 5
    vertices = {
        "nz": rng.normal(size=n), "x": rng.normal(size=n), "red": rng.integers(0, 255, n),
        "y": rng.normal(size=n), "nx": rng.normal(size=n), "z": rng.normal(size=n),
        "ny": rng.normal(size=n),
    }
    vfields = [("nz", "double", "f8"), ("x", "float", "f4"), ("red", "uchar", "u1"),
               ("y", "float", "f4"), ("nx", "double", "f8"), ("z", "float", "f4"),
               ("ny", "double", "f8")]
    faces = {"vertex_indices": np.array([[0, 1, 2], [2, 3, 4]]), "label": np.array([7, 4000000000]),
             "quality": np.array([0.5, 0.25])}
    ffields = [("quality", "float", "f4"), ("vertex_indices", "", "i4"), ("label", "uint", "u4")]
    path = tmp_path / "foreign.ply"
    write_binary_ply(path, vfields, vertices, ffields, faces, big)
    mesh = tmc.read_mesh(path)
    want_v = np.stack([vertices[a].astype(np.float32) for a in "xyz"], axis=1)
    assert np.array_equal(mesh.vertices, want_v.astype(np.float64))
    want_n = np.stack([vertices["n" + a].astype(np.float32) for a in "xyz"], axis=1)
    assert np.array_equal(mesh.normals, want_n)
    assert mesh.labels is not None and mesh.labels.dtype == np.uint32
    assert mesh.labels.tolist() == [7, 4000000000]
    assert mesh.triangles.tolist() == [[0, 1, 2], [2, 3, 4]]


def test_ascii_ply_polygons_take_their_face_label(tmp_path: Path) -> None:
    path = tmp_path / "quad.ply"
    path.write_text(
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
        "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
        "property int label\nend_header\n"
        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 2 2\n"
        "4 0 1 2 3 12\n3 1 4 2 5\n"
    )
    mesh = tmc.read_mesh(path)
    assert mesh.triangles.tolist() == [[0, 1, 2], [0, 2, 3], [1, 4, 2]]
    assert mesh.labels.tolist() == [12, 12, 5]
    assert mesh.normals is None
    # A label that is no uint32 is refused, naming the face.
    path.write_text(path.read_text().replace("3 1 4 2 5", "3 1 4 2 -5"))
    with pytest.raises(ValueError, match="face 1: label -5"):
        tmc.read_mesh(path)
    # Only nx and ny: no normals (not a normal of three components).
    partial = tmp_path / "partial.ply"
    partial.write_text(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nproperty float nx\nproperty float ny\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n"
        "0 0 0 1 0\n1 0 0 1 0\n0 1 0 1 0\n3 0 1 2\n"
    )
    assert tmc.read_mesh(partial).normals is None


def test_noff_and_obj_normals(tmp_path: Path) -> None:
    off = tmp_path / "n.off"
    off.write_text("NOFF\n4 2 0\n0 0 0 0 0 1\n1 0 0 0 0.5 1\n1 1 0 0 0 -1\n0 1 0 1 0 0\n"
                   "3 0 1 2\n3 0 2 3\n")
    mesh = tmc.read_mesh(off)
    assert mesh.normals.tolist() == [[0, 0, 1], [0, 0.5, 1], [0, 0, -1], [1, 0, 0]]
    # Plain OFF: none.
    (tmp_path / "p.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    assert tmc.read_mesh(tmp_path / "p.off").normals is None

    obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nvn 0 1 0\nvn 1 0 0\nvn 0 0 1\n"
    # Every corner names one normal per vertex: vertex 0 names 1 and 4,
    # which are equal; v/vt/vn and negative indices.
    good = tmp_path / "good.obj"
    good.write_text(obj + "f 1//1 2//2 3/1/3\nf 1//4 3//-2 4/1/-4\n")
    mesh = tmc.read_mesh(good)
    assert mesh.normals.tolist() == [[0, 0, 1], [0, 1, 0], [1, 0, 0], [0, 0, 1]]
    # A vertex shaded two ways (vertex 3 with normals 3 and 2): per corner,
    # so no per-vertex normals; nor when a corner names none.
    for faces in ["f 1//1 2//2 3//3\nf 1//1 3//2 4//1\n", "f 1//1 2//2 3//3\nf 1//1 3//3 4\n"]:
        (tmp_path / "per_corner.obj").write_text(obj + faces)
        assert tmc.read_mesh(tmp_path / "per_corner.obj").normals is None, faces
    # A normal index past the last vn is an error, as a vertex index is.
    (tmp_path / "bad.obj").write_text(obj + "f 1//1 2//2 3//9\n")
    with pytest.raises(ValueError, match="normal index 9 out of range"):
        tmc.read_mesh(tmp_path / "bad.obj")


def label_map() -> np.ndarray:
    """Three labels that touch each other and the border, and a lone voxel."""
    seg = np.zeros((10, 11, 12), dtype=np.uint16)
    seg[0:5, 0:6, 0:6] = 3
    seg[0:5, 0:6, 6:10] = 9
    seg[5:8, 2:8, 2:9] = 200
    seg[8, 9, 10] = 9
    return seg


def triangle_set(vertices: np.ndarray, triangles: np.ndarray) -> set:
    """The triangles as tuples of their corners' positions, each rotated to
    start at its smallest corner (orientation kept)."""
    out = set()
    for t in triangles:
        corners = [tuple(vertices[i]) for i in t]
        k = corners.index(min(corners))
        out.add(tuple(corners[k:] + corners[:k]))
    return out


@pytest.mark.parametrize("ext", ["ply", "tmesh"])
def test_one_file_of_labels_reads_back_with_each_label(tmp_path: Path, ext: str) -> None:
    seg = label_map()
    path = tmp_path / f"all.{ext}"
    tmc.extract_labels_to(seg, path, close=True, normals=True)
    mesh = tmc.read_mesh(path)
    assert mesh.labels is not None and len(mesh.labels) == len(mesh.triangles)
    assert sorted(set(mesh.labels.tolist())) == [3, 9, 200]
    assert mesh.normals is not None and len(mesh.normals) == len(mesh.vertices)
    for label in [3, 9, 200]:
        alone = tmc.extract((seg == label).astype(np.uint8), 0.5, close=True)
        mine = mesh.triangles[mesh.labels == label]
        assert len(mine) == len(alone.triangles), label
        assert triangle_set(mesh.vertices, mine) == triangle_set(alone.vertices, alone.triangles)
    # Written again from Python: PLY keeps the labels, OBJ holds none.
    mesh.write(tmp_path / "again.ply")
    again = tmc.read_mesh(tmp_path / "again.ply")
    assert np.array_equal(again.labels, mesh.labels)
    assert np.array_equal(again.normals, mesh.normals)
    mesh.write(tmp_path / "again.obj")
    assert tmc.read_mesh(tmp_path / "again.obj").labels is None
    # A mesh pickles with its labels.
    copy = pickle.loads(pickle.dumps(mesh))
    assert np.array_equal(copy.labels, mesh.labels)
    assert "labels" in repr(mesh)


def test_labels_given_to_a_mesh_are_checked_when_written(tmp_path: Path) -> None:
    mesh = tmc.extract(ball(), 0.5)
    m = len(mesh.triangles)
    mesh.labels = np.arange(m - 1)
    with pytest.raises(ValueError, match=f"{m - 1} labels for {m} triangles"):
        mesh.write(tmp_path / "x.ply")
    mesh.labels = np.full(m, -1)
    with pytest.raises(ValueError, match="label -1 of triangle 0 is not a uint32"):
        mesh.write(tmp_path / "x.ply")
    mesh.labels = np.full(m, 1.5)
    with pytest.raises(TypeError, match="labels must be integers"):
        mesh.write(tmp_path / "x.ply")
    assert not (tmp_path / "x.ply").exists()
    mesh.labels = np.arange(m, dtype=np.int64)
    mesh.write(tmp_path / "x.ply")
    assert tmc.read_mesh(tmp_path / "x.ply").labels.tolist() == list(range(m))


def test_an_empty_mesh_keeps_its_normals_and_labels(tmp_path: Path) -> None:
    """A mesh with no triangles still has the normals or labels its file
    declares (PLY's header, the .tmesh attributes): read_mesh gives them as
    empty arrays, not None, and Mesh.write puts them back, the bytes
    extract_to and extract_labels_to wrote. They were lost: read_mesh said
    None, and writing the empty mesh of extract(..., normals=True) left
    them out of PLY and .tmesh (OBJ cannot say it, and says the same
    either way)."""
    empty = tmc.extract(ball(), 5.0, normals=True)
    assert len(empty.triangles) == 0 and empty.normals is not None
    for ext in ["ply", "obj", "tmesh"]:
        streamed, written = tmp_path / f"s.{ext}", tmp_path / f"w.{ext}"
        tmc.extract_to(ball(), 5.0, streamed, normals=True)
        empty.write(written)
        assert written.read_bytes() == streamed.read_bytes(), ext
        back = tmc.read_mesh(streamed)
        if ext == "obj":
            assert back.normals is None
            continue
        assert back.normals is not None and back.normals.shape == (0, 3), ext
        assert back.normals.dtype == np.float32
    back = tmc.read_mesh(tmp_path / "s.ply")
    back.write(tmp_path / "again.ply")
    assert (tmp_path / "again.ply").read_bytes() == (tmp_path / "s.ply").read_bytes()
    # A label map's one file of labels none of which is present.
    for ext in ["ply", "tmesh"]:
        path = tmp_path / f"labels.{ext}"
        tmc.extract_labels_to(label_map(), path, labels=[7])
        back = tmc.read_mesh(path)
        assert back.labels is not None and back.labels.shape == (0,), ext
        assert back.labels.dtype == np.uint32
        assert back.normals is None
    back = tmc.read_mesh(tmp_path / "labels.ply")
    back.write(tmp_path / "labels-again.ply")
    assert (tmp_path / "labels-again.ply").read_bytes() == (tmp_path / "labels.ply").read_bytes()


def test_a_mesh_of_empty_lists_is_an_empty_mesh(tmp_path: Path) -> None:
    """Mesh([], []) (and normals=[]) is a mesh without vertices or
    triangles, as the empty mesh of an extraction is: it checks, draws and
    writes the bytes of that mesh in every format that takes it (numpy
    makes [] an array of shape (0,), which write, check and preview
    refused: "vertices must be an (N, 3) array")."""
    made = tmc.extract(ball(), 5.0, normals=True)
    given = tmc.Mesh([], [], normals=[])
    assert given.check() == made.check()
    given.preview(tmp_path / "given.png", title="t")
    made.preview(tmp_path / "made.png", title="t")
    assert (tmp_path / "given.png").read_bytes() == (tmp_path / "made.png").read_bytes()
    for ext in ["ply", "obj", "off", "stl"]:
        given.write(tmp_path / f"given.{ext}")
        made.write(tmp_path / f"made.{ext}")
        expected = (tmp_path / f"made.{ext}").read_bytes()
        assert (tmp_path / f"given.{ext}").read_bytes() == expected, ext
