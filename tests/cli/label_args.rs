//! `tmc extract --labels` on the command line: how its arguments are read
//! (negative labels, options that do not apply, hundreds of labels under
//! a low limit on open files), each checked against a
//! run whose meaning is not in doubt.

use crate::common;

use common::cli::{assert_one_line, names, s, tmc};
use common::labels::{ok, write};
use std::fs;
use std::path::Path;
use tmc::volume::ScalarType;

/// A 6x6x6 map of labels -5 (a 2x2x2 block), 7 (one sample) and 0.
fn negative_map(dir: &Path) -> std::path::PathBuf {
    let dims = [6, 6, 6];
    let mut values = vec![0.0; 216];
    for z in 2..4 {
        for y in 2..4 {
            for x in 2..4 {
                values[x + 6 * (y + 6 * z)] = -5.0;
            }
        }
    }
    values[1 + 6 * (1 + 6 * 4)] = 7.0;
    let input = dir.join("map.nrrd");
    write(&input, dims, values, ScalarType::I16);
    input
}

#[test]
fn a_list_may_start_with_a_negative_label() {
    let dir = tempfile::tempdir().unwrap();
    let input = negative_map(dir.path());
    let spaced = dir.path().join("spaced");
    let joined = dir.path().join("joined");
    fs::create_dir(&spaced).unwrap();
    fs::create_dir(&joined).unwrap();
    // `--labels -5,7` as `--iso -500,500` and `--background -5` are read;
    // `--labels=-5,7` is the form no parser can take for an option.
    ok(&[
        "extract",
        s(&input),
        "--labels",
        "-5,7",
        "-o",
        s(&spaced.join("{label}.ply")),
        "-q",
    ]);
    ok(&[
        "extract",
        s(&input),
        "--labels=-5,7",
        "-o",
        s(&joined.join("{label}.ply")),
        "-q",
    ]);
    assert_eq!(names(&spaced), ["-5.ply", "7.ply"]);
    for name in ["-5.ply", "7.ply"] {
        let a = fs::read(spaced.join(name)).unwrap();
        assert_eq!(a, fs::read(joined.join(name)).unwrap(), "{name}");
    }
}

/// Runs `tmc extract INPUT -q ARGS` in `dir` (paths ending in `.ply` or
/// `.png` are taken in `dir`) and asserts a usage error naming `named`
/// and nothing written.
fn refused(dir: &Path, input: &Path, extra: &[&str], named: &str) {
    let mut args = vec!["extract", s(input), "-q"];
    let joined: Vec<String> = extra
        .iter()
        .map(|a| match a.ends_with(".ply") || a.ends_with(".png") {
            true => s(&dir.join(a)).to_string(),
            false => a.to_string(),
        })
        .collect();
    args.extend(joined.iter().map(String::as_str));
    let err = assert_one_line(&tmc(&args), 2);
    assert!(err.contains(named), "{extra:?}: {err}");
    assert_eq!(names(dir), ["map.nrrd"], "{extra:?}");
}

#[test]
fn background_without_labels_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let input = negative_map(dir.path());
    // --background chooses among the labels of --labels all; with an
    // isovalue it would change nothing.
    for extra in [
        &["--iso", "0.5", "--background", "3", "-o", "x.ply"],
        &["--background", "3", "--iso", "0.5", "-o", "x.ply"],
    ] {
        refused(dir.path(), &input, extra, "--background");
    }
}

/// A map of nothing but the background has no label to write: exit 1 in
/// one line, with `{label}` outputs and with one file for all labels, and
/// nothing written; with `--background` naming another value, that value's
/// samples are a label again.
#[test]
fn a_map_of_only_the_background_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("map.nrrd");
    write(&input, [4, 3, 5], vec![-2.0; 60], ScalarType::I16);
    for out in ["{label}.ply", "all.ply", "{label}.tmesh"] {
        let out = s(&dir.path().join(out)).to_string();
        let run = tmc(&[
            "extract",
            s(&input),
            "--labels",
            "all",
            "--background",
            "-2",
            "-o",
            &out,
        ]);
        let err = assert_one_line(&run, 1);
        assert!(err.contains("no label but the background -2"), "{err}");
        assert_eq!(names(dir.path()), ["map.nrrd"], "{out}");
    }
    let out = s(&dir.path().join("{label}.ply")).to_string();
    ok(&["extract", s(&input), "--labels", "all", "-o", &out, "-q"]);
    assert_eq!(names(dir.path()), ["-2.ply", "map.nrrd"]);
}

/// With a list of labels, `--background` would change nothing: refused in
/// one line before anything is read or written.
#[test]
fn background_with_a_list_of_labels_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let input = negative_map(dir.path());
    let output = dir.path().join("{label}.ply");
    let out = tmc(&[
        "extract",
        s(&input),
        "-q",
        "--labels",
        "1",
        "--background",
        "3",
        "-o",
        s(&output),
    ]);
    let err = assert_one_line(&out, 1);
    assert!(
        err.contains("--background 3") && err.contains("--labels all"),
        "{err}"
    );
    assert_eq!(names(dir.path()), ["map.nrrd"]);
}

/// A float label map's background may be written as it is stored
/// (`--background -5.0` is label -5, `-0` is 0); a fraction is refused in
/// one line saying a label is a whole number.
#[test]
fn background_written_as_a_whole_float_is_that_label() {
    let dir = tempfile::tempdir().unwrap();
    let input = negative_map(dir.path());
    let but_minus_5 = ["0.ply", "7.ply"];
    let but_0 = ["-5.ply", "7.ply"];
    for (bg, sub, want) in [
        ("-5", "int", but_minus_5),
        ("-5.0", "float", but_minus_5),
        ("-5e0", "exp", but_minus_5),
        ("0", "zero", but_0),
        ("-0.0", "negzero", but_0),
    ] {
        let out = dir.path().join(sub);
        fs::create_dir(&out).unwrap();
        let o = s(&out.join("{label}.ply")).to_string();
        ok(&[
            "extract",
            s(&input),
            "--labels",
            "all",
            "--background",
            bg,
            "-o",
            &o,
            "-q",
        ]);
        assert_eq!(names(&out), want, "--background {bg}");
    }
    for bg in ["0.5", "nan", "inf", "1e300", "x"] {
        let extra = ["--labels", "all", "--background", bg, "-o", "{label}.ply"];
        let mut args = vec!["extract", s(&input), "-q"];
        args.extend_from_slice(&extra);
        let err = assert_one_line(&tmc(&args), 2);
        assert!(
            err.contains("--background") && err.contains("whole number"),
            "{bg}: {err}"
        );
    }
}

#[test]
fn a_whole_float_beyond_2_53_is_not_called_a_fraction() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut values = vec![0.0; 27];
    values[13] = 2f64.powi(53) + 2.0;
    let input = d.join("big.nrrd");
    write(&input, [3, 3, 3], values, ScalarType::F64);
    let out = d.join("{label}.ply");
    let err = assert_one_line(
        &tmc(&["extract", s(&input), "--labels", "all", "-o", s(&out)]),
        1,
    );
    assert!(err.contains("(x 1, y 1, z 1) is 9007199254740994"), "{err}");
    assert!(err.contains("beyond ±2^53"), "{err}");
    assert!(!err.contains("not a whole number"), "{err}");
    assert_eq!(names(d), ["big.nrrd"]);
}

/// A 64-bit integer is read as an `f64`, so 2^53 + 1 reads as 2^53: two
/// labels that would be one label's mesh. A 64-bit label of magnitude
/// 2^53 or more is refused, naming the first such sample; below it,
/// labels are read exactly (2^53 - 1 and 2^53 - 2 are two labels).
#[test]
fn a_64_bit_label_that_reads_as_2_53_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let raw = |name: &str, dtype: &str, values: [[u8; 8]; 2]| {
        let mut bytes = vec![0u8; 27 * 8];
        bytes[13 * 8..14 * 8].copy_from_slice(&values[0]);
        bytes[14 * 8..15 * 8].copy_from_slice(&values[1]);
        let path = d.join(name);
        fs::write(&path, bytes).unwrap();
        let out = d.join(format!("{dtype}-{{label}}.ply"));
        let args = ["--dims", "3,3,3", "--dtype", dtype, "--labels", "all"];
        let mut all = vec!["extract", s(&path), "-q", "-o", s(&out)];
        all.extend_from_slice(&args);
        tmc(&all)
    };
    let two53 = 1u64 << 53;
    for (dtype, values) in [
        ("u64", [(two53 + 1).to_le_bytes(), two53.to_le_bytes()]),
        (
            "i64",
            [(-(two53 as i64) - 1).to_le_bytes(), 5i64.to_le_bytes()],
        ),
        ("u64", [two53.to_le_bytes(), 7u64.to_le_bytes()]),
        ("u64", [u64::MAX.to_le_bytes(), 7u64.to_le_bytes()]),
        ("i64", [i64::MIN.to_le_bytes(), 7i64.to_le_bytes()]),
    ] {
        let err = assert_one_line(&raw("map.raw", dtype, values), 1);
        assert!(err.contains("sample (x 1, y 1, z 1)"), "{dtype}: {err}");
        assert!(err.contains("2^53"), "{dtype}: {err}");
        assert_eq!(names(d), ["map.raw"], "{dtype}: nothing written");
    }
    // Just below: two labels, each its own file.
    let below = raw(
        "map.raw",
        "u64",
        [(two53 - 1).to_le_bytes(), (two53 - 2).to_le_bytes()],
    );
    assert!(below.status.success(), "{below:?}");
    assert_eq!(
        names(d),
        [
            "map.raw",
            "u64-9007199254740990.ply",
            "u64-9007199254740991.ply"
        ]
    );
}

/// `tmc extract INPUT --labels all -o OUT -q`, asserting success.
fn all_labels(input: &Path, out: &str) {
    ok(&["extract", s(input), "--labels", "all", "-o", out, "-q"]);
}

/// Runs the built `tmc` with `args` under a soft limit of `files` open
/// files (the hard limit unchanged, as a login shell's `ulimit -n` leaves
/// it); `None` when the hard limit is below `need` (the test is skipped).
fn tmc_with_soft_limit(files: u32, need: u32, args: &[&str]) -> Option<std::process::Output> {
    let hard = std::process::Command::new("sh")
        .args(["-c", "ulimit -H -n"])
        .output()
        .unwrap();
    let hard = String::from_utf8_lossy(&hard.stdout).trim().to_string();
    if hard != "unlimited" && hard.parse::<u32>().unwrap() < need {
        println!("SKIPPED: the hard limit on open files, {hard}, is below {need}");
        return None;
    }
    let script = format!("ulimit -S -n {files} && exec \"$0\" \"$@\"");
    let out = std::process::Command::new("sh")
        .args(["-c", &script, common::cli::tmc_path()])
        .args(args)
        .output()
        .unwrap();
    Some(out)
}

#[test]
fn hundreds_of_labels_run_under_a_low_soft_limit_on_open_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 300 labels, each a few samples: a file (and its spools) per label.
    let dims = [20, 20, 8];
    let values: Vec<f64> = (0..3200).map(|i| f64::from(i % 301)).collect();
    let input = d.join("many.nrrd");
    write(&input, dims, values, ScalarType::U16);
    let free = d.join("free");
    let limited = d.join("limited");
    fs::create_dir(&free).unwrap();
    fs::create_dir(&limited).unwrap();
    let each = |dir: &Path| s(&dir.join("{label}.ply")).to_string();
    all_labels(&input, &each(&free));
    let run = [
        "extract",
        s(&input),
        "--labels",
        "all",
        "-o",
        &each(&limited),
        "-q",
    ];
    // Three files a label are open at once; 64 is far below that.
    let Some(out) = tmc_with_soft_limit(64, 2048, &run) else {
        return;
    };
    assert!(out.status.success(), "{out:?}");
    assert_eq!(names(&limited).len(), 300);
    for name in names(&free) {
        let a = fs::read(free.join(&name)).unwrap();
        assert!(a == fs::read(limited.join(&name)).unwrap(), "{name}");
    }
    // Merging the label parts into one file opens every label's too.
    let parts = d.join("parts");
    fs::create_dir(&parts).unwrap();
    let mut merge = vec!["merge".to_string()];
    for i in 1..=2 {
        let part = s(&parts.join("{label}.{part}.tmesh")).to_string();
        let spec = format!("{i}/2");
        ok(&[
            "extract",
            s(&input),
            "--labels",
            "all",
            "--part",
            &spec,
            "-o",
            &part,
            "-q",
        ]);
    }
    merge.extend(names(&parts).iter().map(|n| s(&parts.join(n)).to_string()));
    let one = d.join("one.ply");
    merge.extend(["-o".to_string(), s(&one).to_string()]);
    let merge: Vec<&str> = merge.iter().map(String::as_str).collect();
    let out = tmc_with_soft_limit(64, 2048, &merge).unwrap();
    assert!(out.status.success(), "{out:?}");
    let whole = d.join("whole.ply");
    all_labels(&input, s(&whole));
    assert!(fs::read(&one).unwrap() == fs::read(&whole).unwrap());
}

#[test]
fn more_labels_than_one_pass_takes_are_refused_before_any_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 65536 labels besides the background; one pass takes 65534.
    let values: Vec<f64> = (0..65537).map(f64::from).collect();
    let input = d.join("map.nrrd");
    write(&input, [65537, 1, 1], values, ScalarType::U32);
    let out = d.join("{label}.tmesh");
    let err = assert_one_line(
        &tmc(&[
            "extract",
            s(&input),
            "--labels",
            "all",
            "--close",
            "-o",
            s(&out),
        ]),
        1,
    );
    assert!(
        err.contains("65536 labels; one pass takes at most 65534"),
        "{err}"
    );
    assert_eq!(names(d), ["map.nrrd"]);
}

/// More labels than the hard limit on open files lets one pass keep open:
/// refused before any file is made, in one line that says how many labels
/// fit and what to do (the run used to fail part way with the system's
/// "Too many open files"); under a limit that holds them, the same labels
/// are written, one open file per label for `.tmesh` files.
#[test]
fn more_labels_than_open_files_are_refused_before_the_pass() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 120 labels, one sample each, apart.
    let dims = [12, 12, 12];
    let mut values = vec![0.0; 12 * 12 * 12];
    for l in 0..120usize {
        let (x, y, z) = (1 + 2 * (l % 5), 1 + 2 * (l / 5 % 5), 1 + 2 * (l / 25));
        values[x + 12 * (y + 12 * z)] = (l + 1) as f64;
    }
    let input = d.join("map.nrrd");
    write(&input, dims, values, ScalarType::U16);
    let under_limit = |files: u32, out: &Path| {
        let script = format!("ulimit -S -n {files} && ulimit -H -n {files} && exec \"$0\" \"$@\"");
        let template = out.join("{label}.tmesh");
        std::process::Command::new("sh")
            .args(["-c", &script, common::cli::tmc_path()])
            .args([
                "extract",
                s(&input),
                "--labels",
                "all",
                "-o",
                s(&template),
                "-q",
            ])
            .output()
            .unwrap()
    };
    let refused = d.join("refused");
    fs::create_dir(&refused).unwrap();
    let out = under_limit(150, &refused);
    let line = assert_one_line(&out, 1);
    assert!(
        line.contains("120 labels keep 120 files open at once (1 per label)")
            && line.contains("may open 150")
            && line.contains("at most 86 labels per run"),
        "{line}"
    );
    assert!(names(&refused).is_empty(), "{:?}", names(&refused));
    let written = d.join("written");
    fs::create_dir(&written).unwrap();
    let out = under_limit(200, &written);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(names(&written).len(), 120);
}

/// A listed label the map does not hold gets an empty mesh and a note, as
/// an isovalue outside the data range does (a mistyped label was written
/// as an empty file without a word); so does a `--background` the map
/// does not hold with `all`; `-q` keeps them quiet.
#[test]
fn a_listed_label_not_in_the_map_is_noted() {
    let dir = tempfile::tempdir().unwrap();
    let input = negative_map(dir.path());
    let out = dir.path().join("{label}.ply");
    let run = |labels: &str, more: &[&str]| {
        let args = ["extract", s(&input), "--labels", labels, "-o", s(&out)];
        let result = tmc(&[&args[..], more].concat());
        assert!(result.status.success(), "{result:?}");
        String::from_utf8(result.stderr).unwrap()
    };
    let one = run("-5,8,7", &[]);
    assert_eq!(one.lines().count(), 1, "{one}");
    assert!(
        one.starts_with("tmc: note: label 8 is not in ") && one.contains("its mesh is empty"),
        "{one}"
    );
    let many: Vec<String> = (100..115).map(|l| l.to_string()).collect();
    let several = run(&format!("7,{}", many.join(",")), &[]);
    assert_eq!(several.lines().count(), 1, "{several}");
    assert!(
        several.contains("15 labels are not in") && several.contains("and 5 more"),
        "{several}"
    );
    assert_eq!(run("-5,8", &["-q"]), "");
    assert_eq!(run("-5,7", &[]), "");
    assert!(dir.path().join("8.ply").is_file());
    // A background the map does not hold makes every value a label, the
    // real background's box too: one note says so (it was silent).
    let note = run("all", &["--background", "99"]);
    assert_eq!(note.lines().count(), 1, "{note}");
    assert!(
        note.starts_with("tmc: note: background 99 is not in ")
            && note.contains("every value present is a label (-5, 0, 7)"),
        "{note}"
    );
    assert_eq!(run("all", &["--background", "99", "-q"]), "");
    assert_eq!(run("all", &["--background=-5"]), "");
    assert!(dir.path().join("0.ply").is_file());
}

/// A malformed `--labels` list is a usage error (exit status 2, as a
/// malformed `--background` or `--iso` is), found before the map is read:
/// it was refused with status 1 after the first reading of the map, so a
/// bad map's error came first and a typo cost a full reading of a large
/// one.
#[test]
fn a_malformed_label_list_is_a_usage_error_before_the_map_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A map of label 3 that the scan refuses at its last sample (1.5).
    let values = (0..27).map(|i| [0.0, 3.0, 1.5][usize::from(i == 5) + 2 * usize::from(i == 26)]);
    let input = d.join("map.nrrd");
    write(&input, [3, 3, 3], values.collect(), ScalarType::F32);
    let out = d.join("{label}.ply");
    for (list, says) in [
        ("3,x", "'x' is not an integer"),
        ("3,,4", "'' is not an integer"),
        ("", "'' is not an integer"),
        ("ALL", "'ALL' is not an integer"),
        ("3.5", "'3.5' is not an integer"),
        ("5,3,5", "5 is given twice"),
    ] {
        let arg = format!("--labels={list}");
        let err = assert_one_line(&tmc(&["extract", s(&input), &arg, "-o", s(&out)]), 2);
        assert!(
            err.contains(says) && err.contains("--labels"),
            "{list}: {err}"
        );
        assert!(
            !err.contains("1.5"),
            "{list}: the map was read first: {err}"
        );
        assert_eq!(names(d), ["map.nrrd"]);
    }
}
