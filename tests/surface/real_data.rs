//! The real volumes of `../shared/data` (CT, MRI, simulations, labels, a
//! signed distance field) at the isovalues its README lists: closed, oriented
//! 2-manifolds with `--close`; on the smaller integer volumes, the exact
//! topology of the oracle; on every CT at its integer isovalues (ties), no
//! zero-area triangle and no two vertices at one position. Skipped, with a
//! message, when the folder is absent.

use crate::common;

use common::{compare_with_oracle, oracle};
use std::path::PathBuf;
use tmc::check::check_mesh;
use tmc::{extract, ExtractParams, Inside};

/// (file, isovalues, inside) from `../shared/data/README.md`.
const VOLUMES: &[(&str, &[f64], Inside)] = &[
    ("cthead.nrrd", &[550.0, 1600.0], Inside::High),
    ("headsq_quarter.nrrd", &[500.0, 1150.0], Inside::High),
    ("engine.nrrd", &[80.0, 180.0], Inside::High),
    ("bonsai.nrrd", &[40.0, 100.0], Inside::High),
    ("stent_ct.nrrd", &[600.0, 1500.0], Inside::High),
    ("lidc_chest_ct.nrrd", &[36.0, 114.0], Inside::High),
    ("mni152_2009a_gm.nrrd", &[128.0], Inside::High),
    ("hydrogen.nrrd", &[0.1, 0.01], Inside::High),
    ("neghip.nrrd", &[60.0, 120.0], Inside::High),
    ("fuel.nrrd", &[30.0, 100.0], Inside::High),
    ("carotid.nrrd", &[100.0, 150.0], Inside::High),
    ("bolt.nrrd", &[127.5], Inside::High),
    ("frog_tissues.nrrd", &[0.5], Inside::High),
    ("sdf_bunny_128.nrrd", &[0.0], Inside::Low),
    ("mayavi_heart.nrrd", &[100.0], Inside::High),
    ("ironprot.nrrd", &[64.0, 128.0], Inside::High),
];

fn data_dir() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("skipped: {} not found", dir.display());
        None
    }
}

#[test]
fn real_volumes_give_closed_manifolds() {
    let Some(dir) = data_dir() else { return };
    for (file, isos, inside) in VOLUMES {
        let vol = tmc::volume::open(&dir.join(file), None).expect(file);
        for &iso in *isos {
            let params = ExtractParams {
                iso,
                inside: *inside,
                close: true,
                ..Default::default()
            };
            let (mesh, stats) = extract(vol.as_ref(), &params).expect(file);
            let report = check_mesh(&mesh);
            assert!(report.is_closed_manifold(), "{file} at {iso}: {report:?}");
            assert!(
                report.geometry.is_sound(),
                "{file} at {iso}: {}",
                report.geometry.defects()
            );
            assert!(
                stats.triangles > 1000,
                "{file} at {iso}: {} triangles",
                stats.triangles
            );
            eprintln!(
                "{file} iso {iso}: {} triangles, {} components, euler {}, {} tunnels",
                stats.triangles, report.components, report.euler, stats.tunnels
            );
        }
    }
}

/// The oracle needs integer (or half-integer) samples: every integer volume.
#[test]
fn small_integer_volumes_match_the_oracle() {
    let Some(dir) = data_dir() else { return };
    for (file, isos) in [
        ("headsq_quarter.nrrd", &[500.0, 1150.0][..]),
        ("neghip.nrrd", &[60.0, 120.0]),
        ("fuel.nrrd", &[30.0, 100.0]),
        ("bolt.nrrd", &[127.5]),
        ("ironprot.nrrd", &[64.0, 128.0]),
        ("cthead.nrrd", &[550.0, 1600.0]),
        ("engine.nrrd", &[80.0]),
        ("bonsai.nrrd", &[40.0]),
        ("frog_tissues.nrrd", &[0.5]),
        ("stent_ct.nrrd", &[600.0]),
    ] {
        let vol = tmc::volume::open(&dir.join(file), None).expect(file);
        let grid = *vol.grid();
        let mut values = vec![0.0; grid.dims.iter().product()];
        for (z, plane) in values.chunks_mut(grid.plane_len()).enumerate() {
            vol.read_plane(z, plane).expect("plane");
        }
        for &iso in isos {
            let params = ExtractParams {
                iso,
                close: true,
                ..Default::default()
            };
            let (mesh, _) = extract(vol.as_ref(), &params).expect(file);
            let report = check_mesh(&mesh);
            let (dims, g) = oracle::padded(grid.dims, &oracle::scaled(&values, iso), 1, 0);
            let topo = oracle::topology(dims, &g);
            compare_with_oracle(&report, &topo).unwrap_or_else(|e| panic!("{file} at {iso}: {e}"));
        }
    }
}

/// The CTs at their integer isovalues: integer samples equal to the
/// isovalue (ties: 21 to 71,270 samples per volume), and the padding of
/// `--close`, which is a tie too. Every mesh, either side inside, opened or
/// closed, has no zero-area triangle and no two vertices at one position
/// (counted in the f32 coordinates by `tmc::check`), and stays a manifold.
#[test]
fn cts_at_integer_isovalues_have_no_zero_area_triangles() {
    let Some(dir) = data_dir() else { return };
    let mut ties = 0;
    for (file, isos, _) in &VOLUMES[..6] {
        let vol = tmc::volume::open(&dir.join(file), None).expect(file);
        let grid = *vol.grid();
        let mut plane = vec![0.0; grid.plane_len()];
        for z in 0..grid.dims[2] {
            vol.read_plane(z, &mut plane).expect("plane");
            ties += plane.iter().filter(|v| isos.contains(v)).count();
        }
        for &iso in *isos {
            assert_eq!(iso, iso.round(), "{file}: an integer isovalue");
            for (inside, close) in [
                (Inside::High, false),
                (Inside::High, true),
                (Inside::Low, false),
            ] {
                let params = ExtractParams {
                    iso,
                    inside,
                    close,
                    ..Default::default()
                };
                let (mesh, _) = extract(vol.as_ref(), &params).expect(file);
                let report = check_mesh(&mesh);
                let case = format!("{file} at {iso} ({inside:?}, close {close})");
                assert!(report.is_oriented_manifold(), "{case}: {report:?}");
                assert!(
                    report.geometry.is_sound(),
                    "{case}: {}",
                    report.geometry.defects()
                );
            }
        }
    }
    assert!(ties > 90_000, "only {ties} samples at the isovalues");
}
