//! Writes the library's benchmark volumes (`tmc::synth::gyroid` and
//! `tmc::synth::noise`, the ones `benches/tmc_vs_mc.rs` times) as float32
//! `.npy` files, so that `scripts/bench-peers` can give the very same samples
//! to tmc and to the peer libraries. (`tmc synth` writes different fields: its
//! noise is smooth value noise, not box-filtered uniform noise.)
//!
//! Usage:
//!   bench_volume gyroid N PERIODS OUT.npy
//!   bench_volume noise N SEED PASSES OUT.npy
//!
//! Build with `cargo build --release --example bench_volume`.

use std::path::Path;
use tmc::volume::{write_volume, ScalarType};

fn number<T: std::str::FromStr>(s: &str, what: &str) -> Result<T, String>
where
    T::Err: std::fmt::Display,
{
    s.parse().map_err(|e| format!("bad {what} {s:?}: {e}"))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (volume, out) = match args.as_slice() {
        [kind, n, periods, out] if kind == "gyroid" => (
            tmc::synth::gyroid(number(n, "N")?, number(periods, "PERIODS")?),
            out,
        ),
        [kind, n, seed, passes, out] if kind == "noise" => (
            tmc::synth::noise(
                number(n, "N")?,
                number(seed, "SEED")?,
                number(passes, "PASSES")?,
            ),
            out,
        ),
        _ => {
            return Err("usage: bench_volume gyroid N PERIODS OUT.npy | \
                        bench_volume noise N SEED PASSES OUT.npy"
                .into())
        }
    };
    write_volume(Path::new(out), &volume, ScalarType::F32, None)?;
    Ok(())
}
