//! Preview pictures (`tmc extract --preview`, `tmc preview`): the PNG
//! decodes (the `png` crate, and Pillow through `TMC_PYTHON` when set), has
//! the stated size, shows the mesh, has the same bytes for any threads,
//! slab depth, a merged split and `tmc preview` of the written `.tmesh`,
//! expands batch templates, and fails on bad paths with one line and no
//! file; `tmc compare --preview` puts the two methods' pictures side by
//! side with the differing cells marked, and none where no cell differs.

use crate::common;

use common::cli::{assert_one_line, names, s, synth, tmc};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Width and height of every preview.
pub(crate) const SIZE: (u32, u32) = (1024, 1064);

/// Background colour of the tiles.
pub(crate) const BACKGROUND: [u8; 3] = [30, 32, 36];

/// Decodes `path` with the `png` crate: (width, height, RGB bytes).
pub(crate) fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

/// Pixels of the four tiles (above the caption band) that are not
/// background and not the grey of the tile borders or the white text.
fn shown(path: &Path) -> usize {
    shown_per_tile(path).iter().sum()
}

/// [`shown`] per tile: front, side (top row), top, oblique (bottom row).
pub(crate) fn shown_per_tile(path: &Path) -> [usize; 4] {
    let (w, _, rgb) = decode(path);
    let w = w as usize;
    let mut counts = [0; 4];
    for (i, p) in rgb.chunks(3).take(w * w).enumerate() {
        if p != BACKGROUND && p != [80, 84, 92] && p != [240, 240, 240] {
            let (x, y) = (i % w, i / w);
            counts[usize::from(y >= w / 2) * 2 + usize::from(x >= w / 2)] += 1;
        }
    }
    counts
}

/// With `TMC_PYTHON` set: Pillow's size, mode and non-background count of
/// `path` (it must agree with ours); without it, a SKIPPED line.
fn check_with_pillow(path: &Path) {
    let script = "w, h = im.size\nbg = {(30, 32, 36), (80, 84, 92), (240, 240, 240)}\n\
                  px = im.convert('RGB').getdata()\n\
                  n = sum(1 for i, p in enumerate(px) if i < w * w and p not in bg)\n\
                  print(im.format, im.mode, w, h, n)";
    if let Some(text) = pillow(path, script) {
        let expected = format!("PNG RGB {} {} {}", SIZE.0, SIZE.1, shown(path));
        assert_eq!(text.trim(), expected);
    }
}

/// With `TMC_PYTHON` set: what `script` prints with `im`, the picture at
/// `path` opened and loaded by Pillow; without it, a SKIPPED line and
/// `None`.
fn pillow(path: &Path, script: &str) -> Option<String> {
    let Ok(python) = std::env::var("TMC_PYTHON") else {
        println!("SKIPPED: Pillow check: TMC_PYTHON is not set (see .ci/run)");
        return None;
    };
    let script = format!(
        "import sys\nfrom PIL import Image\nim = Image.open(sys.argv[1])\nim.load()\n{script}"
    );
    let out = Command::new(python)
        .args(["-c", &script, s(path)])
        .output()
        .expect("run TMC_PYTHON");
    assert!(out.status.success(), "{out:?}");
    Some(String::from_utf8(out.stdout).unwrap())
}

/// A sphere volume in `dir`.
fn sphere(dir: &Path) -> PathBuf {
    synth(dir, "sphere", "40,36,44", "f32", "ball.nrrd")
}

/// `tmc extract INPUT --iso ISO -o MESH --preview PICTURE` plus `extra`.
pub(crate) fn extract(input: &Path, iso: &str, mesh: &Path, picture: &Path, extra: &[&str]) {
    let mut args = vec![
        "extract",
        s(input),
        "--iso",
        iso,
        "-o",
        s(mesh),
        "--preview",
        s(picture),
        "-q",
    ];
    args.extend_from_slice(extra);
    let out = tmc(&args);
    assert!(out.status.success(), "{out:?}");
}

#[test]
fn a_sphere_preview_decodes_has_its_size_and_shows_the_ball() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere(dir.path());
    let picture = dir.path().join("ball.png");
    extract(&input, "0", &dir.path().join("ball.ply"), &picture, &[]);
    let (w, h, _) = decode(&picture);
    assert_eq!((w, h), SIZE);
    // The ball's radius is 0.8 of half the shortest side: its disc covers
    // a good part of each view.
    let n = shown(&picture);
    assert!(n > 4 * 50_000, "{n} pixels shown");
    check_with_pillow(&picture);
}

#[test]
fn tmc_preview_of_an_empty_mesh_draws_the_empty_views() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = sphere(d);
    // An isovalue above every sample: `extract` writes empty meshes and
    // draws empty views.
    let drawn = d.join("extract.png");
    extract(&input, "1e30", &d.join("none.ply"), &drawn, &[]);
    let (w, _, expected) = decode(&drawn);
    let tiles = (w * w * 3) as usize;
    for ext in ["obj", "off"] {
        let mesh = d.join(format!("none.{ext}"));
        let out = tmc(&["extract", s(&input), "--iso", "1e30", "-o", s(&mesh), "-q"]);
        assert!(out.status.success(), "{out:?}");
    }
    for ext in ["ply", "obj", "off"] {
        let picture = d.join(format!("{ext}.png"));
        let mesh = d.join(format!("none.{ext}"));
        let out = tmc(&["preview", s(&mesh), "-o", s(&picture)]);
        assert!(out.status.success(), "{ext}: {out:?}");
        let (w, h, rgb) = decode(&picture);
        assert_eq!((w, h), SIZE, "{ext}");
        assert_eq!(shown(&picture), 0, "{ext}");
        // The four views (the caption below differs: no isovalue).
        assert!(rgb[..tiles] == expected[..tiles], "{ext}");
    }
}

#[test]
fn threads_slabs_a_merged_split_and_tmc_preview_give_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Large enough (lines at most two depth-buffer pixels apart) for the
    // axis views to be drawn from the vertices on grid lines.
    let input = synth(d, "gyroid", "131,120,141", "f32", "gyroid.npy");
    let reference = d.join("ref.png");
    extract(
        &input,
        "0.1",
        &d.join("ref.tmesh"),
        &reference,
        &["--threads", "1"],
    );
    let bytes = fs::read(&reference).unwrap();
    for (i, extra) in [
        &["--threads", "2"][..],
        &["--threads", "2", "--slab-depth", "1"],
        &["--threads", "1", "--slab-depth", "5"],
    ]
    .iter()
    .enumerate()
    {
        let picture = d.join(format!("p{i}.png"));
        extract(&input, "0.1", &d.join(format!("m{i}.ply")), &picture, extra);
        assert!(fs::read(&picture).unwrap() == bytes, "{extra:?} differs");
    }
    // The written mesh, and the same mesh split in three and merged.
    let again = d.join("again.png");
    let preview = |mesh: &Path, picture: &Path, threads: &str| {
        let out = tmc(&[
            "preview",
            s(mesh),
            "-o",
            s(picture),
            "--title",
            "gyroid.npy",
            "--threads",
            threads,
        ]);
        assert!(out.status.success(), "{out:?}");
    };
    preview(&d.join("ref.tmesh"), &again, "2");
    assert!(fs::read(&again).unwrap() == bytes, "tmc preview differs");
    let mut parts = Vec::new();
    for i in 1..=3 {
        let part = d.join(format!("part{i}.tmesh"));
        let spec = format!("{i}/3");
        let out = tmc(&[
            "extract",
            s(&input),
            "--iso",
            "0.1",
            "--part",
            &spec,
            "-o",
            s(&part),
            "-q",
        ]);
        assert!(out.status.success(), "{out:?}");
        parts.push(part);
    }
    let merged = d.join("merged.tmesh");
    let mut args = vec!["merge"];
    args.extend(parts.iter().map(|p| s(p)));
    args.extend(["-o", s(&merged)]);
    let out = tmc(&args);
    assert!(out.status.success(), "{out:?}");
    let from_parts = d.join("parts.png");
    preview(&merged, &from_parts, "1");
    assert!(
        fs::read(&from_parts).unwrap() == bytes,
        "merged split differs"
    );
}

/// A `.tmesh` keeps no direction cosines: `tmc preview` of one extracted on
/// a rotated grid must not take its vertices for points of the unrotated
/// grid's lines (they lie on none: the axis views would be a few dots), and
/// draws every view from the triangles. The rotation (0.1 radians about z)
/// keeps the ball in the unrotated grid's box, so this is the one pass
/// framed by that box (no note); a mesh leaving it: `preview_frame.rs`.
#[test]
fn tmc_preview_of_a_rotated_grid_draws_every_view() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Large enough for the unrotated grid's lines to be dense.
    let input = crate::preview_frame::ball_on_grid(
        d,
        "131,120,141",
        "(0.995004165,0.099833417,0) (-0.099833417,0.995004165,0) (0,0,1)",
        "rotated.nrrd",
    );
    let mesh = d.join("rotated.tmesh");
    extract(&input, "0", &mesh, &d.join("extract.png"), &[]);
    let picture = d.join("preview.png");
    let out = tmc(&["preview", s(&mesh), "-o", s(&picture)]);
    assert!(out.status.success(), "{out:?}");
    assert!(out.stderr.is_empty(), "{out:?}");
    for (view, n) in shown_per_tile(&picture).into_iter().enumerate() {
        assert!(n > 5_000, "view {view} shows {n} pixels");
    }
}

#[test]
fn the_streamed_verdict_matches_the_checker() {
    // The caption's counts (components, edges, boundary edges, genus),
    // counted over a window of two chunks, against `tmc::check` on the
    // whole mesh: closed and open meshes with many components and handles.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases = [
        ("torus", "30,30,20", "0", true),
        ("gyroid", "33,29,31", "0.2", true),
        ("gyroid", "33,29,31", "-0.1", false),
        ("noise", "40,37,23", "0.05", false),
    ];
    for (i, (kind, dims, iso, close)) in cases.into_iter().enumerate() {
        let input = synth(d, kind, dims, "f32", &format!("v{i}.npy"));
        let tmesh = d.join(format!("v{i}.tmesh"));
        let mut extra = vec!["--slab-depth", "3"];
        if close {
            extra.push("--close");
        }
        extract(&input, iso, &tmesh, &d.join(format!("v{i}.png")), &extra);
        let mut reader = tmc::meshfile::TmeshReader::open(&tmesh).unwrap();
        let mut sink = tmc::preview::PreviewSink::new(d.join("again.png"), "t".into(), None, 2);
        tmc::export::replay(&mut reader, &mut sink).unwrap();
        let (_, verdict) = sink.summary().unwrap();
        let report = tmc::check::check_mesh(&tmc::check::read_mesh(&tmesh).unwrap());
        let case = format!("{kind} {iso} close={close}");
        assert_eq!(verdict.components, report.components as u64, "{case}");
        assert_eq!(verdict.edges, report.edges as u64, "{case}");
        assert_eq!(
            verdict.boundary_edges, report.boundary_edges as u64,
            "{case}"
        );
        assert_eq!(verdict.euler(), report.euler, "{case}");
        assert_eq!(verdict.closed(), close, "{case}");
        if close {
            assert_eq!(verdict.genus(), report.total_genus(), "{case}");
        }
        if kind == "noise" {
            assert!(report.components > 1, "{case}: {report:?}");
        }
    }
}

#[test]
fn a_batch_expands_stem_and_iso_in_the_preview_template() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let a = synth(d, "sphere", "20,20,20", "f32", "a.npy");
    let b = synth(d, "torus", "20,20,16", "f32", "b.npy");
    let out_dir = d.join("out");
    fs::create_dir(&out_dir).unwrap();
    let mesh = out_dir.join("{stem}_{iso}.ply");
    let picture = out_dir.join("{stem}_{iso}.png");
    let out = tmc(&[
        "extract",
        s(&a),
        s(&b),
        "--iso",
        "0",
        "--iso",
        "0.2",
        "-o",
        s(&mesh),
        "--preview",
        s(&picture),
        "-q",
    ]);
    assert!(out.status.success(), "{out:?}");
    let got = names(&out_dir);
    for name in ["a_0.png", "a_0.2.png", "b_0.png", "b_0.2.png"] {
        assert!(got.contains(&name.to_string()), "{got:?}");
        assert_eq!(decode(&out_dir.join(name)).0, SIZE.0);
    }
    // Several inputs and one picture path: refused before any work.
    let dir2 = tempfile::tempdir().unwrap();
    let out = tmc(&[
        "extract",
        s(&a),
        s(&b),
        "--iso",
        "0",
        "-o",
        s(&dir2.path().join("{stem}.ply")),
        "--preview",
        s(&dir2.path().join("all.png")),
    ]);
    let line = assert_one_line(&out, 1);
    assert!(line.contains("{stem}"), "{line}");
    assert!(names(dir2.path()).is_empty());
}

#[test]
fn bad_paths_give_one_line_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = synth(d, "sphere", "12,12,12", "f32", "s.npy");
    let mesh = d.join("s.tmesh");
    let ok = tmc(&["extract", s(&input), "--iso", "0", "-o", s(&mesh), "-q"]);
    assert!(ok.status.success());
    let before = names(d);
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![
                "preview".into(),
                s(&mesh).into(),
                "-o".into(),
                s(&d.join("s.jpg")).into(),
            ],
            "must end in .png",
        ),
        (
            vec![
                "preview".into(),
                s(&mesh).into(),
                "-o".into(),
                s(&d.join("no/s.png")).into(),
            ],
            "does not exist",
        ),
        (
            vec![
                "preview".into(),
                s(&d.join("missing.tmesh")).into(),
                "-o".into(),
                s(&d.join("m.png")).into(),
            ],
            "missing.tmesh",
        ),
        (
            vec![
                "preview".into(),
                s(&input).into(),
                "-o".into(),
                s(&d.join("v.png")).into(),
            ],
            "s.npy",
        ),
        (
            vec![
                "extract".into(),
                s(&input).into(),
                "--iso".into(),
                "0".into(),
                "-o".into(),
                s(&d.join("x.ply")).into(),
                "--preview".into(),
                s(&d.join("x.gif")).into(),
            ],
            "must end in .png",
        ),
        (
            vec![
                "extract".into(),
                s(&input).into(),
                "--iso".into(),
                "0".into(),
                "--part".into(),
                "1/2".into(),
                "-o".into(),
                s(&d.join("p.tmesh")).into(),
                "--preview".into(),
                s(&d.join("p.png")).into(),
            ],
            "tmc preview",
        ),
    ];
    for (args, needle) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let line = assert_one_line(&tmc(&args), 1);
        assert!(line.contains(needle), "{args:?}: {line}");
        assert_eq!(names(d), before, "{args:?} left a file");
    }
    // A damaged .tmesh: the picture is not written.
    let mut bytes = fs::read(&mesh).unwrap();
    let n = bytes.len();
    bytes[n - 40] ^= 0xff;
    let damaged = d.join("damaged.tmesh");
    fs::write(&damaged, bytes).unwrap();
    let out = tmc(&["preview", s(&damaged), "-o", s(&d.join("d.png"))]);
    assert_one_line(&out, 1);
    assert!(!d.join("d.png").exists());
}

#[test]
fn a_real_ct_preview_shows_the_skull() {
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/cthead.nrrd");
    if !input.exists() {
        println!("SKIPPED: {} is not there", input.display());
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let picture = dir.path().join("cthead.png");
    extract(&input, "1600", &dir.path().join("ct.tmesh"), &picture, &[]);
    let n = shown(&picture);
    // The skull fills more than a quarter of each 512x512 view.
    assert!(n > 4 * 65_000, "{n} pixels shown");
    check_with_pillow(&picture);
}

/// The red of `tmc compare --preview`'s marks.
const MARK: [u8; 3] = [255, 0, 0];

/// Runs `tmc compare INPUT --iso ISO --preview PICTURE` with `extra`
/// options; its JSON report.
fn compare_preview(input: &Path, iso: &str, picture: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "compare",
        s(input),
        "--iso",
        iso,
        "--runs",
        "1",
        "--json",
        "-q",
        "--preview",
        s(picture),
    ];
    args.extend(extra);
    let out = tmc(&args);
    assert!(out.status.success(), "{out:?}");
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Of a side-by-side picture's two halves (left, right): the tile pixels
/// that show a surface (neither background, border, text nor mark) and
/// the marked ones.
fn halves(path: &Path) -> [(usize, usize); 2] {
    let (w, h, rgb) = decode(path);
    assert_eq!((w, h), (2 * SIZE.0, SIZE.1));
    let (w, tiles) = (w as usize, SIZE.0 as usize);
    let mut counts = [(0, 0); 2];
    for (i, p) in rgb.chunks(3).enumerate() {
        let (x, y) = (i % w, i / w);
        if y >= tiles {
            continue;
        }
        let half = &mut counts[x / (w / 2)];
        if p == MARK {
            half.1 += 1;
        } else if p != BACKGROUND && p != [80, 84, 92] && p != [240, 240, 240] {
            half.0 += 1;
        }
    }
    counts
}

#[test]
fn compare_preview_marks_the_differing_cells_in_both_halves() {
    // One cell with two diagonally opposite inside corners and an inside
    // centre (a tunnel): TMC draws a tube, MC two blobs, and that one cell
    // differs.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut values = vec![-1.0f64; 64];
    values[1 + 4 + 16] = 10.0;
    values[2 + 2 * 4 + 2 * 16] = 10.0;
    let mut bytes =
        common::cli::npy_header("{'descr': '<f8', 'fortran_order': False, 'shape': (4, 4, 4), }");
    for v in &values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    let input = d.join("tunnel.npy");
    fs::write(&input, bytes).unwrap();
    let picture = d.join("tunnel.png");
    let json = compare_preview(&input, "0", &picture, &["--threads", "1"]);
    assert_eq!(json["differing_cells"]["cells"], 1);
    let [(tmc_shown, tmc_marks), (mc_shown, mc_marks)] = halves(&picture);
    assert!(tmc_shown > 4 * 1000, "{tmc_shown}");
    assert!(mc_shown > 4 * 1000, "{mc_shown}");
    // One cell: a 3x3 dot in each of the four views of each half.
    assert_eq!((tmc_marks, mc_marks), (4 * 9, 4 * 9));
    // The bytes do not depend on the threads.
    let again = d.join("again.png");
    compare_preview(&input, "0", &again, &["--threads", "2"]);
    assert!(fs::read(&picture).unwrap() == fs::read(&again).unwrap());
    check_with_pillow_size(&picture, 2 * SIZE.0, SIZE.1);
}

#[test]
fn compare_preview_of_a_sphere_has_no_marks() {
    // A sphere's field has no cell the two methods triangulate differently.
    let dir = tempfile::tempdir().unwrap();
    let input = sphere(dir.path());
    let picture = dir.path().join("ball.png");
    let json = compare_preview(&input, "0", &picture, &[]);
    assert_eq!(json["differing_cells"]["cells"], 0, "{json}");
    let [(tmc_shown, tmc_marks), (mc_shown, mc_marks)] = halves(&picture);
    assert!(tmc_shown > 4 * 50_000 && mc_shown > 4 * 50_000);
    assert_eq!((tmc_marks, mc_marks), (0, 0));
}

#[test]
fn compare_preview_to_a_bad_path_is_one_line_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere(dir.path());
    let picture = dir.path().join("ball.jpg");
    let out = tmc(&["compare", s(&input), "--iso", "0", "--preview", s(&picture)]);
    assert_one_line(&out, 1);
    assert!(!picture.exists());
}

/// With `TMC_PYTHON` set: Pillow opens `path` as a `width` x `height` RGB
/// PNG; without it, a SKIPPED line.
fn check_with_pillow_size(path: &Path, width: u32, height: u32) {
    if let Some(text) = pillow(path, "print(im.format, im.mode, *im.size)") {
        assert_eq!(text.trim(), format!("PNG RGB {width} {height}"));
    }
}

/// The four corners of a tetrahedron and its faces, counter-clockwise
/// seen from outside.
const TETRA: ([[f32; 3]; 4], [[usize; 3]; 4]) = (
    [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 3.0, 0.0],
        [0.0, 0.0, 1.5],
    ],
    [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
);

/// A binary STL of the tetrahedron whose 80-byte header starts with
/// "solid", as some exporters write it (binary by its length all the same).
fn tetra_binary_stl() -> Vec<u8> {
    let (v, f) = TETRA;
    let mut bytes = b"solid but binary".to_vec();
    bytes.resize(80, b' ');
    bytes.extend_from_slice(&(f.len() as u32).to_le_bytes());
    for face in f {
        bytes.extend_from_slice(&[0u8; 12]);
        for i in face {
            for c in v[i] {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
        bytes.extend_from_slice(&[0u8; 2]);
    }
    bytes
}

/// An ASCII STL of the tetrahedron (CRLF line ends, indented, as numpy-stl
/// and others write it).
fn tetra_ascii_stl() -> String {
    let (v, f) = TETRA;
    let mut text = String::from("solid tetra\r\n");
    for face in f {
        text += "  facet normal 0 0 0\r\n    outer loop\r\n";
        for i in face {
            let [x, y, z] = v[i];
            text += &format!("      vertex {x:e} {y:e} {z:e}\r\n");
        }
        text += "    endloop\r\n  endfacet\r\n";
    }
    text + "endsolid tetra\r\n"
}

/// `tmc preview` draws STL files, binary (also with a header starting
/// "solid") and ASCII: the facets' shared corners joined, the picture is
/// the one of the same mesh as OFF, and of the STL and the PLY that `tmc
/// extract` writes of one surface (the same caption: closed, genus 1).
/// It said "STL does not share vertices ... topology cannot be checked".
#[test]
fn tmc_preview_draws_stl_files_as_the_mesh_they_were_written_from() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (v, f) = TETRA;
    let mut off = format!("OFF\n{} {} 0\n", v.len(), f.len());
    for [x, y, z] in v {
        off += &format!("{x} {y} {z}\n");
    }
    for [a, b, c] in f {
        off += &format!("3 {a} {b} {c}\n");
    }
    fs::write(d.join("t.off"), off).unwrap();
    fs::write(d.join("b.stl"), tetra_binary_stl()).unwrap();
    fs::write(d.join("a.stl"), tetra_ascii_stl()).unwrap();
    let draw = |mesh: &str, picture: &str| {
        let out = tmc(&[
            "preview",
            s(&d.join(mesh)),
            "-o",
            s(&d.join(picture)),
            "--title",
            "same",
        ]);
        assert!(out.status.success(), "{mesh}: {out:?}");
        fs::read(d.join(picture)).unwrap()
    };
    let expected = draw("t.off", "t.png");
    assert_eq!(draw("b.stl", "b.png"), expected, "binary STL");
    assert_eq!(draw("a.stl", "a.png"), expected, "ASCII STL");
    assert!(shown(&d.join("a.png")) > 10_000);

    let input = synth(d, "torus", "30,30,20", "f32", "torus.npy");
    for ext in ["ply", "stl"] {
        let mesh = d.join(format!("torus.{ext}"));
        extract(
            &input,
            "0",
            &mesh,
            &d.join(format!("{ext}.png")),
            &["--close"],
        );
    }
    assert_eq!(
        draw("torus.stl", "torus_stl.png"),
        draw("torus.ply", "torus_ply.png")
    );
    // A .stl that is neither kind and a cut one are one line each, and
    // leave no picture.
    fs::write(d.join("bad.stl"), b"nothing like an STL").unwrap();
    fs::write(d.join("cut.stl"), &tetra_ascii_stl()[..120]).unwrap();
    for (mesh, needle) in [("bad.stl", "not an STL file"), ("cut.stl", "cut.stl")] {
        let picture = d.join("refused.png");
        let out = tmc(&["preview", s(&d.join(mesh)), "-o", s(&picture)]);
        let line = assert_one_line(&out, 1);
        assert!(line.contains(needle), "{line}");
        assert!(!picture.exists());
    }
}

/// The caption names the isovalue with an exponent where its decimal is
/// long: at 1e-300 and 2e-300 (the same mesh) the pictures differ. The
/// caption printed the decimal, `iso 0.000...`, cut off at the picture's
/// edge with the triangle count and verdict, so both were the same bytes.
#[test]
fn the_caption_shows_a_tiny_isovalue() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere(dir.path());
    let picture = |iso: &str| {
        let (mesh, png) = (
            dir.path().join(format!("{iso}.ply")),
            dir.path().join(format!("{iso}.png")),
        );
        extract(&input, iso, &mesh, &png, &[]);
        (std::fs::read(&mesh).unwrap(), std::fs::read(&png).unwrap())
    };
    let (a, b) = (picture("1e-300"), picture("2e-300"));
    assert!(a.0 == b.0, "the meshes differ");
    assert!(
        a.1 != b.1,
        "the captions of 1e-300 and 2e-300 are the same picture"
    );
}
