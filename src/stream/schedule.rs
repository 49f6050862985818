//! Which slab to start next: cell layers cut into slabs as they are
//! launched, as deep as the memory budget leaves room for.
//!
//! Without a budget every slab has the plan's depth and at most the plan's
//! window of slabs is in flight. With one (`--max-memory`), a slab is also
//! started only when the mesh of the slabs in flight fits what the budget
//! leaves after the workers' buffers: slabs still running count at the
//! largest bytes per cell any finished slab took (before the first has
//! finished, at [`FIRST_BYTES_PER_CELL`], about what uniform noise takes),
//! finished slabs waiting to be written and the spare vectors of written
//! ones count at what they hold (and are freed when they keep a slab
//! thin). So a dense surface gets thinner slabs and fewer of them at once;
//! a slab of one layer is started whenever nothing else is in flight, so
//! the extraction always moves on (one layer's mesh is the least a slab can
//! hold). The output does
//! not depend on how the layers are cut.

use super::budget::{Plan, Workers, OUTPUT_BYTES_PER_CELL};
use std::collections::BTreeMap;
use std::ops::Range;

/// Bytes per cell assumed for the mesh of slabs started before any slab
/// has finished: uniform random noise, the densest surface we know of,
/// takes about 3.8 triangles and 1.5 vertices per cell, about 64 bytes,
/// plus the vectors' room to grow.
pub const FIRST_BYTES_PER_CELL: u64 = 96;

/// The slabs of one extraction, cut as they are started.
#[derive(Debug)]
pub struct Schedule {
    /// The first layer; layers still to cut run from `next` to `end`.
    first: usize,
    next: usize,
    end: usize,
    /// One empty slab is due for the top plane's chunk (a part that holds
    /// no layer but ends at the top of the grid).
    top_only: bool,
    plan: Plan,
    /// The slabs started so far, in order.
    started: Vec<Range<usize>>,
    budget: Option<Budget>,
}

/// What a memory budget allows and what the slabs in flight take.
#[derive(Debug)]
struct Budget {
    /// Bytes the mesh of the slabs in flight may take.
    allowance: u128,
    /// Cells of one layer.
    layer_cells: u128,
    /// Bytes per cell assumed for a running slab.
    bytes_per_cell: u128,
    /// Whether a slab has finished (`bytes_per_cell` is measured).
    measured: bool,
    /// Assumed bytes of the slabs running, by slab.
    running: BTreeMap<usize, u128>,
    /// Bytes of the slabs finished and not yet written, by slab.
    waiting: BTreeMap<usize, u128>,
}

impl Schedule {
    /// The slabs covering `range` of `layers` under `plan`; with a budget of
    /// `max_memory` bytes for `workers`, the mesh gets what their buffers
    /// with slabs of the plan's depth leave. (The plan has checked that
    /// those buffers fit the budget.)
    pub fn new(
        range: Range<usize>,
        layers: usize,
        plan: Plan,
        max_memory: Option<u64>,
        workers: &Workers,
    ) -> Self {
        let budget = max_memory.map(|max| Budget {
            allowance: u128::from(max).saturating_sub(workers.buffers(plan.depth)),
            layer_cells: workers.layer_cells(),
            bytes_per_cell: u128::from(FIRST_BYTES_PER_CELL),
            measured: false,
            running: BTreeMap::new(),
            waiting: BTreeMap::new(),
        });
        Schedule {
            top_only: range.is_empty() && range.end == layers,
            first: range.start,
            next: range.start,
            end: range.end,
            plan,
            started: Vec::new(),
            budget,
        }
    }

    /// Whether every slab has been started.
    pub fn all_started(&self) -> bool {
        self.next >= self.end && !self.top_only
    }

    /// The cell layers all slabs cover.
    pub fn layers_total(&self) -> usize {
        self.end - self.first
    }

    /// The slabs started so far.
    pub fn started(&self) -> &[Range<usize>] {
        &self.started
    }

    /// The next slab to start (its number and layers) when `written` slabs
    /// have been written and `spare_bytes` are held by spare vectors, or
    /// `None` when all have started or the next must wait for one in flight
    /// to finish.
    pub fn start_next(
        &mut self,
        written: usize,
        spare_bytes: u64,
    ) -> Option<(usize, Range<usize>)> {
        if self.all_started() {
            return None;
        }
        let in_flight = self.started.len() - written;
        if in_flight >= self.plan.window {
            return None;
        }
        let mut depth = self.plan.depth;
        if let Some(budget) = &mut self.budget {
            budget.waiting.retain(|&i, _| i >= written);
            depth = depth.min(budget.layers_that_fit(u128::from(spare_bytes)));
            if depth == 0 {
                if in_flight > 0 {
                    return None;
                }
                depth = 1;
            }
        }
        let layers = self.next..(self.next + depth).min(self.end);
        self.top_only = false;
        self.next = layers.end;
        let index = self.started.len();
        if let Some(budget) = &mut self.budget {
            let assumed = budget.layer_cells * layers.len() as u128 * budget.bytes_per_cell;
            budget.running.insert(index, assumed);
        }
        self.started.push(layers.clone());
        Some((index, layers))
    }

    /// Whether spare vectors holding `spare_bytes` keep the next slab
    /// thinner than the plan's depth under the budget (then they are better
    /// freed).
    pub fn spares_in_the_way(&self, spare_bytes: u64) -> bool {
        self.budget.as_ref().is_some_and(|b| {
            spare_bytes > 0 && b.layers_that_fit(u128::from(spare_bytes)) < self.plan.depth
        })
    }

    /// Slab `index` has finished with a mesh of `bytes` (capacities) that
    /// waits to be written.
    pub fn finished(&mut self, index: usize, bytes: u64) {
        let layers = self.started[index].len() as u128;
        if let Some(budget) = &mut self.budget {
            budget.running.remove(&index);
            budget.waiting.insert(index, u128::from(bytes));
            if layers > 0 {
                // The first measurement replaces the assumption; later ones
                // can only raise it.
                let per_cell = u128::from(bytes).div_ceil(layers * budget.layer_cells.max(1));
                let so_far = match budget.measured {
                    true => budget.bytes_per_cell,
                    false => u128::from(OUTPUT_BYTES_PER_CELL),
                };
                budget.bytes_per_cell = so_far.max(per_cell);
                budget.measured = true;
            }
        }
    }
}

impl Budget {
    /// How many layers a new slab may have now.
    fn layers_that_fit(&self, spare_bytes: u128) -> usize {
        let used = self.running.values().sum::<u128>() + self.waiting.values().sum::<u128>();
        let room = self.allowance.saturating_sub(used + spare_bytes);
        let per_layer = (self.layer_cells * self.bytes_per_cell).max(1);
        usize::try_from(room / per_layer).unwrap_or(usize::MAX)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(depth: usize, window: usize) -> Plan {
        Plan { depth, window }
    }

    #[test]
    fn without_a_budget_slabs_have_the_plan_s_depth_and_window() {
        let mut s = Schedule::new(0..10, 10, plan(4, 2), None, &Workers::reading(100, 2));
        assert_eq!(s.start_next(0, 0), Some((0, 0..4)));
        assert_eq!(s.start_next(0, 0), Some((1, 4..8)));
        assert_eq!(s.start_next(0, 0), None, "the window is full");
        assert_eq!(s.start_next(1, 0), Some((2, 8..10)));
        assert!(s.all_started());
        assert_eq!(s.start_next(3, 0), None);
    }

    #[test]
    fn an_empty_part_at_the_top_has_one_empty_slab() {
        let mut s = Schedule::new(7..7, 7, plan(4, 2), None, &Workers::reading(100, 1));
        assert!(!s.all_started());
        assert_eq!(s.start_next(0, 0), Some((0, 7..7)));
        assert!(s.all_started());
        let s = Schedule::new(3..3, 7, plan(4, 2), None, &Workers::reading(100, 1));
        assert!(s.all_started());
    }

    #[test]
    fn a_budget_follows_the_measured_mesh() {
        // 1000 cells a layer; room for 200 kB of mesh.
        let max = (Workers::reading(1000, 1).buffers(8) + 200_000) as u64;
        let mut s = Schedule::new(
            0..100,
            100,
            plan(8, 4),
            Some(max),
            &Workers::reading(1000, 1),
        );
        // Before any slab finished, 96 bytes a cell: two layers fit.
        assert_eq!(s.start_next(0, 0), Some((0, 0..2)));
        // Nothing more fits while it runs.
        assert_eq!(s.start_next(0, 0), None);
        // It took 5 bytes a cell: the next slabs get the plan's depth, as
        // many as fit beside the 10 kB waiting.
        s.finished(0, 10_000);
        assert_eq!(s.start_next(0, 0), Some((1, 2..10)));
        assert_eq!(s.start_next(0, 0), Some((2, 10..18)));
        assert_eq!(s.start_next(0, 0), Some((3, 18..26)));
        assert_eq!(s.start_next(0, 0), None, "the window is full");
        // A dense slab raises the bytes per cell for the slabs to come, and
        // spare vectors count too.
        s.finished(1, 8 * 1000 * 20);
        assert_eq!(s.start_next(1, 0), None, "160 kB waiting, two running");
        s.finished(2, 8_000);
        s.finished(3, 8_000);
        assert_eq!(s.start_next(4, 150_000), Some((4, 26..28)));
        // With nothing in flight a slab of one layer starts, whatever the
        // budget says.
        assert_eq!(s.start_next(5, 1 << 30), Some((5, 28..29)));
        assert_eq!(s.start_next(5, 1 << 30), None);
    }
}
