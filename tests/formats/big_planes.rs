//! What a worker holds does not grow with the plane: planes of 2048^2 and
//! 6144^2 samples (9x the samples) take about the same anonymous memory,
//! from NRRD, NIfTI and MetaImage files (unscaled, native byte order: lent
//! planes, the same mesh as the samples read into `f64`s), from a stack of
//! uncompressed TIFF slices (lent from maps of the slices), and with
//! `--close` (the padded planes lent as views of the inner ones); and a
//! plane whose samples are not aligned for their type (a NRRD header
//! of odd length before 16-bit samples) gives the same mesh as an aligned
//! one.
//!
//! Before planes at any alignment were lent (`volume::Packed`), a
//! misaligned plane was read into `f64`s: 8 bytes per sample, two planes per
//! worker, so two workers on 6144^2 planes held some 1.2 GB more than on
//! 2048^2 planes, where this test allows 96 MiB. So, before they were
//! lent, were TIFF slices (decoded, then turned into `f64`s: 2.5 GiB more
//! at 6144^2) and `--close` (each padded plane read into `f64`s, with the
//! inner plane copied on the way: 2.4 GiB more).

use crate::common;

use common::cli::{json_number, s, synth, tmc};
use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Writes an `n x n x nz` u16 NRRD of a small ball (2000 inside, 1000
/// outside, radius 20 samples) whose header is padded to `header_len`
/// bytes (odd: the samples are not 2-byte aligned in the file).
fn ball(dir: &Path, n: usize, nz: usize, header_len: usize) -> PathBuf {
    let path = dir.join(format!("ball{n}.nrrd"));
    let header = nrrd_header(&format!("{n} {n} {nz}"), header_len);
    write_ball(&path, &header, n, nz);
    path
}

/// Writes `header` and then the little-endian u16 samples of [`ball`] to
/// `path`.
fn write_ball(path: &Path, header: &[u8], n: usize, nz: usize) {
    let mut out = BufWriter::new(fs::File::create(path).unwrap());
    out.write_all(header).unwrap();
    let c = (n / 2) as f64;
    let mut plane = vec![0u8; 2 * n * n];
    for z in 0..nz {
        let dz = z as f64 - nz as f64 / 2.0;
        for y in 0..n {
            for x in 0..n {
                let (dx, dy) = (x as f64 - c, y as f64 - c);
                let v: u16 = if dx * dx + dy * dy + dz * dz < 400.0 {
                    2000
                } else {
                    1000
                };
                plane[2 * (y * n + x)..][..2].copy_from_slice(&v.to_le_bytes());
            }
        }
        out.write_all(&plane).unwrap();
    }
    out.flush().unwrap();
}

/// [`ball`] as a single-file NIfTI-1 (`.nii`, uint16, unscaled: slope 0).
fn ball_nifti(dir: &Path, n: usize, nz: usize) -> PathBuf {
    let path = dir.join(format!("ball{n}.nii"));
    write_ball(&path, &nifti_header([n, n, nz], 0.0), n, nz);
    path
}

/// A single-file NIfTI-1 header of `dims` uint16 samples, unit spacing,
/// `scl_slope` as given (0: unscaled).
fn nifti_header(dims: [usize; 3], slope: f32) -> Vec<u8> {
    let mut h = vec![0u8; 352];
    h[0..4].copy_from_slice(&348i32.to_le_bytes());
    let [nx, ny, nz] = dims;
    for (i, d) in [3, nx, ny, nz, 1, 1, 1, 1].into_iter().enumerate() {
        h[40 + 2 * i..][..2].copy_from_slice(&(d as i16).to_le_bytes());
    }
    h[70..72].copy_from_slice(&512i16.to_le_bytes()); // uint16
    h[72..74].copy_from_slice(&16i16.to_le_bytes()); // bitpix
    for i in 0..4 {
        h[76 + 4 * i..][..4].copy_from_slice(&1f32.to_le_bytes()); // pixdim
    }
    h[108..112].copy_from_slice(&352f32.to_le_bytes()); // vox_offset
    h[112..116].copy_from_slice(&slope.to_le_bytes()); // scl_slope
    h[344..348].copy_from_slice(b"n+1\0");
    h
}

/// [`ball`] as a MetaImage: a `.mhd` header and its `.raw` samples.
fn ball_metaimage(dir: &Path, n: usize, nz: usize) -> PathBuf {
    let path = dir.join(format!("ball{n}.mhd"));
    let raw = format!("ball{n}.raw");
    let header = format!(
        "ObjectType = Image\nNDims = 3\nDimSize = {n} {n} {nz}\nElementType = MET_USHORT\n\
         ElementByteOrderMSB = False\nElementDataFile = {raw}\n"
    );
    fs::write(&path, header).unwrap();
    write_ball(&dir.join(raw), &[], n, nz);
    path
}

/// The samples of [`ball`], plane `z` of `n x n x nz`, x fastest.
fn ball_plane(n: usize, nz: usize, z: usize) -> Vec<u16> {
    let c = (n / 2) as f64;
    let dz = z as f64 - nz as f64 / 2.0;
    let mut plane = vec![1000u16; n * n];
    for y in 0..n {
        for x in 0..n {
            let (dx, dy) = (x as f64 - c, y as f64 - c);
            if dx * dx + dy * dy + dz * dz < 400.0 {
                plane[y * n + x] = 2000;
            }
        }
    }
    plane
}

/// [`ball`] as a directory of single-page uncompressed TIFFs, written by
/// the `tiff` crate's encoder.
fn ball_tiff(dir: &Path, n: usize, nz: usize) -> PathBuf {
    let planes: Vec<Vec<u16>> = (0..nz).map(|z| ball_plane(n, nz, z)).collect();
    tiff_stack(&dir.join(format!("ball{n}")), [n, n], &planes, false)
}

/// Writes `planes` (`dims[0] x dims[1]` u16 samples each) as single-page
/// TIFFs in the new directory `stack` with the `tiff` crate's encoder,
/// uncompressed or PackBits-compressed.
fn tiff_stack(stack: &Path, dims: [usize; 2], planes: &[Vec<u16>], packbits: bool) -> PathBuf {
    use tiff::encoder::{colortype::Gray16, Compression, TiffEncoder};
    fs::create_dir(stack).unwrap();
    for (z, plane) in planes.iter().enumerate() {
        let file = fs::File::create(stack.join(format!("slice_{z:03}.tif"))).unwrap();
        let compression = match packbits {
            true => Compression::Packbits,
            false => Compression::Uncompressed,
        };
        let mut tiff = TiffEncoder::new(BufWriter::new(file))
            .unwrap()
            .with_compression(compression);
        let (w, h) = (dims[0] as u32, dims[1] as u32);
        tiff.write_image::<Gray16>(w, h, plane).unwrap();
    }
    stack.to_path_buf()
}

/// Writes `planes` (`dims[0] x dims[1]` u16 samples each) as a
/// single-file NIfTI-1 whose samples are scaled: stored as twice the
/// value, `scl_slope` 0.5, so they read as `planes`.
fn scaled_nifti(path: &Path, dims: [usize; 2], planes: &[Vec<u16>]) -> PathBuf {
    let [nx, ny] = dims;
    let h = nifti_header([nx, ny, planes.len()], 0.5);
    let mut out = BufWriter::new(fs::File::create(path).unwrap());
    out.write_all(&h).unwrap();
    for plane in planes {
        let bytes: Vec<u8> = plane.iter().flat_map(|v| (2 * v).to_le_bytes()).collect();
        out.write_all(&bytes).unwrap();
    }
    out.flush().unwrap();
    path.to_path_buf()
}

/// [`ball`] as a scaled NIfTI ([`scaled_nifti`]).
fn ball_scaled_nifti(dir: &Path, n: usize, nz: usize) -> PathBuf {
    let planes: Vec<Vec<u16>> = (0..nz).map(|z| ball_plane(n, nz, z)).collect();
    scaled_nifti(&dir.join(format!("ball{n}s.nii")), [n, n], &planes)
}

/// Writes `planes` (`dims[0] x dims[1]` u16 samples each) as a Zarr v2
/// array, one uncompressed chunk per plane (written by hand: the format
/// is a JSON file and the chunks' bytes).
fn zarr_store(store: &Path, dims: [usize; 2], planes: &[Vec<u16>]) -> PathBuf {
    let [nx, ny] = dims;
    fs::create_dir(store).unwrap();
    let zarray = format!(
        r#"{{"shape": [{nz}, {ny}, {nx}], "chunks": [1, {ny}, {nx}], "dtype": "<u2",
"fill_value": 0, "order": "C", "filters": null, "dimension_separator": ".",
"compressor": null, "zarr_format": 2}}"#,
        nz = planes.len()
    );
    fs::write(store.join(".zarray"), zarray).unwrap();
    for (z, plane) in planes.iter().enumerate() {
        let bytes: Vec<u8> = plane.iter().flat_map(|v| v.to_le_bytes()).collect();
        fs::write(store.join(format!("{z}.0.0")), bytes).unwrap();
    }
    store.to_path_buf()
}

/// [`ball`] as a Zarr v2 array ([`zarr_store`]).
fn ball_zarr(dir: &Path, n: usize, nz: usize) -> PathBuf {
    let planes: Vec<Vec<u16>> = (0..nz).map(|z| ball_plane(n, nz, z)).collect();
    zarr_store(&dir.join(format!("ball{n}.zarr")), [n, n], &planes)
}

/// [`ball`] as PackBits-compressed TIFF slices (decoded, not mapped).
fn ball_packbits(dir: &Path, n: usize, nz: usize) -> PathBuf {
    let planes: Vec<Vec<u16>> = (0..nz).map(|z| ball_plane(n, nz, z)).collect();
    tiff_stack(&dir.join(format!("ball{n}p")), [n, n], &planes, true)
}

/// [`ball`] as a big-endian NRRD.
fn ball_big_endian(dir: &Path, n: usize, nz: usize) -> PathBuf {
    let little = fs::read(ball(dir, n, nz, 300)).unwrap();
    let path = dir.join(format!("ball{n}be.nrrd"));
    fs::write(&path, big_endian(&little[300..], &format!("{n} {n} {nz}"))).unwrap();
    path
}

/// A big-endian u16 NRRD of `sizes` holding the little-endian `samples`.
fn big_endian(samples: &[u8], sizes: &str) -> Vec<u8> {
    let header = format!(
        "NRRD0004\ntype: uint16\ndimension: 3\nsizes: {sizes}\nendian: big\nencoding: raw\n\n"
    );
    let mut file = header.into_bytes();
    file.extend(samples.chunks_exact(2).flat_map(|s| [s[1], s[0]]));
    file
}

/// A little-endian u16 raw NRRD header for `sizes`, padded with a comment
/// to exactly `len` bytes.
fn nrrd_header(sizes: &str, len: usize) -> Vec<u8> {
    let fields = format!(
        "NRRD0004\ntype: uint16\ndimension: 3\nsizes: {sizes}\nendian: little\nencoding: raw\n"
    );
    // "#" + padding + "\n" before the blank line that ends the header.
    let pad = len
        .checked_sub(fields.len() + 3)
        .expect("header length too short");
    format!("{fields}#{}\n\n", " ".repeat(pad)).into_bytes()
}

/// Peak anonymous memory of `tmc extract` on `input` (with `more`
/// options) at two threads, slabs of one layer (so both workers hold
/// planes at once).
fn peak_anon(input: &Path, output: &Path, more: &[&str]) -> f64 {
    let mut args = vec![
        "extract",
        s(input),
        "--iso",
        "1500",
        "-o",
        s(output),
        "--threads",
        "2",
        "--slab-depth",
        "1",
        "--json",
    ];
    args.extend_from_slice(more);
    let out = tmc(&args);
    assert!(out.status.success(), "{out:?}");
    assert!(json_number(&out.stdout, "triangles") > 0.0, "no surface");
    json_number(&out.stdout, "peak_rss_anon_bytes")
}

/// The growth of [`peak_anon`] (bytes) from planes of 2048^2 to planes
/// of 6144^2 of the 6-plane volume `write` makes, printed with `name`.
fn growth(name: &str, write: fn(&Path, usize, usize) -> PathBuf, more: &[&str]) -> f64 {
    let (small, large) = (2048, 6144);
    let mut peaks = Vec::new();
    for n in [small, large] {
        // One volume at a time on disk (the large one is 450 MB).
        let dir = tempfile::tempdir().unwrap();
        let mesh = dir.path().join("mesh.tmesh");
        peaks.push(peak_anon(&write(dir.path(), n, 6), &mesh, more));
    }
    let mib = |b: f64| b / f64::from(1 << 20);
    println!(
        "{name}: peak anonymous memory {:.1} MiB at {small}^2, {:.1} MiB at {large}^2",
        mib(peaks[0]),
        mib(peaks[1])
    );
    peaks[1] - peaks[0]
}

/// NRRD (with a misaligned header; big-endian), NIfTI, MetaImage and a
/// TIFF stack: each lends its planes (`SampleSource::lend_plane`) rather than read them
/// into `f64`s; with `--close`, NRRD and TIFF lend the padded planes.
#[test]
fn anonymous_memory_does_not_grow_with_the_plane() {
    type Writer = fn(&Path, usize, usize) -> PathBuf;
    let nrrd: Writer = |dir, n, nz| ball(dir, n, nz, 301);
    let formats: [(&str, Writer, &[&str]); 9] = [
        ("NRRD", nrrd, &[]),
        ("NRRD big-endian", ball_big_endian, &[]),
        ("NIfTI", ball_nifti, &[]),
        ("NIfTI scaled", ball_scaled_nifti, &[]),
        ("NIfTI scaled --close", ball_scaled_nifti, &["--close"]),
        ("MetaImage", ball_metaimage, &[]),
        ("TIFF stack", ball_tiff, &[]),
        ("NRRD --close", nrrd, &["--close"]),
        ("TIFF stack --close", ball_tiff, &["--close"]),
    ];
    for (name, write, more) in formats {
        let grown = growth(name, write, more);
        assert!(
            grown < 96.0 * f64::from(1 << 20),
            "{name}: 6144^2 planes took {:.1} MiB more than 2048^2 planes",
            grown / f64::from(1 << 20)
        );
    }
}

/// Planes that must be decoded (PackBits TIFF slices, a Zarr array, with
/// and without `--close`) are held in their own type, 2 bytes a sample
/// here: going from 2048^2 to 6144^2 planes adds no more than a handful
/// of such planes: for TIFF, two per worker and the one the source keeps
/// (5); for Zarr, also the `threads + 2` layers its cache keeps, which a
/// worker's held planes may have left (8). Read into `f64`s, as they were
/// before, the same runs took 1 to 2.5 GiB more (Zarr `--close`: 23 such
/// planes).
#[test]
fn decoded_planes_are_held_in_their_own_type() {
    type Writer = fn(&Path, usize, usize) -> PathBuf;
    let formats: [(&str, Writer, &[&str], f64); 4] = [
        ("TIFF PackBits", ball_packbits, &[], 5.0),
        ("TIFF PackBits --close", ball_packbits, &["--close"], 5.0),
        ("Zarr", ball_zarr, &[], 8.0),
        ("Zarr --close", ball_zarr, &["--close"], 8.0),
    ];
    // Two bytes a sample, from 2048^2 to 6144^2 samples.
    let plane_growth = ((6144 * 6144 - 2048 * 2048) * 2) as f64;
    for (name, write, more, planes) in formats {
        let grown = growth(name, write, more);
        assert!(
            grown < planes * plane_growth,
            "{name}: 6144^2 planes took {:.1} MiB more than 2048^2 planes",
            grown / f64::from(1 << 20)
        );
    }
}

/// NIfTI, MetaImage, TIFF and big-endian NRRD planes lent give the mesh
/// their samples read into `f64`s gave: that of the same samples as NRRD.
#[test]
fn lent_nifti_metaimage_tiff_and_big_endian_planes_give_the_nrrd_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let mut meshes = Vec::new();
    for input in [
        ball(dir.path(), 96, 48, 300),
        ball_nifti(dir.path(), 96, 48),
        ball_metaimage(dir.path(), 96, 48),
        ball_tiff(dir.path(), 96, 48),
        ball_big_endian(dir.path(), 96, 48),
        ball_scaled_nifti(dir.path(), 96, 48),
        ball_zarr(dir.path(), 96, 48),
        ball_packbits(dir.path(), 96, 48),
    ] {
        let mesh = mesh_of(&input, &dir.path().join("mesh.tmesh"), "2");
        meshes.push((input.display().to_string(), mesh));
    }
    assert_all_alike(&meshes);
}

/// The `.tmesh` bytes of `tmc extract input --iso 1500 --threads threads`
/// (with `more` options).
fn mesh_with(input: &Path, output: &Path, threads: &str, more: &[&str]) -> Vec<u8> {
    let mut args = vec![
        "extract",
        s(input),
        "--iso",
        "1500",
        "-o",
        s(output),
        "--threads",
        threads,
        "-q",
    ];
    args.extend_from_slice(more);
    let out = tmc(&args);
    assert!(out.status.success(), "{out:?}");
    fs::read(output).unwrap()
}

/// [`mesh_with`] without more options.
fn mesh_of(input: &Path, output: &Path, threads: &str) -> Vec<u8> {
    mesh_with(input, output, threads, &[])
}

/// The meshes (named) are one mesh, with a surface.
fn assert_all_alike(meshes: &[(String, Vec<u8>)]) {
    let (_, first) = &meshes[0];
    assert!(first.len() > 10_000, "a surface");
    for (name, mesh) in meshes {
        assert!(mesh == first, "{name}: another mesh");
    }
}

#[test]
fn a_misaligned_plane_gives_the_mesh_of_an_aligned_one() {
    let dir = tempfile::tempdir().unwrap();
    // The head phantom's samples behind headers of odd and even length.
    let head = synth(dir.path(), "head", "96,80,40", "u16", "head.nrrd");
    let bytes = fs::read(&head).unwrap();
    let data = bytes.len() - 96 * 80 * 40 * 2;
    let mut meshes = Vec::new();
    for len in [301, 302, 304, 299] {
        let input = dir.path().join(format!("head{len}.nrrd"));
        let mut file = nrrd_header("96 80 40", len);
        file.extend_from_slice(&bytes[data..]);
        fs::write(&input, file).unwrap();
        let output = dir.path().join(format!("head{len}.tmesh"));
        for threads in ["1", "2"] {
            let mesh = mesh_of(&input, &output, threads);
            meshes.push((format!("header of {len} bytes"), mesh));
        }
    }
    assert_all_alike(&meshes);
}

/// With `--close`, planes lent as padded views (NRRD in either byte
/// order, uncompressed TIFF slices) and planes read into `f64`s and padded
/// in place (PackBits-compressed TIFF slices, which are decoded) give one
/// mesh, with any threads and slab depth, normals or not: the head
/// phantom, whose surface reaches the volume's border.
#[test]
fn close_gives_one_mesh_from_lent_and_read_planes() {
    let dir = tempfile::tempdir().unwrap();
    let [nx, ny, nz] = [96, 80, 40];
    let head = synth(dir.path(), "head", "96,80,40", "u16", "head.nrrd");
    let bytes = fs::read(&head).unwrap();
    let samples = &bytes[bytes.len() - nx * ny * nz * 2..];
    let planes: Vec<Vec<u16>> = samples
        .chunks_exact(nx * ny * 2)
        .map(|p| {
            let p = p.chunks_exact(2);
            p.map(|b| u16::from_le_bytes([b[0], b[1]])).collect()
        })
        .collect();
    let big = dir.path().join("big.nrrd");
    fs::write(&big, big_endian(samples, "96 80 40")).unwrap();
    let inputs = [
        head,
        big,
        tiff_stack(&dir.path().join("plain"), [nx, ny], &planes, false),
        tiff_stack(&dir.path().join("packbits"), [nx, ny], &planes, true),
        zarr_store(&dir.path().join("head.zarr"), [nx, ny], &planes),
        scaled_nifti(&dir.path().join("scaled.nii"), [nx, ny], &planes),
    ];
    for more in [
        &["--close"][..],
        &["--close", "--slab-depth", "3"][..],
        &["--close", "--normals"][..],
        &["--close", "--inside", "low", "--slab-depth", "2"][..],
    ] {
        let mut meshes = Vec::new();
        for input in &inputs {
            for threads in ["1", "2"] {
                let output = dir.path().join("close.tmesh");
                let mesh = mesh_with(input, &output, threads, more);
                let name = format!("{} {threads} {more:?}", input.display());
                meshes.push((name, mesh));
            }
        }
        assert_all_alike(&meshes);
    }
}
