//! TMC against standard marching cubes on the same volume (`tmc compare`,
//! Python's `tmc.compare`): which cells the two triangulate differently
//! ([`survey`]), how sure a ratio of their timings is ([`ratio_interval`]),
//! and the steps that make all the figures ([`compare`]).
//!
//! The timing and the meshes' topology come from the ordinary pipeline
//! ([`crate::stream`]) and checker ([`crate::check`]); this module adds only
//! what neither has. The survey reads the volume once more, two planes per
//! thread, so its memory is set by the plane, not the volume.

mod differing;
mod interval;
mod run;

pub use differing::{survey, survey_marking, DifferingCells, OnDiffering};
pub use interval::{median, ratio_interval, RatioInterval, RESAMPLES};
pub use run::{compare, Comparison, Hooks, Side, Topology, TOPOLOGY_BYTES, TOPOLOGY_MEMORY};
