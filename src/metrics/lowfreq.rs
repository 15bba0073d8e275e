//! The error after a small Gaussian blur, and how much of it there is against white noise.
//!
//! `lowpass_rmse`: what a blur (or a denoiser, or the eye at a distance) leaves of the
//! error. Noise averages out under it, bands and blotches do not.
//!
//! `lowfreq_ratio`: that low-pass energy over the low-pass energy the *same* per-pixel errors would
//! have if they were independent,
//!
//!   R = Σ_i (Σ_j w_ij e_j)² / Σ_i Σ_j w_ij² e_j²,   w_ij = G_ij m_j / Σ_k G_ik m_k,
//!
//! sums over covered pixels i (mask m), e the error minus its mean over them (`lowfreq_ratio` says
//! why), w the normalized Gaussian of `lowpass_rmse` (`denoise::gaussian`: so the image border and the background are handled
//! exactly as there). For independent zero-mean errors of any
//! per-pixel variances σ_j², the numerator's expectation is Σ_i Σ_j w_ij² σ_j², which the denominator
//! estimates without bias (e_j² for σ_j²): R ≈ 1 for white noise however heteroscedastic (AO error is
//! 0 on open pixels and large at occlusion edges). Expanding the square, R = 1 + (Gaussian-weighted
//! sum of the error's autocovariances at non-zero lags) / (the same at lag 0), so the sign of the
//! short-range correlation survives: R < 1 when neighbours' errors cancel (blue noise: the error's
//! power pushed to high frequencies, Ulichney 1988, "Dithering with blue noise"; Georgiev & Fajardo
//! 2016, Heitz & Belcour 2019 for Monte Carlo rendering), R > 1 when they add up (the static seed's
//! blotches, bands). It is the 2-D analogue of the variance ratio of Lo & MacKinlay (1988) — the
//! variance of a q-step sum over q times the one-step variance — and of Kish's (1965) design effect.
//!
//! Unlike a test statistic (the whiteness z, which grows as √(pixels) for a fixed structure), R is a
//! ratio of two sums over the pixels, so a given error texture reads the same at any image size; only
//! its noise shrinks: for white noise, sd(R) ≈ √(4πσ² / n) with n the covered pixels (σ = 1.5: 0.10
//! at 64×48, 0.04 at 160×120), more when a few pixels carry most of the error.

use super::{CONSTANT_SD, covered, rmse_bias};
use crate::denoise::gaussian::{gaussian, masked, separable, taps};
use crate::image::Image;

/// Above this ratio (a mean over replicates) an error is called structured. Chosen from
/// measurements (the seven committed scenes at 96×72, 8 replicates, 8/16/32 rays; the
/// kitchen at 64×48 and 160×120, the slats and the Cornell box at 160×120): per-pixel seeds' means lie
/// in 0.91–1.09 (one image's sd 0.03–0.28), the static seed's in 1.69–19 (lowest: the slats at 32
/// rays, 96×72), pseudo-random × blue noise's in 0.38–0.79. 1.5 leaves the widest margin to both
/// sides that the lowest static reading allows: about 7 standard errors of a 4-replicate mean (advise's
/// default) above white noise at 64×48, yet below every static-seed mean measured.
pub const STRUCTURED_RATIO: f64 = 1.5;

/// RMS over covered pixels of the error blurred by a Gaussian of `sigma` pixels. The blur is a
/// normalized convolution over covered pixels only, so background zeros do not dilute edges.
pub fn lowpass_rmse(err: &Image, mask: &Image, sigma: f64) -> f64 {
    // Background pixels keep `err`'s values; `rmse_bias` reads covered pixels only.
    let blurred = gaussian(err, mask, sigma);
    rmse_bias(&blurred, mask).0
}

/// R, the low-pass energy of the error over the low-pass energy of independent errors of the same
/// per-pixel magnitudes (module doc): 1 = white, < 1 = blue, > 1 = clumped or banded.
///
/// The error is first centred on its mean over the covered pixels, as for the whiteness z and the
/// lag-1 autocorrelation: a bias every pixel shares is the `bias` column's, not a texture (left in,
/// it would read as the lowest frequency there is: a constant offset alone gives R ≈ 4πσ² ≈ 28, and
/// the lattice rotated per pixel, whose fixed polar angles bias the open terrain by +0.006, read 1.5
/// instead of 1.04 at 8 rays, 96×72). A bias that varies across the image — a static seed's — stays
/// and counts. A constant error (sd ≤ `CONSTANT_SD`: f32 rounding of an exact answer) or nothing
/// covered has no structure and reads 1.
pub fn lowfreq_ratio(err: &Image, mask: &Image, sigma: f64) -> f64 {
    let (rmse, mean) = rmse_bias(err, mask);
    if (rmse * rmse - mean * mean).max(0.0).sqrt() <= CONSTANT_SD {
        return 1.0;
    }
    let centred = Image::from_vec(
        err.width,
        err.height,
        (0..err.len())
            .map(|i| if covered(mask, i) { (err.data[i] as f64 - mean) as f32 } else { 0.0 })
            .collect(),
    );
    let (energy, white) = energies(&centred, mask, sigma);
    if white > 0.0 { energy / white } else { 1.0 }
}

/// (Σ_i (Σ_j w_ij e_j)², Σ_i Σ_j w_ij² e_j²) over covered pixels i, for the error `err` as given:
/// R's numerator (n · `lowpass_rmse(err)`², before that one's f32 rounding) and denominator.
fn energies(err: &Image, mask: &Image, sigma: f64) -> (f64, f64) {
    let (w, h) = (err.width as usize, err.height as usize);
    let g = taps(sigma);
    // The 2-D kernel is separable, so its square is too: g(kx)² · g(ky)².
    let g2: Vec<f64> = g.iter().map(|k| k * k).collect();
    let (m, v) = masked(err, mask);
    let sq: Vec<f64> = v.iter().map(|e| e * e).collect();
    let num = separable(&v, w, h, &g);
    let den = separable(&m, w, h, &g);
    let var = separable(&sq, w, h, &g2);
    let (mut energy, mut white) = (0.0f64, 0.0f64);
    for i in (0..err.len()).filter(|&i| m[i] > 0.0 && den[i] > 0.0) {
        energy += (num[i] / den[i]).powi(2);
        white += var[i] / (den[i] * den[i]);
    }
    (energy, white)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::LOWPASS_SIGMA;

    /// SplitMix64-based standard normals (Box–Muller), fixed seeds: the tests cannot flake.
    fn normals(n: usize, seed: u64) -> Vec<f64> {
        crate::stats::normals_from_state(n, seed.wrapping_mul(0x2545_F491_4F6C_DD1D))
    }

    fn image(w: u32, h: u32, f: impl Fn(u32, u32, usize) -> f64) -> Image {
        Image::from_vec(w, h, (0..w * h).map(|i| f(i % w, i / w, i as usize) as f32).collect())
    }

    fn full(w: u32, h: u32) -> Image {
        image(w, h, |_, _, _| 1.0)
    }

    fn ratio(err: &Image, mask: &Image) -> f64 {
        lowfreq_ratio(err, mask, LOWPASS_SIGMA)
    }

    /// White noise of sd 0.05 on a w × h image: R over 20 seeds.
    fn white(w: u32, h: u32) -> Vec<f64> {
        (0..20)
            .map(|s| {
                let n = normals((w * h) as usize, s);
                ratio(&image(w, h, |_, _, i| 0.05 * n[i]), &full(w, h))
            })
            .collect()
    }

    fn mean(v: &[f64]) -> f64 {
        v.iter().sum::<f64>() / v.len() as f64
    }

    #[test]
    fn white_noise_reads_one_at_any_image_size() {
        // sd of one image's R ≈ √(4πσ²/n): 0.096 at 64×48, 0.019 at 320×240, and the mean of 20
        // has √20 times less. Every image within 4 sd of 1, the means within 3 sd of theirs.
        let (small, large) = (white(64, 48), white(320, 240));
        for (v, sd) in [(&small, 0.096), (&large, 0.019)] {
            assert!(v.iter().all(|r| (r - 1.0).abs() < 4.0 * sd), "{v:.3?}");
            assert!((mean(v) - 1.0).abs() < 3.0 * sd / 20f64.sqrt(), "mean {:.3}: {v:.3?}", mean(v));
        }
        eprintln!("white noise R: 64x48 {:.3} (of {small:.2?}), 320x240 {:.3}", mean(&small), mean(&large));
        // The same reading at both sizes: a ratio, not a test statistic that grows with the pixels.
        assert!((mean(&small) - mean(&large)).abs() < 0.07, "{:.3} vs {:.3}", mean(&small), mean(&large));
    }

    #[test]
    fn heteroscedastic_white_noise_reads_one() {
        // Noise only in blobs, the rest exactly 0 (like open AO pixels): clustered variance, no
        // correlation. The denominator uses each pixel's own e², so R stays 1.
        let (w, h) = (96, 72);
        let rs: Vec<f64> = (0..20)
            .map(|s| {
                let n = normals((w * h) as usize, 100 + s);
                let blob = |x: u32, y: u32| ((x / 12) + (y / 12)).is_multiple_of(2);
                let img = image(w, h, |x, y, i| if blob(x, y) { 0.1 * n[i] } else { 0.01 * n[i] });
                ratio(&img, &full(w, h))
            })
            .collect();
        assert!((mean(&rs) - 1.0).abs() < 0.05, "mean {:.3}: {rs:.3?}", mean(&rs));
    }

    #[test]
    fn smooth_and_banded_errors_read_well_above_one() {
        use std::f64::consts::PI;
        let (w, h) = (96, 72);
        let n = normals((w * h) as usize, 3);
        type Pattern = Box<dyn Fn(f64, f64) -> f64>;
        let patterns: [(&str, Pattern); 3] = [
            ("horizontal bands, period 12", Box::new(|_, y| (2.0 * PI * y / 12.0).sin())),
            (
                "blotches",
                Box::new(|x, y| (x / 9.0).sin() * (y / 7.0).cos() + (0.7 * x / 11.0 + y / 13.0).sin()),
            ),
            ("steps of 8 px", Box::new(|x, _| if (x as u32 / 8).is_multiple_of(2) { 1.0 } else { -1.0 })),
        ];
        for (name, p) in patterns {
            // A pattern of the noise's amplitude (RMSE up by 22 % for the bands): R several times 1.
            let img = image(w, h, |x, y, i| 0.05 * n[i] + 0.05 * p(x as f64, y as f64));
            let r = ratio(&img, &full(w, h));
            eprintln!("{name}: R = {r:.2}");
            assert!(r > 2.0 * STRUCTURED_RATIO, "{name}: R = {r:.2}");
        }
        // A bias shared by every pixel is taken out (it is the `bias` column's); a constant error
        // has no texture at all.
        let biased = image(w, h, |_, _, i| 0.05 * n[i] + 0.02);
        let r = ratio(&biased, &full(w, h));
        assert!((r - 1.0).abs() < 0.25, "white noise plus an offset: R = {r:.2}");
        assert_eq!(ratio(&image(w, h, |_, _, _| 0.125), &full(w, h)), 1.0);
    }

    #[test]
    fn checkerboard_and_high_pass_errors_read_below_one() {
        let (w, h) = (96, 72);
        let checker = image(w, h, |x, y, _| if (x + y) % 2 == 0 { 0.05 } else { -0.05 });
        let r = ratio(&checker, &full(w, h));
        assert!(r < 0.05, "checkerboard: R = {r:.3}");
        // Blue-like: white noise minus the mean of its four neighbours (a discrete Laplacian, power
        // ∝ |f|⁴ at low frequencies).
        for s in 0..5 {
            let n = normals((w * h) as usize, 200 + s);
            let at =
                |x: i64, y: i64| n[(y.clamp(0, h as i64 - 1) * w as i64 + x.clamp(0, w as i64 - 1)) as usize];
            let img = image(w, h, |x, y, _| {
                let (x, y) = (x as i64, y as i64);
                at(x, y) - 0.25 * (at(x - 1, y) + at(x + 1, y) + at(x, y - 1) + at(x, y + 1))
            });
            let r = ratio(&img, &full(w, h));
            assert!(r < 0.3, "high-passed noise, seed {s}: R = {r:.3}");
        }
    }

    #[test]
    fn background_and_border_are_handled_as_in_lowpass() {
        let (w, h) = (96, 72);
        // Background (x ≥ w/2) carries a huge smooth error that must be ignored; the covered half's
        // error is white. Its border (image edge and mask edge) must not read as structure.
        let rs: Vec<f64> = (0..20)
            .map(|s| {
                let n = normals((w * h) as usize, 300 + s);
                let img = image(w, h, |x, _, i| if x < w / 2 { 0.05 * n[i] } else { 5.0 });
                let mask = image(w, h, |x, _, _| if x < w / 2 { 1.0 } else { 0.0 });
                ratio(&img, &mask)
            })
            .collect();
        assert!((mean(&rs) - 1.0).abs() < 0.05, "mean {:.3}: {rs:.3?}", mean(&rs));
        // The numerator is the low-pass energy `lowpass_rmse` measures, over the same pixels.
        let n = normals((w * h) as usize, 7);
        let img = image(w, h, |x, _, i| 0.05 * n[i] + if x < w / 2 { 0.0 } else { 5.0 });
        let mask = image(w, h, |x, _, _| if x < w / 2 { 1.0 } else { 0.0 });
        let lp = lowpass_rmse(&img, &mask, LOWPASS_SIGMA);
        let (energy, _) = energies(&img, &mask, LOWPASS_SIGMA);
        let covered = (w / 2 * h) as f64;
        assert!((energy / covered - lp * lp).abs() < 1e-6 * lp * lp, "{energy} vs {}", covered * lp * lp);
        // Nothing to measure: no error, or no covered pixel.
        assert_eq!(ratio(&image(w, h, |_, _, _| 0.0), &full(w, h)), 1.0);
        assert_eq!(ratio(&img, &image(w, h, |_, _, _| 0.0)), 1.0);
    }
}
