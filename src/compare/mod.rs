//! TMC against standard marching cubes on the same volume (`tmc compare`):
//! which cells the two triangulate differently ([`survey`]) and how sure
//! a ratio of their timings is ([`ratio_interval`]).
//!
//! The timing and the meshes' topology come from the ordinary pipeline
//! ([`crate::stream`]) and checker ([`crate::check`]); this module adds only
//! what neither has. The survey reads the volume once more, two planes per
//! thread, so its memory is set by the plane, not the volume.

mod differing;
mod interval;

pub use differing::{survey, survey_marking, DifferingCells, OnDiffering};
pub use interval::{median, ratio_interval, RatioInterval, RESAMPLES};
