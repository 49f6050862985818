//! `tmc extract` in batch: several inputs, a manifest, several isovalues in
//! one pass, the JSON-lines report and the exit status.

use crate::common;

use common::cli::{assert_one_line, names, s, synth, tmc};
use std::fs;
use std::path::Path;
use std::process::Output;

/// The JSON lines of `text`, each parsed.
fn json_lines(text: &[u8]) -> Vec<serde_json::Value> {
    String::from_utf8_lossy(text)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn several_isovalues_in_one_pass_equal_separate_runs() {
    let dir = tempfile::tempdir().unwrap();
    let input = synth(dir.path(), "noise", "23,19,29", "f32", "v.nrrd");
    let isos = ["-0.2", "0", "0.35"];
    for ext in ["tmesh", "ply"] {
        for method in ["tmc", "mc"] {
            for close in [false, true] {
                let tag = format!("{method}{}", if close { "c" } else { "" });
                let template = dir.path().join(format!("m_{tag}_{{iso}}.{ext}"));
                let mut args = vec![
                    "extract",
                    s(&input),
                    "--iso",
                    "-0.2,0,0.35",
                    "-o",
                    s(&template),
                    "--method",
                    method,
                    "--slab-depth",
                    "4",
                    "--threads",
                    "2",
                ];
                if close {
                    args.push("--close");
                }
                let out = tmc(&args);
                assert!(out.status.success(), "{}", stderr(&out));
                for iso in isos {
                    let single = dir.path().join(format!("s_{tag}_{iso}.{ext}"));
                    let mut args = vec![
                        "extract",
                        s(&input),
                        "--iso",
                        iso,
                        "-o",
                        s(&single),
                        "--method",
                        method,
                    ];
                    if close {
                        args.push("--close");
                    }
                    let out = tmc(&args);
                    assert!(out.status.success(), "{}", stderr(&out));
                    let multi = dir.path().join(format!("m_{tag}_{iso}.{ext}"));
                    let (a, b) = (fs::read(&single).unwrap(), fs::read(&multi).unwrap());
                    assert!(a.len() > 100, "{ext} {tag} iso {iso}: nearly empty");
                    assert!(a == b, "{ext} {tag} iso {iso}: one pass differs");
                }
            }
        }
    }
}

#[test]
fn several_isovalues_without_iso_in_the_name_get_a_suffix() {
    let dir = tempfile::tempdir().unwrap();
    let input = synth(dir.path(), "noise", "12,12,12", "f32", "v.nrrd");
    let out = tmc(&[
        "extract",
        s(&input),
        "--iso",
        "0,0.2",
        "-o",
        s(&dir.path().join("mesh.ply")),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        names(dir.path()),
        ["mesh_iso0.2.ply", "mesh_iso0.ply", "v.nrrd"]
    );
}

#[test]
fn a_broken_input_in_the_middle_fails_alone_with_keep_going() {
    let dir = tempfile::tempdir().unwrap();
    let good1 = synth(dir.path(), "noise", "12,11,10", "f32", "good1.nrrd");
    let bad = dir.path().join("bad.nrrd");
    fs::write(
        &bad,
        "NRRD0004\ntype: float\ndimension: 3\nsizes: 9 9 9\nencoding: raw\n\n12",
    )
    .unwrap();
    let good2 = synth(dir.path(), "noise", "10,11,12", "f32", "good2.nrrd");
    let report = dir.path().join("report.jsonl");
    let out_dir = dir.path().join("out");
    fs::create_dir(&out_dir).unwrap();
    let out = tmc(&[
        "extract",
        s(&good1),
        s(&bad),
        s(&good2),
        "--iso",
        "0,0.1",
        "-o",
        s(&out_dir.join("{stem}_{iso}.tmesh")),
        "--keep-going",
        "--json",
        "--report",
        s(&report),
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    let last = err.lines().last().unwrap();
    assert!(
        last.starts_with("tmc: error: 1 of 3 inputs failed: "),
        "{err}"
    );
    assert!(last.ends_with("bad.nrrd"), "{err}");
    assert!(err.lines().all(|l| l.starts_with("tmc: error: ")), "{err}");
    assert_eq!(
        names(&out_dir),
        [
            "good1_0.1.tmesh",
            "good1_0.tmesh",
            "good2_0.1.tmesh",
            "good2_0.tmesh"
        ]
    );
    let lines = json_lines(&out.stdout);
    assert_eq!(lines, json_lines(&fs::read(&report).unwrap()));
    let status: Vec<&str> = lines
        .iter()
        .map(|l| l["status"].as_str().unwrap())
        .collect();
    assert_eq!(status, ["ok", "failed", "ok"]);
    assert_eq!(lines[1]["input"].as_str(), Some(s(&bad)));
    assert!(lines[1]["error"].as_str().unwrap().contains("bad.nrrd"));
    assert!(lines[0]["error"].is_null());
    assert_eq!(lines[0]["isos"], serde_json::json!([0.0, 0.1]));
    let triangles = lines[2]["triangles"].as_array().unwrap();
    assert_eq!(triangles.len(), 2);
    assert!(triangles.iter().all(|t| t.as_u64().unwrap() > 0));
}

#[test]
fn without_keep_going_the_batch_stops_at_the_first_failure() {
    let dir = tempfile::tempdir().unwrap();
    let good1 = synth(dir.path(), "noise", "10,10,10", "f32", "good1.nrrd");
    let missing = dir.path().join("missing.nrrd");
    let good2 = synth(dir.path(), "noise", "10,10,10", "f32", "good2.nrrd");
    let out = tmc(&[
        "extract",
        s(&good1),
        s(&missing),
        s(&good2),
        "--iso",
        "0",
        "-o",
        s(&dir.path().join("{stem}.ply")),
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("1 of 3 inputs failed"), "{err}");
    assert!(err.contains("1 not run"), "{err}");
    assert_eq!(json_lines(&out.stdout).len(), 2);
    assert!(dir.path().join("good1.ply").exists());
    assert!(!dir.path().join("good2.ply").exists());
    assert!(!dir.path().join("missing.ply").exists());
}

#[test]
fn a_manifest_runs_its_lines() {
    let dir = tempfile::tempdir().unwrap();
    let a = synth(dir.path(), "noise", "11,12,13", "f32", "a.nrrd");
    let manifest = dir.path().join("m.txt");
    let out_a = dir.path().join("a out {iso}.off");
    let plain = dir.path().join("plain.ply");
    fs::write(
        &manifest,
        format!(
            "# input iso output\n\n{}\t0,0.25\t{}\n{} 0.1 {}\n",
            s(&a),
            s(&out_a),
            s(&a),
            s(&plain)
        ),
    )
    .unwrap();
    let out = tmc(&["extract", "--manifest", s(&manifest), "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let lines = json_lines(&out.stdout);
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[0]["line"].as_u64(), Some(3));
    assert_eq!(lines[1]["line"].as_u64(), Some(4));
    let single = dir.path().join("single.off");
    let out = tmc(&["extract", s(&a), "--iso", "0.25", "-o", s(&single)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        fs::read(&single).unwrap(),
        fs::read(dir.path().join("a out 0.25.off")).unwrap()
    );
    assert!(dir.path().join("a out 0.off").exists());
    assert!(plain.exists());
}

#[test]
fn manifest_errors_name_the_line_and_run_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let a = synth(dir.path(), "noise", "8,8,8", "f32", "a.nrrd");
    let manifest = dir.path().join("m.txt");
    for (text, expect) in [
        (
            format!("{} 0 x.ply\n# ok\n{} 0\n", s(&a), s(&a)),
            "m.txt:3: expected 3 fields",
        ),
        (format!("{} 0,nan x.ply\n", s(&a)), "m.txt:1: bad isovalue"),
        (
            format!("{} 0 x.ply\n{} 1 x.ply\n", s(&a), s(&a)),
            "two outputs",
        ),
        ("# nothing\n".to_string(), "lists no input"),
    ] {
        fs::write(&manifest, text).unwrap();
        let out = tmc(&["extract", "--manifest", s(&manifest)]);
        let line = assert_one_line(&out, 1);
        assert!(line.contains(expect), "{line}");
        assert!(!Path::new("x.ply").exists());
    }
}

#[test]
fn several_inputs_need_stem_in_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let a = synth(dir.path(), "noise", "8,8,8", "f32", "a.nrrd");
    let out = tmc(&[
        "extract",
        s(&a),
        s(&a),
        "--iso",
        "0",
        "-o",
        s(&dir.path().join("x.ply")),
    ]);
    let line = assert_one_line(&out, 1);
    assert!(line.contains("{stem}"), "{line}");
    assert_eq!(names(dir.path()), ["a.nrrd"]);
}

#[test]
fn the_single_input_form_keeps_its_json_object() {
    let dir = tempfile::tempdir().unwrap();
    let a = synth(dir.path(), "noise", "8,8,8", "f32", "a.nrrd");
    let out = tmc(&[
        "extract",
        s(&a),
        "--iso",
        "0",
        "-o",
        s(&dir.path().join("x.ply")),
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let lines = json_lines(&out.stdout);
    assert_eq!(lines.len(), 1);
    assert_eq!(lines[0]["iso"].as_f64(), Some(0.0));
    assert!(lines[0].get("status").is_none());
    assert!(lines[0]["triangles"].as_u64().unwrap() > 0);
}

#[test]
fn require_surface_with_one_empty_isovalue_writes_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let a = synth(dir.path(), "noise", "10,10,10", "f32", "a.nrrd");
    let out = tmc(&[
        "extract",
        s(&a),
        "--iso",
        "0,5",
        "-o",
        s(&dir.path().join("m_{iso}.tmesh")),
        "--require-surface",
    ]);
    let line = assert_one_line(&out, 1);
    assert!(line.contains("no surface at isovalue 5"), "{line}");
    assert_eq!(names(dir.path()), ["a.nrrd"]);
    let out = tmc(&[
        "extract",
        s(&a),
        "--iso",
        "0,0.1",
        "-o",
        s(&dir.path().join("m_{iso}.tmesh")),
        "--require-surface",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(names(dir.path()), ["a.nrrd", "m_0.1.tmesh", "m_0.tmesh"]);
}

/// `{stem}` and `{iso}` are replaced in a single run too (one input, one
/// isovalue), as `--help` says, so that a shell loop over inputs writes one
/// file per input.
#[test]
fn a_single_run_names_its_output_from_the_template() {
    let dir = tempfile::tempdir().unwrap();
    let a = synth(dir.path(), "noise", "10,10,10", "f32", "vol.nrrd");
    let out = tmc(&[
        "extract",
        s(&a),
        "--iso",
        "0.25",
        "-o",
        s(&dir.path().join("{stem}_{iso}.ply")),
        "-q",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.path().join("vol_0.25.ply").exists());
    assert!(!dir.path().join("{stem}_{iso}.ply").exists());
}

/// The report is appended to while the batch runs, so it may not be the
/// manifest, an output or a preview of the batch; the manifest is left as
/// it was.
#[test]
fn the_report_may_not_be_the_manifest_or_an_output() {
    let dir = tempfile::tempdir().unwrap();
    let a = synth(dir.path(), "noise", "10,10,10", "f32", "a.nrrd");
    let manifest = dir.path().join("m.txt");
    let text = format!("{} 0 {}\n", s(&a), s(&dir.path().join("a.ply")));
    fs::write(&manifest, &text).unwrap();
    let out = tmc(&[
        "extract",
        "--manifest",
        s(&manifest),
        "--report",
        s(&manifest),
    ]);
    let line = assert_one_line(&out, 1);
    assert!(line.contains("the report is the manifest"), "{line}");
    assert_eq!(fs::read_to_string(&manifest).unwrap(), text);
    let ply = dir.path().join("b.ply");
    let out = tmc(&[
        "extract",
        s(&a),
        "--iso",
        "0",
        "-o",
        s(&ply),
        "--report",
        s(&ply),
    ]);
    let line = assert_one_line(&out, 1);
    assert!(line.contains("the report is an output"), "{line}");
    assert!(!ply.exists());
    // Nor one of its preview pictures: the report's lines were appended,
    // then the picture replaced them (exit 0, the report lost).
    let (picture, template) = (
        dir.path().join("a_0.png"),
        dir.path().join("{stem}_{iso}.png"),
    );
    let ply = dir.path().join("{stem}_{iso}.ply");
    let (ply, template) = (s(&ply), s(&template));
    let args = [
        "extract",
        s(&a),
        "--iso",
        "0,1",
        "-o",
        ply,
        "--preview",
        template,
    ];
    let out = tmc(&[&args[..], &["--report", s(&picture)]].concat());
    let line = assert_one_line(&out, 1);
    assert!(
        line.contains("the report is a preview of the batch"),
        "{line}"
    );
    assert!(!picture.exists() && !dir.path().join("a_0.ply").exists());
}

/// A report in a missing directory fails before any extraction, naming the
/// report's path and what to do (it is opened, not written atomically, so
/// the message is the open's).
#[test]
fn a_report_in_a_missing_directory_says_what_to_do() {
    let dir = tempfile::tempdir().unwrap();
    let a = synth(dir.path(), "noise", "10,10,10", "f32", "a.nrrd");
    let report = dir.path().join("no such/r.jsonl");
    let ply = dir.path().join("a.ply");
    let out = tmc(&[
        "extract",
        s(&a),
        "--iso",
        "0",
        "-o",
        s(&ply),
        "--report",
        s(&report),
    ]);
    let line = assert_one_line(&out, 1);
    assert!(line.contains(s(&report)), "{line}");
    assert!(line.contains("does not exist"), "{line}");
    assert!(line.contains("mkdir -p"), "{line}");
    assert_eq!(names(dir.path()), ["a.nrrd"]);
}

/// `--progress lines` prints plain progress lines on stderr (not a
/// terminal here), naming each input of a batch, up to 100%; without it
/// a run whose stderr is not a terminal prints no progress; `--quiet`
/// with it is a usage error.
#[test]
fn progress_lines_name_each_input_and_reach_100_percent() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let a = synth(d, "sphere", "24,20,40", "f32", "a.npy");
    let b = synth(d, "gyroid", "16,16,48", "f32", "b.npy");
    let out = d.join("{stem}.ply");
    let run = |extra: &[&str]| {
        let mut args = vec!["extract", s(&a), s(&b), "--iso", "0", "-o", s(&out)];
        args.extend_from_slice(extra);
        tmc(&args)
    };
    let lines = run(&["--progress", "lines", "--threads", "2", "--slab-depth", "4"]);
    assert!(lines.status.success(), "{lines:?}");
    let stderr = String::from_utf8_lossy(&lines.stderr);
    for (input, layers) in [(&a, 39), (&b, 47)] {
        let mine: Vec<f64> = stderr
            .lines()
            .filter_map(|l| l.strip_prefix(&format!("tmc: {}: ", input.display())))
            .map(|rest| {
                let (percent, tail) = rest.split_once("% of ").expect(rest);
                assert!(
                    tail.starts_with(&format!("{layers} cell layers, ")),
                    "{rest}"
                );
                percent.parse().expect(rest)
            })
            .collect();
        assert!(mine.len() >= 3, "{}: {stderr}", input.display());
        assert!(mine.windows(2).all(|w| w[0] < w[1]), "{mine:?}");
        assert_eq!(mine.last(), Some(&100.0), "{stderr}");
    }
    for extra in [&[][..], &["--progress", "never"], &["--progress", "auto"]] {
        let quiet = run(extra);
        assert!(quiet.status.success(), "{quiet:?}");
        let stderr = String::from_utf8_lossy(&quiet.stderr);
        assert!(!stderr.contains("% of"), "{extra:?}: {stderr}");
    }
    let e = assert_one_line(&run(&["--progress", "lines", "--quiet"]), 2);
    assert!(
        e.contains("'--progress <WHEN>' cannot be used with '--quiet'"),
        "{e}"
    );
}

/// A manifest line chooses the series of a DICOM directory (`series=`):
/// each line writes the bytes of `tmc extract DIR --series UID`, and the
/// report line names the series; a line's series wins over `--series`.
#[test]
fn manifest_lines_choose_dicom_series() {
    let dir = tempfile::tempdir().unwrap();
    let two = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/dicom_bad_two_series");
    let uid = |n: u32| format!("1.2.826.0.1.3680043.8.498.7777.{n}");
    let out = |name: &str| dir.path().join(name);
    let manifest = out("m.txt");
    fs::write(
        &manifest,
        format!(
            "{t}\t3.5\t{a}\tseries={u32}\n{t}\t3.5\t{b}\tseries={u31}\n",
            t = s(&two),
            a = s(&out("a.off")),
            b = s(&out("b.off")),
            u32 = uid(32),
            u31 = uid(31)
        ),
    )
    .unwrap();
    let report = out("r.jsonl");
    let run = tmc(&[
        "extract",
        "--manifest",
        s(&manifest),
        "--close",
        "--report",
        s(&report),
        "-q",
        "--series",
        "no-such-series",
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let lines = json_lines(&fs::read(&report).unwrap());
    assert_eq!(lines[0]["series"], uid(32).as_str());
    assert_eq!(lines[1]["series"], uid(31).as_str());
    for (name, n) in [("a.off", 32), ("b.off", 31)] {
        let single = out(&format!("single_{name}"));
        let run = tmc(&[
            "extract",
            s(&two),
            "--iso",
            "3.5",
            "--close",
            "--series",
            &uid(n),
            "-o",
            s(&single),
            "-q",
        ]);
        assert!(run.status.success(), "{}", stderr(&run));
        let mine = fs::read(out(name)).unwrap();
        assert!(mine.len() > 100, "{name}");
        assert_eq!(mine, fs::read(&single).unwrap(), "{name}");
    }
    let a = fs::read(out("a.off")).unwrap();
    assert_ne!(a, fs::read(out("b.off")).unwrap());
    // A bad option of a line is one error naming the line.
    fs::write(
        &manifest,
        format!("{} 3.5 {} series=\n", s(&two), s(&out("c.off"))),
    )
    .unwrap();
    let run = tmc(&["extract", "--manifest", s(&manifest)]);
    let line = assert_one_line(&run, 1);
    assert!(
        line.contains("m.txt:1: unexpected field \"series=\""),
        "{line}"
    );
}

/// Two items of a batch drawing one picture (two manifest lines of one
/// input, `--preview 'DIR/{stem}.png'`) are refused before anything runs,
/// as two meshes of one name are: the second picture replaced the first
/// and the batch exited 0.
#[test]
fn two_previews_of_one_name_are_refused_before_the_batch() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = synth(d, "sphere", "10,10,10", "f32", "ball.nrrd");
    let manifest = d.join("list.txt");
    let (a, b) = (d.join("a.ply"), d.join("b.ply"));
    fs::write(
        &manifest,
        format!("{0} 0.3 {1}\n{0} 0.5 {2}\n", s(&input), s(&a), s(&b)),
    )
    .unwrap();
    let batch = |picture: &Path| {
        tmc(&[
            "extract",
            "--manifest",
            s(&manifest),
            "--preview",
            s(picture),
            "-q",
        ])
    };
    let err = assert_one_line(&batch(&d.join("{stem}.png")), 1);
    assert!(
        err.contains("ball.png: two previews of the batch have this name"),
        "{err}"
    );
    assert_eq!(names(d), ["ball.nrrd", "list.txt"]);
    // With {iso} each picture has its own name.
    let out = batch(&d.join("{stem}_{iso}.png"));
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        names(d),
        [
            "a.ply",
            "b.ply",
            "ball.nrrd",
            "ball_0.3.png",
            "ball_0.5.png",
            "list.txt"
        ]
    );
}

/// Two manifest lines writing one file under two spellings of its path
/// (`out/a.ply` and `./out/a.ply`, `out/../out/a.ply`, a link to the
/// folder) are refused before anything runs, as two lines of one spelling
/// are: the second mesh replaced the first and the batch exited 0.
#[test]
fn one_output_spelled_two_ways_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = synth(d, "sphere", "10,10,10", "f32", "ball.nrrd");
    fs::create_dir(d.join("out")).unwrap();
    std::os::unix::fs::symlink(d.join("out"), d.join("link")).unwrap();
    let manifest = d.join("list.txt");
    let plain = d.join("out/a.ply");
    for other in [
        format!("{}/./out/a.ply", s(d)),
        format!("{}/out/../out/a.ply", s(d)),
        format!("{}/link/a.ply", s(d)),
    ] {
        fs::write(
            &manifest,
            format!("{0} 0.3 {1}\n{0} 0.5 {other}\n", s(&input), s(&plain)),
        )
        .unwrap();
        let out = tmc(&["extract", "--manifest", s(&manifest), "-q"]);
        let err = assert_one_line(&out, 1);
        assert!(err.contains("two outputs of the batch"), "{other}: {err}");
        assert!(names(&d.join("out")).is_empty(), "{other}");
    }
}

/// A manifest saved with a byte order mark (as Windows editors write
/// UTF-8) runs: the mark was read as part of the first input's name, which
/// then did not exist.
#[test]
fn a_manifest_with_a_byte_order_mark_runs() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = synth(d, "sphere", "10,10,10", "f32", "ball.nrrd");
    let manifest = d.join("list.txt");
    let mesh = d.join("ball.ply");
    fs::write(
        &manifest,
        format!("\u{feff}{} 0.3 {}\r\n", s(&input), s(&mesh)),
    )
    .unwrap();
    let out = tmc(&["extract", "--manifest", s(&manifest), "-q"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(mesh.exists());
}
