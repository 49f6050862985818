//! What the checker finds: [`MeshReport`] for the whole mesh and a
//! [`ComponentReport`] per connected component, with their text form.

use serde::Serialize;
use std::io::Write;

/// Per-component figures of a [`MeshReport`].
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ComponentReport {
    /// Referenced vertices of the component.
    pub vertices: usize,
    /// Undirected edges of the component.
    pub edges: usize,
    /// Proper triangles of the component.
    pub triangles: usize,
    /// `vertices - edges + triangles`.
    pub euler: i64,
    /// Edges used by exactly one triangle.
    pub boundary_edges: usize,
    /// Connected components of the graph of the boundary edges.
    pub boundary_loops: usize,
    /// Edges used by more than two triangles.
    pub non_manifold_edges: usize,
    /// Vertices whose triangles do not form a single fan.
    pub non_manifold_vertices: usize,
    /// Manifold edges traversed twice in the same direction.
    pub inconsistent_edges: usize,
    /// Whether the triangles can be oriented so that every manifold edge is
    /// consistent (non-manifold edges are ignored).
    pub orientable: bool,
    /// Whether the triangles as given are consistently oriented
    /// (`inconsistent_edges == 0`).
    pub consistently_oriented: bool,
    /// `(2 - euler - boundary_loops) / 2` for an orientable component
    /// without non-manifold edges or vertices, `None` otherwise.
    pub genus: Option<i64>,
}

impl ComponentReport {
    /// True for a closed, consistently oriented 2-manifold component.
    pub fn is_closed_manifold(&self) -> bool {
        self.boundary_edges == 0
            && self.non_manifold_edges == 0
            && self.non_manifold_vertices == 0
            && self.inconsistent_edges == 0
    }
}

/// The geometric part of a [`MeshReport`]: what [`check_geometry`](super::check_geometry)
/// finds; see [the definitions](crate::check#definitions).
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize)]
pub struct Geometry {
    /// Triangles (without a repeated or invalid index) whose three corners
    /// are collinear or coincide: zero area in the `f32` coordinates.
    pub zero_area_triangles: usize,
    /// The numbers of the first few of them (at most five), from 0.
    pub first_zero_area_triangles: Vec<usize>,
    /// Vertices whose position another vertex has too.
    pub shared_position_vertices: usize,
    /// Triangles (as above) with a corner among those vertices.
    pub shared_position_triangles: usize,
    /// The numbers of the first few of them (at most five), from 0.
    pub first_shared_position_triangles: Vec<usize>,
}

impl Geometry {
    /// No zero-area triangle and no two vertices at one position.
    pub fn is_sound(&self) -> bool {
        self.zero_area_triangles == 0 && self.shared_position_vertices == 0
    }

    /// One line naming the geometric defects, with the first triangles of
    /// each (empty when [`Geometry::is_sound`]).
    pub fn defects(&self) -> String {
        let first = |t: &[usize]| {
            let list: Vec<String> = t.iter().map(usize::to_string).collect();
            list.join(", ")
        };
        let mut parts = Vec::new();
        if self.zero_area_triangles > 0 {
            parts.push(format!(
                "{} zero-area triangles (first: {})",
                self.zero_area_triangles,
                first(&self.first_zero_area_triangles)
            ));
        }
        if self.shared_position_vertices > 0 {
            parts.push(format!(
                "{} vertices sharing a position, in {} triangles (first: {})",
                self.shared_position_vertices,
                self.shared_position_triangles,
                first(&self.first_shared_position_triangles)
            ));
        }
        parts.join(", ")
    }
}

/// The result of [`check_mesh`](super::check_mesh); see [the
/// definitions](crate::check#definitions).
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize)]
pub struct MeshReport {
    /// Vertices in the mesh (referenced or not).
    pub vertices: usize,
    /// Triangles in the mesh (proper or not).
    pub triangles: usize,
    /// Triangles with an index out of range (ignored otherwise).
    pub invalid_triangles: usize,
    /// Triangles repeating an index (ignored otherwise).
    pub degenerate_triangles: usize,
    /// Vertices used by no proper triangle.
    pub unreferenced_vertices: usize,
    /// Undirected edges of the proper triangles.
    pub edges: usize,
    /// Edges used by exactly one triangle.
    pub boundary_edges: usize,
    /// Edges used by more than two triangles.
    pub non_manifold_edges: usize,
    /// Referenced vertices whose triangles do not form a single fan.
    pub non_manifold_vertices: usize,
    /// Manifold edges whose two triangles traverse them in the same
    /// direction.
    pub inconsistent_edges: usize,
    /// Connected components (triangles sharing a vertex are connected).
    pub components: usize,
    /// `V - E + F` over referenced vertices, edges and proper triangles.
    pub euler: i64,
    /// One entry per component, largest (by triangles) first.
    pub per_component: Vec<ComponentReport>,
    /// Zero-area triangles and vertices sharing a position (in the JSON
    /// form, its fields sit beside the others).
    #[serde(flatten)]
    pub geometry: Geometry,
}

impl MeshReport {
    /// True when the mesh is a closed, consistently oriented 2-manifold: no
    /// invalid or degenerate triangle, no boundary edge, no non-manifold edge
    /// or vertex and no inconsistent edge. Unreferenced vertices are allowed.
    /// An empty mesh is (vacuously) a closed manifold.
    pub fn is_closed_manifold(&self) -> bool {
        self.invalid_triangles == 0
            && self.degenerate_triangles == 0
            && self.boundary_edges == 0
            && self.non_manifold_edges == 0
            && self.non_manifold_vertices == 0
            && self.inconsistent_edges == 0
    }

    /// True when the mesh is a consistently oriented 2-manifold, possibly
    /// with boundary (an open surface): everything [`is_closed_manifold`]
    /// asks for except that boundary edges are allowed.
    ///
    /// [`is_closed_manifold`]: MeshReport::is_closed_manifold
    pub fn is_oriented_manifold(&self) -> bool {
        self.invalid_triangles == 0
            && self.degenerate_triangles == 0
            && self.non_manifold_edges == 0
            && self.non_manifold_vertices == 0
            && self.inconsistent_edges == 0
    }

    /// One line naming what keeps the mesh from being a consistently
    /// oriented manifold (empty when [`MeshReport::is_oriented_manifold`]).
    pub fn defects(&self) -> String {
        [
            (self.invalid_triangles, "invalid triangles"),
            (self.degenerate_triangles, "degenerate triangles"),
            (self.non_manifold_edges, "non-manifold edges"),
            (self.non_manifold_vertices, "non-manifold vertices"),
            (self.inconsistent_edges, "inconsistently oriented edges"),
        ]
        .iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, what)| format!("{n} {what}"))
        .collect::<Vec<_>>()
        .join(", ")
    }

    /// Sets the components (in the order the report lists them) and the
    /// whole mesh's counts that are their sums.
    pub(super) fn set_components(&mut self, per_component: Vec<ComponentReport>) {
        self.components = per_component.len();
        for c in &per_component {
            self.edges += c.edges;
            self.boundary_edges += c.boundary_edges;
            self.non_manifold_edges += c.non_manifold_edges;
            self.non_manifold_vertices += c.non_manifold_vertices;
            self.inconsistent_edges += c.inconsistent_edges;
            self.euler += c.euler;
        }
        self.per_component = per_component;
    }

    /// Sum of the genera of the components, when every component has one.
    pub fn total_genus(&self) -> Option<i64> {
        self.per_component.iter().map(|c| c.genus).sum()
    }

    /// Writes a human-readable, aligned summary (at most 20 component rows).
    /// The verdict of a mesh without triangles reads `yes (empty)`: it is
    /// closed only vacuously.
    pub fn print_text(&self, w: &mut impl Write) -> std::io::Result<()> {
        const MAX_ROWS: usize = 20;
        let yes_no = |b: bool| if b { "yes" } else { "no" };
        let list = |n: usize, first: &[usize]| {
            if first.is_empty() {
                n.to_string()
            } else {
                let first: Vec<String> = first.iter().map(usize::to_string).collect();
                format!("{n} (first triangles: {})", first.join(", "))
            }
        };
        let g = &self.geometry;
        let rows: [(&str, String); 16] = [
            ("vertices", self.vertices.to_string()),
            ("triangles", self.triangles.to_string()),
            ("edges", self.edges.to_string()),
            ("invalid triangles", self.invalid_triangles.to_string()),
            (
                "degenerate triangles",
                self.degenerate_triangles.to_string(),
            ),
            (
                "unreferenced vertices",
                self.unreferenced_vertices.to_string(),
            ),
            (
                "zero-area triangles",
                list(g.zero_area_triangles, &g.first_zero_area_triangles),
            ),
            (
                "shared positions",
                list(
                    g.shared_position_vertices,
                    &g.first_shared_position_triangles,
                ),
            ),
            ("boundary edges", self.boundary_edges.to_string()),
            ("non-manifold edges", self.non_manifold_edges.to_string()),
            (
                "non-manifold vertices",
                self.non_manifold_vertices.to_string(),
            ),
            ("inconsistent edges", self.inconsistent_edges.to_string()),
            ("components", self.components.to_string()),
            ("euler characteristic", self.euler.to_string()),
            (
                "total genus",
                self.total_genus()
                    .map_or_else(|| "-".to_string(), |g| g.to_string()),
            ),
            (
                "closed manifold",
                if self.triangles == 0 {
                    "yes (empty)".into()
                } else {
                    yes_no(self.is_closed_manifold()).into()
                },
            ),
        ];
        for (label, value) in &rows {
            writeln!(w, "{label:<22} {value:>12}")?;
        }
        if self.per_component.is_empty() {
            return Ok(());
        }
        writeln!(w)?;
        writeln!(
            w,
            "{:>6} {:>12} {:>12} {:>12} {:>8} {:>6} {:>6} {:>8} {:>8}",
            "comp",
            "vertices",
            "edges",
            "triangles",
            "euler",
            "loops",
            "genus",
            "oriented",
            "manifold"
        )?;
        for (i, c) in self.per_component.iter().take(MAX_ROWS).enumerate() {
            let oriented = if c.consistently_oriented {
                "yes"
            } else if c.orientable {
                "fixable"
            } else {
                "no"
            };
            let manifold = c.non_manifold_edges == 0 && c.non_manifold_vertices == 0;
            writeln!(
                w,
                "{:>6} {:>12} {:>12} {:>12} {:>8} {:>6} {:>6} {:>8} {:>8}",
                i,
                c.vertices,
                c.edges,
                c.triangles,
                c.euler,
                c.boundary_loops,
                c.genus.map_or_else(|| "-".to_string(), |g| g.to_string()),
                oriented,
                yes_no(manifold),
            )?;
        }
        if self.per_component.len() > MAX_ROWS {
            writeln!(
                w,
                "{:>6} ... and {} more components",
                "",
                self.per_component.len() - MAX_ROWS
            )?;
        }
        Ok(())
    }
}
