//! Bad inputs to `tmc extract`, one table row each: the one-line message
//! (a substring), the exit status, and nothing left in the output directory
//! (no mesh, no `.tmc-*.tmp`). Cases already covered by `tests/cli/io.rs` (a
//! missing input, a garbage `.npy`, an unknown extension, a NaN or infinite
//! `--iso`, an unknown `--dtype`, an output directory that does not exist or
//! cannot be written) are not repeated here. Also: the output refused when it
//! is the input, an isovalue outside the data range (a note and an empty
//! mesh, or an error with `--require-surface`), and `tmc check` failing on
//! a mesh that is not a manifold.

use crate::common;

use common::cli::{assert_one_line, names, npy_header, s, sphere_npy, temp_files, tmc, tmc_within};
use common::formats::data_dir;
use std::fs;
use std::path::{Path, PathBuf};

/// Writes `bytes` to `dir/name`.
fn file(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    fs::write(&path, bytes).unwrap();
    path
}

/// A `.npy` file with header dictionary `dict` and `data` zero bytes.
fn npy(dir: &Path, name: &str, dict: &str, data: usize) -> PathBuf {
    let mut bytes = npy_header(dict);
    bytes.resize(bytes.len() + data, 0);
    file(dir, name, &bytes)
}

/// An attached-data NRRD file with header `fields` (after the magic line)
/// and `data` zero bytes.
fn nrrd(dir: &Path, name: &str, fields: &str, data: usize) -> PathBuf {
    let mut bytes = format!("NRRD0004\n{fields}encoding: raw\n\n").into_bytes();
    bytes.resize(bytes.len() + data, 0);
    file(dir, name, &bytes)
}

/// A FIFO at `dir/name` (opening it for reading would block forever).
#[cfg(unix)]
fn fifo(dir: &Path, name: &str) -> PathBuf {
    let path = dir.join(name);
    let status = std::process::Command::new("mkfifo")
        .arg(&path)
        .status()
        .expect("run mkfifo");
    assert!(status.success());
    path
}

/// The arguments that follow `extract` for one case: input and options.
type Setup = fn(&Path) -> Vec<String>;

/// `path` and `rest` as owned arguments.
fn args(path: &Path, rest: &[&str]) -> Vec<String> {
    std::iter::once(s(path).to_string())
        .chain(rest.iter().map(|a| a.to_string()))
        .collect()
}

/// A 4x4x4 raw volume of zero bytes, with `rest` after its raw options.
fn raw4(dir: &Path, rest: &[&str]) -> Vec<String> {
    let mut all = vec!["--dims", "4,4,4", "--dtype", "u8"];
    all.extend(rest);
    args(&file(dir, "z.raw", &[0; 64]), &all)
}

/// The table: name, setup, expected message substring, exit status.
fn cases() -> Vec<(&'static str, Setup, &'static str, i32)> {
    const U16: &[&str] = &["--dims", "10,10,10", "--dtype", "u16", "--iso", "0"];
    vec![
        (
            "truncated raw data",
            |d| args(&file(d, "t.raw", &[0; 1000]), U16),
            "t.raw: file has 1000 bytes, dims 10x10x10 u16 need 2000 after a 0-byte header",
            1,
        ),
        (
            // Read as samples, a compressed file whose length fits the dims
            // made a mesh of noise.
            "gzip-compressed raw data",
            |d| {
                let mut gz = vec![0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3];
                gz.resize(2000, 0);
                args(&file(d, "v.raw.gz", &gz), U16)
            },
            "v.raw.gz: gzip-compressed data, not raw samples: decompress it first (e.g. gunzip -k ",
            1,
        ),
        (
            // Said only "bad magic".
            "gzip-compressed .npy named .npy",
            |d| {
                let mut gz = vec![0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3];
                gz.resize(200, 0);
                args(&file(d, "v.npy", &gz), &["--iso", "0"])
            },
            "v.npy: gzip-compressed data, not a .npy file: decompress it first (e.g. gunzip -c ",
            1,
        ),
        (
            // Said "unknown input format".
            "gzip-compressed .npy named .npy.gz",
            |d| {
                let mut gz = vec![0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3];
                gz.resize(200, 0);
                args(&file(d, "v.npy.gz", &gz), &["--iso", "0"])
            },
            "v.npy.gz: gzip-compressed data, not an uncompressed volume file: decompress it first (e.g. gunzip -k ",
            1,
        ),
        (
            "truncated .npy data",
            |d| {
                let dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (8, 8, 8), }";
                args(&npy(d, "t.npy", dict, 100), &["--iso", "0"])
            },
            "dims 8x8x8 f32 need 2048",
            1,
        ),
        (
            "truncated .nrrd data",
            |d| {
                let fields = "type: uchar\ndimension: 3\nsizes: 100 100 100\n";
                args(&nrrd(d, "t.nrrd", fields, 640), &["--iso", "0"])
            },
            "dims 100x100x100 u8 need 1000000",
            1,
        ),
        (
            "raw dims whose product overflows u64",
            |d| {
                let big = "4294967296,4294967296,4294967296";
                let rest = ["--dims", big, "--dtype", "u8", "--iso", "0"];
                args(&file(d, "z.raw", &[0; 64]), &rest)
            },
            "dims 4294967296x4294967296x4294967296 u8 are too large",
            1,
        ),
        (
            ".nrrd sizes whose product overflows u64",
            |d| {
                let fields = "type: uchar\ndimension: 3\nsizes: 4294967296 4294967296 4294967296\n";
                args(&nrrd(d, "o.nrrd", fields, 0), &["--iso", "0"])
            },
            "are too large",
            1,
        ),
        (
            ".npy shape whose product overflows u64",
            |d| {
                let dict = "{'descr': '|u1', 'fortran_order': False, 'shape': (4294967296, 4294967296, 4294967296), }";
                args(&npy(d, "o.npy", dict, 0), &["--iso", "0"])
            },
            "too large",
            1,
        ),
        (
            "raw dims beyond the file",
            |d| {
                let rest = ["--dims", "100000,100000,100", "--dtype", "u8", "--iso", "0"];
                args(&file(d, "z.raw", &[0; 64]), &rest)
            },
            "z.raw: file has 64 bytes, dims 100000x100000x100 u8 need 1000000000000",
            1,
        ),
        (
            "raw dims with zero samples along y",
            |d| {
                let rest = ["--dims", "4,0,4", "--dtype", "u8", "--iso", "0"];
                args(&file(d, "z.raw", &[0; 64]), &rest)
            },
            "every dimension must be at least 1",
            2,
        ),
        (
            ".nrrd sizes with zero samples along y",
            |d| {
                let fields = "type: uchar\ndimension: 3\nsizes: 4 0 4\n";
                args(&nrrd(d, "z.nrrd", fields, 0), &["--iso", "0"])
            },
            "sizes 4x0x4 contain a zero",
            1,
        ),
        (
            ".npy shape with zero samples along z",
            |d| {
                let dict = "{'descr': '|u1', 'fortran_order': False, 'shape': (0, 4, 4), }";
                args(&npy(d, "z.npy", dict, 0), &["--iso", "0"])
            },
            "contain a zero",
            1,
        ),
        (
            ".npy with one sample along z",
            |d| args(&sphere_npy(d, "flat.npy", [5, 5, 1]), &["--iso", "0"]),
            "grid 5x5x1 has 1 sample along z; need at least 2 on every axis",
            1,
        ),
        (
            "raw with one sample along x",
            |d| {
                let rest = ["--dims", "1,4,4", "--dtype", "u8", "--iso", "0"];
                args(&file(d, "z.raw", &[0; 16]), &rest)
            },
            "grid 1x4x4 has 1 sample along x",
            1,
        ),
        (
            "raw with a negative spacing",
            |d| raw4(d, &["--spacing=-1,1,1", "--iso", "0"]),
            "spacing must be positive",
            2,
        ),
        (
            "raw with a negative spacing as its own argument",
            |d| raw4(d, &["--spacing", "-1,1,1", "--iso", "0"]),
            "spacing must be positive",
            2,
        ),
        (
            "raw with a NaN spacing",
            |d| raw4(d, &["--spacing", "nan,1,1", "--iso", "0"]),
            "'nan,1,1' is not three comma-separated finite numbers",
            2,
        ),
        (
            ".nrrd with a NaN spacing",
            |d| {
                let fields = "type: uchar\ndimension: 3\nsizes: 4 4 4\nspacings: nan 1 1\n";
                args(&nrrd(d, "s.nrrd", fields, 64), &["--iso", "0"])
            },
            "s.nrrd: 'spacings' NaN 1 1 must be finite and nonzero",
            1,
        ),
        (
            ".nrrd of an unknown type",
            |d| {
                let fields = "type: quad\ndimension: 3\nsizes: 4 4 4\n";
                args(&nrrd(d, "q.nrrd", fields, 512), &["--iso", "0"])
            },
            "type 'quad' is not supported",
            1,
        ),
        (
            ".npy of an unknown type",
            |d| {
                let dict = "{'descr': '<c8', 'fortran_order': False, 'shape': (4, 4, 4), }";
                args(&npy(d, "c.npy", dict, 512), &["--iso", "0"])
            },
            "<c8",
            1,
        ),
        (
            "isovalue above the data with --require-surface",
            |d| raw4(d, &["--iso", "5", "--require-surface"]),
            "no surface at isovalue 5: every sample of",
            1,
        ),
        (
            "an empty directory",
            |d| {
                let dir = d.join("empty");
                fs::create_dir(&dir).unwrap();
                args(&dir, &["--iso", "0"])
            },
            "empty: a directory is read as a TIFF stack (files ending in .tif or .tiff) or a DICOM series",
            1,
        ),
        (
            "a directory as raw input",
            |d| {
                let dir = d.join("dir.raw");
                fs::create_dir(&dir).unwrap();
                args(&dir, &["--dims", "4,4,4", "--dtype", "u8", "--iso", "0"])
            },
            "dir.raw: not a regular file",
            1,
        ),
        #[cfg(unix)]
        (
            "a FIFO as raw input",
            |d| {
                let rest = ["--dims", "4,4,4", "--dtype", "u8", "--iso", "0"];
                args(&fifo(d, "pipe.raw"), &rest)
            },
            "pipe.raw: is a FIFO (named pipe), not a regular file",
            1,
        ),
        #[cfg(unix)]
        (
            "a FIFO named .npy",
            |d| args(&fifo(d, "pipe.npy"), &["--iso", "0"]),
            "pipe.npy: is a FIFO",
            1,
        ),
        #[cfg(unix)]
        (
            "a FIFO without an extension (probed for DICOM magic)",
            |d| args(&fifo(d, "pipe"), &["--iso", "0"]),
            "pipe: is a FIFO",
            1,
        ),
        #[cfg(unix)]
        (
            "a FIFO as the data file of a detached NRRD header",
            |d| {
                fifo(d, "pipe.raw");
                let header = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: pipe.raw\n";
                args(&file(d, "vol.nhdr", header.as_bytes()), &["--iso", "0"])
            },
            "pipe.raw: is a FIFO (named pipe), not a regular file",
            1,
        ),
        #[cfg(unix)]
        (
            "a FIFO as the data file of a MetaImage header",
            |d| {
                fifo(d, "pipe.raw");
                let header = "ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\nElementDataFile = pipe.raw\n";
                args(&file(d, "vol.mhd", header.as_bytes()), &["--iso", "0"])
            },
            "pipe.raw: is a FIFO (named pipe), not a regular file",
            1,
        ),
        #[cfg(unix)]
        (
            "a character device",
            |_| {
                let rest = ["--dims", "4,4,4", "--dtype", "u8", "--iso", "0"];
                args(Path::new("/dev/zero"), &rest)
            },
            "/dev/zero: is a device",
            1,
        ),
        (
            "--max-memory below one thin slab per worker",
            |d| {
                let rest = ["--iso", "0", "--threads", "2", "--max-memory", "1M"];
                args(&sphere_npy(d, "ball.npy", [8, 8, 8]), &rest)
            },
            "--max-memory of 1048576 bytes (1.0 MiB) is too small: 2 workers",
            1,
        ),
        (
            "--max-memory that is not a byte count",
            |d| {
                args(
                    &sphere_npy(d, "ball.npy", [8, 8, 8]),
                    &["--iso", "0", "--max-memory", "4X"],
                )
            },
            "is not a byte count",
            2,
        ),
        (
            "raw data longer than the dims describe",
            |d| {
                let rest = ["--dims", "7,5,3", "--dtype", "u8", "--iso", "0"];
                args(&file(d, "long.raw", &[0; 140]), &rest)
            },
            "long.raw: file has 35 bytes more than dims 7x5x3 u8 need",
            1,
        ),
        (
            "raw options on a file that describes itself",
            |d| {
                let dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 2, 2), }";
                let rest = ["--dims", "4,2,1", "--dtype", "f32", "--iso", "0"];
                args(&npy(d, "self.npy", dict, 32), &rest)
            },
            "self.npy: NumPy data describe their own grid and samples",
            1,
        ),
        (
            "ascii .nrrd declaring far more samples than it holds",
            |d| {
                let text = "NRRD0004\ntype: short\ndimension: 3\n\
                            sizes: 3000 3000 3000\nencoding: ascii\n\n1 2 3\n";
                args(&file(d, "a.nrrd", text.as_bytes()), &["--iso", "0"])
            },
            "ascii data holds 3 values, 3000x3000x3000 i16 needs 27000000000",
            1,
        ),
        (
            "an absurd number of threads",
            |d| raw4(d, &["--iso", "0", "--threads", "100000"]),
            "100000 threads: at most 1024",
            2,
        ),
        (
            "a spacing that puts vertices beyond f32",
            |d| raw4(d, &["--iso", "0", "--spacing", "1e308,1,1"]),
            "lie beyond the range of 32-bit float coordinates",
            1,
        ),
        (
            "--part with an output that is not .tmesh",
            |d| raw4(d, &["--iso", "0", "--part", "1/2"]),
            "--part writes a part file for 'tmc merge', so the output must end in .tmesh",
            1,
        ),
        (
            "--report onto the input",
            |d| {
                let path = file(d, "in.raw", &[0; 64]);
                let report = s(&path).to_string();
                let rest = ["--dims", "4,4,4", "--dtype", "u8", "--iso", "0", "--report"];
                let mut all = args(&path, &rest);
                all.push(report);
                all
            },
            "the report is an input of the batch",
            1,
        ),
    ]
}

#[test]
fn bad_inputs_fail_with_one_line_and_leave_nothing() {
    for (name, setup, expected, code) in cases() {
        let dir = tempfile::tempdir().unwrap();
        let out_dir = dir.path().join("out");
        fs::create_dir(&out_dir).unwrap();
        let output = out_dir.join("mesh.ply");
        let mut argv = vec!["extract".to_string()];
        argv.extend(setup(dir.path()));
        argv.extend(["-o".to_string(), s(&output).to_string()]);
        let argv: Vec<&str> = argv.iter().map(String::as_str).collect();
        let out = tmc_within(&argv, 30);
        let line = assert_one_line(&out, code);
        assert!(
            line.contains(expected),
            "{name}: {line:?} lacks {expected:?}"
        );
        assert!(!output.exists(), "{name}: output written");
        assert!(
            names(&out_dir).is_empty(),
            "{name}: left {:?}",
            names(&out_dir)
        );
    }
}

#[test]
fn the_output_may_not_be_the_input() {
    let dir = tempfile::tempdir().unwrap();
    let bytes: Vec<u8> = (0..64u8).collect();
    let input = file(dir.path(), "vol.ply", &bytes);
    let raw = ["--dims", "4,4,4", "--dtype", "u8", "--iso", "10"];
    let symlink = dir.path().join("link.ply");
    let hard = dir.path().join("hard.ply");
    #[cfg(unix)]
    std::os::unix::fs::symlink(&input, &symlink).unwrap();
    fs::hard_link(&input, &hard).unwrap();
    let relative = dir.path().join(".").join("vol.ply");
    for output in [&input, &symlink, &hard, &relative] {
        if !output.exists() {
            continue;
        }
        let mut argv = vec!["extract", s(&input), "-o", s(output)];
        argv.extend(raw);
        let line = assert_one_line(&tmc(&argv), 1);
        assert!(
            line.contains("the output is the input file"),
            "{}: {line}",
            output.display()
        );
        assert_eq!(fs::read(&input).unwrap(), bytes, "input changed");
        assert!(temp_files(dir.path()).is_empty());
    }
    // Another name in the same directory is fine.
    let mut argv = vec!["extract", s(&input), "-o"];
    let other = dir.path().join("mesh.ply");
    argv.push(s(&other));
    argv.extend(raw);
    let out = tmc(&argv);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(other.is_file());
}

/// `tmc merge` may not write over one of its parts, nor `tmc convert` over
/// its input; the file is left as it was.
#[test]
fn merge_and_convert_do_not_write_over_their_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere_npy(dir.path(), "ball.npy", [8, 8, 8]);
    let part = |i: usize| dir.path().join(format!("p{i}.tmesh"));
    for i in 1..=2 {
        let (spec, out) = (format!("{i}/2"), part(i));
        let argv = [
            "extract",
            s(&input),
            "--iso",
            "0",
            "--part",
            &spec,
            "-o",
            s(&out),
        ];
        assert!(tmc(&argv).status.success());
    }
    let (p1, p2) = (part(1), part(2));
    let before = fs::read(&p1).unwrap();
    let line = assert_one_line(&tmc(&["merge", s(&p1), s(&p2), "-o", s(&p1)]), 1);
    assert!(line.contains("the output is the input file"), "{line}");
    let whole = dir.path().join("whole.tmesh");
    let argv = ["extract", s(&input), "--iso", "0", "-o", s(&whole)];
    assert!(tmc(&argv).status.success());
    let line = assert_one_line(&tmc(&["convert", s(&whole), "-o", s(&whole)]), 1);
    assert!(line.contains("the output is the input file"), "{line}");
    assert_eq!(fs::read(&p1).unwrap(), before);
    assert!(temp_files(dir.path()).is_empty());
}

#[test]
fn the_output_may_not_be_a_data_file_of_the_input() {
    let dir = tempfile::tempdir().unwrap();
    let bytes: Vec<u8> = (0..64u8).collect();
    let nhdr =
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: vol.raw\n";
    let mhd = "ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\nElementDataFile = vol.ply\n";
    // Decoded, not mapped, data files count too: gzip and ASCII.
    let gz = fs::read(data_dir().join("nrrd_detached_gz_u16.raw.gz")).unwrap();
    let gz_nhdr =
        "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 9 7 6\nendian: little\nencoding: gzip\ndata file: gz.stl\n";
    let text: String = (0..64).map(|i| format!("{i}\n")).collect();
    let ascii_nhdr =
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: ascii\ndata file: text.obj\n";
    for (header, text, data, bytes) in [
        ("vol.nhdr", nhdr, "vol.raw", &bytes),
        ("vol.mhd", mhd, "vol.ply", &bytes),
        ("gz.nhdr", gz_nhdr, "gz.stl", &gz),
        ("text.nhdr", ascii_nhdr, "text.obj", &text.into_bytes()),
    ] {
        let header = file(dir.path(), header, text.as_bytes());
        let data = file(dir.path(), data, bytes);
        let line = assert_one_line(
            &tmc(&["extract", s(&header), "--iso", "10", "-o", s(&data)]),
            1,
        );
        assert!(
            line.contains("the output is the input file") && line.contains(s(&data)),
            "{}: {line}",
            header.display()
        );
        assert_eq!(&fs::read(&data).unwrap(), bytes, "data file changed");
        assert!(temp_files(dir.path()).is_empty());
    }
}

#[test]
fn every_page_file_of_a_tiff_stack_is_a_data_file() {
    let dir = data_dir().join("vt_tiff_dir");
    let stack = tmc::volume::open(&dir, None).unwrap();
    let mut pages: Vec<_> = fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    pages.sort();
    let mut listed: Vec<_> = stack.data_files().iter().map(|p| p.to_path_buf()).collect();
    listed.sort();
    assert_eq!(listed, pages);
}

/// The vertex and face counts in the header of a binary PLY.
fn ply_counts(path: &Path) -> (u64, u64) {
    let bytes = fs::read(path).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    let count = |element: &str| -> u64 {
        let prefix = format!("element {element} ");
        let line = text.lines().find(|l| l.starts_with(&prefix)).unwrap();
        line[prefix.len()..].trim().parse().unwrap()
    };
    (count("vertex"), count("face"))
}

#[test]
fn an_isovalue_outside_the_data_writes_an_empty_mesh_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    // Samples 0..=63.
    let input = file(dir.path(), "ramp.raw", &(0..64u8).collect::<Vec<_>>());
    let raw = ["--dims", "4,4,4", "--dtype", "u8"];
    let run = |iso: &str, extra: &[&str], name: &str| {
        let output = dir.path().join(name);
        let mut argv = vec!["extract", s(&input), "-o", s(&output), "--iso", iso];
        argv.extend(raw);
        argv.extend(extra);
        (tmc(&argv), output)
    };
    for (iso, extra) in [
        ("63", &[][..]),
        ("1000", &[][..]),
        ("-5", &[][..]),
        ("1000", &["--close"][..]),
    ] {
        let (out, output) = run(iso, extra, "empty.ply");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{iso} {extra:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.starts_with(&format!(
                "tmc: note: no surface at isovalue {iso}: every sample of"
            )),
            "{stderr}"
        );
        assert!(stderr.contains("wrote an empty mesh"), "{stderr}");
        assert_eq!(ply_counts(&output), (0, 0), "{iso} {extra:?}");
        fs::remove_file(&output).unwrap();
    }
    // Below the data with --close, the closing caps are the surface: no note.
    let (out, output) = run("-5", &["--close", "--require-surface"], "box.ply");
    assert_eq!(out.status.code(), Some(0));
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(ply_counts(&output).1 > 0);
    // --quiet drops the note, not the empty mesh.
    let (out, output) = run("1000", &["--quiet"], "quiet.ply");
    assert_eq!(out.status.code(), Some(0));
    assert!(out.stderr.is_empty());
    assert_eq!(ply_counts(&output), (0, 0));
    // --require-surface: an error and no file, in every format.
    for name in ["none.ply", "none.tmesh", "none.stl", "none.obj", "none.off"] {
        let (out, output) = run("1000", &["--require-surface"], name);
        let line = assert_one_line(&out, 1);
        assert!(
            line.contains("nothing written (--require-surface)"),
            "{line}"
        );
        assert!(!output.exists(), "{name}");
    }
    assert!(temp_files(dir.path()).is_empty());
}

#[test]
fn check_fails_on_a_mesh_that_is_not_a_manifold() {
    let dir = tempfile::tempdir().unwrap();
    // Three triangles on the edge 0-1: a non-manifold edge.
    let fin = file(
        dir.path(),
        "fin.off",
        b"OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n",
    );
    // Two triangles that traverse their shared edge the same way.
    let flipped = file(
        dir.path(),
        "flipped.off",
        b"OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n3 0 1 2\n3 0 1 3\n",
    );
    // One triangle: an open surface, but a manifold.
    let open = file(
        dir.path(),
        "open.off",
        b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    );
    for (mesh, expected) in [
        (
            &fin,
            "fin.off: not a consistently oriented manifold: 1 non-manifold edges",
        ),
        (
            &flipped,
            "flipped.off: not a consistently oriented manifold: 1 inconsistently oriented edges",
        ),
    ] {
        let out = tmc(&["check", s(mesh)]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.starts_with("tmc: error: "), "{stderr}");
        assert!(stderr.contains(expected), "{stderr}");
        // The report is still printed.
        assert!(String::from_utf8_lossy(&out.stdout).contains("non-manifold edges"));
    }
    let out = tmc(&["check", s(&open)]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(out.stderr.is_empty());
}

/// `tmc check` on a PLY, OBJ or OFF file without triangles (none declared,
/// an empty file, vertices only) says so: the verdict reads `yes (empty)`
/// and a note on stderr gives the counts; exit 0, or 1 with
/// `--require-surface` (after the report). A mesh with triangles is not
/// affected by the option.
#[test]
fn check_says_plainly_that_a_mesh_is_empty() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let ply = b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
                property float z\nelement face 0\nproperty list uchar int vertex_indices\n\
                end_header\n";
    let empty = [
        (file(d, "none.off", b"OFF\n0 0 0\n"), 0),
        (file(d, "none.ply", ply), 0),
        (file(d, "none.obj", b""), 0),
        (
            file(d, "points.off", b"OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"),
            3,
        ),
    ];
    for (mesh, vertices) in &empty {
        let note = format!(
            "tmc: note: {}: the mesh is empty ({vertices} vertices, 0 triangles)",
            s(mesh)
        );
        for json in [false, true] {
            let args = if json {
                vec!["check", s(mesh), "--json"]
            } else {
                vec!["check", s(mesh)]
            };
            let out = tmc(&args);
            let (stdout, stderr) = (
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr),
            );
            assert_eq!(out.status.code(), Some(0), "{args:?}: {stderr}");
            assert_eq!(stderr.lines().count(), 1, "{stderr}");
            assert!(stderr.starts_with(&note), "{stderr}");
            if json {
                assert!(stdout.contains("\"triangles\":0,"), "{stdout}");
            } else {
                assert!(verdict(&stdout, " yes (empty)"), "{stdout}");
            }
        }
        let out = tmc(&["check", s(mesh), "--require-surface"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        let error = note.replace("note", "error");
        assert!(stderr.starts_with(&error), "{stderr}");
        assert!(stderr.contains("--require-surface"), "{stderr}");
        assert!(!out.stdout.is_empty(), "no report");
    }
    let open = file(d, "open.off", b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    let out = tmc(&["check", s(&open), "--require-surface"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(out.stderr.is_empty(), "{out:?}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(verdict(&stdout, " no"), "{stdout}");
}

/// Whether the text report `stdout` has the verdict line ending in `end`.
fn verdict(stdout: &str, end: &str) -> bool {
    stdout
        .lines()
        .any(|l| l.starts_with("closed manifold ") && l.ends_with(end))
}

/// A FIFO as the `.tmesh` input of `convert`, `merge` or `check` is refused
/// with one line (a `.tmesh` is read by seeking; opening a FIFO would wait
/// for a writer, past SIGINT and SIGTERM).
#[cfg(unix)]
#[test]
fn a_fifo_mesh_input_is_refused() {
    use common::cli::{assert_one_line, s, tmc};
    let dir = tempfile::tempdir().unwrap();
    let pipe = fifo(dir.path(), "pipe.tmesh");
    let out = dir.path().join("out.ply");
    for args in [
        vec!["convert", s(&pipe), "-o", s(&out)],
        vec!["merge", s(&pipe), "-o", s(&out)],
        vec!["check", s(&pipe)],
    ] {
        let line = assert_one_line(&tmc(&args), 1);
        assert!(
            line.contains("pipe.tmesh: is a FIFO (named pipe), not a regular file"),
            "{args:?}: {line}"
        );
        assert!(!out.exists());
    }
}
