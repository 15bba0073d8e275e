//! Times the generation of the `blue-noise` seed mode's masks and draws them, so they can be looked
//! at: `cargo run --release --example blue_noise_mask -- /tmp/mask.png [repeats] [size to time]`.
//! Panels, each the 64² mask tiled 2 × 2 and drawn at 2×: the x mask, the y mask, both as red and
//! green, and the x mask's lowest quarter of ranks (a blue-noise dot pattern).

use hemilab::sampling::blue_noise::{BlueNoiseMask, MASK_SIGMA, MASK_SIZE, masks};
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "/tmp/blue_noise_mask.png".into()));
    let repeats: usize = std::env::args().nth(2).map_or(Ok(9), |s| s.parse())?;
    let size: u32 = std::env::args().nth(3).map_or(Ok(MASK_SIZE), |s| s.parse())?;

    let mut times: Vec<f64> = (0..repeats)
        .map(|i| {
            let t = Instant::now();
            let m = BlueNoiseMask::void_and_cluster(size, MASK_SIGMA, i as u64);
            std::hint::black_box(m);
            t.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    println!(
        "one {size}x{size} mask by void-and-cluster (sigma {MASK_SIGMA}), {repeats} runs: min {:.1} ms, median {:.1} ms, max {:.1} ms",
        times[0] * 1e3,
        times[repeats / 2] * 1e3,
        times[repeats - 1] * 1e3
    );

    let [mx, my] = masks();
    let n = (MASK_SIZE * MASK_SIZE) as f32;
    let size = MASK_SIZE as usize;
    let (tile, scale, gap) = (2 * size, 2, 8);
    let panels = 4;
    let (w, h) = (panels * tile * scale + (panels - 1) * gap, tile * scale);
    let mut rgb = vec![255u8; w * h * 3];
    for panel in 0..panels {
        for py in 0..h {
            for px in 0..tile * scale {
                let (x, y) = ((px / scale) as u32, (py / scale) as u32);
                let (vx, vy) = (mx.rank(x, y) as f32 / n, my.rank(x, y) as f32 / n);
                let c = match panel {
                    0 => [vx; 3],
                    1 => [vy; 3],
                    2 => [vx, vy, 0.0],
                    _ => [if vx < 0.25 { 0.0 } else { 1.0 }; 3],
                };
                let i = (py * w + panel * (tile * scale + gap) + px) * 3;
                for k in 0..3 {
                    rgb[i + k] = hemilab::image::to_u8(c[k]);
                }
            }
        }
    }
    let png = hemilab::image::encode_png_rgb(w as u32, h as u32, &rgb)?;
    hemilab::io::write_atomic(&out, &png)?;
    println!("wrote {}", out.display());
    Ok(())
}
