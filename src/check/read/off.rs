//! OFF and its `[ST][C][N][4][n]OFF` variants: the columns each vertex and
//! face line may hold are set by the header keyword; an `NOFF` file's
//! vertex normals are kept as the mesh's normals.

use super::source::{finite, parse, point, push_fan, Source, MAX_RESERVE, MAX_TRIANGLES};
use crate::mesh::Mesh;
use crate::Result;

/// The columns of an OFF vertex line, which the header keyword
/// `[ST][C][N]OFF` declares (Geomview's OFF; the prefixes in any order,
/// each at most once): `x y z`, then with `N` a normal `nx ny nz`, with `C`
/// a colour `r g b` or `r g b a`, with `ST` texture coordinates `s t`.
/// Every column must be a number; a line with fewer or more columns is
/// refused (so that a colour, say, is never taken for part of the next
/// vertex or silently dropped).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct OffLayout {
    normal: bool,
    colour: bool,
    texture: bool,
}

impl OffLayout {
    /// The layout the prefix of `OFF` declares; `None` for an unknown or
    /// repeated prefix.
    fn parse(mut prefix: &str) -> Option<OffLayout> {
        let mut layout = OffLayout::default();
        while !prefix.is_empty() {
            let (flag, len) = match prefix.as_bytes()[0] {
                b'S' if prefix.starts_with("ST") => (&mut layout.texture, 2),
                b'C' => (&mut layout.colour, 1),
                b'N' => (&mut layout.normal, 1),
                _ => return None,
            };
            if std::mem::replace(flag, true) {
                return None;
            }
            prefix = &prefix[len..];
        }
        Some(layout)
    }

    /// The fewest and most columns of a vertex line.
    fn columns(self) -> (usize, usize) {
        let least = 3
            + 3 * usize::from(self.normal)
            + 3 * usize::from(self.colour)
            + 2 * usize::from(self.texture);
        (least, least + usize::from(self.colour))
    }

    /// The columns, for messages: `x y z nx ny nz r g b [a] s t`.
    fn describe(self) -> String {
        let mut s = String::from("x y z");
        for (on, what) in [
            (self.normal, " nx ny nz"),
            (self.colour, " r g b [a]"),
            (self.texture, " s t"),
        ] {
            if on {
                s += what;
            }
        }
        s
    }

    /// Checks the columns of the vertex line in `src` against the layout.
    fn check(self, src: &Source, keyword: &str) -> Result<()> {
        let (least, most) = self.columns();
        let mut n = 0;
        for word in src.words() {
            n += 1;
            if n > 3 && n <= most && finite(word).is_none() {
                return Err(src.err_line(format!(
                    "vertex column {n} '{}' is not a finite number",
                    String::from_utf8_lossy(word)
                )));
            }
        }
        // Fewer than three: `point` names the missing coordinate.
        if n >= 3 && !(least..=most).contains(&n) {
            let count = if least == most {
                least.to_string()
            } else {
                format!("{least} or {most}")
            };
            return Err(src.err_line(format!(
                "vertex has {n} columns; the header '{keyword}' declares {count} ({})",
                self.describe()
            )));
        }
        Ok(())
    }
}

/// Checks what follows the `n` vertex indices of an OFF face line: nothing,
/// a colour index (as some writers emit), or an RGB or RGBA colour, every
/// column a number. Anything else is refused, so that a face with more
/// indices than its count says, or a line run together with the next, is
/// never read as a smaller face with a "colour".
fn check_face_colour<'a>(
    src: &Source,
    rest: impl Iterator<Item = &'a [u8]>,
    n: usize,
) -> Result<()> {
    let mut extra = 0;
    for word in rest {
        extra += 1;
        if finite(word).is_none() {
            return Err(src.err_line(format!(
                "face column {} '{}' is not a finite number (a face's colour follows its {n} vertex indices)",
                1 + n + extra,
                String::from_utf8_lossy(word)
            )));
        }
    }
    if matches!(extra, 0 | 1 | 3 | 4) {
        return Ok(());
    }
    Err(src.err_line(format!(
        "face has {extra} numbers after its {n} vertex indices; OFF allows 0, 1 (a colour index), 3 (r g b) or 4 (r g b a)"
    )))
}

pub(super) fn read_off(src: &mut Source) -> Result<Mesh> {
    if !src.next_content_line()? {
        return Err(src.err("empty OFF file"));
    }
    let words: Vec<Vec<u8>> = src.words().map(<[u8]>::to_vec).collect();
    let keyword = String::from_utf8_lossy(&words[0]).into_owned();
    let prefix = keyword
        .strip_suffix("OFF")
        .ok_or_else(|| src.err_line(format!("not an OFF file (header '{keyword}')")))?;
    if prefix.contains('4') || prefix.contains('n') {
        return Err(src.err_line(format!("{keyword} files (not 3-D) are not supported")));
    }
    let layout = OffLayout::parse(prefix).ok_or_else(|| {
        src.err_line(format!(
            "unknown OFF header keyword '{keyword}' (expected OFF with prefixes ST, C or N)"
        ))
    })?;
    let mut counts: Vec<Vec<u8>> = words[1..].to_vec();
    if counts.first().is_some_and(|w| w == b"BINARY") {
        return Err(src.err_line("binary OFF files are not supported"));
    }
    if counts.is_empty() {
        if !src.next_content_line()? {
            return Err(src.err("truncated OFF file: no vertex and face counts"));
        }
        counts = src.words().map(<[u8]>::to_vec).collect();
    }
    let count = |i: usize| -> Result<usize> {
        counts
            .get(i)
            .and_then(|w| parse::<usize>(w))
            .ok_or_else(|| src.err_line("invalid OFF counts (expected 'vertices faces edges')"))
    };
    let (nv, nf) = (count(0)?, count(1)?);
    if nv > u32::MAX as usize {
        return Err(src.err(format!("too many vertices ({nv})")));
    }
    let mut mesh = Mesh {
        vertices: Vec::with_capacity(nv.min(MAX_RESERVE)),
        triangles: Vec::with_capacity(nf.min(MAX_RESERVE)),
        ..Mesh::default()
    };
    // NOFF declares normals: an empty mesh has them too.
    let mut normals = Vec::with_capacity(if layout.normal {
        nv.min(MAX_RESERVE)
    } else {
        0
    });
    for i in 0..nv {
        if !src.next_content_line()? {
            return Err(src.err(format!("truncated OFF file: {i} of {nv} vertices")));
        }
        layout.check(src, &keyword)?;
        mesh.vertices.push(point(src, 0)?);
        if layout.normal {
            // The three columns after x y z (`check` found them finite).
            normals.push(point(src, 3)?);
        }
    }
    mesh.normals = layout.normal.then_some(normals);
    let mut polygon: Vec<u32> = Vec::new();
    for i in 0..nf {
        if !src.next_content_line()? {
            return Err(src.err(format!("truncated OFF file: {i} of {nf} faces")));
        }
        let mut words = src.words();
        let n: usize = words
            .next()
            .and_then(parse)
            .ok_or_else(|| src.err_line("invalid face vertex count"))?;
        if n < 3 {
            return Err(src.err_line(format!("face has {n} vertices (at least 3 needed)")));
        }
        polygon.clear();
        for _ in 0..n {
            let index: u32 = words
                .next()
                .and_then(parse)
                .filter(|&k: &u32| (k as usize) < nv)
                .ok_or_else(|| {
                    src.err_line(format!(
                        "missing or out-of-range vertex index ({nv} vertices)"
                    ))
                })?;
            polygon.push(index);
        }
        check_face_colour(src, words, n)?;
        push_fan(&mut mesh.triangles, &polygon);
        if mesh.triangles.len() > MAX_TRIANGLES {
            return Err(src.err("too many triangles"));
        }
    }
    if src.next_content_line()? {
        return Err(src.err_line(format!(
            "content after the {nv} vertices and {nf} faces that the OFF header declares"
        )));
    }
    Ok(mesh)
}
