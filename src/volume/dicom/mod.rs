//! DICOM series: a directory of single-slice files, one slice file (its
//! series is read from its directory), or one multi-frame file.
//!
//! DICOM stores a volume as many files in no particular order, each with its
//! own position and value scaling, so the reader's job is assembling the
//! series: parsing and decoding one file is left to the dicom-rs crates
//! (`dicom-object`, `dicom-pixeldata`, pure-Rust codecs only).
//!
//! * Files are recognised by the `DICM` magic at byte 128 (any name) or a
//!   `.dcm` extension; other files (a README, a DICOMDIR) are skipped. A
//!   file that looks like DICOM but does not parse is an error naming it.
//! * Files are grouped by `SeriesInstanceUID` from their headers alone
//!   (`series_index.rs`); several series in one directory are an error
//!   listing them unless one is chosen ([`open_series`] by UID or
//!   `SeriesNumber`, or by opening one file of the series), and
//!   [`list_series`] describes them all. Other series, non-image objects
//!   and files that do not parse are skipped, named in
//!   [`DicomSeries::skipped`]; copies of one image, unreadable files and
//!   slices that do not stack with the rest (localizers) are left out of
//!   the chosen series.
//! * Slices are sorted by their position along the slice normal
//!   (`row cosine x column cosine` of `ImageOrientationPatient`, position =
//!   `ImagePositionPatient . normal`), never by file name or
//!   `InstanceNumber`. The slice spacing comes from the sorted positions;
//!   uneven gaps (a missing slice), duplicate positions, slices not stacked
//!   along their normal (gantry tilt) and slices that differ in size, sample
//!   type, orientation or pixel spacing never stack (they are left out).
//! * The grid: dims = `[Columns, Rows, slices]`, spacing = `[column spacing,
//!   row spacing, slice spacing]` (`PixelSpacing` is `[row, column]`),
//!   origin = `ImagePositionPatient` of the first slice, direction columns =
//!   row cosine, column cosine and the normal. Coordinates stay in DICOM's
//!   patient system (LPS: x to the patient's left, y posterior, z head).
//!   A series without `PixelSpacing` gets 1 mm.
//! * `RescaleSlope`/`RescaleIntercept` are applied per slice, so CT values
//!   are Hounsfield units.
//! * Multi-frame files: frames are positioned by the per-frame
//!   `PlanePositionSequence` (enhanced objects; orientation, pixel measures
//!   and rescale from the per-frame or shared functional groups), else by
//!   one `ImagePositionPatient` moved along the normal by Grid Frame
//!   Offset Vector (RT Dose, `rt_dose.rs`: values scaled by Dose Grid
//!   Scaling) or stepped by `SpacingBetweenSlices` (or `SliceThickness`).
//! * Segmentation objects (SEG) are read on their own, as the label map of
//!   their segments or one segment alone ([`DicomSegmentation`],
//!   `segmentation.rs` and `seg_volume.rs`); [`open_source`] opens either
//!   kind.
//! * Only the headers are read at open. A plane is decoded when it is asked
//!   for, by parsing its file again. The last file parsed is kept, so the
//!   frames of a multi-frame file come from one parse of it (parsed for
//!   each frame, a 256-frame file of 33 MB took 4.8 s to read, in 8.6 GB of
//!   reads); nothing else of the volume is kept.
//! * Transfer syntaxes: implicit/explicit VR little endian, explicit VR big
//!   endian, deflate, RLE lossless, JPEG baseline/extended/lossless and
//!   JPEG 2000 and HTJ2K (lossless and lossy, through the pure-Rust OpenJPEG
//!   port). JPEG-LS and JPEG XL need codecs tmc leaves out and are refused
//!   at open, and pixel data a decoder fails on is an error when its plane
//!   is read; both name the transfer syntax and say how to decompress the
//!   files (`syntax.rs`). Attributes stored with VR UN are re-read under their
//!   dictionary VR (`unknown_vr.rs`). Samples must be greyscale (1 sample per pixel) of 8, 16 or 32
//!   bits, unsigned or signed.

mod attributes;
mod files;
mod header;
mod lengths;
mod rt_dose;
mod seg_volume;
mod segmentation;
mod series;
mod series_index;
mod syntax;
mod unknown_vr;
mod walker;

pub use files::{dir_has_dicom, has_magic};
pub use seg_volume::DicomSegmentation;
pub use series::DicomSeries;
pub use series_index::SeriesSummary;
pub use series_index::{list_series, open, open_series, open_source};
