#!/usr/bin/env python3
"""Writes the inputs of docs/formats.md "Inputs of unusual shape" (needs numpy,
pydicom and tifffile from PyPI).

Usage: scripts/make-shape-volumes.py DIR

* mf256.dcm: one multi-frame DICOM file, 256 frames of 256x256 u16
  (explicit VR little endian), concentric shells 1000 + 500 cos(r / 5);
  isovalue 1200;
* mp4096.tif: one multi-page TIFF, 4,096 pages of 64x64 u16, the same
  shells; isovalue 1200;
* tall.raw: 2x2x1,000,000 float32 (x fastest), uniform in [0, 1) (numpy
  seed 1); `--dims 2,2,1000000 --dtype f32`, isovalue 0.5.
"""
import sys
from pathlib import Path

import numpy as np
import tifffile
from pydicom.dataset import Dataset, FileMetaDataset
from pydicom.uid import ExplicitVRLittleEndian


def shells(n, nz):
    """1000 + 500 cos(r / 5) around the centre, u16, shape (nz, n, n)."""
    z, y, x = np.meshgrid(np.arange(nz), np.arange(n), np.arange(n), indexing="ij")
    r = np.sqrt((x - n / 2) ** 2 + (y - n / 2) ** 2 + (z - nz / 2) ** 2)
    return (1000 + 500 * np.cos(r / 5)).astype(np.uint16)


def multi_frame_dicom(path, n, nz):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = "1.2.840.10008.5.1.4.1.1.2"
    meta.MediaStorageSOPInstanceUID = "1.2.826.0.1.3680043.8.498.7778.1"
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    ds = Dataset()
    ds.file_meta = meta
    ds.SOPClassUID = meta.MediaStorageSOPClassUID
    ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
    ds.StudyInstanceUID = "1.2.826.0.1.3680043.8.498.7778.2"
    ds.SeriesInstanceUID = "1.2.826.0.1.3680043.8.498.7778.3"
    ds.FrameOfReferenceUID = "1.2.826.0.1.3680043.8.498.7778.4"
    ds.Modality = "CT"
    ds.Rows = ds.Columns = n
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = "MONOCHROME2"
    ds.BitsAllocated = ds.BitsStored = 16
    ds.HighBit = 15
    ds.PixelRepresentation = 0
    ds.NumberOfFrames = nz
    ds.ImagePositionPatient = [0.0, 0.0, 0.0]
    ds.ImageOrientationPatient = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
    ds.PixelSpacing = [1.0, 1.0]
    ds.SpacingBetweenSlices = ds.SliceThickness = 1.0
    ds.PixelData = shells(n, nz).tobytes()
    ds.save_as(path, enforce_file_format=True)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    multi_frame_dicom(out / "mf256.dcm", 256, 256)
    tifffile.imwrite(out / "mp4096.tif", shells(64, 4096))
    np.random.seed(1)
    np.random.rand(1000000, 2, 2).astype(np.float32).tofile(out / "tall.raw")


if __name__ == "__main__":
    main()
