//! The memory budget of an extraction (`--max-memory`): how deep the slabs
//! are and how many of them are in flight.
//!
//! The model counts what grows with the plane size and the slab depth; the
//! memory-mapped input is not counted (its pages belong to the page cache,
//! which the kernel reclaims). The plan assumes the mesh of a slab takes
//! [`OUTPUT_BYTES_PER_CELL`] per cell, about what dense value noise takes
//! (sparse surfaces such as CT skin or bone take far less); the surface
//! decides, so [`super::schedule`] measures the mesh as it is made and
//! starts slabs only as far as the budget allows.

use crate::volume::PlaneMemory;
use crate::{Error, Result};

/// Bytes each worker holds per sample of a z-plane, whatever the depth: two
/// planes of `f64` samples (for sources that cannot lend theirs) and their
/// inside bits, rounded up (edge numbers are kept per row, see
/// `slab::edges`).
pub const WORK_BYTES_PER_SAMPLE: u64 = 17;

/// [`WORK_BYTES_PER_SAMPLE`] for planes lent or shared in their own type
/// ([`PlaneMemory::Lent`], [`PlaneMemory::Decoded`]): the inside bits of
/// two planes (a quarter of a byte), rounded up for the rows' edge
/// numbers and the bands of samples converted on the way.
pub const LENT_WORK_BYTES_PER_SAMPLE: u64 = 1;

/// Planes a worker may hold beyond its slab's cell layers (the top plane,
/// and the normals' neighbours: `HeldPlanes` holds from the plane below
/// the slab to the third above its last layer).
pub const HELD_EXTRA_PLANES: usize = 4;

/// Bytes the mesh of one cell is assumed to take while its slab waits to be
/// written (vertices of 12 bytes, triangles of 12 bytes; dense value noise
/// has about 0.16 triangles per cell).
pub const OUTPUT_BYTES_PER_CELL: u64 = 4;

/// Bytes taken whatever the grid: output buffers, thread stacks, tables.
pub const FIXED_BYTES: u64 = 16 << 20;

/// The thinnest slab the budget may choose (cell layers).
pub const MIN_DEPTH: usize = 2;

/// Slab depth and slabs in flight chosen for a budget.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Plan {
    /// Cell layers per slab.
    pub depth: usize,
    /// Slabs computed or being computed but not yet written (at least one
    /// per worker).
    pub window: usize,
}

/// The workers of a pass as the budget counts them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Workers {
    /// Samples of a plane.
    pub plane_len: usize,
    /// Planes the work holds per plane of the slab loop, each counted as
    /// one read into `f64`s: 1 for the slab loop alone, more with normals
    /// or a label pass's work.
    pub work_planes: usize,
    /// Worker threads.
    pub threads: usize,
    /// How the source's planes are held ([`crate::volume::SampleSource::plane_memory`]).
    pub planes: PlaneMemory,
    /// Bytes the pass holds from its start to its end besides the
    /// workers' buffers (a label map's runs), counted with the fixed
    /// bytes: a refusal names the whole need, so that the size it names
    /// is enough.
    pub held: u64,
}

impl Workers {
    /// Workers reading planes of `plane_len` samples into `f64`s (the most
    /// a plane can take), one plane of work each.
    pub fn reading(plane_len: usize, threads: usize) -> Self {
        Workers {
            plane_len,
            work_planes: 1,
            threads,
            planes: PlaneMemory::Read,
            held: 0,
        }
    }

    /// Cells of one layer, as the mesh estimate counts them (times the
    /// work's planes).
    pub fn layer_cells(&self) -> u128 {
        self.plane_len as u128 * self.work_planes.max(1) as u128
    }

    /// Estimated peak bytes besides the mesh with slabs of `depth` layers:
    /// the fixed buffers, each worker's planes, and for a source that
    /// decodes layers of chunks the layers its cache keeps
    /// (`threads + 2`), a decode in flight on every worker and the planes
    /// each worker's slab holds, counted apart although mostly the same.
    pub fn buffers(&self, depth: usize) -> u128 {
        let plane = self.plane_len as u128;
        let threads = self.threads.max(1) as u128;
        let per_sample = match (self.planes, self.work_planes) {
            (PlaneMemory::Lent | PlaneMemory::Decoded { .. }, 0 | 1) => {
                u128::from(LENT_WORK_BYTES_PER_SAMPLE)
            }
            (_, planes) => u128::from(WORK_BYTES_PER_SAMPLE) * planes.max(1) as u128,
        };
        let decoded = match self.planes {
            PlaneMemory::Decoded {
                sample_bytes,
                layer,
                decoding,
            } => {
                let layer = layer.max(1) as u128;
                let kept = (threads + 2) * layer;
                let decoding = threads * decoding as u128 * layer;
                let held = threads * (depth + HELD_EXTRA_PLANES) as u128;
                plane * sample_bytes as u128 * (kept + decoding + held)
            }
            PlaneMemory::Read | PlaneMemory::Lent => 0,
        };
        u128::from(FIXED_BYTES) + u128::from(self.held) + threads * plane * per_sample + decoded
    }
}

/// Estimated peak bytes of `workers` with slabs of `depth` layers, `window`
/// of them in flight (plus one slab's worth of written block vectors kept
/// for reuse, see [`crate::slab::Spares`]).
pub fn estimate(workers: &Workers, depth: usize, window: usize) -> u128 {
    let slabs = window as u128 + 1;
    let output = slabs * depth as u128 * workers.layer_cells() * u128::from(OUTPUT_BYTES_PER_CELL);
    workers.buffers(depth) + output
}

/// The estimate up to which `depth` layers may have `2 * threads + 2` slabs
/// in flight rather than `threads + 1`. Slabs finish out of order (a slab
/// full of surface takes longer than its neighbours), and a worker whose
/// next slab is beyond the window waits for the writer: with one spare slab
/// per worker, two workers on bonsai (256^3) waited for 12% of the run.
pub const ROOMY_WINDOW_BYTES: u64 = 512 << 20;

/// Chooses the slab depth and the slabs in flight: `depth` layers and
/// `2 * threads + 2` slabs when their estimate is within
/// [`ROOMY_WINDOW_BYTES`] and `max_bytes`, else `threads + 1` slabs when that
/// fits in `max_bytes` (or there is no budget), otherwise the deepest slabs
/// that fit with `threads + 1`, then with `threads` slabs in flight, and
/// when no mesh estimate fits, slabs of [`MIN_DEPTH`] layers, one per
/// worker, which [`super::schedule`] thins further to the mesh it
/// measures. An error, before anything is read, when even the buffers of
/// slabs of [`MIN_DEPTH`] layers do not fit: what the workers hold whatever
/// the surface.
pub fn plan(workers: &Workers, depth: usize, max_bytes: Option<u64>) -> Result<Plan> {
    let threads = workers.threads.max(1);
    let depth = depth.max(1);
    let roomy = Plan {
        depth,
        window: 2 * threads + 2,
    };
    let roomy_cap = max_bytes.map_or(ROOMY_WINDOW_BYTES, |max| max.min(ROOMY_WINDOW_BYTES));
    if estimate(workers, depth, roomy.window) <= u128::from(roomy_cap) {
        return Ok(roomy);
    }
    let full = Plan {
        depth,
        window: threads + 1,
    };
    let Some(max) = max_bytes else {
        return Ok(full);
    };
    let fits = |p: &Plan| estimate(workers, p.depth, p.window) <= u128::from(max);
    for window in [threads + 1, threads] {
        let found = (MIN_DEPTH.min(depth)..=depth)
            .rev()
            .map(|depth| Plan { depth, window })
            .find(fits);
        if let Some(plan) = found {
            return Ok(plan);
        }
    }
    let thinnest = MIN_DEPTH.min(depth);
    let needed = workers.buffers(thinnest);
    if needed <= u128::from(max) {
        return Ok(Plan {
            depth: thinnest,
            window: threads,
        });
    }
    let workers_text = match threads {
        1 => "1 worker".to_string(),
        n => format!("{n} workers"),
    };
    let bytes = match max {
        1 => "1 byte".to_string(),
        n => format!("{n} bytes"),
    };
    let layers = match workers.planes {
        PlaneMemory::Decoded { .. } => {
            let without = Workers {
                planes: PlaneMemory::Lent,
                ..*workers
            };
            format!(
                ", {} of them decoded chunk layers",
                mebibytes(needed - without.buffers(thinnest))
            )
        }
        _ => String::new(),
    };
    let held = match workers.held {
        0 => String::new(),
        held => format!(", {} of the label map's runs", mebibytes(u128::from(held))),
    };
    Err(Error::OutOfMemory(format!(
        "--max-memory of {bytes} ({}) is too small: {workers_text} on planes of {} samples need about {} before any mesh (slabs of {thinnest} layers, {} MiB of buffers{layers}{held}); allow at least that{}",
        mebibytes(u128::from(max)),
        workers.plane_len,
        mebibytes(needed),
        FIXED_BYTES >> 20,
        match threads {
            1 => "",
            _ => ", or use fewer --threads",
        }
    )))
}

/// `bytes` in MiB with one decimal, for messages.
fn mebibytes(bytes: u128) -> String {
    format!("{:.1} MiB", bytes as f64 / f64::from(1u32 << 20))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_budget_keeps_the_depth_and_widens_the_window_of_small_slabs() {
        assert_eq!(
            plan(&Workers::reading(1000, 2), 64, None).unwrap(),
            Plan {
                depth: 64,
                window: 6
            }
        );
        // 2048^2 planes, 64 layers: 1 GiB per slab by the estimate.
        assert_eq!(
            plan(&Workers::reading(2048 * 2048, 2), 64, None).unwrap(),
            Plan {
                depth: 64,
                window: 3
            }
        );
        // A budget below the wide window's estimate keeps the narrow one.
        let narrow = estimate(&Workers::reading(1 << 20, 2), 16, 3) as u64;
        assert!(estimate(&Workers::reading(1 << 20, 2), 16, 6) <= u128::from(ROOMY_WINDOW_BYTES));
        assert_eq!(
            plan(&Workers::reading(1 << 20, 2), 16, Some(narrow))
                .unwrap()
                .window,
            3
        );
        assert_eq!(
            plan(&Workers::reading(1 << 20, 2), 16, None)
                .unwrap()
                .window,
            6
        );
    }

    #[test]
    fn a_budget_thins_the_slabs_then_shrinks_the_window() {
        let w = Workers::reading(1 << 20, 2);
        let roomy = estimate(&w, 64, 3) as u64;
        assert_eq!(plan(&w, 64, Some(roomy)).unwrap().depth, 64);
        let tight = estimate(&w, 10, 3) as u64;
        assert_eq!(
            plan(&w, 64, Some(tight)).unwrap(),
            Plan {
                depth: 10,
                window: 3
            }
        );
        let tighter = estimate(&w, 2, 2) as u64;
        assert_eq!(
            plan(&w, 64, Some(tighter)).unwrap(),
            Plan {
                depth: 2,
                window: 2
            }
        );
        // Below any mesh estimate, the thinnest slabs while the buffers
        // fit (the schedule measures the mesh); below the buffers, an
        // error.
        let buffers = w.buffers(2) as u64;
        assert_eq!(
            plan(&w, 64, Some(buffers)).unwrap(),
            Plan {
                depth: 2,
                window: 2
            }
        );
        let err = plan(&w, 64, Some(buffers - 1)).unwrap_err();
        assert!(err.to_string().contains("too small"), "{err}");
    }

    #[test]
    fn what_the_pass_holds_counts_and_a_refusal_names_it() {
        let workers = Workers::reading(1 << 20, 2);
        let holding = Workers {
            held: 40 << 20,
            ..workers
        };
        assert_eq!(holding.buffers(2), workers.buffers(2) + (40 << 20));
        // Room for the workers alone is not room for what the pass holds.
        let room = workers.buffers(2) as u64;
        assert!(plan(&workers, 64, Some(room)).is_ok());
        let err = plan(&holding, 64, Some(room)).unwrap_err().to_string();
        assert!(err.contains("40.0 MiB of the label map's runs"), "{err}");
        assert!(plan(&holding, 64, Some(room + (40 << 20))).is_ok());
    }

    #[test]
    fn lent_planes_take_their_bits_and_decoded_layers_count() {
        let plane = 4096 * 4096;
        let read = Workers::reading(plane, 2);
        let lent = Workers {
            planes: PlaneMemory::Lent,
            ..read
        };
        // 4096^2 u8 lent: a 64 MiB budget holds the buffers; read into
        // f64s it does not.
        assert!(lent.buffers(2) <= 64 << 20);
        assert!(plan(&lent, 5, Some(64 << 20)).is_ok());
        assert!(plan(&read, 5, Some(64 << 20)).is_err());
        // Normals' planes count as before, lent or not.
        let normals = Workers {
            work_planes: 3,
            ..lent
        };
        assert_eq!(
            normals.buffers(2),
            Workers {
                work_planes: 3,
                ..read
            }
            .buffers(2)
        );
        // A Zarr of f32 in chunks 8 deep: the cache's 4 layers, a decode
        // of 2 layers a worker, and the 2 + 4 planes each worker holds.
        let zarr = Workers {
            planes: PlaneMemory::Decoded {
                sample_bytes: 4,
                layer: 8,
                decoding: 2,
            },
            ..read
        };
        let plane_bytes = 4 * plane as u128;
        let layers = plane_bytes * (4 * 8 + 2 * 2 * 8 + 2 * 6);
        assert_eq!(zarr.buffers(2), lent.buffers(2) + layers);
        let err = plan(&zarr, 16, Some(1 << 30)).unwrap_err().to_string();
        assert!(err.contains("decoded chunk layers"), "{err}");
    }
}
