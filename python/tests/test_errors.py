"""Bad input raises ValueError or TypeError with the CLI's words, and never
leaves anything at an output path."""

from __future__ import annotations

import numpy as np
import pytest

import tmc

GOOD = np.zeros((4, 5, 6), dtype=np.float32)


@pytest.mark.parametrize(
    "volume, error, words",
    [
        (np.zeros((4, 5)), ValueError, "expected a 3-D array"),
        (np.zeros((2, 3, 4, 5)), ValueError, r"shape \(2, 3, 4, 5\) is not one volume: axis 0"),
        (np.zeros((1, 2, 3, 4, 5)), ValueError, "is not one volume: axis 1 has size 2"),
        # A channel axis last: the volume is volume[..., 0] (volume[0] a plane).
        (np.zeros((4, 5, 6, 1)), ValueError, r"axis 0 has size 4.*volume\[\.\.\., 0\]"),
        (np.zeros((2, 4, 5, 6)), ValueError, r"axis 0 has size 2.*volume\[0\]"),
        (np.zeros((4, 5, 6), dtype=np.complex64), TypeError, "unsupported dtype"),
        (np.zeros((4, 5, 6), dtype=object), TypeError, "unsupported dtype"),
        (np.zeros((4, 5, 6), dtype="U3"), TypeError, "unsupported dtype"),
        (np.zeros((4, 5, 6), dtype=np.clongdouble), TypeError, "unsupported dtype"),
        (np.zeros((4, 5, 6), dtype="m8[s]"), TypeError, "unsupported dtype"),
        (np.zeros((0, 5, 6), dtype=np.uint8), ValueError, "contain a zero"),
        (np.zeros((1, 5, 6), dtype=np.uint8), ValueError, "need at least 2 on every axis"),
    ],
)
def test_bad_volumes(tmp_path, volume, error, words):
    with pytest.raises(error, match=words):
        tmc.extract(volume, 0.5)
    with pytest.raises(error, match=words):
        tmc.extract_to(volume, 0.5, tmp_path / "out.ply")
    assert list(tmp_path.iterdir()) == []
    if volume.ndim != 3 or volume.dtype.kind in "cOU":
        with pytest.raises(error):
            tmc.marching_cubes(volume, 0.5)


@pytest.mark.parametrize("iso", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_isovalue(tmp_path, iso):
    with pytest.raises(ValueError, match="the isovalue must be a finite number"):
        tmc.extract(GOOD, iso)
    with pytest.raises(ValueError, match="the isovalue must be a finite number"):
        tmc.extract_to(GOOD, iso, tmp_path / "out.ply")
    with pytest.raises(ValueError, match="finite"):
        tmc.marching_cubes(GOOD, iso)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "spacing", [(float("nan"), 1, 1), (1, 0, 1), (1, -2, 1), (1, 1, float("inf"))]
)
def test_bad_spacing(spacing):
    with pytest.raises(ValueError, match="spacing .* must be finite and positive"):
        tmc.extract(GOOD, 0.5, spacing=spacing)
    with pytest.raises(ValueError, match="spacing"):
        tmc.marching_cubes(GOOD, 0.5, spacing=spacing[::-1])


def test_bad_arguments(tmp_path):
    with pytest.raises(ValueError, match="origin"):
        tmc.extract(GOOD, 0.5, origin=(0, float("nan"), 0))
    with pytest.raises(ValueError, match="three numbers"):
        tmc.extract(GOOD, 0.5, spacing=(1, 1))
    with pytest.raises(ValueError, match="unknown method"):
        tmc.extract(GOOD, 0.5, method="flying-edges")
    with pytest.raises(ValueError, match="unknown inside"):
        tmc.extract(GOOD, 0.5, inside="middle")
    with pytest.raises(ValueError, match="threads"):
        tmc.extract(GOOD, 0.5, threads=-1)
    # As --threads: at most 1024 (not an OverflowError of the binding),
    # and a whole number (1.5 was taken as 1, "2" as 2).
    for bad, error in [(10**30, ValueError), (1025, ValueError), (1.5, TypeError), ("2", TypeError)]:
        with pytest.raises(error, match="threads"):
            tmc.extract(GOOD, 0.5, threads=bad)
    assert len(tmc.extract(GOOD, 0.5, threads=np.int64(2)).triangles) == 0
    with pytest.raises(ValueError, match="header"):
        tmc.extract(tmp_path / "v.npy", 0.5, spacing=(1, 1, 1))


def test_bad_files(tmp_path):
    with pytest.raises(FileNotFoundError):
        tmc.extract(tmp_path / "missing.nrrd", 0.5)
    junk = tmp_path / "junk.npy"
    junk.write_bytes(b"not numpy at all")
    with pytest.raises(ValueError, match="not a .npy file"):
        tmc.extract(junk, 0.5)
    with pytest.raises(ValueError):
        tmc.extract_to(GOOD, 0.5, tmp_path / "out.unknown")
    with pytest.raises(ValueError, match="is the input"):
        np.save(tmp_path / "v.npy", GOOD)
        tmc.extract_to(tmp_path / "v.npy", 0.5, tmp_path / "v.npy")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["junk.npy", "v.npy"]
    with pytest.raises(FileNotFoundError):
        tmc.read_mesh(tmp_path / "missing.ply")
    with pytest.raises(ValueError):
        tmc.read_mesh(junk)
    with pytest.raises(FileNotFoundError):
        tmc.info(tmp_path / "missing.nrrd")


def test_bad_mesh_arrays(tmp_path):
    """A Mesh's triangles must be integer indices, none negative (a cast
    truncated 1.5 to 1 and wrapped -1 to 4294967295), and its vertices
    finite as float32 (NaN or 1e300 was written into PLY, OBJ, OFF and STL
    files that tmc check then refused); nothing is left at the path."""
    mesh = tmc.extract(np.pad(np.ones((3, 3, 3), np.float32), 1), 0.5)
    assert len(mesh.triangles) > 0
    for bad in (mesh.triangles + 0.5, mesh.triangles.astype(float)):
        with pytest.raises(TypeError, match="integer vertex indices"):
            tmc.Mesh(mesh.vertices, bad).write(tmp_path / "f.ply")
        with pytest.raises(TypeError, match="integer vertex indices"):
            tmc.Mesh(mesh.vertices, bad).check()
    negative = mesh.triangles.astype(np.int64)
    negative[3, 1] = -1
    with pytest.raises(ValueError, match="triangle 3 .* negative vertex index"):
        tmc.Mesh(mesh.vertices, negative).check()
    for value in (np.nan, np.inf, 1e300):
        vertices = mesh.vertices.copy()
        vertices[5, 2] = value
        for suffix in (".ply", ".obj", ".off", ".stl"):
            with pytest.raises(ValueError, match="vertex 5 .* not finite"):
                tmc.Mesh(vertices, mesh.triangles).write(tmp_path / f"v{suffix}")
    assert list(tmp_path.iterdir()) == []
    # Integer triangles of any width, and the mesh itself, still write.
    tmc.Mesh(mesh.vertices, mesh.triangles.astype(np.int64)).write(tmp_path / "ok.ply")
    assert tmc.read_mesh(tmp_path / "ok.ply").triangles.shape == mesh.triangles.shape


def test_arguments_not_taken_apart(tmp_path):
    """A string is not three numbers ("123" was spacing (1, 2, 3)), and a
    negative count is a ValueError naming it (was the binding's
    OverflowError)."""
    with pytest.raises(ValueError, match="spacing must be three numbers"):
        tmc.extract(GOOD, 0.5, spacing="123")
    with pytest.raises(ValueError, match="origin must be three numbers"):
        tmc.extract(GOOD, 0.5, origin=b"000")
    path = tmp_path / "v.npy"
    np.save(path, GOOD)
    for name in ("bins", "plane_step"):
        with pytest.raises(ValueError, match=f"{name} must be 0 or more"):
            tmc.info(path, **{name: -1})


BOOL_OPTIONS = [
    (tmc.extract, ("close", "normals"), (0.5,)),
    (tmc.extract_to, ("close", "normals"), (0.5, "OUT")),
    (tmc.extract_labels, ("close", "normals"), ()),
    (tmc.extract_labels_to, ("close", "normals", "stats"), ("OUT",)),
    (tmc.marching_cubes, ("allow_degenerate",), (0.5,)),
]


@pytest.mark.parametrize("function, names, args", BOOL_OPTIONS)
def test_bool_options_take_only_bools(tmp_path, function, names, args):
    """A boolean option is True/False or a numpy bool; "no", 1 or None is a
    TypeError naming it (``bool("no")`` is True: it silently meant yes)."""
    volume = np.zeros((4, 5, 6), dtype=np.uint8)
    volume[1:3, 1:4, 1:5] = 1
    args = tuple(str(tmp_path / "out.ply") if a == "OUT" else a for a in args)
    for name in names:
        for bad in ("no", "False", 1, 0, None, 1.0, [True]):
            with pytest.raises(TypeError, match=f"{name} must be True or False, not"):
                function(volume, *args, **{name: bad})
    assert list(tmp_path.iterdir()) == []
    for name in names:
        for good in (True, False, np.bool_(True), np.bool_(False)):
            function(volume, *args, **{name: good})


def test_masked_array_refused():
    """A masked array's mask would be ignored: refused, pointing to
    ``.filled(value)``; one with nothing masked is its data."""
    volume = np.ma.masked_array(np.zeros((4, 5, 6), np.float32), mask=False)
    volume.mask[0, 0, 0] = True
    for call in (
        lambda v: tmc.extract(v, 0.5),
        lambda v: tmc.extract_labels(v.astype(np.uint8)),
        lambda v: tmc.marching_cubes(v, 0.5),
    ):
        with pytest.raises(TypeError, match=r"masked array.*\.filled\(value\)"):
            call(volume)
    nothing_masked = np.ma.masked_array(GOOD, mask=False)
    assert len(tmc.extract(nothing_masked, 0.5).triangles) == 0


def test_leading_unit_axes_are_the_volume(tmp_path):
    """(1, nz, ny, nx), as the .npy reader takes it, in C or Fortran order,
    and a memmap of one: the mesh of (nz, ny, nx)."""
    rng = np.random.default_rng(3)
    volume = rng.random((5, 6, 7)).astype(np.float32)
    want = tmc.extract(volume, 0.5)
    path = tmp_path / "v.npy"
    np.save(path, volume[None, None])
    for four in (
        volume[None],
        volume[None, None],
        np.asfortranarray(volume[None]),
        np.load(path, mmap_mode="r"),
    ):
        got = tmc.extract(four, 0.5)
        assert np.array_equal(got.vertices, want.vertices)
        assert np.array_equal(got.triangles, want.triangles)
    labels = (volume > 0.5).astype(np.uint8)
    assert tmc.extract_labels(labels[None])[1].triangles.shape == (
        tmc.extract_labels(labels)[1].triangles.shape
    )


def test_numbers_and_counts_are_not_converted_from_other_types(tmp_path):
    """A string is not an isovalue ("1" was taken as 1.0), 1.5 not a
    segment (was segment 1) nor a step (was step 1), True not a series
    (was the series "True"): TypeError naming the argument, nothing
    written."""
    for bad in ("1", b"1", True, None, [1]):
        with pytest.raises(TypeError, match="iso must be a number"):
            tmc.extract(GOOD, bad)
        with pytest.raises(TypeError, match="iso must be a number"):
            tmc.extract_to(GOOD, bad, tmp_path / "out.ply")
    with pytest.raises(TypeError, match="level must be a number"):
        tmc.marching_cubes(GOOD, "0.5")
    path = tmp_path / "v.npy"
    np.save(path, GOOD)
    for bad in (1.5, "a", True):
        with pytest.raises(TypeError, match="segment must be a segment number"):
            tmc.extract(path, 0.5, segment=bad)
        with pytest.raises(TypeError, match="segment must be a segment number"):
            tmc.info(path, segment=bad)
    for bad in (True, 1.5, b"1"):
        with pytest.raises(TypeError, match="series must be a number or a UID"):
            tmc.info(path, series=bad)
    for bad in (1.5, "2", True):
        with pytest.raises(TypeError, match="step_size must be an integer"):
            tmc.marching_cubes(GOOD, 0.5, step_size=bad)
    for name, bad in (("method", 1), ("method", None), ("inside", None), ("inside", 1)):
        with pytest.raises(TypeError, match=f"{name} must be"):
            tmc.extract(GOOD, 0.5, **{name: bad})
    with pytest.raises(TypeError, match="method must be"):
        tmc.marching_cubes(GOOD, 0.5, method=["tmc"])
    assert list(tmp_path.iterdir()) == [path]
    # numpy scalars are numbers.
    assert tmc.extract(GOOD, np.float32(0.5)).stats["iso"] == 0.5


@pytest.mark.parametrize("shape", [(0, 5, 6), (4, 0, 6), (4, 5, 1)])
def test_marching_cubes_names_a_too_small_shape(shape):
    """An axis of 0 samples gave numpy's "zero-size array to reduction
    operation fmin which has no identity"; now the shape and the rule."""
    with pytest.raises(ValueError, match=r"needs at least 2 samples along every axis"):
        tmc.marching_cubes(np.zeros(shape, np.float32), 0.5)


def test_marching_cubes_spacing_error_in_the_callers_order():
    """The message lists the spacing as given (array axis order), not
    reversed into tmc's x, y, z."""
    with pytest.raises(ValueError, match=r"spacing \[0\.0, 1\.0, 2\.0\] must be finite and positive"):
        tmc.marching_cubes(GOOD, 0.5, spacing=(0, 1, 2))


def test_indices_of_2_to_the_32_are_refused_not_wrapped(tmp_path):
    """uint64/int64 triangles past 2**32 were cast to uint32, wrapping
    2**33 + k to k: a file of valid indices of the wrong vertices was
    written. Now a ValueError naming the triangle, nothing written."""
    mesh = tmc.extract(np.pad(np.ones((3, 3, 3), np.float32), 1), 0.5)
    for dtype in (np.uint64, np.int64):
        wrapped = mesh.triangles.astype(dtype)
        wrapped[2, 0] += 2**33
        with pytest.raises(ValueError, match=r"triangle 2 .* index of 2\*\*32 or more"):
            tmc.Mesh(mesh.vertices, wrapped).write(tmp_path / "m.ply")
        with pytest.raises(ValueError, match=r"triangle 2 .* index of 2\*\*32 or more"):
            tmc.Mesh(mesh.vertices, wrapped).check()
    assert list(tmp_path.iterdir()) == []


def test_counts_name_themselves(tmp_path):
    """bins, plane_step and background of another type, or too large for
    the binding, are TypeError / ValueError naming the argument (were
    "'float' object cannot be interpreted as an integer" and OverflowError
    "int too big to convert")."""
    path = tmp_path / "v.npy"
    np.save(path, GOOD)
    for name in ("bins", "plane_step"):
        for bad in (1.5, True, "8"):
            with pytest.raises(TypeError, match=f"{name} must be an integer"):
                tmc.info(path, **{name: bad})
        with pytest.raises(ValueError, match=f"{name} must be less than 2\\*\\*63"):
            tmc.info(path, **{name: 10**20})
    labels = np.zeros((4, 5, 6), np.uint8)
    labels[1:3, 1:3, 1:3] = 1
    for bad in (1.5, True, "0"):
        with pytest.raises(TypeError, match="background must be an integer"):
            tmc.extract_labels(labels, background=bad)


def test_output_directory_errors_are_one_class_before_the_run_and_at_the_write(tmp_path):
    """A missing output directory raised ValueError from the check before
    a run (extract_to, extract_labels_to) but FileNotFoundError from
    Mesh.write, which has no such check: now every call raises the OSError
    subclass of what is wrong (FileNotFoundError, NotADirectoryError,
    IsADirectoryError), with the CLI's words, and writes nothing."""
    ball = np.zeros((6, 6, 6), np.float32)
    ball[2:4, 2:4, 2:4] = 1
    mesh = tmc.extract(ball, 0.5)
    seg = (ball > 0).astype(np.uint8)
    (tmp_path / "file").write_bytes(b"")
    (tmp_path / "dir.ply").mkdir()
    writers = {
        "extract_to": lambda out: tmc.extract_to(ball, 0.5, out),
        "extract_labels_to": lambda out: tmc.extract_labels_to(seg, out),
        "Mesh.write": mesh.write,
    }
    cases = [
        (tmp_path / "missing" / "m.ply", FileNotFoundError, "does not exist"),
        (tmp_path / "file" / "m.ply", NotADirectoryError, None),
        (tmp_path / "dir.ply", IsADirectoryError, None),
    ]
    for out, error, words in cases:
        for name, write in writers.items():
            with pytest.raises(error, match=words) as caught:
                write(out)
            assert str(out) in str(caught.value), (name, caught.value)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dir.ply", "file"]
    assert list((tmp_path / "dir.ply").iterdir()) == []


def test_extract_to_refuses_a_placeholder_it_does_not_fill_in(tmp_path):
    # tmc.extract_to fills in no placeholder: '{stem}' and '{iso}', which
    # the CLI's -o fills in, stayed in the file's name ('{stem}_{iso}.ply'
    # was written as such), as any '{NAME}' did. Refused before the volume
    # is read, naming it, as extract_labels_to refuses those it does not
    # fill in; other braces are text.
    volume = np.random.default_rng(3).random((4, 5, 6))
    for template in ("{stem}_{iso}.ply", "{iso}.tmesh", "{part}.ply", "{label}.obj"):
        with pytest.raises(ValueError, match=r"unknown placeholder \{\w+\} in output; it may use none"):
            tmc.extract_to(volume, 0.5, tmp_path / template)
        with pytest.raises(ValueError, match=r"unknown placeholder \{\w+\} in output; it may use none"):
            tmc.extract_to(tmp_path / "missing.npy", 0.5, tmp_path / template)
    assert list(tmp_path.iterdir()) == []
    tmc.extract_to(volume, 0.5, tmp_path / "{}{a b}.ply")
    assert [p.name for p in tmp_path.iterdir()] == ["{}{a b}.ply"]


def test_normals_into_a_format_without_them_are_refused(tmp_path):
    # normals=True into .off or .stl, which hold no vertex normals, computed
    # them and wrote a file without them; tmc extract --normals refuses
    # such an output with the same words, before the volume is read.
    volume = np.random.default_rng(4).random((4, 5, 6))
    labels = (volume > 0.5).astype(np.uint8)
    for suffix in (".off", ".stl", ".OFF"):
        with pytest.raises(ValueError, match=r"needs an output that holds vertex normals \(\.ply, \.obj or \.tmesh\)"):
            tmc.extract_to(volume, 0.5, tmp_path / f"m{suffix}", normals=True)
        with pytest.raises(ValueError, match=r"needs an output that holds vertex normals"):
            tmc.extract_labels_to(labels, tmp_path / f"{{label}}{suffix}", normals=True)
    assert list(tmp_path.iterdir()) == []
    tmc.extract_to(volume, 0.5, tmp_path / "m.off")
    tmc.extract_labels_to(labels, tmp_path / "{label}.stl")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["1.stl", "m.off"]


def test_spacing_and_origin_are_three_numbers_in_order():
    """spacing and origin are an ordered sequence of three real numbers: a
    set or a dict (whose order is not the caller's: {3, 1, 2} iterated as
    1, 2, 3 and was spacing (1, 2, 3); a dict gave its keys) raises
    ValueError, so does a bool (TypeError in marching_cubes, as iso=True;
    spacing (True, True, True) was (1, 1, 1)), and an integer past float's
    range names the argument (was the bare OverflowError "int too large to
    convert to float"), for extract, the label calls and marching_cubes
    alike."""
    box = np.zeros((4, 5, 6), dtype=np.uint8)
    box[1:3, 1:4, 1:5] = 1
    calls = {
        "extract": lambda **kw: tmc.extract(box, 0.5, **kw),
        "extract_labels": lambda **kw: tmc.extract_labels(box, **kw),
        "marching_cubes": lambda **kw: tmc.marching_cubes(box, 0.5, **kw),
    }
    for name, call in calls.items():
        arguments = ["spacing"] if name == "marching_cubes" else ["spacing", "origin"]
        for argument in arguments:
            for unordered in ({3.0, 1.0, 2.0}, frozenset({3, 1, 2}), {3: 0, 1: 0, 2: 0}):
                with pytest.raises(ValueError, match=f"{argument}.*three numbers"):
                    call(**{argument: unordered})
            with pytest.raises((TypeError, ValueError), match=f"{argument} must be"):
                call(**{argument: (True, 1.0, 1.0)})
            with pytest.raises(ValueError, match=f"{argument}.*finite"):
                call(**{argument: (10**400, 1, 1)})
        # Ordered sequences of numbers, numpy's included, are taken.
        call(spacing=np.array([3.0, 1.0, 2.0], dtype=np.float32))
    for huge in (10**400, -(10**400)):
        with pytest.raises(ValueError, match="iso must be a finite number"):
            tmc.extract(box, huge)
        with pytest.raises(ValueError, match="level must be a finite number"):
            tmc.marching_cubes(box, huge)
