//! scikit-image's arrays, written as the chunks come: [`SkimageArrays`],
//! the sink of `marching_cubes`.
//!
//! Each chunk goes straight into the arrays numpy gets, in their final
//! layout and types: vertices in array index order `[z, y, x]` as float32,
//! faces as int32 global indices, normals in the same order (pointing
//! toward lower values, as scikit-image's), and the per-vertex values
//! (`values.rs`), which the workers computed into each chunk
//! ([`tmc::PipelineOptions::vertex_values`]). Nothing is converted, copied
//! or visited again after the extraction; the vectors grow by remapping,
//! not copying ([`tmc::mesh::reserve_for_planes`]).

use tmc::mesh::{fit, reserve_for_planes, Chunk, MeshInfo, MeshSink, Totals};

/// The four arrays of `skimage.measure.marching_cubes`, collected from an
/// extraction with normals and per-vertex values.
pub(crate) struct SkimageArrays {
    /// Negate the normals: the extraction's point out of the object, which
    /// is toward higher values when the object is below the level.
    flip: bool,
    /// Grid planes, from [`MeshSink::begin`].
    planes: u64,
    /// `[z, y, x]` positions.
    pub verts: Vec<[f32; 3]>,
    /// Global vertex indices, in the extraction's winding (counter-clockwise
    /// in `[x, y, z]`, so clockwise in `[z, y, x]`: scikit-image's).
    pub faces: Vec<[i32; 3]>,
    /// `[z, y, x]` unit normals.
    pub normals: Vec<[f32; 3]>,
    /// Per vertex, the largest nearby sample (`values.rs`).
    pub values: Vec<f32>,
}

impl SkimageArrays {
    /// An empty sink; `flip` negates the normals (for an object below the
    /// level).
    pub fn new(flip: bool) -> Self {
        SkimageArrays {
            flip,
            planes: 0,
            verts: Vec::new(),
            faces: Vec::new(),
            normals: Vec::new(),
            values: Vec::new(),
        }
    }
}

/// `[x, y, z]` as `[z, y, x]`, times `sign`.
#[inline(always)]
fn reversed([x, y, z]: [f32; 3], sign: f32) -> [f32; 3] {
    [z * sign, y * sign, x * sign]
}

impl MeshSink for SkimageArrays {
    fn begin(&mut self, info: &MeshInfo) -> tmc::Result<()> {
        if !info.normals {
            return Err(tmc::Error::Invalid(
                "internal: scikit-image's arrays need an extraction with normals".into(),
            ));
        }
        self.planes = info.grid.dims[2] as u64 + if info.close { 2 } else { 0 };
        Ok(())
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> tmc::Result<()> {
        let n = chunk.vertices.len();
        if base + n as u64 > i32::MAX as u64 {
            return Err(tmc::Error::Invalid(format!(
                "the mesh has more than {} vertices, more than scikit-image's int32 faces index; use tmc.extract",
                i32::MAX
            )));
        }
        if chunk.normals.len() != n || chunk.values.len() != n {
            return Err(tmc::Error::Invalid(
                "internal: a chunk without a normal and a value per vertex".into(),
            ));
        }
        let (plane, planes) = (chunk.plane, self.planes);
        let t = chunk.triangles.len();
        reserve_for_planes(&mut self.verts, n, plane, planes, "the mesh's vertices")?;
        reserve_for_planes(&mut self.normals, n, plane, planes, "the mesh's normals")?;
        reserve_for_planes(&mut self.values, n, plane, planes, "the mesh's values")?;
        reserve_for_planes(&mut self.faces, t, plane, planes, "the mesh's triangles")?;
        self.verts
            .extend(chunk.vertices.iter().map(|&v| reversed(v, 1.0)));
        let sign = if self.flip { -1.0 } else { 1.0 };
        self.normals
            .extend(chunk.normals.iter().map(|&v| reversed(v, sign)));
        self.values.extend_from_slice(&chunk.values);
        // Below i32::MAX + 1: a triangle reaches at most into the next
        // chunk, whose own check bounds it.
        let base = base as u32;
        self.faces.extend(
            chunk
                .triangles
                .iter()
                .map(|tri| tri.map(|i| base.wrapping_add(i) as i32)),
        );
        Ok(())
    }

    fn finish(&mut self, _totals: &Totals) -> tmc::Result<()> {
        fit(&mut self.verts);
        fit(&mut self.faces);
        fit(&mut self.normals);
        fit(&mut self.values);
        Ok(())
    }
}
