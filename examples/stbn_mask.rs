//! Times the generation of one `stbn` mask (void-and-cluster over 64² × 32 with the Wolfe et al.
//! energy; the seed mode uses two, generated once per process):
//! `cargo run --release --example stbn_mask -- [repeats]`, min / median / max.

use hemilab::sampling::stbn::{STBN_DEPTH, STBN_SIGMA, STBN_SIZE, StbnMask};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let repeats: usize = std::env::args().nth(1).map_or(Ok(5), |s| s.parse())?;
    let mut times: Vec<f64> = (0..repeats.max(1))
        .map(|i| {
            let t = Instant::now();
            std::hint::black_box(StbnMask::void_and_cluster(STBN_SIZE, STBN_DEPTH, STBN_SIGMA, i as u64));
            t.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    let n = times.len();
    println!(
        "one {STBN_SIZE}x{STBN_SIZE}x{STBN_DEPTH} stbn mask, {n} runs: min {:.0} ms, median {:.0} ms, max {:.0} ms",
        times[0] * 1e3,
        times[n / 2] * 1e3,
        times[n - 1] * 1e3
    );
    Ok(())
}
