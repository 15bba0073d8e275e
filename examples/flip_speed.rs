//! How long LDR-FLIP (`metrics::flip::ldr_flip_map`) takes per pixel on a 320x180 image, the size
//! of the real-time runs' frames: every measured image of a run gets one map. Prints the best of
//! several repetitions (a loaded machine only ever makes it slower).
//!
//!     cargo run --release --example flip_speed

use hemilab::image::Image;
use hemilab::metrics::flip::{DEFAULT_PPD, ldr_flip_map};
use std::time::Instant;

fn main() {
    let (w, h) = (320u32, 180u32);
    // An AO-like reference and a noisy test image (a small LCG: the values do not matter, only
    // that both images vary).
    let mut state = 12345u64;
    let mut rand = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let reference =
        Image::from_vec(w, h, (0..w * h).map(|i| 0.3 + 0.6 * ((i % w) as f32 / w as f32)).collect());
    let test = Image::from_vec(w, h, reference.data.iter().map(|v| v + 0.2 * (rand() - 0.5)).collect());
    let mut best = f64::INFINITY;
    let mut sink = 0.0f32;
    for _ in 0..20 {
        let t = Instant::now();
        let map = ldr_flip_map(&reference, &test, DEFAULT_PPD);
        best = best.min(t.elapsed().as_secs_f64());
        sink += map.data[0];
    }
    println!(
        "ldr_flip_map {w}x{h}: best of 20 {:.2} ms, {:.0} ns per pixel (check {sink:.3})",
        best * 1e3,
        best * 1e9 / (w * h) as f64
    );
}
