//! `plane_runs` and `scan_labels` (the label maps' first reading and the
//! codes of `--labels`) on every sample type, lent at any alignment or
//! read: the runs and counts of values a direct reading of the samples
//! gives.

use super::readers::raw_volume;
use std::collections::BTreeMap;
use tmc::volume::{plane_runs, scan_labels, Endian, ScalarType};
use tmc::SampleSource;

/// The label of sample `(x, y, z)`: runs of two to five equal values along
/// x, whole numbers from 0 to 21 (every type holds them).
fn label([x, y, z]: [usize; 3]) -> f64 {
    (((x / 2 + y + 2 * z) % 4) * 7) as f64
}

#[test]
fn runs_and_counts_match_the_samples_for_every_type_and_alignment() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [11usize, 6, 4];
    let mut want_counts: BTreeMap<i64, u64> = BTreeMap::new();
    let mut want_runs = Vec::new();
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            let row: Vec<f64> = (0..dims[0]).map(|x| label([x, y, z])).collect();
            let mut x = 0;
            while x < dims[0] {
                let end = (x..dims[0]).find(|&e| row[e] != row[x]).unwrap_or(dims[0]);
                want_runs.push((z, y, x, end, row[x]));
                *want_counts.entry(row[x] as i64).or_default() += (end - x) as u64;
                x = end;
            }
        }
    }
    let want_counts: Vec<(i64, u64)> = want_counts.into_iter().collect();
    for scalar in ScalarType::ALL {
        // Aligned and misaligned native planes (the latter lent as byte
        // arrays for 16- and 32-bit samples), and foreign ones (swapped).
        for (header, endian) in [
            (0u64, Endian::native()),
            (1, Endian::native()),
            (3, Endian::native()),
            (1, Endian::Big),
        ] {
            let name = format!("labels-{scalar:?}-{header}-{endian:?}.raw");
            let at =
                |i: usize| label([i % dims[0], i / dims[0] % dims[1], i / (dims[0] * dims[1])]);
            let raw = raw_volume(dir.path(), &name, (dims, scalar, endian, header), at);
            let what = format!("{scalar:?} header {header} {endian:?}");
            // Every plane is lent: native ones at any alignment (misaligned
            // as byte arrays), foreign ones swapped as they are read.
            assert!(raw.lend_plane(0).is_some(), "{what}: lends its planes");
            let mut runs = Vec::new();
            let mut buffer = Vec::new();
            for z in 0..dims[2] {
                plane_runs(&raw, z, &mut buffer, |y, x, end, v| {
                    runs.push((z, y, x, end, v));
                    Ok(())
                })
                .unwrap();
            }
            assert_eq!(runs, want_runs, "{what}: runs");
            let counts = scan_labels(&raw, None).unwrap();
            assert_eq!(counts.counts, want_counts, "{what}: counts");
        }
    }
}
