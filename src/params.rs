//! The parameter vocabulary: what an extraction computes ([`ExtractParams`])
//! and how it runs ([`PipelineOptions`]).
//!
//! Every stage reads these types, so this module imports nothing of the
//! crate: it sits at the bottom of the dependency graph.

use std::sync::atomic::AtomicBool;

/// Which algorithm triangulates the cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Grosso's topologically correct and manifold hybrid marching cubes.
    #[default]
    Tmc,
    /// Standard marching cubes with one consistent face rule (inside corners
    /// of an ambiguous face are always separated).
    Mc,
}

impl Method {
    /// The method's name on the command line and in reports: "tmc" or "mc".
    pub fn name(self) -> &'static str {
        match self {
            Method::Tmc => "tmc",
            Method::Mc => "mc",
        }
    }
}

/// Which side of the isovalue is the object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Inside {
    /// Values above the isovalue are inside (CT, MRI, densities).
    #[default]
    High,
    /// Values below the isovalue are inside (signed distance fields).
    Low,
}

impl Inside {
    /// The side's name on the command line and in reports: "high" or "low".
    pub fn name(self) -> &'static str {
        match self {
            Inside::High => "high",
            Inside::Low => "low",
        }
    }
}

/// Options of one extraction.
#[derive(Debug, Clone, PartialEq)]
pub struct ExtractParams {
    /// The isovalue (finite).
    pub iso: f64,
    /// The cell algorithm.
    pub method: Method,
    /// Which side is the object.
    pub inside: Inside,
    /// Treat everything outside the volume as outside the object, so that
    /// every surface is closed.
    pub close: bool,
    /// Worker threads (0 = all cores).
    pub threads: usize,
    /// Give every vertex a unit outward normal (`Chunk::normals`), from
    /// the field's gradient, computed by the workers as they triangulate
    /// (see `crate::normals`). Off: nothing about the output changes.
    pub normals: bool,
}

impl Default for ExtractParams {
    fn default() -> Self {
        ExtractParams {
            iso: 0.0,
            method: Method::Tmc,
            inside: Inside::High,
            close: false,
            threads: 0,
            normals: false,
        }
    }
}

/// How the pipeline runs (not what it computes: the output does not depend
/// on these).
#[derive(Clone, Copy, Default)]
pub struct PipelineOptions<'a> {
    /// Cell layers per slab; 0 chooses from the plane size.
    pub slab_depth: usize,
    /// Called on the writing thread after each slab is written.
    pub progress: Option<&'a (dyn Fn(&Progress) + Sync)>,
    /// Set to `true` (from any thread or a signal handler) to stop the
    /// extraction: it is looked at before each slab starts, before each
    /// chunk is written and before the output is finished (one relaxed
    /// atomic load each), and the extraction then returns
    /// [`Error::Interrupted`](crate::Error::Interrupted) without finishing
    /// the sink.
    pub cancel: Option<&'a AtomicBool>,
    /// A memory budget in bytes: the workers' buffers are planned to fit it
    /// (see [`crate::stream::budget`]; the extraction fails with
    /// [`Error::OutOfMemory`](crate::Error::OutOfMemory) if even the thinnest slabs do not fit), and
    /// slabs start only as far as the measured mesh in flight allows (see
    /// [`crate::stream::schedule`]).
    /// `None`: no budget.
    pub max_memory: Option<u64>,
    /// Appends one value per vertex of `vertices` to `values`; called with
    /// each chunk's vertices and its [`Chunk::values`](crate::Chunk::values)
    /// on the worker that made the chunk, as soon as the slab loop has
    /// made it (the samples near its vertices are then still in the
    /// caches), so that a per-vertex quantity a caller wants is computed
    /// by all the workers side by side, not by the sink on the one writing
    /// thread (the Python package's scikit-image `values`). Must not
    /// depend on which worker calls it.
    /// `None`: the chunks' `values` stay empty.
    pub vertex_values: Option<&'a VertexValues<'a>>,
}

/// The function of [`PipelineOptions::vertex_values`]: a chunk's vertices
/// in, one value per vertex appended to the vector.
pub type VertexValues<'a> = dyn Fn(&[[f32; 3]], &mut Vec<f32>) + Sync + 'a;

/// How far an extraction has got.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progress {
    /// Cell layers written.
    pub layers_done: usize,
    /// Cell layers in all.
    pub layers_total: usize,
}

/// A number as tmc's text reports, notes and picture captions print it
/// (and `{iso}` names a file): its shortest decimal (`1600`, `0.25`) where
/// that has at most 24 characters, else with an exponent (`1e300`,
/// `1.5e-30`). Every finite double's decimal is exact, up to 309 digits
/// before the point and 330 after it: `1e-300` printed as a point, 299
/// zeros and a 1, which a caption cut off as `0.000...`.
pub fn number_text(x: f64) -> String {
    let decimal = x.to_string();
    match decimal.len() > 24 {
        true => format!("{x:e}"),
        false => decimal,
    }
}
