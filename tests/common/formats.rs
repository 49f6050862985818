//! Helpers of the reader tests (`tests/formats/`): the fixture
//! directory, the manifests written with the fixtures, reading every sample
//! of a source, and small numeric and error checks.

use std::fs;
use std::path::{Path, PathBuf};
use tmc::volume;
use tmc::SampleSource;

/// `tests/data` of this crate.
pub fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

/// One fixture of a manifest (`tests/data/*_manifest.json`).
pub struct Fixture {
    pub name: String,
    pub file: PathBuf,
    pub dims: [usize; 3],
    pub spacing: [f64; 3],
    pub origin: [f64; 3],
    pub direction: [[f64; 3]; 3],
    /// How many files hold the data (1 where the manifest does not say).
    pub files: usize,
}

fn vec3(v: &serde_json::Value) -> [f64; 3] {
    let a = v.as_array().expect("array");
    [0, 1, 2].map(|i| a[i].as_f64().expect("number"))
}

/// The fixtures listed by `tests/data/<manifest>`.
pub fn fixtures(manifest: &str) -> Vec<Fixture> {
    let text = fs::read_to_string(data_dir().join(manifest)).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    json.as_array()
        .unwrap()
        .iter()
        .map(|f| {
            let d = f["direction"].as_array().unwrap();
            Fixture {
                name: f["name"].as_str().unwrap().to_string(),
                file: data_dir().join(f["file"].as_str().unwrap()),
                dims: vec3(&f["dims"]).map(|x| x as usize),
                spacing: vec3(&f["spacing"]),
                origin: vec3(&f["origin"]),
                direction: [vec3(&d[0]), vec3(&d[1]), vec3(&d[2])],
                files: f["files"].as_u64().map_or(1, |n| n as usize),
            }
        })
        .collect()
}

/// All planes, read in the order `order` and stored at their own place.
pub fn samples_in_order(source: &dyn SampleSource, order: &[usize]) -> Vec<f64> {
    let grid = *source.grid();
    let n = grid.plane_len();
    let mut out = vec![0.0; n * grid.dims[2]];
    for &z in order {
        source.read_plane(z, &mut out[z * n..(z + 1) * n]).unwrap();
    }
    out
}

/// All samples, plane by plane from z = 0.
pub fn all_samples(source: &dyn SampleSource) -> Vec<f64> {
    let order: Vec<usize> = (0..source.grid().dims[2]).collect();
    samples_in_order(source, &order)
}

/// `a` and `b` agree to the relative tolerance `tol` (absolute below 1).
pub fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * a.abs().max(b.abs()).max(1.0)
}

/// The determinant of a 3x3 matrix given by rows.
pub fn det(d: &[[f64; 3]; 3]) -> f64 {
    d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
        - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
        + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0])
}

/// The error of opening `path`, checked to be one line.
pub fn open_err(path: &Path) -> String {
    let e = match volume::open(path, None) {
        Ok(v) => panic!("{} opened: {:?}", path.display(), v.grid()),
        Err(e) => e.to_string(),
    };
    assert!(!e.contains('\n'), "multi-line error: {e}");
    e
}

/// Checks the geometry of `grid` against the fixture `f`: dims exactly,
/// spacing and origin to the relative tolerance `tol`, direction cosines to
/// the absolute tolerance `dir_tol` (NIfTI quaternions give about 1e-7).
pub fn check_grid(grid: &tmc::volume::Grid, f: &Fixture, tol: f64, dir_tol: f64) {
    let name = &f.name;
    assert_eq!(grid.dims, f.dims, "{name}");
    for i in 0..3 {
        assert!(
            close(grid.spacing[i], f.spacing[i], tol),
            "{name}: {grid:?}"
        );
        assert!(close(grid.origin[i], f.origin[i], tol), "{name}: {grid:?}");
        for j in 0..3 {
            assert!(
                (grid.direction[i][j] - f.direction[i][j]).abs() < dir_tol,
                "{name}: {:?} vs {:?}",
                grid.direction,
                f.direction
            );
        }
    }
}
