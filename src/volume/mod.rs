//! Sample sources: a regular grid of scalar samples read one z-plane at a time.
//!
//! Every reader (one file per format) implements [`SampleSource`]; the slab
//! loop only ever asks for whole planes, so a reader may memory-map its file
//! and convert a plane on demand without holding the volume in memory.
//! [`write_volume`] goes the other way: it writes any source, plane by
//! plane, as a `.nrrd`, `.npy` or raw file.

mod array;
mod ascii;
mod chunk_layers;
pub mod dicom;
mod guarded;
pub mod hdf5;
mod held;
pub mod histogram;
pub mod info;
mod label_runs;
mod labels;
mod layered;
pub mod leading_axes;
mod lent;
mod mapped;
pub mod metaimage;
pub mod nifti;
mod notes;
pub mod npy;
pub mod nrrd;
mod nrrd_data;
mod nrrd_header;
mod nrrd_pattern;
mod open;
mod padded;
pub mod raw;
mod regrid;
mod sample;
mod scalar;
mod shared;
mod slab_stack;
mod source;
mod spill;
mod strided;
pub mod summary;
mod tiff_meta;
mod tiff_pages;
pub mod tiff_stack;
mod units;
pub mod vti;
pub mod vtk_legacy;
pub mod write;
pub mod zarr;
mod zarr_ome;

pub use crate::files::check_input_kind;
pub(crate) use crate::grid::set_direction;
pub use crate::grid::{Grid, IDENTITY};
pub use array::ArrayVolume;
pub use guarded::in_guarded_call;
pub use held::HeldPlanes;
pub use info::{
    automatic_plane_step, describe, volume_info, VolumeInfo, HISTOGRAM_BUDGET, MAX_BINS, MIN_BINS,
};
pub use label_runs::{MapRuns, PlaneRuns};
#[cfg(test)]
pub(crate) use labels::scan as scan_keeping_runs;
pub use labels::{
    plane_runs, scan_label_map, scan_labels, scan_labels_on, LabelCounts, MOST_LABELS,
};
pub use layered::{LayerReader, LayeredVolume};
pub use lent::{LentPlane, PlaneView};
pub use notes::{ChunkNotes, SegmentNote, SourceNotes, ValueFrom};
pub use open::{
    dicom_series_to_choose, format_name, open, open_cancellable, open_selected, Format,
};
pub use padded::Padded;
pub use raw::{RawOptions, RawVolume};
pub use regrid::{regrid, Regridded};
pub use sample::{Sample, Threshold};
pub use scalar::{decode_samples, decode_strided, encode_samples, Endian, ScalarType};
pub use shared::SharedPlane;
pub(crate) use source::forward_to_inner;
pub use source::{Access, PlaneMemory, SampleSource};
pub use strided::{StridedLayout, StridedVolume};
pub use summary::{summarize, Suggestions, Summary, SummaryOptions};
pub use write::{write_volume, write_volume_cancellable, VolumeFormat};
