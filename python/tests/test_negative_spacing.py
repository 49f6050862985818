"""Negative NRRD `spacings` and NIfTI `pixdim`: the CLI's index-to-world map
(`tmc info --json`) against the reference readers, pynrrd (with teem's
rule that a spacing keeps its sign: position = spacing * index) and
nibabel (whose affine uses |pixdim|, the header fixed on load). The files
are written by those libraries; the Rust side is tests/surface/edge_values.rs."""

from __future__ import annotations

import json

import numpy as np
import pytest

from conftest import run_cli

nrrd = pytest.importorskip("nrrd", reason="pynrrd is not installed")
nib = pytest.importorskip("nibabel", reason="nibabel is not installed")


def info_affine(path) -> np.ndarray:
    """The 4x4 index-to-world matrix `tmc info --json` reports."""
    return np.array(json.loads(run_cli("info", str(path), "--json").stdout)["affine"])


@pytest.mark.parametrize("spacings", [[-1.0, 2.0, 3.0], [1.5, -0.5, -4.0], [2.0, 3.0, 4.0]])
def test_nrrd_spacings_keep_their_sign(tmp_path, spacings):
    path = tmp_path / "v.nrrd"
    data = np.arange(24, dtype=np.uint8).reshape(2, 3, 4)  # pynrrd: x first
    nrrd.write(str(path), data, {"spacings": spacings, "encoding": "raw"})
    _, header = nrrd.read(str(path))
    # teem's nrrdSpacingCalculate hands a spacing on with its sign, and ITK
    # maps index i to origin + spacing * i: the signed diagonal.
    want = np.diag([*header["spacings"], 1.0])
    np.testing.assert_array_equal(info_affine(path), want)


@pytest.mark.parametrize("qfac", [1.0, -1.0])
@pytest.mark.parametrize("codes", [(1, 0), (0, 2)])
def test_nifti_negative_pixdim_as_nibabel_reads_it(tmp_path, qfac, codes):
    qform_code, sform_code = codes
    data = np.arange(24, dtype=np.uint8).reshape(2, 3, 4)
    affine = np.array(
        [[0.0, -3.0, 0.0, 10.0], [2.0, 0.0, 0.0, -5.0], [0.0, 0.0, 4.0 * qfac, 7.0], [0, 0, 0, 1]]
    )
    img = nib.Nifti1Image(data, affine)
    header = img.header
    header.set_qform(affine, code=qform_code)
    header.set_sform(affine if sform_code else None, code=sform_code)
    # Damage the stored voxel sizes' signs, as the files of the issue.
    header["pixdim"][1:4] = -np.abs(header["pixdim"][1:4])
    header["pixdim"][2] *= -1
    header["vox_offset"] = 352
    path = tmp_path / "v.nii"
    path.write_bytes(header.binaryblock + b"\0" * 4 + data.tobytes(order="F"))
    assert (np.frombuffer(path.read_bytes()[76:92], "<f4")[1:4] < 0).any()
    loaded = nib.load(str(path))
    np.testing.assert_allclose(info_affine(path), loaded.affine, rtol=1e-6, atol=1e-6)
