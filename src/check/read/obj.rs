//! Wavefront OBJ: `v` and `f` statements (negative indices relative), and
//! `vn` where it gives each vertex one normal; every other statement must be
//! one OBJ defines.

use super::source::{parse, point, push_fan, Source, MAX_TRIANGLES};
use crate::mesh::Mesh;
use crate::Result;

/// The statement keywords of OBJ: every line with content must start with
/// one. Only `v`, `vn` and `f` are read; the others (texture coordinates,
/// groups, materials, free-form geometry...) are skipped.
const OBJ_KEYWORDS: &str = "v vt vn vp f l p g o s mg mtllib usemtl maplib usemap \
    cstype deg bmat step curv curv2 surf parm trim hole scrv sp end con bevel c_interp d_interp \
    lod shadow_obj trace_obj ctech stech call csh";

/// Joins into the current line the lines that a backslash at the end of
/// the line before continues (OBJ's line continuation: `f 1 2 \` then
/// `3`), each backslash replaced by a space; errors then name the last of
/// the joined lines. A backslash on the last line of the file continues
/// nothing; nor does one in a `#` comment.
fn join_continued(src: &mut Source) -> Result<()> {
    if src.buf.contains(&b'#') || !src.buf.trim_ascii_end().ends_with(b"\\") {
        return Ok(());
    }
    let mut joined = Vec::new();
    loop {
        match src.buf.trim_ascii_end().strip_suffix(b"\\") {
            Some(head) => {
                joined.extend_from_slice(head);
                joined.push(b' ');
                if !src.next_line()? {
                    break;
                }
            }
            None => {
                joined.extend_from_slice(&src.buf);
                break;
            }
        }
    }
    src.buf = joined;
    src.pos = 0;
    Ok(())
}

/// The vertex normals of an OBJ file: the `vn` statements and the one each
/// face corner (`v//vn`, `v/vt/vn`) names for its vertex. A mesh has normals
/// only when every vertex gets one, and one only: every corner names a
/// normal, and the corners of a vertex name the same (or equal) ones, as
/// tmc's OBJ writer gives them. A file with per-corner normals (a vertex's
/// faces shaded apart) or without them for some corners has none.
#[derive(Default)]
struct ObjNormals {
    /// The `vn` statements so far.
    given: Vec<[f32; 3]>,
    /// Per vertex index, the normal its corners named (`u32::MAX`: none yet).
    of_vertex: Vec<u32>,
    /// Whether a corner named no normal, or a vertex two different ones.
    inconsistent: bool,
    /// The largest normal index named and its line, checked at the end
    /// (as vertex indices are: they may name statements that come later).
    max_index: Option<(u32, usize)>,
}

impl ObjNormals {
    /// Records that a corner of `vertex` names the normal `field` (the
    /// corner's third `/` field; `None` when it has none).
    fn corner(&mut self, src: &Source, vertex: u32, field: Option<&[u8]>) -> Result<()> {
        let Some(field) = field.filter(|f| !f.is_empty()) else {
            self.inconsistent = true;
            return Ok(());
        };
        let resolved = resolve(src, field, "normal", self.given.len(), &mut self.max_index)?;
        let vertex = vertex as usize;
        if self.of_vertex.len() <= vertex {
            self.of_vertex.resize(vertex + 1, u32::MAX);
        }
        let named = &mut self.of_vertex[vertex];
        if *named == u32::MAX {
            *named = resolved;
        } else if *named != resolved {
            // Equal values under two indices are one normal; compared at
            // the end, when every `vn` is known.
            self.inconsistent |= self.given.get(*named as usize).is_none()
                || self.given.get(resolved as usize) != self.given.get(*named as usize);
        }
        Ok(())
    }

    /// The mesh's normals (one per vertex, or none), or an error for a
    /// normal index past the last `vn`.
    fn finish(self, src: &Source, vertices: usize) -> Result<Vec<[f32; 3]>> {
        if let Some((index, line)) = self.max_index {
            if index as usize >= self.given.len() {
                return Err(src.err(format!(
                    "line {line}: normal index {} out of range ({} normals)",
                    u64::from(index) + 1,
                    self.given.len()
                )));
            }
        }
        if self.inconsistent || self.given.is_empty() || self.of_vertex.len() < vertices {
            return Ok(Vec::new());
        }
        let named = &self.of_vertex[..vertices];
        if named.contains(&u32::MAX) {
            return Ok(Vec::new());
        }
        Ok(named.iter().map(|&i| self.given[i as usize]).collect())
    }
}

/// A face corner's vertex or normal index (`what`) counted from 0: OBJ
/// counts from 1, and a negative index back from the last of the `defined`
/// statements so far. `max` keeps the largest and its line, for the check
/// at the end (a positive index may name a statement that comes later).
fn resolve(
    src: &Source,
    field: &[u8],
    what: &str,
    defined: usize,
    max: &mut Option<(u32, usize)>,
) -> Result<u32> {
    let index: i64 = parse(field).ok_or_else(|| {
        src.err_line(format!(
            "invalid face {what} index '{}'",
            String::from_utf8_lossy(field)
        ))
    })?;
    let resolved = match index {
        0 => return Err(src.err_line(format!("{what} index 0 (OBJ counts from 1)"))),
        i if i > 0 => i - 1,
        i => defined as i64 + i,
    };
    if resolved < 0 || resolved >= i64::from(u32::MAX) {
        return Err(src.err_line(format!(
            "{what} index {index} out of range ({defined} {what}s so far)"
        )));
    }
    let resolved = resolved as u32;
    if max.is_none_or(|(m, _)| resolved > m) {
        *max = Some((resolved, src.line));
    }
    Ok(resolved)
}

pub(super) fn read_obj(src: &mut Source) -> Result<Mesh> {
    let mut mesh = Mesh::default();
    let mut normals = ObjNormals::default();
    let mut polygon: Vec<u32> = Vec::new();
    // The largest positive index seen and its line, checked at the end
    // (positive indices may refer to vertices defined later).
    let mut max_index: Option<(u32, usize)> = None;
    while src.next_line()? {
        join_continued(src)?;
        if src.line == 1 {
            // A UTF-8 byte order mark, as some Windows tools write.
            if let Some(rest) = src.buf.strip_prefix(b"\xEF\xBB\xBF") {
                src.buf = rest.to_vec();
            }
        }
        if src.buf.contains(&0) || std::str::from_utf8(&src.buf).is_err() {
            return Err(src.err_line("not an OBJ file: NUL or non-UTF-8 bytes"));
        }
        if !src.strip_comment() {
            continue;
        }
        let mut words = src.words();
        let keyword = words.next().unwrap_or_default();
        if !OBJ_KEYWORDS
            .split_ascii_whitespace()
            .any(|k| k.as_bytes() == keyword)
        {
            let keyword: String = String::from_utf8_lossy(keyword).chars().take(40).collect();
            return Err(src.err_line(format!(
                "not an OBJ file: '{keyword}' is not an OBJ statement"
            )));
        }
        match keyword {
            b"v" => {
                let p = point(src, 1)?;
                if mesh.vertices.len() >= u32::MAX as usize {
                    return Err(src.err("too many vertices"));
                }
                mesh.vertices.push(p);
            }
            b"vn" => normals.given.push(point(src, 1)?),
            b"f" => {
                polygon.clear();
                for word in words {
                    let mut fields = word.split(|&b| b == b'/');
                    let first = fields.next().unwrap_or(word);
                    let defined = mesh.vertices.len();
                    let resolved = resolve(src, first, "vertex", defined, &mut max_index)?;
                    normals.corner(src, resolved, fields.nth(1))?;
                    polygon.push(resolved);
                }
                if polygon.len() < 3 {
                    return Err(src.err_line(format!(
                        "face has {} vertices (at least 3 needed)",
                        polygon.len()
                    )));
                }
                push_fan(&mut mesh.triangles, &polygon);
                if mesh.triangles.len() > MAX_TRIANGLES {
                    return Err(src.err("too many triangles"));
                }
            }
            _ => {}
        }
    }
    if let Some((index, line)) = max_index {
        if index as usize >= mesh.vertices.len() {
            return Err(src.err(format!(
                "line {line}: vertex index {} out of range ({} vertices)",
                u64::from(index) + 1,
                mesh.vertices.len()
            )));
        }
    }
    let normals = normals.finish(src, mesh.vertices.len())?;
    mesh.normals = (!normals.is_empty()).then_some(normals);
    Ok(mesh)
}

// ---------------------------------------------------------------- OFF ----
