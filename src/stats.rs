//! Run statistics: the paper's Table 1 plus sizes and timing.

use serde::Serialize;

/// Counts of the cell configurations met during an extraction (the paper's
/// Table 1), plus output sizes and wall time.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Stats {
    /// Cells that are ambiguous by the paper's Definition 1.
    pub ambiguous_cells: u64,
    /// Contours in ambiguous cells triangulated without an interior vertex,
    /// by vertex count: index 0 is 3 vertices, ..., index 3 is 6 vertices.
    pub contours: [u64; 4],
    /// Ambiguous contours (one interior vertex), by vertex count: index 0 is
    /// 6 vertices, ..., index 3 is 9 vertices.
    pub ambiguous_contours: [u64; 4],
    /// Tunnels (two contours joined through the inner hexagon).
    pub tunnels: u64,
    /// Contours with 12 vertices (triangulated through the inner hexagon).
    pub contours_12: u64,
    /// Vertices in the output mesh.
    pub vertices: u64,
    /// Triangles in the output mesh.
    pub triangles: u64,
    /// Slabs the cell layers were cut into.
    pub slabs: u64,
    /// Grid planes read (a plane on a slab seam is read by both slabs).
    pub planes_read: u64,
    /// Seconds spent reading and converting samples, summed over threads.
    pub read_seconds: f64,
    /// Seconds spent triangulating cells, summed over threads.
    pub cell_seconds: f64,
    /// Seconds spent handing chunks to the sink (writing), on the writer thread.
    pub write_seconds: f64,
    /// Wall time of the extraction in seconds.
    pub seconds: f64,
}

impl Stats {
    /// Adds the counts and thread times of `other` into `self` (sizes and
    /// wall time excluded).
    pub fn add_counts(&mut self, other: &Stats) {
        self.ambiguous_cells += other.ambiguous_cells;
        for i in 0..4 {
            self.contours[i] += other.contours[i];
            self.ambiguous_contours[i] += other.ambiguous_contours[i];
        }
        self.tunnels += other.tunnels;
        self.contours_12 += other.contours_12;
        self.planes_read += other.planes_read;
        self.read_seconds += other.read_seconds;
        self.cell_seconds += other.cell_seconds;
    }
}
