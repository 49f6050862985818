//! `tmc extract MAP --labels ... --preview FILE.png`: one picture of every
//! label's surface, drawn while the pass streams. It is the picture `tmc
//! preview` draws of the one `.tmesh` of every label (whose verdict counts
//! one stream, checked against the checker in preview.rs), byte for byte,
//! for any threads, slab depth and output format; its verdict sums the
//! labels' own; it refuses parts and placeholders it cannot fill, and a
//! path that is an output, before anything is written.

use crate::common;
use crate::preview::{decode, shown_per_tile, SIZE};

use common::cli::{assert_one_line, s, tmc};
use common::labels::{label_map, ok, write};
use std::fs;
use std::path::Path;
use tmc::volume::ScalarType;

/// A 30x26x22 map: touching Voronoi labels touching the border, one-voxel
/// labels and a torus.
fn map(dir: &Path) -> std::path::PathBuf {
    let path = dir.join("seg.nrrd");
    let dims = [30, 26, 22];
    write(&path, dims, label_map(dims, 9, 5), ScalarType::U16);
    path
}

#[test]
fn the_labels_picture_is_tmc_previews_of_the_one_tmesh_of_every_label() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let seg = map(d);
    let seg = s(&seg);
    let picture = |name: &str| d.join(name);
    // One pass of every label with --close and a picture.
    let pass = |output: &str, preview: &str, extra: &[&str]| {
        let (output, preview) = (format!("{}/{output}", s(d)), format!("{}/{preview}", s(d)));
        let mut args = vec!["extract", seg, "--labels", "all", "--close", "-q"];
        args.extend(["-o", &output, "--preview", &preview]);
        args.extend_from_slice(extra);
        ok(&args);
    };
    pass("{label}.tmesh", "a.png", &["--threads", "1"]);
    pass(
        "p{label}.ply",
        "b.png",
        &["--threads", "2", "--slab-depth", "3"],
    );
    pass("all.tmesh", "{stem}.png", &[]);
    ok(&[
        "preview",
        s(&d.join("all.tmesh")),
        "-o",
        s(&picture("d.png")),
        "--title",
        "seg.nrrd",
    ]);
    let a = fs::read(picture("a.png")).unwrap();
    for other in ["b.png", "seg.png", "d.png"] {
        assert!(
            a == fs::read(picture(other)).unwrap(),
            "a.png and {other} differ"
        );
    }
    let (w, h, _) = decode(&picture("a.png"));
    assert_eq!((w, h), SIZE);
    let tiles = shown_per_tile(&picture("a.png"));
    assert!(tiles.iter().all(|&n| n > 2000), "{tiles:?}");
    // Each label in its colour: the shown pixels' hues (the colour over its
    // brightest channel, in eighths, with enough pixels to count) are many,
    // where one colour shaded (before, or a single surface) gives two or
    // three.
    let hues = hues_shown(&picture("a.png"));
    assert!(hues >= 6, "{hues} hues shown");

    // The verdict of all the surfaces is the sum of the labels' own: the
    // union file's counts (what the caption says) against each label's.
    let all = tmc::check::check_mesh(&tmc::check::read_mesh(&d.join("all.tmesh")).unwrap());
    let (mut components, mut euler, mut labels) = (0, 0, 0);
    for entry in fs::read_dir(d).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name.ends_with(".tmesh") && name != "all.tmesh" {
            let report = tmc::check::check_mesh(&tmc::check::read_mesh(&path).unwrap());
            assert!(report.components > 0, "{name}");
            components += report.components;
            euler += report.euler;
            labels += 1;
        }
    }
    assert!(labels >= 10, "{labels} labels");
    assert_eq!(all.components, components);
    assert_eq!(all.euler, euler);
}

#[test]
fn a_labels_preview_refuses_what_it_cannot_draw_before_writing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let seg = map(d);
    let out = d.join("out");
    fs::create_dir(&out).unwrap();
    let cases: [(&[&str], &str); 4] = [
        (
            &[
                "-o",
                &format!("{}/{{label}}.{{part}}.tmesh", s(&out)),
                "--part",
                "1/2",
                "--preview",
                &format!("{}/p.png", s(&out)),
            ],
            "merge the parts",
        ),
        (
            &[
                "-o",
                &format!("{}/{{label}}.ply", s(&out)),
                "--preview",
                &format!("{}/{{label}}.png", s(&out)),
            ],
            "{label}",
        ),
        (
            &[
                "-o",
                &format!("{}/{{label}}.ply", s(&out)),
                "--preview",
                &format!("{}/{{iso}}.png", s(&out)),
            ],
            "{iso}",
        ),
        (
            &[
                "-o",
                &format!("{}/all.ply", s(&out)),
                "--preview",
                &format!("{}/all.ply", s(&out)),
            ],
            ".png",
        ),
    ];
    for (extra, said) in cases {
        let mut args = vec!["extract", s(&seg), "--labels", "all", "-q"];
        args.extend_from_slice(extra);
        let line = assert_one_line(&tmc(&args), 1);
        assert!(line.contains(said), "{args:?}: {line}");
        assert_eq!(
            fs::read_dir(&out).unwrap().count(),
            0,
            "{args:?} left files"
        );
    }
}

/// The hues of [`crate::preview::BACKGROUND`]-free tile pixels of a
/// picture (each colour over its brightest channel, in eighths) that at
/// least 200 pixels have, not counting the dark ones.
fn hues_shown(path: &Path) -> usize {
    let (w, _, rgb) = decode(path);
    let w = w as usize;
    let mut counts = std::collections::HashMap::new();
    for p in rgb.chunks(3).take(w * w) {
        let top = *p.iter().max().unwrap();
        let shown = p != crate::preview::BACKGROUND && p != [80, 84, 92] && p != [240, 240, 240];
        if shown && top >= 96 {
            let hue =
                [0, 1, 2].map(|i| (u32::from(p[i]) * 8 + u32::from(top) / 2) / u32::from(top));
            *counts.entry(hue).or_insert(0usize) += 1;
        }
    }
    counts.values().filter(|&&n| n >= 200).count()
}
