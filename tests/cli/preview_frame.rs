//! `tmc preview` of a `.tmesh` extracted on a rotated or mirrored grid,
//! whose direction the format does not keep: the picture is framed by the
//! recorded (unrotated) grid's box as long as the mesh lies in it, and else
//! drawn again, framed by the mesh's own box: the whole mesh in every view,
//! the views of `tmc preview` of the same mesh as a PLY (read whole, framed
//! by its vertices: independent of the streaming pass), the same bytes for
//! any threads; `-q` silences the note saying so.

use crate::common;
use crate::preview::{decode, extract, shown_per_tile, BACKGROUND, SIZE};

use common::cli::{s, synth, tmc};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

/// The identity directions `tmc synth` writes.
const IDENTITY: &str = "space directions: (1,0,0) (0,1,0) (0,0,1)";

/// A ball volume of `dims` in `dir`, with `directions` (an NRRD `space
/// directions` value) instead of the identity: its path.
pub(crate) fn ball_on_grid(dir: &Path, dims: &str, directions: &str, name: &str) -> PathBuf {
    let plain = synth(dir, "sphere", dims, "f32", &format!("plain-{name}"));
    let bytes = fs::read(&plain).unwrap();
    let end = bytes.windows(2).position(|w| w == b"\n\n").unwrap();
    let header = String::from_utf8(bytes[..end].to_vec()).unwrap();
    assert!(header.contains(IDENTITY), "{header}");
    let mut out = header
        .replace(IDENTITY, &format!("space directions: {directions}"))
        .into_bytes();
    out.extend_from_slice(&bytes[end..]);
    let path = dir.join(name);
    fs::write(&path, out).unwrap();
    path
}

/// Per tile (front, side, top, oblique): the surface pixels (neither
/// background, tile border nor text) within four pixels of the tile's
/// edge, inside its border line: a mesh cut off by the frame has some.
fn at_the_edges(path: &Path) -> [usize; 4] {
    let (w, _, rgb) = decode(path);
    let (w, tile) = (w as usize, w as usize / 2);
    let mut counts = [0; 4];
    for (i, p) in rgb.chunks(3).take(w * w).enumerate() {
        let (x, y) = (i % w, i / w);
        let (tx, ty) = (x % tile, y % tile);
        let edge = tx.min(tile - 1 - tx).min(ty).min(tile - 1 - ty);
        if (1..=4).contains(&edge) && p != BACKGROUND && p != [80, 84, 92] && p != [240, 240, 240] {
            counts[usize::from(y >= tile) * 2 + usize::from(x >= tile)] += 1;
        }
    }
    counts
}

/// `tmc preview MESH -o PICTURE` plus `extra`, which must succeed.
fn preview(mesh: &Path, picture: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["preview", s(mesh), "-o", s(picture), "--title", "ball"];
    args.extend_from_slice(extra);
    let out = tmc(&args);
    assert!(out.status.success(), "{out:?}");
    out
}

/// The four tiles' RGB bytes (the caption band below them left out).
fn tiles(path: &Path) -> Vec<u8> {
    let (w, _, mut rgb) = decode(path);
    rgb.truncate((w * w * 3) as usize);
    rgb
}

#[test]
fn a_rotated_or_mirrored_grids_tmesh_is_framed_by_its_own_box() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A ball of radius 24 round sample (30, 30, 30), and grids that take
    // it out of the unrotated grid's box (x from -1 to 60): rotated by
    // 37 degrees about z (the centre at x = 6, y = 42), mirrored in x
    // (x from -54 to -6), mirrored in y and z; and a larger grid (the axis
    // views' lines dense), rotated.
    let cases = [
        (
            "60,60,60",
            "(0.8,0.6,0) (-0.6,0.8,0) (0,0,1)",
            "rotated.nrrd",
        ),
        ("60,60,60", "(-1,0,0) (0,1,0) (0,0,1)", "mirrored.nrrd"),
        ("60,60,60", "(1,0,0) (0,-1,0) (0,0,-1)", "mirrored_yz.nrrd"),
        (
            "131,120,141",
            "(0.8,0.6,0) (-0.6,0.8,0) (0,0,1)",
            "big.nrrd",
        ),
    ];
    for (dims, directions, name) in cases {
        let input = ball_on_grid(d, dims, directions, name);
        let mesh = d.join(format!("{name}.tmesh"));
        let extracted = d.join(format!("{name}-extract.png"));
        extract(&input, "0", &mesh, &extracted, &[]);
        // The extraction, which knows the direction, frames it whole.
        assert_eq!(at_the_edges(&extracted), [0; 4], "{name}: extract");
        let picture = d.join(format!("{name}.png"));
        let first = preview(&mesh, &picture, &["--threads", "1"]);
        assert_eq!(at_the_edges(&picture), [0; 4], "{name}: cut off");
        for (view, n) in shown_per_tile(&picture).into_iter().enumerate() {
            assert!(n > 20_000, "{name}: view {view} shows {n} pixels");
        }
        // The same views as the mesh read whole from a PLY.
        let ply = d.join(format!("{name}.ply"));
        let out = tmc(&["convert", s(&mesh), "-o", s(&ply)]);
        assert!(out.status.success(), "{out:?}");
        let from_ply = d.join(format!("{name}-ply.png"));
        preview(&ply, &from_ply, &[]);
        assert!(tiles(&picture) == tiles(&from_ply), "{name}: not the PLY's");
        let note = String::from_utf8_lossy(&first.stderr);
        assert!(
            note.starts_with("tmc: note: ") && note.contains("framed by its own box"),
            "{name}: {note}"
        );
        // Any threads: the same bytes.
        let again = d.join(format!("{name}-2.png"));
        preview(&mesh, &again, &["--threads", "2"]);
        assert!(fs::read(&again).unwrap() == fs::read(&picture).unwrap());
    }
}

#[test]
fn quiet_silences_the_note_and_a_mesh_in_the_box_takes_one_pass() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = ball_on_grid(d, "60,60,60", "(0.8,0.6,0) (-0.6,0.8,0) (0,0,1)", "r.nrrd");
    let mesh = d.join("r.tmesh");
    extract(&input, "0", &mesh, &d.join("extract.png"), &[]);
    let (loud, quiet) = (d.join("loud.png"), d.join("quiet.png"));
    assert!(!preview(&mesh, &loud, &[]).stderr.is_empty());
    for flag in ["-q", "--quiet"] {
        let out = preview(&mesh, &quiet, &[flag]);
        assert!(out.stderr.is_empty(), "{flag}: {out:?}");
        assert!(fs::read(&quiet).unwrap() == fs::read(&loud).unwrap());
    }
    // Rotated by 0.1 radians, the ball (x from 2.9 to 50.9, y from 8.8 to
    // 56.8) stays in the unrotated grid's box: framed by it, no note.
    let input = ball_on_grid(
        d,
        "60,60,60",
        "(0.995004165,0.099833417,0) (-0.099833417,0.995004165,0) (0,0,1)",
        "in.nrrd",
    );
    let mesh = d.join("in.tmesh");
    extract(&input, "0", &mesh, &d.join("in-extract.png"), &[]);
    let picture = d.join("in.png");
    let out = preview(&mesh, &picture, &[]);
    assert!(out.stderr.is_empty(), "{out:?}");
    assert_eq!(at_the_edges(&picture), [0; 4]);
    let (w, h, _) = decode(&picture);
    assert_eq!((w, h), SIZE);
}

/// The library's side: a recorded-grid sink whose mesh left the frame
/// writes nothing and hands back the second pass's sink, which refuses a
/// mesh other than the one first read; a mesh in its frame needs none.
#[test]
fn the_second_pass_must_read_the_same_mesh() {
    use tmc::export::replay;
    use tmc::meshfile::TmeshReader;
    use tmc::preview::PreviewSink;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rotated = ball_on_grid(d, "60,60,60", "(0.8,0.6,0) (-0.6,0.8,0) (0,0,1)", "r.nrrd");
    let (mesh, other) = (d.join("r.tmesh"), d.join("other.tmesh"));
    for (path, iso) in [(&mesh, "0"), (&other, "0.1")] {
        let out = tmc(&["extract", s(&rotated), "--iso", iso, "-o", s(path), "-q"]);
        assert!(out.status.success(), "{out:?}");
    }
    let picture = d.join("p.png");
    let first = || {
        let mut sink = PreviewSink::new(picture.clone(), "t".into(), None, 2).with_recorded_grid();
        replay(&mut TmeshReader::open(&mesh).unwrap(), &mut sink).unwrap();
        assert!(!picture.exists(), "the first pass wrote its picture");
        assert!(sink.summary().is_none());
        sink.reframed().expect("a second pass")
    };
    let mut again = first();
    let err = replay(&mut TmeshReader::open(&other).unwrap(), &mut again).unwrap_err();
    assert!(err.to_string().contains("not the one read first"), "{err}");
    assert!(!picture.exists());
    let mut again = first();
    replay(&mut TmeshReader::open(&mesh).unwrap(), &mut again).unwrap();
    assert!(picture.exists());
    assert!(again.reframed().is_none());
    // An unrotated grid's mesh: one pass.
    let plain = synth(d, "sphere", "60,60,60", "f32", "plain.nrrd");
    let out = tmc(&["extract", s(&plain), "--iso", "0", "-o", s(&mesh), "-q"]);
    assert!(out.status.success(), "{out:?}");
    let one = d.join("one.png");
    let mut sink = PreviewSink::new(one.clone(), "t".into(), None, 2).with_recorded_grid();
    replay(&mut TmeshReader::open(&mesh).unwrap(), &mut sink).unwrap();
    assert!(one.exists() && sink.reframed().is_none());
}
