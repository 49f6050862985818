//! [`check_tmesh`]: `tmc check` of a `.tmesh` file while its chunks
//! stream, in bounded memory: [`check_mesh`](super::check_mesh)'s report
//! without holding the mesh.

use super::report::MeshReport;
use super::stream::{Scratch, StreamCheck};
use super::stream_geometry::StreamGeometry;
use crate::meshfile::TmeshReader;
use crate::Result;
use std::path::Path;

/// Checks a `.tmesh` file chunk by chunk (every checksum verified, as
/// [`read_mesh`](super::read_mesh) does), giving the report
/// [`check_mesh`](super::check_mesh) gives the mesh read whole, or `None`
/// when some edge is inconsistently oriented: whether such a component
/// can be oriented, and so its genus, needs the whole component (read the
/// mesh whole then). Part files of `tmc extract --part` are refused, as by
/// `read_mesh`.
///
/// Memory is that of a window of chunks, not of the mesh: three chunks
/// (the geometric counts), the streaming check's
/// window of two ([`StreamCheck`]: the edges, links and classes of the
/// vertices still open, those of the next chunk that the current chunk's
/// triangles reach), and a few words per component for the report. Vertices
/// sharing a position are looked for among those of consecutive chunks,
/// where every file tmc writes has them: a chunk holds the vertices
/// between its grid plane and the next.
pub fn check_tmesh(path: &Path) -> Result<Option<MeshReport>> {
    crate::part::PartRecord::refuse_part(path)?;
    let mut reader = TmeshReader::open(path)?;
    let mut check = StreamCheck::per_component();
    let mut scratch = Scratch::default();
    let mut geometry = StreamGeometry::default();
    let (mut vertices, mut triangles) = (0usize, 0usize);
    for i in 0..reader.entries().len() {
        let next = reader.entries().get(i + 1).map_or(0, |e| e.vertex_count);
        let chunk = reader.chunk(i)?;
        let own = chunk.vertices.len() as u32;
        vertices += chunk.vertices.len();
        triangles += chunk.triangles.len();
        check.chunk(&mut scratch, own, next, &chunk.triangles);
        geometry.chunk(chunk.vertices, chunk.triangles);
    }
    let (verdict, parts) = check.finish_components();
    let links = verdict.links.unwrap_or_default();
    let Some(per_component) = parts.and_then(|p| p.reports()) else {
        return Ok(None);
    };
    let mut report = MeshReport {
        vertices,
        triangles,
        invalid_triangles: verdict.invalid_triangles as usize,
        degenerate_triangles: links.degenerate_triangles as usize,
        unreferenced_vertices: links.unreferenced_vertices as usize,
        geometry: geometry.finish(),
        ..MeshReport::default()
    };
    report.set_components(per_component);
    debug_assert_eq!(report.edges as u64, verdict.edges);
    Ok(Some(report))
}
