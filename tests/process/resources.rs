//! Running out of resources: a full disk is one clean error with nothing
//! left behind, `--max-memory` bounds the pipeline without changing the
//! output (its refusal when too small is a row of `bad_inputs.rs`), and
//! `--labels --json` counts each label's figures without holding its mesh,
//! and `tmc check` checks a `.tmesh` file without holding its mesh.

use crate::common;

use common::cli::{assert_one_line, json_number, names, s, synth, tmc};
use std::fs;
use std::path::Path;
use std::process::Command;

/// A small tmpfs mounted on a directory, unmounted when dropped (also
/// when the test fails).
struct SmallDisk {
    dir: tempfile::TempDir,
}

impl SmallDisk {
    /// Mounts a tmpfs of `size` (e.g. `1m`), or `None` if this process may
    /// not mount (not root, or in a container without the capability).
    fn mount(size: &str) -> Option<SmallDisk> {
        let dir = tempfile::tempdir().unwrap();
        let status = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
            .arg(dir.path())
            .stderr(std::process::Stdio::null())
            .status()
            .ok()?;
        status.success().then_some(SmallDisk { dir })
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }
}

impl Drop for SmallDisk {
    fn drop(&mut self) {
        let unmounted = Command::new("umount")
            .arg(self.dir.path())
            .status()
            .is_ok_and(|s| s.success());
        if !unmounted {
            eprintln!("could not unmount {}", self.dir.path().display());
        }
    }
}

#[test]
fn a_full_disk_is_one_clean_error_with_nothing_left() {
    let _cores = crate::CORES.read().unwrap_or_else(|e| e.into_inner());
    let Some(disk) = SmallDisk::mount("1m") else {
        println!("skipped: cannot mount a tmpfs here (needs root)");
        return;
    };
    let work = tempfile::tempdir().unwrap();
    // Dense noise: a mesh of over 1 MiB in every format, .tmesh included
    // (2.0 MB: version 3 packs 96^3's to 0.88 MB, which fit on the disk).
    let input = synth(work.path(), "noise", "128,128,128", "f32", "noise.npy");
    for name in ["mesh.ply", "mesh.obj", "mesh.off", "mesh.stl", "mesh.tmesh"] {
        let output = disk.path().join(name);
        let out = tmc(&["extract", s(&input), "--iso", "0", "-o", s(&output)]);
        let line = assert_one_line(&out, 1);
        assert!(
            line.contains(name) && line.contains("No space left on device"),
            "{line}"
        );
        assert!(
            names(disk.path()).is_empty(),
            "{name}: left {:?}",
            names(disk.path())
        );
    }
    // The same mesh fits elsewhere: the failure was the disk.
    let output = work.path().join("mesh.tmesh");
    let out = tmc(&["extract", s(&input), "--iso", "0", "-o", s(&output)]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(fs::metadata(&output).unwrap().len() > 1 << 20);
}

/// The `"slabs"` figure of `--json` output.
fn slabs(json: &[u8]) -> u64 {
    let text = String::from_utf8_lossy(json);
    let at = text.find("\"slabs\":").expect("slabs in JSON") + "\"slabs\":".len();
    let digits: String = text[at..]
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    digits.parse().unwrap()
}

#[test]
fn max_memory_thins_the_slabs_and_keeps_the_output() {
    let _cores = crate::CORES.read().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let input = synth(dir.path(), "gyroid", "200,200,100", "f32", "gyroid.npy");
    let run = |name: &str, extra: &[&str]| {
        let output = dir.path().join(name);
        let mut argv = vec!["extract", s(&input), "--iso", "0", "-o", s(&output)];
        argv.extend(["--json", "--threads", "2"]);
        argv.extend(extra);
        let out = tmc(&argv);
        assert_eq!(out.status.code(), Some(0), "{extra:?}: {out:?}");
        (fs::read(&output).unwrap(), slabs(&out.stdout))
    };
    let (free, free_slabs) = run("free.ply", &[]);
    // 20 MiB: 16 MiB of buffers, two workers on 200x200 planes, and slabs
    // of 4 layers instead of 8 (99 layers, the thinnest default slabs).
    let (bounded, bounded_slabs) = run("bounded.ply", &["--max-memory", "20M"]);
    assert_eq!(free_slabs, 13);
    assert!(bounded_slabs > free_slabs, "{bounded_slabs} slabs");
    assert!(free == bounded, "--max-memory changed the output");
    let (roomy, roomy_slabs) = run("roomy.ply", &["--max-memory", "4G"]);
    assert_eq!(roomy_slabs, free_slabs);
    assert!(roomy == free);
}

#[test]
fn max_memory_holds_on_the_densest_surface() {
    let _cores = crate::CORES.read().unwrap_or_else(|e| e.into_inner());
    // Uniform random samples: about 3.8 triangles a cell, some 25 times
    // what the budget's first estimate of a slab's mesh assumed.
    let dir = tempfile::tempdir().unwrap();
    let input = common::cli::uniform_npy(dir.path(), [256, 256, 48]);
    let run = |name: &str, extra: &[&str]| {
        let output = dir.path().join(name);
        let mut argv = vec!["extract", s(&input), "--iso", "0.5", "-o", s(&output)];
        argv.extend(["--json", "-q", "--threads", "2"]);
        argv.extend(extra);
        let out = tmc(&argv);
        assert_eq!(out.status.code(), Some(0), "{extra:?}: {out:?}");
        (fs::read(&output).unwrap(), out.stdout)
    };
    let (free, free_json) = run("free.tmesh", &[]);
    let (bounded, bounded_json) = run("bounded.tmesh", &["--max-memory", "48M"]);
    assert!(free == bounded, "--max-memory changed the output");
    let peak = json_number(&bounded_json, "peak_rss_anon_bytes");
    let free_peak = json_number(&free_json, "peak_rss_anon_bytes");
    assert!(
        peak <= 48.0 * (1 << 20) as f64,
        "peak {peak} bytes beyond --max-memory 48M (without it: {free_peak})"
    );
}

/// The peak resident memory of `tmc args` in bytes, from `/usr/bin/time
/// -f %M` (`None` where there is no such program).
fn peak_rss(args: &[&str]) -> Option<f64> {
    let time = Path::new("/usr/bin/time");
    if !time.exists() {
        return None;
    }
    let out = Command::new(time)
        .args(["-f", "peak %M"])
        .arg(common::cli::tmc_path())
        .args(args)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{args:?}: {out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    let kib: f64 = err.lines().last()?.strip_prefix("peak ")?.parse().ok()?;
    Some(kib * 1024.0)
}

#[test]
fn label_stats_hold_no_label_mesh() {
    let _cores = crate::CORES.read().unwrap_or_else(|e| e.into_inner());
    // Three labels at random: about 2.5 triangles a voxel each, some
    // 100 MiB of meshes in all, over a pipeline held to 48 MiB.
    use rand::{Rng, SeedableRng};
    let dir = tempfile::tempdir().unwrap();
    let dims = [128, 128, 48];
    let mut rng = rand_pcg::Pcg64::seed_from_u64(5);
    let values = (0..dims.iter().product::<usize>())
        .map(|_| f64::from(rng.gen_range(1..4u8)))
        .collect();
    let input = dir.path().join("labels.nrrd");
    common::labels::write(&input, dims, values, tmc::volume::ScalarType::U16);
    let out = dir.path().join("{label}.tmesh");
    let args = |extra: &'static str| {
        let mut a = vec!["extract", s(&input), "--labels", "all", "-o", s(&out)];
        a.extend(["-q", "--threads", "2", "--max-memory", "48M", extra]);
        a.retain(|a| !a.is_empty());
        a
    };
    let Some(plain) = peak_rss(&args("")) else {
        println!("skipped: no /usr/bin/time here");
        return;
    };
    let with_stats = peak_rss(&args("--json")).unwrap();
    let json = common::labels::ok(&args("--json"));
    let json: serde_json::Value = serde_json::from_slice(&json).unwrap();
    // The labels' meshes as a MeshBuilder holds them: 12 bytes a vertex
    // and a triangle.
    let meshes: f64 = json["labels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| 12.0 * (r["triangles"].as_f64().unwrap() + r["vertices"].as_f64().unwrap()))
        .sum();
    assert!(meshes > 80.0 * (1 << 20) as f64, "meshes of {meshes} bytes");
    assert!(
        with_stats < plain + meshes / 3.0,
        "--json peaks at {with_stats} bytes, {plain} without it, for {meshes} bytes of meshes"
    );
}

#[test]
fn check_streams_a_tmesh_without_holding_it() {
    let _cores = crate::CORES.read().unwrap_or_else(|e| e.into_inner());
    // A gyroid of some 2.5 million triangles: about 45 MiB as a mesh in
    // memory (12 bytes a vertex and a triangle), more than twice that for
    // the in-memory checker; `tmc check` streams the file's chunks.
    let dir = tempfile::tempdir().unwrap();
    let volume = synth(dir.path(), "gyroid", "256,256,256", "u8", "g.nrrd");
    let mesh = dir.path().join("g.tmesh");
    let out = tmc(&["extract", s(&volume), "--iso", "128", "-o", s(&mesh), "-q"]);
    assert!(out.status.success(), "{out:?}");
    fs::remove_file(&volume).unwrap();
    let Some(streamed) = peak_rss(&["check", s(&mesh)]) else {
        println!("skipped: no /usr/bin/time here");
        return;
    };
    let whole = peak_rss(&["check", s(&mesh), "--in-memory"]).unwrap();
    let json = tmc(&["check", s(&mesh), "--json"]);
    let bytes =
        12.0 * (json_number(&json.stdout, "vertices") + json_number(&json.stdout, "triangles"));
    assert!(bytes > 40.0 * (1 << 20) as f64, "a mesh of {bytes} bytes");
    // The in-memory check holds the mesh (so the bound below can fail).
    assert!(
        whole > bytes,
        "--in-memory peaks at {whole} bytes, for {bytes} bytes of mesh"
    );
    assert!(
        streamed < bytes / 2.0,
        "the streamed check peaks at {streamed} bytes, for {bytes} bytes of mesh ({whole} in memory)"
    );
}
