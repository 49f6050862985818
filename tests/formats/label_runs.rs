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
            // The types read as f64 are not lent.
            assert_eq!(
                raw.lend_plane(0).is_some(),
                scalar.is_lent(),
                "{what}: lends its planes"
            );
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

/// `scan_labels_on` at any number of threads: the counts a direct reading
/// gives (small, negative and large values), and of two samples that are not whole numbers in different
/// threads' planes, the first in the file's order named (whichever thread
/// finds its own first).
#[test]
fn scan_on_threads_counts_and_names_the_first_fraction() {
    use tmc::volume::scan_labels_on;
    let dir = tempfile::tempdir().unwrap();
    let dims = [7usize, 5, 12];
    let xyz = |i: usize| [i % dims[0], i / dims[0] % dims[1], i / (dims[0] * dims[1])];
    // Beside the small labels, values the scan keeps apart from its
    // array of 0 to 65535: negative ones and ones from 65536 up.
    // And two values that end early (one in the array, one not), so that
    // their last planes are in the first threads' planes.
    let whole = |i: usize| match (i % 13, xyz(i)) {
        (_, [0, 0, z]) if z <= 3 => 500.0,
        (_, [6, 4, z]) if z <= 6 => 80000.0,
        (0, _) => -3.0,
        (5, _) => 65536.0,
        (7, _) => 70001.0,
        (9, _) => 65535.0,
        _ => label(xyz(i)),
    };
    let mut want: BTreeMap<i64, (u64, usize)> = BTreeMap::new();
    for i in 0..dims.iter().product::<usize>() {
        let entry = want.entry(whole(i) as i64).or_default();
        *entry = (entry.0 + 1, xyz(i)[2]);
    }
    let want_last: Vec<usize> = want.values().map(|&(_, z)| z).collect();
    assert_eq!(want[&500].1, 3);
    assert_eq!(want[&80000].1, 6);
    let want: Vec<(i64, u64)> = want.iter().map(|(&v, &(n, _))| (v, n)).collect();
    let raw = raw_volume(
        dir.path(),
        "whole.raw",
        (dims, ScalarType::F32, Endian::native(), 0),
        whole,
    );
    // Fractions at (1, 1, 4) and (3, 2, 9): in the planes of two threads
    // (of three: planes 4-7 and 8-11; of two: 0-5 and 6-11), whichever
    // comes to its own first.
    let broken = |i: usize| match xyz(i) {
        [1, 1, 4] => 0.25,
        [3, 2, 9] => 2.5,
        _ => whole(i),
    };
    let bad = raw_volume(
        dir.path(),
        "fractions.raw",
        (dims, ScalarType::F32, Endian::native(), 0),
        broken,
    );
    for threads in [0, 1, 2, 3, 5, 12, 40] {
        let counts = scan_labels_on(&raw, None, threads).unwrap();
        assert_eq!(counts.counts, want, "{threads} threads: counts");
        assert_eq!(
            counts.last_planes, want_last,
            "{threads} threads: last planes"
        );
        assert_eq!(counts.last_plane(80000), Some(6));
        assert_eq!(counts.last_plane(4), None);
        let err = scan_labels_on(&bad, None, threads).unwrap_err().to_string();
        assert!(
            err.contains("sample (x 1, y 1, z 4) is 0.25"),
            "{threads} threads: {err}"
        );
    }
    // A cancelled scan stops, at any number of threads.
    let cancel = std::sync::atomic::AtomicBool::new(true);
    for threads in [1, 3] {
        let err = scan_labels_on(&raw, Some(&cancel), threads).unwrap_err();
        assert!(matches!(err, tmc::Error::Interrupted), "{threads}: {err}");
    }
}
