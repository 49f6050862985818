//! The `tmc` binary's I/O behaviour (help, usage errors, one-line failures,
//! no output left behind on failure); the mesh writers in `writers.rs`, the
//! binary's own failing streams in `closed_streams.rs`.

use crate::common;

use common::cli::{assert_one_line, names, npy_header, s, sphere_npy, tmc};
use std::fs;
use std::path::{Path, PathBuf};
use tmc::export::write_mesh;

mod closed_streams;
mod writers;

use writers::{parse_obj, parse_ply, parse_stl};

#[test]
fn help_states_the_convention_formats_and_exit_codes() {
    for args in [&["--help"][..], &["extract", "--help"][..]] {
        let out = tmc(args);
        assert_eq!(out.status.code(), Some(0));
        let text = String::from_utf8_lossy(&out.stdout);
        for needle in [
            "inside iff its value > ISO",
            "equal to ISO is outside",
            "NaN samples are outside",
            ".npy",
            ".nrrd",
            "--dims and --dtype",
            "STL cannot share vertices",
            "'tmc check' joins corners at the same position",
            ".tmesh",
            "tmc convert",
            "0    success",
            "1    failure",
            "disk full",
            "'tmc check' also exits 1 when the mesh is not a consistently",
            "2    usage error",
            "130  interrupted by SIGINT, 143 by SIGTERM",
        ] {
            assert!(text.contains(needle), "{args:?}: help lacks '{needle}'");
        }
    }
    let extract = String::from_utf8_lossy(&tmc(&["extract", "--help"]).stdout).into_owned();
    for option in [
        "--iso",
        "--output",
        "--method",
        "--inside",
        "--close",
        "--stats",
        "--json",
        "--threads",
        "--slab-depth",
        "--max-memory",
        "--require-surface",
        "--dims",
        "--dtype",
        "--endian",
        "--header-bytes",
        "--spacing",
        "--origin",
    ] {
        assert!(extract.contains(option), "extract help lacks {option}");
    }
    let check = String::from_utf8_lossy(&tmc(&["check", "--help"]).stdout).into_owned();
    assert!(check.contains("STL") && check.contains("--json") && check.contains(".tmesh"));
    let top = String::from_utf8_lossy(&tmc(&["--help"]).stdout).into_owned();
    assert!(top.contains("convert"), "{top}");
    let convert = String::from_utf8_lossy(&tmc(&["convert", "--help"]).stdout).into_owned();
    for needle in ["--output", ".tmesh", ".ply", "byte-identical", "chunk"] {
        assert!(convert.contains(needle), "convert help lacks {needle}");
    }
}

/// `tmc synth --help` gives every `--dtype` its stored values and
/// isovalues, and those synth prints after writing: each type is in a row
/// of the unit fields' table and of the head phantom's lists, and the
/// row holds the isovalues synth suggests for it (i64, u64 and f16 were
/// in none, and "MAX is the largest value of the type" sent a u64 user to
/// an isovalue outside the data).
#[test]
fn synth_help_gives_every_dtype_its_isovalues() {
    let help = String::from_utf8_lossy(&tmc(&["synth", "--help"]).stdout).into_owned();
    let section = |start: &str, end: &str| {
        let after = help
            .split(start)
            .nth(1)
            .unwrap_or_else(|| panic!("no '{start}'"));
        after.split(end).next().unwrap().to_string()
    };
    // Entries: a line of the table, a ';'-separated group of the lists.
    let unit_rows = section("Stored values of sphere", "Inside is above");
    let head_stored = section("Stored as:", "Suggested isovalues");
    let head_isos = section("Suggested isovalues", "Output formats");
    let words = |entry: &str| -> Vec<String> {
        entry
            .split_whitespace()
            .map(|w| {
                w.trim_matches(|c| c == ',' || c == ':' || c == '(' || c == ')')
                    .to_string()
            })
            .collect()
    };
    let entry_of = |text: &str, dtype: &str| -> Option<Vec<String>> {
        text.split(['\n', ';'])
            .map(words)
            .find(|w| w.iter().take_while(|w| is_dtype(w)).any(|w| w == dtype))
    };
    let dtypes = [
        "u8", "i8", "u16", "i16", "u32", "i32", "i64", "u64", "f16", "f32", "f64",
    ];
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("v.npy");
    for dtype in dtypes {
        assert!(
            entry_of(&head_stored, dtype).is_some(),
            "head 'Stored as' names no {dtype}: {head_stored}"
        );
        for (kind, rows) in [("sphere", &unit_rows), ("head", &head_isos)] {
            let out = tmc(&[
                "synth",
                kind,
                "--dims",
                "4,4,4",
                "--dtype",
                dtype,
                "-o",
                path.to_str().unwrap(),
            ]);
            assert_eq!(out.status.code(), Some(0), "{kind} {dtype}");
            let said = String::from_utf8_lossy(&out.stderr).into_owned();
            let isos: Vec<&str> = said
                .split("--iso ")
                .skip(1)
                .map(|r| r.split([' ', ')']).next().unwrap())
                .collect();
            assert!(!isos.is_empty(), "{kind} {dtype}: {said}");
            let entry = entry_of(rows, dtype)
                .unwrap_or_else(|| panic!("{kind}: no row of the help names {dtype}: {rows}"));
            for iso in isos {
                assert!(
                    entry.iter().any(|w| w == iso),
                    "{kind} {dtype}: synth suggests --iso {iso}, its row of the help says {entry:?}"
                );
            }
        }
    }
}

/// The input formats of `tmc --help` name the 64-bit and half-float types
/// their readers read: a NRRD and a `.npy` of each (written by `tmc
/// synth`) read as that type, and the help's paragraph of the format lists
/// it (it said NRRD reads "not 64-bit integers", NIfTI "integer types up to
/// 32 bits" and `.npy` only dtypes up to 4 bytes; NIfTI's int64 and uint64
/// are read by `tests/formats/readers.rs`).
#[test]
fn help_names_the_wide_types_the_readers_read() {
    let help = String::from_utf8_lossy(&tmc(&["--help"]).stdout).into_owned();
    // A format's lines, up to the next format's (.nhdr shares NRRD's).
    let next = |ext: &str| match ext {
        ".npy" => ".nrrd",
        ".nrrd" => ".nii",
        _ => ".mhd",
    };
    let paragraph = |ext: &str| -> String {
        let text = help.split(&format!("\n  {ext} ")).nth(1).unwrap();
        text.split(&format!("\n  {} ", next(ext)))
            .next()
            .unwrap()
            .to_string()
    };
    let dir = tempfile::tempdir().unwrap();
    // (type, file, what the paragraph must say)
    for (dtype, file, says) in [
        ("i64", "v.nrrd", "64-bit integer"),
        ("u64", "v.nrrd", "64-bit integer"),
        ("i64", "v.npy", "i8"),
        ("u64", "v.npy", "u8"),
        ("f16", "v.npy", "f2"),
    ] {
        let path = dir.path().join(file);
        let out = tmc(&[
            "synth",
            "sphere",
            "--dims",
            "4,4,4",
            "--dtype",
            dtype,
            "-o",
            s(&path),
        ]);
        assert_eq!(out.status.code(), Some(0), "{dtype} {file}");
        let info: serde_json::Value =
            serde_json::from_slice(&tmc(&["info", s(&path), "--json"]).stdout).unwrap();
        assert_eq!(info["sample_type"], dtype, "{file}");
        let ext = &file[1..];
        let text = paragraph(ext);
        assert!(
            text.contains(says) && !text.contains("not 64-bit"),
            "{ext} reads {dtype}, its help says: {text}"
        );
    }
    let nifti = paragraph(".nii");
    assert!(
        nifti.contains("64-bit integer") && !nifti.contains("up to"),
        "{nifti}"
    );
}

/// Whether `w` names a sample type of `tmc synth --dtype`.
fn is_dtype(w: &str) -> bool {
    w.len() >= 2 && matches!(w.as_bytes()[0], b'u' | b'i' | b'f') && w[1..].parse::<u32>().is_ok()
}

#[test]
fn help_that_cannot_be_written_is_a_failure() {
    let Ok(full) = fs::OpenOptions::new().write(true).open("/dev/full") else {
        eprintln!("skipped: no /dev/full on this system");
        return;
    };
    for args in [
        &["--help"][..],
        &["extract", "--help"][..],
        &["--version"][..],
    ] {
        let out = std::process::Command::new(common::cli::tmc_path())
            .args(args)
            .stdout(full.try_clone().unwrap())
            .output()
            .unwrap();
        let line = assert_one_line(&out, 1);
        assert!(
            line.contains("cannot write to standard output"),
            "{args:?}: {line}"
        );
    }
}

#[test]
fn usage_errors_exit_2_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere_npy(dir.path(), "in.npy", [4, 4, 4]);
    let output = dir.path().join("out.ply");
    let (i, o) = (s(&input), s(&output));
    for args in [
        vec!["extract", i, "--iso", "abc", "-o", o],
        vec!["extract", i, "--iso", "nan", "-o", o],
        vec!["extract", i, "--iso", "inf", "-o", o],
        vec!["extract", i, "-o", o],
        vec!["extract", i, "--iso", "1", "-o", o, "--method", "fast"],
        vec!["extract", i, "--iso", "1", "-o", o, "--dims", "4,4,4"],
        vec!["extract", i, "--iso", "1", "-o", o, "--dtype", "u8"],
        vec![
            "extract", i, "--iso", "1", "-o", o, "--dims", "4,4", "--dtype", "u8",
        ],
        vec![
            "extract", i, "--iso", "1", "-o", o, "--dims", "4,4,4", "--dtype", "u128",
        ],
        vec![
            "extract",
            i,
            "--iso",
            "1",
            "-o",
            o,
            "--dims",
            "4,4,4",
            "--dtype",
            "u8",
            "--spacing",
            "1,0,1",
        ],
        vec!["extract", i, "--iso", "1", "-o", o, "--threads", "-1"],
        vec!["extract", i, "--iso", "1", "-o", o, "--slab-depth", "x"],
        vec!["convert", i],
        vec!["convert", "-o", o],
        vec!["extract", i, "--iso", "1", "-o", o, "--bogus"],
        vec!["frobnicate"],
    ] {
        let line = assert_one_line(&tmc(&args), 2);
        assert!(line.contains("--help"), "{args:?}: {line}");
        assert_eq!(names(dir.path()), ["in.npy"], "{args:?}");
    }
}

#[test]
fn negative_isovalues_parse() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.npy");
    let out = tmc(&["extract", s(&missing), "--iso", "-5", "-o", "x.ply"]);
    // Parsed fine: the failure is the missing input, status 1.
    let line = assert_one_line(&out, 1);
    assert!(line.contains("missing.npy"), "{line}");
}

#[test]
fn missing_or_bad_input_fails_with_one_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("out.ply");
    let missing = dir.path().join("missing.npy");
    let line = assert_one_line(
        &tmc(&["extract", s(&missing), "--iso", "0", "-o", s(&output)]),
        1,
    );
    assert!(line.contains("missing.npy"), "{line}");

    let garbage = dir.path().join("garbage.npy");
    fs::write(&garbage, b"not numpy").unwrap();
    let line = assert_one_line(
        &tmc(&["extract", s(&garbage), "--iso", "0", "-o", s(&output)]),
        1,
    );
    assert!(line.contains("not a .npy file"), "{line}");

    let unknown = dir.path().join("in.xyz");
    fs::write(&unknown, b"x").unwrap();
    let line = assert_one_line(
        &tmc(&["extract", s(&unknown), "--iso", "0", "-o", s(&output)]),
        1,
    );
    assert!(line.contains("unknown input format"), "{line}");

    let vti = dir.path().join("in.vti");
    fs::write(&vti, b"x").unwrap();
    let line = assert_one_line(
        &tmc(&["extract", s(&vti), "--iso", "0", "-o", s(&output)]),
        1,
    );
    assert!(line.contains("not a VTK XML file"), "{line}");

    assert!(!output.exists());
}

#[test]
fn bad_output_paths_fail_before_extraction() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere_npy(dir.path(), "in.npy", [4, 4, 4]);
    let file = dir.path().join("a_file");
    fs::write(&file, b"x").unwrap();
    fs::create_dir(dir.path().join("dir.ply")).unwrap();
    let cases = [
        (dir.path().join("no/such/dir/out.ply"), "does not exist"),
        (file.join("out.ply"), "not a directory"),
        (dir.path().join("dir.ply"), "is a directory"),
        (dir.path().join("out.ply/"), "ends in a path separator"),
        (dir.path().join("out.vtk"), "unknown output format"),
        (dir.path().join("out"), "unknown output format"),
    ];
    for (output, expected) in cases {
        let out = tmc(&["extract", s(&input), "--iso", "0", "-o", s(&output)]);
        let line = assert_one_line(&out, 1);
        assert!(line.contains(expected), "{}: {line}", output.display());
        assert!(!output.is_file(), "{} was written", output.display());
    }
    assert_eq!(names(dir.path()), ["a_file", "dir.ply", "in.npy"]);
}

#[test]
fn unwritable_output_directory_fails_with_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere_npy(dir.path(), "in.npy", [4, 4, 4]);

    #[cfg(target_os = "linux")]
    {
        // Nobody, not even root, can create files in /proc/self.
        let output = Path::new("/proc/self/out.ply");
        let line = assert_one_line(
            &tmc(&["extract", s(&input), "--iso", "0", "-o", s(output)]),
            1,
        );
        assert!(line.contains("cannot write"), "{line}");
    }

    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let locked = dir.path().join("locked");
        fs::create_dir(&locked).unwrap();
        fs::set_permissions(&locked, fs::Permissions::from_mode(0o555)).unwrap();
        if fs::write(locked.join("probe"), b"").is_ok() {
            println!("skipped read-only directory case: running with permission to write anyway");
        } else {
            let output = locked.join("out.ply");
            let line = assert_one_line(
                &tmc(&["extract", s(&input), "--iso", "0", "-o", s(&output)]),
                1,
            );
            assert!(line.contains("cannot write"), "{line}");
            assert!(names(&locked).is_empty());
        }
        fs::set_permissions(&locked, fs::Permissions::from_mode(0o755)).unwrap();
    }
}

#[test]
fn check_of_a_missing_mesh_fails_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.ply");
    let line = assert_one_line(&tmc(&["check", s(&missing)]), 1);
    assert!(line.contains("missing.ply"), "{line}");
}

#[test]
fn extract_writes_mesh_stats_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere_npy(dir.path(), "ball.npy", [10, 9, 8]);
    let output = dir.path().join("ball.ply");
    let out = tmc(&[
        "extract",
        s(&input),
        "--iso",
        "0",
        "-o",
        s(&output),
        "--stats",
        "--json",
        "--threads",
        "2",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    for row in [
        "ambiguous cells",
        "contours with 3 vertices",
        "contours with 6 vertices",
        "ambiguous contours with 6 vertices",
        "ambiguous contours with 9 vertices",
        "tunnels",
        "contours with 12 vertices",
        "vertices",
        "triangles",
        "time",
    ] {
        assert!(stderr.contains(row), "table lacks '{row}': {stderr}");
    }
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert_eq!(stdout.lines().count(), 1);
    let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    for key in [
        "input",
        "output",
        "iso",
        "method",
        "inside",
        "close",
        "threads",
        "dims",
        "spacing",
        "origin",
        "ambiguous_cells",
        "contours",
        "ambiguous_contours",
        "tunnels",
        "contours_12",
        "vertices",
        "triangles",
        "seconds",
    ] {
        assert!(json.get(key).is_some(), "JSON lacks '{key}': {stdout}");
    }
    assert_eq!(json["dims"], serde_json::json!([10, 9, 8]));
    assert_eq!(json["method"], "tmc");
    assert_eq!(json["threads"], 2);
    let mesh = parse_ply(&fs::read(&output).unwrap());
    assert_eq!(json["vertices"], mesh.vertices.len());
    assert_eq!(json["triangles"], mesh.triangles.len());
    assert!(!mesh.triangles.is_empty());
}

#[test]
fn extract_is_quiet_without_stats_and_reads_raw_and_nrrd() {
    let dir = tempfile::tempdir().unwrap();
    // Raw big-endian u16 with a header: a ramp along x.
    let raw = dir.path().join("ramp.raw");
    let mut bytes = vec![0u8; 3];
    for _z in 0..3 {
        for _y in 0..3 {
            for x in 0..4u16 {
                bytes.extend_from_slice(&(x * 100).to_be_bytes());
            }
        }
    }
    fs::write(&raw, bytes).unwrap();
    let output = dir.path().join("ramp.obj");
    let out = tmc(&[
        "extract",
        s(&raw),
        "--iso",
        "150",
        "-o",
        s(&output),
        "--dims",
        "4,3,3",
        "--dtype",
        "u16",
        "--endian",
        "big",
        "--header-bytes",
        "3",
        "--spacing",
        "2,1,1",
        "--origin=-1,0,0",
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty() && out.stderr.is_empty());
    let mesh = parse_obj(&fs::read_to_string(&output).unwrap());
    // The plane x = 1.5 in index space, 2 in world space.
    assert!(mesh.vertices.iter().all(|v| (v[0] - 2.0).abs() < 1e-5));

    let demo = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/headsq_quarter.nrrd");
    let output = dir.path().join("head.stl");
    let out = tmc(&[
        "extract",
        s(&demo),
        "--iso",
        "500",
        "-o",
        s(&output),
        "--close",
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!parse_stl(&fs::read(&output).unwrap()).is_empty());

    // `tmc check` refuses a volume given by mistake (binary, not an STL's
    // 84 + 50 n bytes) as an unknown mesh format.
    let volume = noise_npy(dir.path(), "volume.npy");
    let check = tmc(&["check", s(&volume)]);
    let said = String::from_utf8_lossy(&check.stderr);
    assert!(!check.status.success(), "{said}");
    assert!(
        said.contains("unrecognised mesh format") && !said.contains("STL"),
        "{said}"
    );
    assert_eq!(said.lines().count(), 1, "{said}");
}

/// Writes `tmc::synth::noise(24, 3, 1)` as a little-endian f64 `.npy`.
fn noise_npy(dir: &Path, name: &str) -> PathBuf {
    let volume = tmc::synth::noise(24, 3, 1);
    let mut bytes = npy_header("{'descr': '<f8', 'fortran_order': False, 'shape': (24, 24, 24), }");
    for v in volume.data() {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    let path = dir.join(name);
    fs::write(&path, bytes).unwrap();
    path
}

/// Runs `tmc` and asserts success with nothing on stdout or stderr.
pub(crate) fn tmc_ok(args: &[&str]) {
    let out = tmc(args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty() && out.stderr.is_empty(), "{args:?}");
}

#[test]
fn extract_streams_and_convert_matches_it_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let input = noise_npy(dir.path(), "noise.npy");
    let tmesh = dir.path().join("noise.tmesh");
    let i = s(&input);
    tmc_ok(&[
        "extract",
        i,
        "--iso",
        "0",
        "-o",
        s(&tmesh),
        "--slab-depth",
        "1",
    ]);
    for ext in ["ply", "obj", "off", "stl", "tmesh"] {
        let direct = dir.path().join(format!("direct.{ext}"));
        tmc_ok(&[
            "extract",
            i,
            "--iso",
            "0",
            "-o",
            s(&direct),
            "--threads",
            "2",
        ]);
        let deep = dir.path().join(format!("deep.{ext}"));
        tmc_ok(&[
            "extract",
            i,
            "--iso",
            "0",
            "-o",
            s(&deep),
            "--slab-depth",
            "7",
        ]);
        let converted = dir.path().join(format!("converted.{ext}"));
        tmc_ok(&["convert", s(&tmesh), "-o", s(&converted)]);
        let expected = fs::read(&direct).unwrap();
        assert!(fs::read(&deep).unwrap() == expected, "{ext}: slab depth");
        assert!(fs::read(&converted).unwrap() == expected, "{ext}: convert");
    }
    assert!(fs::read(&tmesh).unwrap() == fs::read(dir.path().join("direct.tmesh")).unwrap());
    // The same mesh as the in-memory extraction written by write_mesh.
    let (mesh, _) =
        tmc::extract(&tmc::synth::noise(24, 3, 1), &tmc::ExtractParams::default()).unwrap();
    let reference = dir.path().join("reference.ply");
    write_mesh(&reference, &mesh).unwrap();
    assert!(fs::read(&reference).unwrap() == fs::read(dir.path().join("direct.ply")).unwrap());
    assert!(names(dir.path()).iter().all(|n| !n.starts_with(".tmc-")));
}

#[test]
fn check_reads_tmesh_like_ply() {
    let dir = tempfile::tempdir().unwrap();
    let input = noise_npy(dir.path(), "noise.npy");
    let mesh = |ext: &str| dir.path().join(format!("m.{ext}"));
    let (ply, tmesh) = (mesh("ply"), mesh("tmesh"));
    for output in ["ply", "tmesh", "obj", "off"].map(mesh) {
        tmc_ok(&[
            "extract",
            s(&input),
            "--iso",
            "0",
            "--close",
            "-o",
            s(&output),
        ]);
    }
    let report = |path: &Path| {
        let out = tmc(&["check", s(path), "--json"]);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stdout).unwrap()
    };
    let expected = report(&ply);
    assert!(expected.contains("\"vertices\""), "{expected}");
    assert_eq!(report(&tmesh), expected);
    // So do the OBJ and OFF files that extract writes.
    for ext in ["obj", "off"] {
        assert_eq!(report(&mesh(ext)), expected, "{ext}");
    }
    // Recognised by its magic bytes, whatever the name.
    let renamed = dir.path().join("m.bin");
    fs::copy(&tmesh, &renamed).unwrap();
    assert_eq!(report(&renamed), expected);
    // An open surface (boundary edges) is still a manifold: exit status 0.
    let open = dir.path().join("open.tmesh");
    tmc_ok(&["extract", s(&input), "--iso", "0", "-o", s(&open)]);
    let out = tmc(&["check", s(&open)]);
    assert_eq!(out.status.code(), Some(0));
    assert!(!out.stdout.is_empty());
}

/// `tmc check` reads STL (it refused it): corners at the same position are
/// joined, so the STL tmc writes checks as its PLY does (with a note on
/// stderr); two vertices that share a position in the mesh written become
/// one, non-manifold where the surfaces only touch there.
#[test]
fn check_reads_stl_with_corners_joined_by_position() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = common::cli::synth(d, "torus", "30,30,20", "f32", "torus.npy");
    let report = |mesh: &Path| {
        let out = tmc(&["check", s(mesh), "--json"]);
        assert_eq!(out.status.code(), Some(0), "{out:?}");
        let note = String::from_utf8_lossy(&out.stderr).into_owned();
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        (json, note)
    };
    let (ply, stl) = (d.join("t.ply"), d.join("t.stl"));
    for mesh in [&ply, &stl] {
        tmc_ok(&["extract", s(&input), "--iso", "0", "--close", "-o", s(mesh)]);
    }
    let (from_ply, quiet) = report(&ply);
    let (from_stl, note) = report(&stl);
    assert_eq!(from_stl, from_ply);
    assert_eq!(from_stl["per_component"][0]["genus"], 1);
    assert!(quiet.is_empty(), "{quiet}");
    assert!(note.contains("joined into one vertex"), "{note}");
    assert_eq!(note.lines().count(), 1, "{note}");

    // Two tetrahedra touching at one point, each with its own vertex
    // there: the OFF is a manifold with two vertices at one position, the
    // STL (ASCII) one non-manifold vertex.
    let tet = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let faces = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
    let (mut off, mut ascii) = (String::new(), String::from("solid two\n"));
    let mut corners = Vec::new();
    for (k, sign) in [1.0f32, -1.0].into_iter().enumerate() {
        for p in tet {
            corners.push(p.map(|c| c * sign));
        }
        for f in faces {
            off += &format!("3 {} {} {}\n", 4 * k + f[0], 4 * k + f[1], 4 * k + f[2]);
            ascii += "facet normal 0 0 0\nouter loop\n";
            for v in f {
                let [x, y, z] = corners[4 * k + v];
                ascii += &format!("vertex {x} {y} {z}\n");
            }
            ascii += "endloop\nendfacet\n";
        }
    }
    let points: String = corners
        .iter()
        .map(|[x, y, z]| format!("{x} {y} {z}\n"))
        .collect();
    fs::write(d.join("two.off"), format!("OFF\n8 8 0\n{points}{off}")).unwrap();
    fs::write(d.join("two.stl"), ascii + "endsolid two\n").unwrap();
    let (from_off, _) = report(&d.join("two.off"));
    assert_eq!(from_off["shared_position_vertices"], 2);
    assert_eq!(from_off["components"], 2);
    let out = tmc(&["check", s(&d.join("two.stl")), "--json", "-q"]);
    let line = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{line}");
    assert_eq!(line.lines().count(), 1, "{line}");
    assert!(line.contains("non-manifold"), "{line}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["vertices"], 7);
    assert_eq!(json["non_manifold_vertices"], 1);
}

#[test]
fn check_refuses_what_is_not_a_valid_mesh_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let file = |name: &str, bytes: &[u8]| {
        let path = d.join(name);
        fs::write(&path, bytes).unwrap();
        path
    };
    let nrrd =
        fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/nrrd_raw_le_f32.nrrd"))
            .unwrap();
    let elf = fs::read(std::env::current_exe().unwrap()).unwrap();
    let tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
    let off = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n\
               3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n3 0 1 2\n3 0 1 2\n";
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
               property float z\nend_header\n0 0 0\n1 0 0\n0 1 nan\n";
    let cases = [
        (file("volume.obj", &nrrd), "line 1: not an OBJ file"),
        (file("program.obj", &elf[..4096]), "line 1: not an OBJ file"),
        (
            file("prose.obj", b"Just some words.\n"),
            "line 1: not an OBJ file",
        ),
        (
            file("nan.obj", tet.replace("v 0 1 0", "v 0 1 NaN").as_bytes()),
            "line 3:",
        ),
        (file("faces.off", off.as_bytes()), "line 11: content after"),
        (file("nan.ply", ply.as_bytes()), "vertex 2: coordinate NaN"),
        (
            file("tail.ply", ply.replace("nan", "0 7").as_bytes()),
            "after the last element",
        ),
    ];
    for (path, expected) in &cases {
        let line = assert_one_line(&tmc(&["check", s(path)]), 1);
        assert!(line.contains(&path.display().to_string()), "{line}");
        assert!(line.contains(expected), "{line} lacks '{expected}'");
    }
    // The same tetrahedron is fine.
    let out = tmc(&["check", s(&file("tet.obj", tet.as_bytes()))]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
}

#[test]
fn a_damaged_tmesh_fails_convert_and_check_with_one_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let input = noise_npy(dir.path(), "noise.npy");
    let tmesh = dir.path().join("m.tmesh");
    tmc_ok(&["extract", s(&input), "--iso", "0", "-o", s(&tmesh)]);
    let good = fs::read(&tmesh).unwrap();
    let entries = tmc::meshfile::TmeshReader::open(&tmesh)
        .unwrap()
        .entries()
        .to_vec();
    // The last chunk: everything before it is converted before the failure.
    let last = entries.len() - 1;
    let mut bad = good.clone();
    bad[entries[last].offset as usize + 48 + 3] ^= 0x01;
    fs::write(&tmesh, &bad).unwrap();
    let keep = dir.path().join("keep.ply");
    fs::write(&keep, b"old").unwrap();
    for ext in ["ply", "obj", "off", "stl", "tmesh"] {
        let output = dir.path().join(format!("out.{ext}"));
        let line = assert_one_line(&tmc(&["convert", s(&tmesh), "-o", s(&output)]), 1);
        assert!(
            line.contains(&format!("chunk {last}")) && line.contains("checksum"),
            "{line}"
        );
        assert!(!output.exists(), "{ext}");
    }
    let line = assert_one_line(&tmc(&["convert", s(&tmesh), "-o", s(&keep)]), 1);
    assert!(line.contains("m.tmesh"), "{line}");
    assert_eq!(fs::read(&keep).unwrap(), b"old");
    let line = assert_one_line(&tmc(&["check", s(&tmesh)]), 1);
    assert!(line.contains(&format!("chunk {last}")), "{line}");
    assert_eq!(names(dir.path()), ["keep.ply", "m.tmesh", "noise.npy"]);

    // Truncated, not a .tmesh at all, a missing output directory.
    fs::write(&tmesh, &good[..good.len() - 10]).unwrap();
    let output = dir.path().join("out.ply");
    for args in [
        vec!["convert", s(&tmesh), "-o", s(&output)],
        vec!["check", s(&tmesh)],
    ] {
        let line = assert_one_line(&tmc(&args), 1);
        assert!(line.contains("truncated"), "{line}");
    }
    let line = assert_one_line(&tmc(&["convert", s(&input), "-o", s(&output)]), 1);
    assert!(line.contains("not a valid .tmesh file"), "{line}");
    fs::write(&tmesh, &good).unwrap();
    let missing = dir.path().join("no/dir/out.ply");
    let line = assert_one_line(&tmc(&["convert", s(&tmesh), "-o", s(&missing)]), 1);
    assert!(line.contains("does not exist"), "{line}");
    let line = assert_one_line(
        &tmc(&["convert", s(&tmesh), "-o", s(&dir.path().join("x.vtk"))]),
        1,
    );
    assert!(line.contains("unknown output format"), "{line}");
    assert_eq!(names(dir.path()), ["keep.ply", "m.tmesh", "noise.npy"]);
}

#[test]
fn extract_to_a_missing_directory_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let input = noise_npy(dir.path(), "noise.npy");
    for ext in ["ply", "tmesh"] {
        let output = dir.path().join(format!("gone/out.{ext}"));
        let line = assert_one_line(
            &tmc(&["extract", s(&input), "--iso", "0", "-o", s(&output)]),
            1,
        );
        assert!(line.contains("does not exist"), "{line}");
    }
    assert_eq!(names(dir.path()), ["noise.npy"]);
}

#[test]
fn grids_one_sample_thin_extract_with_close_only() {
    // A block of inside samples one sample thin along some axes: without
    // --close there are no cells (one clear error); with it the padding
    // gives cells, and the surface is one closed, oriented sphere.
    let dir = tempfile::tempdir().unwrap();
    for dims in [[1, 1, 1], [3, 1, 1], [1, 4, 2], [2, 3, 1]] {
        let raw = dir.path().join("thin.raw");
        fs::write(&raw, vec![10u8; dims.iter().product()]).unwrap();
        let dims_arg = format!("{},{},{}", dims[0], dims[1], dims[2]);
        let output = dir.path().join("thin.obj");
        let base = [
            "extract",
            s(&raw),
            "--iso",
            "5",
            "-o",
            s(&output),
            "--dims",
            &dims_arg,
            "--dtype",
            "u8",
        ];
        let line = assert_one_line(&tmc(&base), 1);
        assert!(
            line.ends_with("need at least 2 on every axis (or --close)"),
            "{line}"
        );
        assert!(!output.exists(), "{dims:?}");

        tmc_ok(&[&base[..], &["--close"]].concat());
        let mesh = parse_obj(&fs::read_to_string(&output).unwrap());
        // Every directed edge once, its reverse once: closed and oriented.
        let mut directed = std::collections::HashMap::new();
        for t in &mesh.triangles {
            for k in 0..3 {
                *directed.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &n) in &directed {
            assert_eq!((n, directed.get(&(b, a))), (1, Some(&1)), "{dims:?}");
        }
        let (v, e, f) = (
            mesh.vertices.len(),
            directed.len() / 2,
            mesh.triangles.len(),
        );
        assert_eq!(v as i64 - e as i64 + f as i64, 2, "{dims:?}: not a sphere");
        fs::remove_file(&output).unwrap();
    }
}
