//! Wavefront OBJ: `v` and `f` statements (negative indices relative);
//! every other statement must be one OBJ defines.

use super::source::{parse, point, push_fan, Source, MAX_TRIANGLES};
use crate::mesh::Mesh;
use crate::Result;

/// The statement keywords of OBJ: every line with content must start with
/// one. Only `v` and `f` are read; the others (texture coordinates, normals,
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

pub(super) fn read_obj(src: &mut Source) -> Result<Mesh> {
    let mut mesh = Mesh::default();
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
            b"f" => {
                polygon.clear();
                for word in words {
                    let first = word.split(|&b| b == b'/').next().unwrap_or(word);
                    let index: i64 = parse(first).ok_or_else(|| {
                        src.err_line(format!(
                            "invalid face vertex '{}'",
                            String::from_utf8_lossy(word)
                        ))
                    })?;
                    let resolved = match index {
                        0 => return Err(src.err_line("vertex index 0 (OBJ counts from 1)")),
                        i if i > 0 => i - 1,
                        i => mesh.vertices.len() as i64 + i,
                    };
                    if resolved < 0 || resolved >= i64::from(u32::MAX) {
                        return Err(src.err_line(format!(
                            "vertex index {index} out of range ({} vertices so far)",
                            mesh.vertices.len()
                        )));
                    }
                    let resolved = resolved as u32;
                    if max_index.is_none_or(|(m, _)| resolved > m) {
                        max_index = Some((resolved, src.line));
                    }
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
    Ok(mesh)
}

// ---------------------------------------------------------------- OFF ----
