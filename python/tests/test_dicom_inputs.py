"""DICOM inputs chosen from the package: a series of a directory of two
(written by pydicom at test time) by number or UID, as `--series` does, and
one segment of a Segmentation written by highdicom
(`scripts/fixtures/dicom_clinical.py seg`), as `--segment` does. Each mesh
is compared with that of the numpy array the files were written from, on
the same grid."""

import importlib.util
import subprocess
import sys

import numpy as np
import pytest

import tmc
from conftest import REPO, tmc_binary

pydicom = pytest.importorskip("pydicom")

SCRIPT = REPO / "scripts" / "fixtures" / "dicom_clinical.py"


def fixtures_module():
    """The fixture script, imported (its CT geometry and writer)."""
    spec = importlib.util.spec_from_file_location("dicom_clinical", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def write_series(folder, module, number, samples):
    """`samples` (nz, ny, nx) int16 as a CT series numbered `number`, one
    file per slice, on the script's CT geometry; its SeriesInstanceUID."""
    slices = module.ct_series()
    for k, ds in enumerate(slices):
        ds.SeriesNumber = number
        ds.PixelData = samples[k].astype("<i2").tobytes()
        ds.save_as(folder / f"s{number}_{k:02d}.dcm", enforce_file_format=True)
    return str(slices[0].SeriesInstanceUID)


def volumes(module):
    """Two volumes on the CT grid: a ball and a box, in HU-like values."""
    nx, ny, nz = module.SEG_DIMS
    z, y, x = np.mgrid[0:nz, 0:ny, 0:nx].astype(float)
    ball = 1000 - 60 * np.sqrt((x - 9.3) ** 2 + (y - 7.6) ** 2 + (2.8 * (z - 5.4)) ** 2)
    box = np.where((abs(x - 10) < 6) & (abs(y - 8) < 5) & (abs(z - 6) < 4), 800, -200)
    return ball.astype(np.int16), box.astype(np.int16)


def grid(module):
    spacing = module.SEG_SPACING
    return dict(spacing=spacing, origin=module.SEG_ORIGIN)


@pytest.fixture
def two_series(tmp_path):
    module = fixtures_module()
    ball, box = volumes(module)
    uid3 = write_series(tmp_path, module, 3, ball)
    uid5 = write_series(tmp_path, module, 5, box)
    return tmp_path, module, (ball, uid3), (box, uid5)


def same_mesh(a, b):
    assert len(a.triangles) > 50
    np.testing.assert_array_equal(a.vertices, b.vertices)
    np.testing.assert_array_equal(a.triangles, b.triangles)


def test_info_lists_the_series_and_picks_one(two_series):
    folder, module, (ball, uid3), (box, uid5) = two_series
    listing = tmc.info(folder)
    assert listing["format"] == "DICOM"
    assert [s["number"] for s in listing["series"]] == ["3", "5"]
    assert [s["uid"] for s in listing["series"]] == [uid3, uid5]
    assert all(s["readable"] and s["dims"] == [20, 16, 12] for s in listing["series"])
    facts = tmc.info(folder, series=5)
    assert facts["dims"] == [20, 16, 12]
    assert (facts["min"], facts["max"]) == (float(box.min()), float(box.max()))
    assert tmc.info(folder, series=uid3)["max"] == float(ball.max())


def test_extract_picks_a_series_by_number_or_uid(two_series, tmp_path):
    folder, module, (ball, uid3), (box, uid5) = two_series
    for volume, number, uid, iso in ((ball, 3, uid3, 600.5), (box, 5, uid5, 300.0)):
        want = tmc.extract(volume, iso, **grid(module))
        same_mesh(tmc.extract(folder, iso, series=number), want)
        same_mesh(tmc.extract(folder, iso, series=str(number)), want)
        same_mesh(tmc.extract(folder, iso, series=uid), want)
    # extract_to writes the bytes of `tmc extract DIR --series 3`.
    mine, cli = tmp_path / "mine.ply", tmp_path / "cli.ply"
    report = tmc.extract_to(folder, 600.5, mine, series=3)
    assert report["triangles"] > 50
    subprocess.run(
        [tmc_binary(), "extract", str(folder), "--iso", "600.5", "--series", "3",
         "-o", str(cli), "-q"],
        check=True,
    )
    assert mine.read_bytes() == cli.read_bytes()


def test_bad_series_choices_raise(two_series):
    folder, module, (ball, _), _ = two_series
    with pytest.raises(ValueError, match="DICOM series in one directory"):
        tmc.extract(folder, 600.5)
    with pytest.raises(ValueError, match="no DICOM series 99"):
        tmc.extract(folder, 600.5, series=99)
    with pytest.raises(ValueError, match="not of an array"):
        tmc.extract(ball, 600.5, series=3)
    with pytest.raises(TypeError, match="series must be"):
        tmc.info(folder, series=3.5)


def test_one_segment_of_a_segmentation(tmp_path):
    pytest.importorskip("highdicom")
    out = subprocess.run(
        [sys.executable, str(SCRIPT), "seg", str(tmp_path)],
        check=True, capture_output=True, text=True,
    ).stdout.split()
    origin, spacing = [float(v) for v in out[:3]], [float(v) for v in out[3:]]
    labels = np.load(tmp_path / "labels.npy")
    seg = tmp_path / "binary.dcm"
    facts = tmc.info(seg)
    assert [(s["number"], s["label"]) for s in facts["segments"]] == [
        (1, "ball"), (2, "box"), (3, "bar")
    ]
    assert facts["dims"] == [20, 16, 8]
    for n in (1, 2, 3):
        want = tmc.extract((labels == n).astype(np.uint8), 0.5, spacing=spacing, origin=origin)
        same_mesh(tmc.extract(seg, 0.5, segment=n), want)
    fractions = np.load(tmp_path / "fraction1.npy")
    want = tmc.extract(fractions, 0.5, spacing=spacing, origin=origin)
    same_mesh(tmc.extract(tmp_path / "fractional.dcm", 0.5, segment=1), want)
    assert tmc.info(tmp_path / "overlap.dcm")["overlapping_segments"] == [[1, 2]]
    with pytest.raises(ValueError, match="no segment 4"):
        tmc.extract(seg, 0.5, segment=4)
