//! Compressed samples spilled to a temporary file, then memory-mapped.
//!
//! gzip, bzip2 and zlib streams cannot be read at random, but the slab loop reads
//! planes in any order and from several threads. Rather than holding the
//! decompressed volume in memory, a reader streams it once into an unnamed
//! temporary file (in `TMPDIR`, removed by the system when it is closed,
//! even if the process dies) and maps that file like uncompressed data: the
//! page cache, which the kernel can write back, holds the samples, not the
//! process. A volume larger than memory therefore needs as much free space
//! in `TMPDIR`, not as much memory.

use crate::{Error, Result};
use std::fs::File;
use std::io::{self, Read, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// Size of the copy buffer.
const BUFFER: usize = 1 << 20;

/// Writes `head` and then at most `limit - head.len()` more bytes of
/// `stream` into a new temporary file, and reads the rest of the stream to
/// its end, so that the stream's checksum is verified. Returns the file and
/// the number of bytes it holds (less than `limit` if the stream was
/// shorter; the caller checks the length it needs).
///
/// `path` and `what` (for example "gzip") name the input in errors. Once
/// `cancel` is set (it is looked at every [`BUFFER`] bytes of decompressed
/// data) the spilling stops with [`Error::Interrupted`] and the temporary
/// file is closed, which removes it.
pub(crate) fn spill(
    path: &Path,
    what: &str,
    head: &[u8],
    mut stream: impl Read,
    limit: u64,
    cancel: &AtomicBool,
) -> Result<(File, u64)> {
    let bad = |e: io::Error| Error::Format(format!("{}: bad {what} data: {e}", path.display()));
    let temp_dir = std::env::temp_dir();
    let no_room = |e: io::Error| {
        Error::Format(format!(
            "{}: cannot write the decompressed samples to the temporary directory {} \
             (set TMPDIR to a disk with room): {e}",
            path.display(),
            temp_dir.display()
        ))
    };
    let mut file = tempfile::tempfile().map_err(no_room)?;
    let keep = (head.len() as u64).min(limit);
    file.write_all(&head[..keep as usize]).map_err(no_room)?;
    let mut written = keep;
    let mut buffer = vec![0u8; BUFFER];
    let interrupted = || match cancel.load(Ordering::Relaxed) {
        true => Err(Error::Interrupted),
        false => Ok(()),
    };
    while written < limit {
        interrupted()?;
        let want = (limit - written).min(BUFFER as u64) as usize;
        let got = read_some(&mut stream, &mut buffer[..want]).map_err(bad)?;
        if got == 0 {
            break;
        }
        file.write_all(&buffer[..got]).map_err(no_room)?;
        written += got as u64;
    }
    // Trailing data is not needed, but reading it checks the stream's CRC.
    loop {
        interrupted()?;
        if read_some(&mut stream, &mut buffer).map_err(bad)? == 0 {
            break;
        }
    }
    file.flush().map_err(no_room)?;
    Ok((file, written))
}

/// One `read`, retried when interrupted.
fn read_some(stream: &mut impl Read, buffer: &mut [u8]) -> io::Result<usize> {
    loop {
        match stream.read(buffer) {
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            other => return other,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flate2::write::GzEncoder;
    use flate2::Compression;

    static NEVER: AtomicBool = AtomicBool::new(false);

    /// Reads from `inner`, setting `flag` once `after` bytes were read.
    struct SetsFlag<'a, R> {
        inner: R,
        read: usize,
        after: usize,
        flag: &'a AtomicBool,
    }

    impl<R: Read> Read for SetsFlag<'_, R> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            let n = self.inner.read(buf)?;
            self.read += n;
            if self.read >= self.after {
                self.flag.store(true, Ordering::Relaxed);
            }
            Ok(n)
        }
    }

    #[test]
    fn a_cancel_stops_the_decompression_and_the_checksum_read() {
        let data = vec![5u8; 8 * BUFFER];
        let packed = gzip(&data);
        // While spilling, and while reading the trailing data for the CRC.
        for (after, limit) in [(BUFFER, data.len() as u64), (BUFFER, 10)] {
            let flag = AtomicBool::new(false);
            let stream = SetsFlag {
                inner: flate2::read::GzDecoder::new(&packed[..]),
                read: 0,
                after,
                flag: &flag,
            };
            let result = spill(Path::new("x.gz"), "gzip", &[], stream, limit, &flag);
            assert!(matches!(result, Err(Error::Interrupted)), "{result:?}");
        }
    }

    fn gzip(bytes: &[u8]) -> Vec<u8> {
        let mut e = GzEncoder::new(Vec::new(), Compression::fast());
        e.write_all(bytes).unwrap();
        e.finish().unwrap()
    }

    fn contents(mut file: File) -> Vec<u8> {
        use std::io::Seek;
        let mut out = Vec::new();
        file.rewind().unwrap();
        file.read_to_end(&mut out).unwrap();
        out
    }

    #[test]
    fn spills_head_and_stream_up_to_the_limit() {
        let data: Vec<u8> = (0..3_000_000u32).map(|i| (i % 251) as u8).collect();
        let packed = gzip(&data[10..]);
        let decoder = flate2::read::GzDecoder::new(&packed[..]);
        let (file, len) = spill(
            Path::new("x.gz"),
            "gzip",
            &data[..10],
            decoder,
            2_000_000,
            &NEVER,
        )
        .unwrap();
        assert_eq!(len, 2_000_000);
        assert_eq!(contents(file), data[..2_000_000]);
    }

    #[test]
    fn short_streams_report_their_length_and_corruption_is_an_error() {
        let packed = gzip(&[7u8; 1000]);
        let decoder = flate2::read::GzDecoder::new(&packed[..]);
        let (_, len) = spill(Path::new("x.gz"), "gzip", &[], decoder, 5000, &NEVER).unwrap();
        assert_eq!(len, 1000);

        let mut broken = packed.clone();
        let n = broken.len();
        broken[n - 6] ^= 0xff; // inside the CRC-32 trailer
        let decoder = flate2::read::GzDecoder::new(&broken[..]);
        let e = spill(Path::new("x.gz"), "gzip", &[], decoder, 10, &NEVER)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("x.gz: bad gzip data"), "{e}");
    }
}
