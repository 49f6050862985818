//! STL, binary and ASCII, for drawing (`tmc preview`) and for `tmc check`:
//! STL repeats the corners of every facet instead of sharing vertices, so
//! the reader joins corners at bit-identical positions (`-0` as `0`) into
//! one vertex. That gives back the connectivity of a mesh written from an
//! indexed one with no two vertices at one position (what `tmc extract -o
//! X.stl` writes), so the picture's caption and the check's report are
//! those of the PLY. Vertices that shared a position become one, so it is
//! no proof of the connectivity the mesh had; [`read_mesh`] (the library's
//! and Python's reader) still refuses STL, and `tmc check` says so in a
//! note.
//!
//! [`read_mesh`]: super::read_mesh

use super::source::{parse, Source, MAX_RESERVE, MAX_TRIANGLES};
use crate::mesh::Mesh;
use crate::Result;
use std::collections::HashMap;
use std::io::Read;

/// Corners joined by their position's bits; builds the [`Mesh`].
struct Welder {
    mesh: Mesh,
    index: HashMap<[u32; 3], u32>,
}

impl Welder {
    fn new(facets: usize) -> Welder {
        Welder {
            mesh: Mesh {
                vertices: Vec::with_capacity((facets / 2).min(MAX_RESERVE)),
                triangles: Vec::with_capacity(facets.min(MAX_RESERVE)),
                ..Mesh::default()
            },
            index: HashMap::new(),
        }
    }

    /// Adds a facet of three finite corners.
    fn facet(&mut self, src: &Source, corners: &[[f32; 3]; 3]) -> Result<()> {
        if self.mesh.triangles.len() >= MAX_TRIANGLES {
            return Err(src.err("too many triangles"));
        }
        let vertices = &mut self.mesh.vertices;
        let triangle = corners.map(|p| {
            // `+ 0.0` turns -0 into 0, so that the two zeros are one position.
            let key = p.map(|c| (c + 0.0).to_bits());
            *self.index.entry(key).or_insert_with(|| {
                vertices.push(p);
                (vertices.len() - 1) as u32
            })
        });
        self.mesh.triangles.push(triangle);
        Ok(())
    }
}

/// Reads a binary or ASCII STL file (binary when its length is that of
/// the facet count at bytes 80..84, as some binary headers also start with
/// `solid`); corners at the same position become one vertex.
pub(super) fn read_stl(src: &mut Source, binary: bool) -> Result<Mesh> {
    if binary {
        read_binary(src)
    } else {
        read_ascii(src)
    }
}

fn read_binary(src: &mut Source) -> Result<Mesh> {
    let mut head = [0u8; 84];
    src.reader.read_exact(&mut head).map_err(|e| src.io(e))?;
    let count = u32::from_le_bytes(head[80..84].try_into().expect("four bytes")) as usize;
    let mut welder = Welder::new(count);
    let mut record = [0u8; 50];
    for facet in 0..count {
        src.reader.read_exact(&mut record).map_err(|e| src.io(e))?;
        let mut corners = [[0.0f32; 3]; 3];
        for (k, corner) in corners.iter_mut().enumerate() {
            for (j, c) in corner.iter_mut().enumerate() {
                let at = 12 + 12 * k + 4 * j;
                *c = f32::from_le_bytes(record[at..at + 4].try_into().expect("four bytes"));
                if !c.is_finite() {
                    return Err(src.err(format!(
                        "STL facet {facet}: coordinate {c} is not a finite number"
                    )));
                }
            }
        }
        welder.facet(src, &corners)?;
    }
    Ok(welder.mesh)
}

fn read_ascii(src: &mut Source) -> Result<Mesh> {
    let mut welder = Welder::new(0);
    // Where in a solid the reader is: outside one, or in one with the
    // corners of the current facet (None between facets).
    let mut in_solid = false;
    let mut corners: Option<Vec<[f32; 3]>> = None;
    let mut solids = 0usize;
    while src.next_line()? {
        let words: Vec<&[u8]> = src.words().collect();
        let Some(&first) = words.first() else {
            continue;
        };
        let unexpected = || {
            src.err_line(format!(
                "unexpected '{}' in an ASCII STL file",
                String::from_utf8_lossy(first)
            ))
        };
        match (first, in_solid, corners.is_some()) {
            (b"solid", false, _) => {
                in_solid = true;
                solids += 1;
            }
            (b"endsolid", true, false) => in_solid = false,
            (b"facet", true, false) => corners = Some(Vec::with_capacity(3)),
            (b"outer" | b"endloop", true, true) => {}
            (b"vertex", true, true) => {
                let corner = corners.as_mut().expect("in a facet");
                if words.len() != 4 {
                    return Err(src.err_line("an STL vertex needs three coordinates"));
                }
                let mut p = [0.0f32; 3];
                for (c, word) in p.iter_mut().zip(&words[1..]) {
                    *c = parse(word).filter(|c: &f32| c.is_finite()).ok_or_else(|| {
                        src.err_line(format!(
                            "STL vertex coordinate '{}' is not a finite number",
                            String::from_utf8_lossy(word)
                        ))
                    })?;
                }
                corner.push(p);
            }
            (b"endfacet", true, true) => {
                let facet = corners.take().expect("in a facet");
                let Ok(facet) = <[[f32; 3]; 3]>::try_from(facet) else {
                    return Err(src.err_line("an STL facet needs exactly three vertices"));
                };
                welder.facet(src, &facet)?;
            }
            _ => return Err(unexpected()),
        }
    }
    if solids == 0 {
        return Err(src.err("not an STL file (no 'solid' line)"));
    }
    if in_solid {
        return Err(src.err("truncated ASCII STL file (no 'endsolid')"));
    }
    Ok(welder.mesh)
}
