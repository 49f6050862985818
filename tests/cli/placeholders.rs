//! Placeholders in output names: an unknown `{NAME}` is refused before the
//! run, naming it and the known ones (it was written into the file's name
//! without a word), in `-o`, `--preview`, a manifest's OUTPUT and `tmc
//! merge -o`; other braces stay literal; `{part}` is the part's number of
//! `--part I/N`, which every part of a label map needs in its `-o` (the
//! same `-o` let part 2 replace part 1's files without a word).

use crate::common;

use common::cli::{assert_one_line, names, s, sphere_npy, tmc};
use common::labels::{ok, write};
use std::fs;
use std::path::Path;
use tmc::volume::ScalarType;

/// A 6x6x8 map of labels 3 (low planes) and 7 (high planes) on 0.
fn label_map(dir: &Path) -> std::path::PathBuf {
    let mut values = vec![0.0; 6 * 6 * 8];
    for z in 1..7 {
        for y in 1..5 {
            for x in 1..5 {
                values[x + 6 * (y + 6 * z)] = if z < 4 { 3.0 } else { 7.0 };
            }
        }
    }
    let input = dir.join("map.nrrd");
    write(&input, [6, 6, 8], values, ScalarType::U8);
    input
}

#[test]
fn an_unknown_placeholder_is_refused_before_the_run_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = sphere_npy(d, "ball.npy", [8, 8, 8]);
    let other = sphere_npy(d, "other.npy", [8, 8, 8]);
    let out = d.join("out");
    fs::create_dir(&out).unwrap();
    let o = |name: &str| s(&out.join(name)).to_string();
    let cases: Vec<(Vec<String>, &str, &str)> = vec![
        // One run.
        (
            vec![
                "--iso".into(),
                "0.5".into(),
                "-o".into(),
                o("{nonsense}.ply"),
            ],
            "{nonsense} in -o",
            "{stem} and {iso}",
        ),
        // A batch: several isovalues, several inputs.
        (
            vec![
                "--iso".into(),
                "0.5,0.7".into(),
                "-o".into(),
                o("{stem}_{Iso}.ply"),
            ],
            "{Iso} in -o",
            "{stem} and {iso}",
        ),
        (
            vec![
                s(&other).into(),
                "--iso".into(),
                "0.5".into(),
                "-o".into(),
                o("{stem}{x}.ply"),
            ],
            "{x} in -o",
            "{stem} and {iso}",
        ),
        // The picture's name.
        (
            vec![
                "--iso".into(),
                "0.5".into(),
                "-o".into(),
                o("m.ply"),
                "--preview".into(),
                o("{stem}_{what}.png"),
            ],
            "{what} in --preview",
            "{stem} and {iso}",
        ),
        // A label map's files.
        (
            vec![
                "--labels".into(),
                "all".into(),
                "-o".into(),
                o("{lable}.ply"),
            ],
            "{lable} in -o",
            "{stem} and {label}",
        ),
        // {part} without --part.
        (
            vec![
                "--iso".into(),
                "0.5".into(),
                "-o".into(),
                o("p{part}.tmesh"),
            ],
            "{part} in -o",
            "--part I/N",
        ),
    ];
    for (extra, named, known) in cases {
        let mut args = vec!["extract", s(&input), "-q"];
        args.extend(extra.iter().map(String::as_str));
        let err = assert_one_line(&tmc(&args), 1);
        assert!(
            err.contains(named) && err.contains(known),
            "{args:?}: {err}"
        );
    }
    // The manifest's OUTPUT, named by its line.
    let manifest = d.join("list.txt");
    fs::write(
        &manifest,
        format!("# x\n{} 0.5 {}\n", s(&input), o("{stm}.ply")),
    )
    .unwrap();
    let err = assert_one_line(&tmc(&["extract", "--manifest", s(&manifest), "-q"]), 1);
    assert!(
        err.contains("list.txt:2:") && err.contains("{stm}"),
        "{err}"
    );
    assert!(names(&out).is_empty(), "{:?}", names(&out));
}

#[test]
fn braces_that_are_no_placeholder_stay_in_the_name() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere_npy(dir.path(), "ball.npy", [8, 8, 8]);
    let out = dir.path().join("a{}{b c}_{stem}.ply");
    ok(&["extract", s(&input), "--iso", "0.5", "-o", s(&out), "-q"]);
    assert!(dir.path().join("a{}{b c}_ball.ply").is_file());
}

#[test]
fn a_merge_output_takes_label_only() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = sphere_npy(d, "ball.npy", [8, 8, 8]);
    let parts: Vec<String> = (1..=2)
        .map(|i| {
            let part = s(&d.join(format!("p{i}.tmesh"))).to_string();
            let spec = format!("{i}/2");
            ok(&[
                "extract",
                s(&input),
                "--iso",
                "0.5",
                "--part",
                &spec,
                "-o",
                &part,
                "-q",
            ]);
            part
        })
        .collect();
    let out = d.join("{stem}.ply");
    let err = assert_one_line(
        &tmc(&["merge", &parts[0], &parts[1], "-o", s(&out), "-q"]),
        1,
    );
    assert!(err.contains("{stem} in -o; it may use {label}"), "{err}");
    assert!(!out.exists());
}

/// The same `-o` with `{part}` for every part of a label map gives each
/// part's files their own names, and the merge is the one run's bytes.
#[test]
fn label_parts_with_one_output_name_merge_into_the_one_run() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = label_map(d);
    let parts = d.join("parts");
    fs::create_dir(&parts).unwrap();
    let template = parts.join("{stem}_{label}.{part}.tmesh");
    for i in 1..=2 {
        let spec = format!("{i}/2");
        let args = ["extract", s(&input), "--labels", "all", "--part", &spec];
        ok(&[&args[..], &["-o", s(&template), "-q"]].concat());
    }
    assert_eq!(
        names(&parts),
        [
            "map_3.1.tmesh",
            "map_3.2.tmesh",
            "map_7.1.tmesh",
            "map_7.2.tmesh"
        ]
    );
    let mut merge = vec!["merge".to_string()];
    merge.extend(names(&parts).iter().map(|n| s(&parts.join(n)).to_string()));
    let merged = d.join("merged.ply");
    merge.extend(["-o".into(), s(&merged).into(), "-q".into()]);
    ok(&merge.iter().map(String::as_str).collect::<Vec<_>>());
    let one = d.join("one.ply");
    ok(&["extract", s(&input), "--labels", "all", "-o", s(&one), "-q"]);
    assert!(fs::read(&merged).unwrap() == fs::read(&one).unwrap());
}

/// Without `{part}` every part wrote the same names: part 2 replaced part
/// 1's files and exited 0, and the merge said a part was missing.
#[test]
fn label_parts_without_part_in_the_output_are_refused_before_any_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = label_map(d);
    let parts = d.join("parts");
    fs::create_dir(&parts).unwrap();
    for name in ["{label}.tmesh", "{label}.1.tmesh", "{label}.{part}.ply"] {
        let out = parts.join(name);
        let args = ["extract", s(&input), "--labels", "all", "--part", "1/2"];
        let err = assert_one_line(&tmc(&[&args[..], &["-o", s(&out), "-q"]].concat()), 1);
        assert!(
            err.contains("must contain {label} and {part} and end in .tmesh"),
            "{name}: {err}"
        );
        assert!(names(&parts).is_empty(), "{:?}", names(&parts));
    }
}

/// One isovalue's parts may name themselves with `{part}` too.
#[test]
fn isosurface_parts_take_part_in_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = sphere_npy(d, "ball.npy", [8, 8, 12]);
    let template = d.join("{stem}-{part}-of-3.tmesh");
    for i in 1..=3 {
        let spec = format!("{i}/3");
        let args = ["extract", s(&input), "--iso", "0.5", "--part", &spec];
        ok(&[&args[..], &["-o", s(&template), "-q"]].concat());
    }
    let parts: Vec<String> = (1..=3)
        .map(|i| s(&d.join(format!("ball-{i}-of-3.tmesh"))).to_string())
        .collect();
    let merged = d.join("merged.tmesh");
    let mut args = vec!["merge", "-o", s(&merged), "-q"];
    args.extend(parts.iter().map(String::as_str));
    ok(&args);
    let one = d.join("one.tmesh");
    ok(&["extract", s(&input), "--iso", "0.5", "-o", s(&one), "-q"]);
    assert!(fs::read(&merged).unwrap() == fs::read(&one).unwrap());
}

/// `tmc compare --preview` fills `{stem}` and `{iso}` as `tmc extract
/// --preview` does (it wrote a picture named `{stem}_{iso}.png`).
#[test]
fn a_compare_preview_takes_stem_and_iso() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = sphere_npy(d, "ball.npy", [8, 8, 8]);
    let out = d.join("out");
    fs::create_dir(&out).unwrap();
    let compare = |picture: &Path| {
        let args = ["compare", s(&input), "--iso", "0.5", "--runs", "1", "-q"];
        tmc(&[&args[..], &["--preview", s(picture)]].concat())
    };
    let err = assert_one_line(&compare(&out.join("{stem}_{isovalue}.png")), 1);
    assert!(err.contains("{isovalue} in --preview"), "{err}");
    assert!(names(&out).is_empty(), "{:?}", names(&out));
    let result = compare(&out.join("{stem}_{iso}.png"));
    assert!(result.status.success(), "{result:?}");
    assert_eq!(names(&out), ["ball_0.5.png"]);
}

/// `tmc convert -o` and `tmc preview -o` fill in no placeholder: a
/// `{NAME}` (`{stem}`, which extract's -o fills in, or a typo) is refused
/// before the mesh is read, naming it; it was written into the file's
/// name (`{stem}.ply`) without a word. Other braces stay literal.
#[test]
fn convert_and_preview_outputs_take_no_placeholder() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, out) = (dir.path().join("m.tmesh"), dir.path().join("out"));
    let ball = sphere_npy(dir.path(), "ball.npy", [8, 8, 8]);
    ok(&["extract", s(&ball), "--iso", "0.5", "-o", s(&mesh), "-q"]);
    fs::create_dir(&out).unwrap();
    for (command, name) in [
        ("convert", "{stem}.ply"),
        ("convert", "{iso}.obj"),
        ("preview", "{stem}.png"),
        ("preview", "{nonsense}.png"),
    ] {
        let target = out.join(name);
        let err = assert_one_line(&tmc(&[command, s(&mesh), "-o", s(&target)]), 1);
        let placeholder = &name[..name.find('}').unwrap() + 1];
        assert!(
            err.contains(&format!(
                "unknown placeholder {placeholder} in -o; it may use none"
            )),
            "{command} {name}: {err}"
        );
        assert!(
            names(&out).is_empty(),
            "{command} {name}: {:?}",
            names(&out)
        );
    }
    ok(&["convert", s(&mesh), "-o", s(&out.join("{}.ply")), "-q"]);
    ok(&["preview", s(&mesh), "-o", s(&out.join("{a b}.png")), "-q"]);
    assert_eq!(names(&out).len(), 2, "{:?}", names(&out));
}
