"""Preview pictures from Python: ``extract_to(..., preview=)`` writes the
bytes of ``tmc extract --preview`` for the same file, ``Mesh.preview`` the
bytes of ``tmc preview`` of the mesh written as PLY (same title); Pillow
decodes them at the stated size with something drawn, the same for any
threads; bad picture paths raise with nothing written."""

import numpy as np
import pytest

import tmc
from conftest import REPO, run_cli

Image = pytest.importorskip("PIL.Image")
HEAD = REPO / "data" / "headsq_quarter.nrrd"


def decoded(path):
    """The picture as an RGB array, by Pillow."""
    with Image.open(path) as picture:
        assert picture.format == "PNG"
        return np.asarray(picture.convert("RGB"))


def drawn(rgb):
    """Pixels that differ from the top-left corner's (the background)."""
    return int((rgb != rgb[0, 0]).any(axis=-1).sum())


def test_extract_to_with_a_preview_writes_the_clis_picture(tmp_path):
    mesh, picture = tmp_path / "head.tmesh", tmp_path / "head.png"
    report = tmc.extract_to(HEAD, 500, mesh, preview=picture, threads=1)
    assert report["triangles"] > 1000
    cli_mesh, cli_picture = tmp_path / "cli.tmesh", tmp_path / "cli.png"
    run_cli("extract", str(HEAD), "--iso", "500", "-o", str(cli_mesh),
            "--preview", str(cli_picture), "-q")
    assert picture.read_bytes() == cli_picture.read_bytes()
    assert mesh.read_bytes() == cli_mesh.read_bytes()
    rgb = decoded(picture)
    assert rgb.shape[0] >= 900 and rgb.shape[1] >= 900
    assert drawn(rgb) > 0.05 * rgb.shape[0] * rgb.shape[1]
    two = tmp_path / "two.png"
    tmc.extract_to(HEAD, 500, tmp_path / "two.ply", preview=two, threads=2)
    assert two.read_bytes() == picture.read_bytes()


def test_an_arrays_preview_is_drawn_the_same_for_any_threads(tmp_path):
    z, y, x = np.mgrid[0:30, 0:32, 0:34]
    ball = 12.0 - np.sqrt((x - 16.5) ** 2 + (y - 15.5) ** 2 + (z - 14.5) ** 2)
    pictures = []
    for threads in (1, 2):
        # The same output name: the caption's title.
        (tmp_path / str(threads)).mkdir()
        picture = tmp_path / str(threads) / "ball.png"
        tmc.extract_to(ball, 0.0, tmp_path / str(threads) / "ball.tmesh", preview=picture,
                       close=True, threads=threads)
        pictures.append(picture.read_bytes())
    assert pictures[0] == pictures[1]
    assert drawn(decoded(tmp_path / "1" / "ball.png")) > 1000


def test_mesh_preview_draws_what_tmc_preview_draws(tmp_path):
    mesh = tmc.extract(HEAD, 500)
    ply, ours, theirs = tmp_path / "m.ply", tmp_path / "ours.png", tmp_path / "theirs.png"
    mesh.write(ply)
    mesh.preview(ours, title="skin")
    run_cli("preview", str(ply), "-o", str(theirs), "--title", "skin", "-q")
    assert ours.read_bytes() == theirs.read_bytes()
    assert drawn(decoded(ours)) > 0
    one = tmp_path / "one.png"
    mesh.preview(one, title="skin", threads=1)
    assert one.read_bytes() == ours.read_bytes()
    # The default title is the input file's name.
    default, named = tmp_path / "default.png", tmp_path / "named.png"
    mesh.preview(default)
    mesh.preview(named, title=HEAD.name)
    assert default.read_bytes() == named.read_bytes()
    # A mesh read from a file, or built by hand, is drawn all the same.
    tet = tmc.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float),
                   np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], np.uint32))
    tet.preview(tmp_path / "tet.png")
    assert drawn(decoded(tmp_path / "tet.png")) > 0


def test_bad_picture_paths_raise_and_write_nothing(tmp_path):
    mesh = tmc.extract(HEAD, 500)
    with pytest.raises(ValueError, match="png"):
        mesh.preview(tmp_path / "x.jpg")
    with pytest.raises(FileNotFoundError):
        mesh.preview(tmp_path / "missing" / "x.png")
    with pytest.raises(ValueError, match="png"):
        tmc.extract_to(HEAD, 500, tmp_path / "m.ply", preview=tmp_path / "x.gif")
    with pytest.raises(ValueError, match="placeholder"):
        tmc.extract_to(HEAD, 500, tmp_path / "m.ply", preview=tmp_path / "{stem}.png")
    with pytest.raises(TypeError):
        mesh.preview(tmp_path / "x.png", title=3)
    corners = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    with pytest.raises(ValueError, match="triangle 0 .* past the 3 vertices"):
        tmc.Mesh(corners, np.array([[0, 1, 5]], np.uint32)).preview(tmp_path / "x.png")
    corners[0, 2] = np.nan
    with pytest.raises(ValueError, match="vertex 0 .* not finite"):
        tmc.Mesh(corners, np.array([[0, 1, 2]], np.uint32)).preview(tmp_path / "x.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_extract_labels_to_with_a_preview_writes_the_clis_picture(tmp_path):
    """A label map's picture: the CLI's bytes for the same file, the same
    from an array (titled with the output's name, as ``tmc preview`` of the
    one ``.tmesh`` titled so) and for one or two threads; a bad picture
    path raises with nothing written."""
    z, y, x = np.mgrid[0:24, 0:22, 0:26]
    seg = ((x // 9) + 3 * (y // 8) + 1).astype(np.uint16)
    seg[(x - 13) ** 2 + (y - 11) ** 2 + (z - 12) ** 2 < 30] = 40
    path = tmp_path / "seg.npy"
    np.save(path, seg)
    out = tmp_path / "py"
    out.mkdir()
    report = tmc.extract_labels_to(path, out / "{label}.ply", close=True,
                                   preview=tmp_path / "py.png", threads=1)
    assert len(report["labels"]) == 10
    run_cli("extract", str(path), "--labels", "all", "--close", "-o",
            str(tmp_path / "{label}.tmesh"), "--preview", str(tmp_path / "cli.png"), "-q")
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    tmc.extract_labels_to(seg, tmp_path / "all.tmesh", close=True,
                          preview=tmp_path / "array.png", threads=2)
    run_cli("preview", str(tmp_path / "all.tmesh"), "-o", str(tmp_path / "again.png"),
            "--title", "all.tmesh")
    assert (tmp_path / "array.png").read_bytes() == (tmp_path / "again.png").read_bytes()
    rgb = decoded(tmp_path / "array.png")
    assert drawn(rgb) > 0.05 * rgb.shape[0] * rgb.shape[1]
    bad = tmp_path / "bad"
    bad.mkdir()
    for picture, error in ((bad / "p.jpg", ValueError), (bad / "no" / "p.png", OSError),
                           (bad / "{label}.png", ValueError)):
        with pytest.raises(error):
            tmc.extract_labels_to(seg, bad / "{label}.ply", preview=picture)
        assert list(bad.iterdir()) == []
