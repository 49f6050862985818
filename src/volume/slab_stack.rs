//! A volume whose z-planes are spread over several files, each holding a
//! slab of the same number of consecutive planes (a NRRD `data file: LIST`
//! or printf pattern, one file per slice or per block of slices).
//!
//! Each file stays its own [`RawVolume`] (memory-mapped, or parsed text
//! data held in memory), so nothing is read before the slab loop asks for a plane;
//! plane `z` lives in file `z / depth` at plane `z % depth`.

use super::{Access, Grid, LentPlane, PlaneMemory, RawVolume, SampleSource};
use crate::{Error, Result};
use std::ops::Range;
use std::path::Path;

/// Consecutive slabs of `depth` planes, one [`RawVolume`] each.
#[derive(Debug)]
pub(crate) struct SlabStack {
    grid: Grid,
    depth: usize,
    slabs: Vec<RawVolume>,
}

impl SlabStack {
    /// Stacks `slabs` along z into `grid`; every slab must hold
    /// `grid.dims[2] / slabs.len()` planes of `grid.dims[0] x grid.dims[1]`
    /// samples (the caller checks that the count divides evenly).
    pub(crate) fn new(grid: Grid, slabs: Vec<RawVolume>) -> SlabStack {
        let depth = (grid.dims[2] / slabs.len().max(1)).max(1);
        debug_assert!(slabs
            .iter()
            .all(|s| s.grid().dims == [grid.dims[0], grid.dims[1], depth]));
        SlabStack { grid, depth, slabs }
    }

    /// How many files hold the planes.
    pub(crate) fn files(&self) -> usize {
        self.slabs.len()
    }
}

impl SampleSource for SlabStack {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        let slab = self.slabs.get(z / self.depth).ok_or_else(|| {
            Error::Invalid(format!(
                "plane {z} out of range: the volume has {} planes",
                self.grid.dims[2]
            ))
        })?;
        slab.read_plane(z % self.depth, out)
    }

    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        self.slabs.get(z / self.depth)?.lend_plane(z % self.depth)
    }

    fn plane_memory(&self) -> PlaneMemory {
        self.slabs
            .first()
            .map_or(PlaneMemory::Read, |s| s.plane_memory())
    }

    fn advise(&self, planes: Range<usize>, access: Access) {
        let end = planes.end.min(self.grid.dims[2]);
        let mut z = planes.start;
        while z < end {
            let (file, first) = (z / self.depth, z % self.depth);
            let last = (end - file * self.depth).min(self.depth);
            if let Some(slab) = self.slabs.get(file) {
                slab.advise(first..last, access);
            }
            z = (file + 1) * self.depth;
        }
    }

    fn check_unchanged(&self) -> Result<()> {
        self.slabs.iter().try_for_each(|s| s.check_unchanged())
    }

    fn data_files(&self) -> Vec<&Path> {
        self.slabs.iter().flat_map(|s| s.data_files()).collect()
    }

    fn sample_bytes(&self) -> usize {
        self.slabs.first().map_or(8, |s| s.sample_bytes())
    }
}
