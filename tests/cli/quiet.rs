//! `-q/--quiet` on every subcommand that may write to stderr (batch
//! scripts pass it to all of them): nothing on stderr but errors, the
//! report on stdout all the same.

use crate::common;

use common::cli::{s, synth, tmc, uniform_npy};

/// Runs `tmc ARGS`, asserting success and nothing on stderr; returns
/// stdout.
fn quiet(args: &[&str]) -> Vec<u8> {
    let out = tmc(args);
    assert!(out.status.success(), "{args:?}: {out:?}");
    assert!(out.stderr.is_empty(), "{args:?}: {out:?}");
    out.stdout
}

#[test]
fn every_subcommand_takes_quiet_and_keeps_its_report() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let volume = synth(d, "sphere", "12,12,12", "f32", "v.nrrd");
    // A note without -q (the spacing overrides the file's), none with it.
    let info = ["info", s(&volume), "--spacing", "2,2,2"];
    assert!(!tmc(&info).stderr.is_empty());
    for q in ["-q", "--quiet"] {
        let mut args = info.to_vec();
        args.push(q);
        assert!(String::from_utf8(quiet(&args)).unwrap().contains("spacing"));
    }
    let mesh = d.join("m.tmesh");
    quiet(&["extract", s(&volume), "--iso", "0", "-o", s(&mesh), "-q"]);
    quiet(&["convert", s(&mesh), "-o", s(&d.join("m.ply")), "-q"]);
    assert!(!quiet(&["check", s(&d.join("m.ply")), "-q"]).is_empty());
    let parts: Vec<_> = (1..=2).map(|i| d.join(format!("p{i}.tmesh"))).collect();
    for (i, part) in parts.iter().enumerate() {
        let spec = format!("{}/2", i + 1);
        let args = ["extract", s(&volume), "--iso", "0", "--part", &spec];
        quiet(&[&args[..], &["-o", s(part), "-q"]].concat());
    }
    let merged = d.join("merged.ply");
    quiet(&[
        "merge",
        s(&parts[0]),
        s(&parts[1]),
        "-o",
        s(&merged),
        "--quiet",
    ]);
    assert_eq!(
        std::fs::read(&merged).unwrap(),
        std::fs::read(d.join("m.ply")).unwrap()
    );
}

/// `tmc check` of an empty mesh: a note on stderr, which -q drops; the
/// report is on stdout either way.
#[test]
fn check_quiet_drops_the_note_on_an_empty_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let volume = uniform_npy(dir.path(), [4, 4, 4]);
    let mesh = dir.path().join("empty.ply");
    quiet(&["extract", s(&volume), "--iso", "1e6", "-o", s(&mesh), "-q"]);
    let loud = tmc(&["check", s(&mesh)]);
    assert!(loud.status.success() && !loud.stderr.is_empty(), "{loud:?}");
    assert_eq!(quiet(&["check", s(&mesh), "-q"]), loud.stdout);
}

/// A NIfTI whose `pixdim[1]` is 0 reads with spacing 1 there (as nibabel
/// reads it), saying so in a note on stderr that -q drops; the mesh is
/// the same either way.
#[test]
fn zero_pixdim_is_read_as_one_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut bytes = std::fs::read(common::formats::data_dir().join("nifti1_u8.nii")).unwrap();
    bytes[252..256].copy_from_slice(&[0; 4]); // qform_code = sform_code = 0
    bytes[80..84].copy_from_slice(&0.0f32.to_le_bytes()); // pixdim[1] = 0
    let input = d.join("flat.nii");
    std::fs::write(&input, bytes).unwrap();
    let (loud, quiet_mesh) = (d.join("loud.ply"), d.join("quiet.ply"));
    let out = tmc(&["extract", s(&input), "--iso", "128", "-o", s(&loud)]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.starts_with("tmc: note: ") && stderr.contains("pixdim[1] = 0"),
        "{stderr}"
    );
    quiet(&[
        "extract",
        s(&input),
        "--iso",
        "128",
        "-o",
        s(&quiet_mesh),
        "-q",
    ]);
    assert_eq!(
        std::fs::read(&loud).unwrap(),
        std::fs::read(&quiet_mesh).unwrap()
    );
    let info = String::from_utf8(quiet(&["info", s(&input), "-q"])).unwrap();
    assert!(info.contains("spacing"), "{info}");
}

/// `tmc --help` describes extract by its own words, not by those of the
/// raw-input options it shares with info.
#[test]
fn help_describes_extract() {
    let out = tmc(&["--help"]);
    let text = String::from_utf8(out.stdout).unwrap();
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("extract "))
        .expect("an extract line");
    assert!(line.contains("isosurface"), "{line}");
}
