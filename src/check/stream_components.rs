//! The per-component figures of a streaming check
//! ([`StreamCheck::per_component`](super::StreamCheck::per_component)):
//! what [`check_mesh`](super::check_mesh) counts per component, counted
//! while the chunks stream.
//!
//! Each count of the streaming check is made at one vertex of the window
//! (an edge at its smaller end, a triangle at its first corner, a link at
//! its vertex, a union of two boundary classes at one end of the boundary
//! edge), so it is first tallied per window vertex ([`Tally`]); once the
//! chunk's triangles have joined the classes, each vertex's tally goes to
//! its class's root, with the tallies the classes carried from the chunk
//! before. A class that reaches no vertex of the next chunk is a finished
//! component and is kept as its [`ComponentReport`]'s counts; the others
//! are carried on. Memory: a tally per vertex of the window and per
//! carried class, and one per finished component (which the report lists).

use super::report::ComponentReport;

/// What is counted of one component (or, while a chunk is counted, at one
/// vertex of the window).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Tally {
    /// The smallest number in the mesh of a referenced vertex
    /// (`u64::MAX`: none yet), which orders components of equal size as
    /// `check_mesh` does.
    pub first: u64,
    pub vertices: u64,
    pub edges: u64,
    pub triangles: u64,
    pub boundary_edges: u64,
    pub non_manifold_edges: u64,
    pub non_manifold_vertices: u64,
    pub inconsistent_edges: u64,
    /// Vertices with a boundary edge, and the unions of two classes of the
    /// graph of boundary edges: the boundary loops are their difference.
    pub boundary_vertices: u64,
    pub boundary_merges: u64,
}

impl Default for Tally {
    fn default() -> Self {
        Tally {
            first: u64::MAX,
            vertices: 0,
            edges: 0,
            triangles: 0,
            boundary_edges: 0,
            non_manifold_edges: 0,
            non_manifold_vertices: 0,
            inconsistent_edges: 0,
            boundary_vertices: 0,
            boundary_merges: 0,
        }
    }
}

impl Tally {
    /// Adds `o`'s counts to these.
    pub fn add(&mut self, o: &Tally) {
        self.first = self.first.min(o.first);
        self.vertices += o.vertices;
        self.edges += o.edges;
        self.triangles += o.triangles;
        self.boundary_edges += o.boundary_edges;
        self.non_manifold_edges += o.non_manifold_edges;
        self.non_manifold_vertices += o.non_manifold_vertices;
        self.inconsistent_edges += o.inconsistent_edges;
        self.boundary_vertices += o.boundary_vertices;
        self.boundary_merges += o.boundary_merges;
    }

    /// One more edge, used by `count` triangles.
    pub fn edge(&mut self, count: u32) {
        self.edges += 1;
        match count {
            1 => self.boundary_edges += 1,
            2 => {}
            _ => self.non_manifold_edges += 1,
        }
    }

    /// The component's report, with the definitions of `check_mesh`.
    /// `None` when an edge is inconsistently oriented: whether the
    /// component can be oriented (and so its genus) needs the whole
    /// component, which the stream does not hold.
    pub fn report(&self) -> Option<ComponentReport> {
        if self.inconsistent_edges > 0 {
            return None;
        }
        let n = |x: u64| x as usize;
        let euler = self.vertices as i64 - self.edges as i64 + self.triangles as i64;
        let loops = self.boundary_vertices - self.boundary_merges;
        let manifold = self.non_manifold_edges == 0 && self.non_manifold_vertices == 0;
        let twice_genus = 2 - euler - loops as i64;
        let genus =
            (manifold && twice_genus >= 0 && twice_genus % 2 == 0).then_some(twice_genus / 2);
        Some(ComponentReport {
            vertices: n(self.vertices),
            edges: n(self.edges),
            triangles: n(self.triangles),
            euler,
            boundary_edges: n(self.boundary_edges),
            boundary_loops: n(loops),
            non_manifold_edges: n(self.non_manifold_edges),
            non_manifold_vertices: n(self.non_manifold_vertices),
            inconsistent_edges: 0,
            orientable: true,
            consistently_oriented: true,
            genus,
        })
    }
}

/// The components of a streaming check: the tallies of the classes
/// carried to the next chunk, and those of the finished components.
#[derive(Debug, Default)]
pub(super) struct ComponentState {
    /// Per class of the next chunk's first vertices (`StreamCheck::carry`).
    pub carried: Vec<Tally>,
    /// The finished components (referenced vertices only).
    pub done: Vec<Tally>,
}

/// The per-chunk working space of the component tallies.
#[derive(Debug, Default)]
pub(super) struct ComponentScratch {
    /// Per window vertex.
    pub at: Vec<Tally>,
    /// Per window vertex that is the root of a set of the union-find
    /// (its smallest vertex), the set's tallies (with those its carried
    /// classes brought).
    pub root: Vec<Tally>,
}

impl ComponentState {
    /// A finished class: kept when a triangle uses it (a vertex no
    /// triangle uses is a class of its own, and no component).
    pub fn finish(&mut self, t: Tally) {
        if t.vertices > 0 || t.triangles > 0 {
            self.done.push(t);
        }
    }

    /// The finished components' reports, ordered as `check_mesh` orders
    /// them (more triangles first, then more vertices, then by first
    /// vertex); `None` when one of them has an inconsistently oriented
    /// edge ([`Tally::report`]).
    pub fn reports(mut self) -> Option<Vec<ComponentReport>> {
        self.done
            .sort_by_key(|t| (std::cmp::Reverse((t.triangles, t.vertices)), t.first));
        self.done.iter().map(Tally::report).collect()
    }
}
