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

use crate::{Error, Result};

/// Bytes each worker holds per sample of a z-plane, whatever the depth: two
/// planes of `f64` samples (for sources that cannot lend theirs) and their
/// inside bits, rounded up (edge numbers are kept per row, see
/// `slab::edges`).
pub const WORK_BYTES_PER_SAMPLE: u64 = 17;

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

/// Estimated peak bytes of `threads` workers on planes of `plane_len`
/// samples with slabs of `depth` layers, `window` of them in flight (plus
/// one slab's worth of written block vectors kept for reuse, see
/// [`crate::slab::Spares`]).
pub fn estimate(plane_len: usize, threads: usize, depth: usize, window: usize) -> u128 {
    let plane = plane_len as u128;
    let work = threads as u128 * plane * u128::from(WORK_BYTES_PER_SAMPLE);
    let slabs = window as u128 + 1;
    let output = slabs * depth as u128 * plane * u128::from(OUTPUT_BYTES_PER_CELL);
    u128::from(FIXED_BYTES) + work + output
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
/// that fit with `threads + 1`, then with `threads` slabs in flight. An
/// error when even slabs of [`MIN_DEPTH`] layers, one per worker, do not
/// fit.
pub fn plan(
    plane_len: usize,
    threads: usize,
    depth: usize,
    max_bytes: Option<u64>,
) -> Result<Plan> {
    let threads = threads.max(1);
    let depth = depth.max(1);
    let roomy = Plan {
        depth,
        window: 2 * threads + 2,
    };
    let roomy_cap = max_bytes.map_or(ROOMY_WINDOW_BYTES, |max| max.min(ROOMY_WINDOW_BYTES));
    if estimate(plane_len, threads, depth, roomy.window) <= u128::from(roomy_cap) {
        return Ok(roomy);
    }
    let full = Plan {
        depth,
        window: threads + 1,
    };
    let Some(max) = max_bytes else {
        return Ok(full);
    };
    let fits = |p: &Plan| estimate(plane_len, threads, p.depth, p.window) <= u128::from(max);
    for window in [threads + 1, threads] {
        let found = (MIN_DEPTH.min(depth)..=depth)
            .rev()
            .map(|depth| Plan { depth, window })
            .find(fits);
        if let Some(plan) = found {
            return Ok(plan);
        }
    }
    let needed = estimate(plane_len, threads, MIN_DEPTH.min(depth), threads);
    let workers = match threads {
        1 => "1 worker".to_string(),
        n => format!("{n} workers"),
    };
    let bytes = match max {
        1 => "1 byte".to_string(),
        n => format!("{n} bytes"),
    };
    Err(Error::OutOfMemory(format!(
        "--max-memory of {bytes} ({}) is too small: {workers} on planes of {plane_len} samples need about {} (one slab of {} layers each, plus {} MiB of buffers); allow at least that{}",
        mebibytes(u128::from(max)),
        mebibytes(needed),
        MIN_DEPTH.min(depth),
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
            plan(1000, 2, 64, None).unwrap(),
            Plan {
                depth: 64,
                window: 6
            }
        );
        // 2048^2 planes, 64 layers: 1 GiB per slab by the estimate.
        assert_eq!(
            plan(2048 * 2048, 2, 64, None).unwrap(),
            Plan {
                depth: 64,
                window: 3
            }
        );
        // A budget below the wide window's estimate keeps the narrow one.
        let narrow = estimate(1 << 20, 2, 16, 3) as u64;
        assert!(estimate(1 << 20, 2, 16, 6) <= u128::from(ROOMY_WINDOW_BYTES));
        assert_eq!(plan(1 << 20, 2, 16, Some(narrow)).unwrap().window, 3);
        assert_eq!(plan(1 << 20, 2, 16, None).unwrap().window, 6);
    }

    #[test]
    fn a_budget_thins_the_slabs_then_shrinks_the_window() {
        let plane = 1 << 20;
        let roomy = estimate(plane, 2, 64, 3) as u64;
        assert_eq!(plan(plane, 2, 64, Some(roomy)).unwrap().depth, 64);
        let tight = estimate(plane, 2, 10, 3) as u64;
        assert_eq!(
            plan(plane, 2, 64, Some(tight)).unwrap(),
            Plan {
                depth: 10,
                window: 3
            }
        );
        let tighter = estimate(plane, 2, 2, 2) as u64;
        assert_eq!(
            plan(plane, 2, 64, Some(tighter)).unwrap(),
            Plan {
                depth: 2,
                window: 2
            }
        );
        let err = plan(plane, 2, 64, Some(tighter - 1)).unwrap_err();
        assert!(err.to_string().contains("too small"), "{err}");
    }
}
