//! Is the error image white noise? A 2-D portmanteau (Ljung–Box / Box–Pierce) statistic over every
//! short lag, so that structure in *any* direction and at *any* short period is seen: bands along x or
//! y, diagonal stripes and moiré, period-2 alternation, smooth blotches. The lag-1 autocorrelations
//! along the axes (`autocorrelation`) miss diagonal patterns and read a checkerboard as its negative,
//! and the low-pass RMSE averages fine patterns away; this statistic sees them all.
//!
//! For each lag h = (dx, dy) of the half-window (|dx|, |dy| ≤ `MAX_LAG`, each ±h pair once: 40 lags),
//! over the pairs (i, i + h) of covered pixels of the mean-removed error e,
//!
//!   T_h = (Σ e_i e_{i+h})² / Σ e_i² e_{i+h}²,
//!
//! the squared autocovariance over its variance under independence. Dividing by Σ e_i² e_{i+h}²
//! rather than by n·var² (the textbook Box–Pierce form) keeps the test honest for *heteroscedastic*
//! noise — an AO error is exactly 0 on open pixels and large at occlusion edges, and the textbook form
//! calls that clustering of variance "structure" (the heteroscedasticity-robust portmanteau of Lobato,
//! Nankervis & Savin 2001). Under independent zero-mean errors each T_h is approximately χ²(1) and the
//! T_h of different lags are uncorrelated, so Q = Σ_h T_h is approximately χ²(K), K = the lags used.
//!
//! The reported number is a z-score against white noise: the Wilson–Hilferty normal approximation of
//! χ²(K) (Wilson & Hilferty 1931), z = ((Q/K)^{1/3} − (1 − 2/(9K))) / √(2/(9K)): about N(0, 1) for
//! white noise, large for structure, and — unlike −Φ⁻¹(p), whose p underflows to 0 once Q passes ~1500 —
//! finite and increasing for any Q, so that strongly structured images can still be compared. The test
//! below checks it against the exact χ² tail of statrs where that tail is representable.

use super::{CONSTANT_SD, covered, rmse_bias};
use crate::image::Image;

/// Largest |dx| and |dy| of the lags tested: up to period-8 patterns, within a few pixels' reach.
pub const MAX_LAG: i32 = 4;

/// Above this z the error is significantly correlated: one-sided p ≈ 3e-7 for white noise ("5
/// sigma"), so a table of hundreds of white-noise images flags none of them by chance. It is a test,
/// not the structure verdict: T_h squares each autocovariance, so blue noise's *negative* short-range
/// correlation counts like banding, and for a fixed texture z grows as √(pixels). The report and
/// `advise` call an error structured by `lowfreq::STRUCTURED_RATIO`.
pub const STRUCTURED_Z: f64 = 5.0;

/// The lags of the half-window, each ±h pair once: (dx, 0) for dx = 1..=L, and (dx, dy) for
/// dy = 1..=L, dx = −L..=L.
pub fn lags() -> Vec<(i32, i32)> {
    let mut v: Vec<(i32, i32)> = (1..=MAX_LAG).map(|dx| (dx, 0)).collect();
    for dy in 1..=MAX_LAG {
        v.extend((-MAX_LAG..=MAX_LAG).map(|dx| (dx, dy)));
    }
    v
}

/// The portmanteau statistic of one error image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Whiteness {
    /// Q = Σ_h T_h.
    pub q: f64,
    /// Lags that had pairs with non-zero error (the χ² degrees of freedom).
    pub lags: usize,
    /// z-score of Q against white noise (0 when nothing could be tested).
    pub z: f64,
}

/// Wilson–Hilferty: the standard normal deviate matching χ²(k) = q.
pub fn wilson_hilferty_z(q: f64, k: usize) -> f64 {
    if k == 0 {
        return 0.0;
    }
    let k = k as f64;
    let s = 2.0 / (9.0 * k);
    ((q.max(0.0) / k).cbrt() - (1.0 - s)) / s.sqrt()
}

/// The whiteness statistic of `err` over the pixels `mask` covers. A constant error (sd ≤
/// `CONSTANT_SD`: f32 rounding of an exact answer) or an image without pairs tests nothing: z = 0.
pub fn whiteness(err: &Image, mask: &Image) -> Whiteness {
    let none = Whiteness { q: 0.0, lags: 0, z: 0.0 };
    let (w, h) = (err.width as i32, err.height as i32);
    let (_, mean) = rmse_bias(err, mask);
    let e: Vec<f64> =
        (0..err.len()).map(|i| if covered(mask, i) { err.data[i] as f64 - mean } else { 0.0 }).collect();
    let n = (0..err.len()).filter(|&i| covered(mask, i)).count();
    if n == 0 || (e.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt() <= CONSTANT_SD {
        return none;
    }
    let (mut q, mut used) = (0.0f64, 0usize);
    for (s, v) in lag_sums(&e, mask, w, h) {
        if v > 0.0 {
            q += s * s / v;
            used += 1;
        }
    }
    if used == 0 {
        return none;
    }
    Whiteness { q, lags: used, z: wilson_hilferty_z(q, used) }
}

/// `lag_sums` pair by pair over each lag's pairs of covered pixels: the definition, for errors that
/// are not all finite.
fn pairwise_sums(e: &[f64], mask: &Image, w: i32, h: i32) -> Vec<(f64, f64)> {
    lags()
        .iter()
        .map(|&(dx, dy)| {
            let (mut s, mut v) = (0.0f64, 0.0f64);
            for y in 0..(h - dy).max(0) {
                for x in (-dx).max(0)..(w - dx.max(0)).max(0) {
                    let i = (y * w + x) as usize;
                    let j = ((y + dy) * w + x + dx) as usize;
                    if covered(mask, i) && covered(mask, j) {
                        let p = e[i] * e[j];
                        s += p;
                        v += p * p;
                    }
                }
            }
            (s, v)
        })
        .collect()
}

/// Per lag of `lags()`, (Σ e_i e_{i+h}, Σ (e_i e_{i+h})²) over the pairs of covered pixels, each
/// sum in row-major order of i. `e` is 0 off the mask, so a pair with an uncovered pixel adds ±0,
/// which leaves a sum that starts at +0 as it was: every lag can run over every pixel of a copy of
/// `e` padded with zeros, 8 lags in one pass (16 independent sums instead of 2 in a chain: half the
/// time at 320x180, the same bits). A non-finite error (±0 · ∞ is NaN) takes the pairwise loop.
fn lag_sums(e: &[f64], mask: &Image, w: i32, h: i32) -> Vec<(f64, f64)> {
    let lags = lags();
    if !e.iter().all(|v| v.is_finite()) {
        return pairwise_sums(e, mask, w, h);
    }
    const L: usize = MAX_LAG as usize;
    const GROUP: usize = 8;
    let (w, h) = (w.max(0) as usize, h.max(0) as usize);
    // L zero columns either side, L zero rows below (every lag's dy ≥ 0).
    let pw = w + 2 * L;
    let mut padded = vec![0.0f64; pw * (h + L)];
    for y in 0..h {
        padded[y * pw + L..y * pw + L + w].copy_from_slice(&e[y * w..y * w + w]);
    }
    let mut out = Vec::with_capacity(lags.len());
    for group in lags.chunks(GROUP) {
        let mut off = [0usize; GROUP];
        for (o, &(dx, dy)) in off.iter_mut().zip(group) {
            *o = (dy as usize * pw).wrapping_add_signed(dx as isize);
        }
        let (mut s, mut v) = ([0.0f64; GROUP], [0.0f64; GROUP]);
        let k = group.len();
        for y in 0..h {
            for i in y * pw + L..y * pw + L + w {
                let a = padded[i];
                // All GROUP sums (a short group's spare ones unused): a fixed count the compiler
                // unrolls, every sum in a register.
                for j in 0..GROUP {
                    let p = a * padded[i + off[j]];
                    s[j] += p;
                    v[j] += p * p;
                }
            }
        }
        out.extend((0..k).map(|j| (s[j], v[j])));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::{chi2_p_value, normal_quantile};

    const W: u32 = 96;
    const H: u32 = 72;

    /// SplitMix64-based standard normals (Box–Muller), fixed seed: the tests cannot flake.
    fn normals(n: usize, seed: u64) -> Vec<f64> {
        crate::stats::normals_from_state(n, seed)
    }

    fn image(f: impl Fn(u32, u32, usize) -> f64) -> Image {
        let data = (0..W * H).map(|i| f(i % W, i / W, i as usize) as f32).collect();
        Image::from_vec(W, H, data)
    }

    fn full() -> Image {
        Image::from_vec(W, H, vec![1.0; (W * H) as usize])
    }

    /// White noise of sd 0.05 plus `pattern` of amplitude `a` (a fraction of the noise).
    fn z_of(pattern: impl Fn(f64, f64) -> f64, a: f64, seed: u64) -> f64 {
        let noise = normals((W * H) as usize, seed);
        let img = image(|x, y, i| 0.05 * noise[i] + 0.05 * a * pattern(x as f64, y as f64));
        whiteness(&img, &full()).z
    }

    #[test]
    fn the_padded_pass_sums_as_the_pairs_do_bit_for_bit() {
        for (w, h, seed) in [(1, 1, 1), (3, 2, 2), (9, 5, 3), (40, 7, 4), (37, 23, 5)] {
            let n = (w * h) as usize;
            let z = normals(n, seed);
            // Every third pixel uncovered (its error 0, as `whiteness` makes it), some covered ones
            // exactly 0.
            let mask = Image::from_vec(w, h, (0..n).map(|i| if i % 3 == 1 { 0.0 } else { 1.0 }).collect());
            let e: Vec<f64> =
                (0..n).map(|i| if i % 3 == 1 || i % 7 == 0 { 0.0 } else { 0.05 * z[i] - 0.01 }).collect();
            let (a, b) =
                (lag_sums(&e, &mask, w as i32, h as i32), pairwise_sums(&e, &mask, w as i32, h as i32));
            assert_eq!(a.len(), b.len());
            for (k, (x, y)) in a.iter().zip(&b).enumerate() {
                assert_eq!(
                    (x.0.to_bits(), x.1.to_bits()),
                    (y.0.to_bits(), y.1.to_bits()),
                    "{w}x{h}, lag {k}"
                );
            }
        }
    }

    #[test]
    fn lag_window_is_the_half_plane() {
        let l = lags();
        assert_eq!(l.len(), 40);
        for &(dx, dy) in &l {
            assert!(!l.contains(&(-dx, -dy)), "({dx}, {dy}) and its mirror both counted");
        }
    }

    #[test]
    fn white_noise_is_not_structured() {
        let zs: Vec<f64> = (0..20).map(|s| z_of(|_, _| 0.0, 0.0, s)).collect();
        let mean = zs.iter().sum::<f64>() / zs.len() as f64;
        assert!(zs.iter().all(|z| z.abs() < 4.0), "{zs:.2?}");
        assert!(mean.abs() < 1.0, "mean z {mean:.2} over 20 white images: {zs:.2?}");
    }

    #[test]
    fn heteroscedastic_white_noise_is_not_structured() {
        // Noise only in blobs (the rest exactly 0, like open AO pixels), independent per pixel: the
        // variance is clustered but the values are not correlated.
        let noise = normals((W * H) as usize, 9);
        let img = image(|x, y, i| {
            let blob = ((x / 12) + (y / 12)) % 2 == 0;
            if blob { 0.1 * noise[i] } else { 0.0 }
        });
        let z = whiteness(&img, &full()).z;
        assert!(z.abs() < 4.0, "z = {z:.2}");
    }

    #[test]
    fn every_kind_of_pattern_is_structured() {
        use std::f64::consts::PI;
        type Pattern = Box<dyn Fn(f64, f64) -> f64>;
        let patterns: [(&str, Pattern); 6] = [
            ("horizontal bands", Box::new(|_, y| (2.0 * PI * y / 6.0).sin())),
            ("vertical bands", Box::new(|x, _| (2.0 * PI * x / 6.0).sin())),
            ("45 degree stripes", Box::new(|x, y| (2.0 * PI * (x + y) / 5.0).sin())),
            ("-45 degree stripes", Box::new(|x, y| (2.0 * PI * (x - y) / 7.0).sin())),
            ("period-2 checkerboard", Box::new(|x, y| if (x + y) as i64 % 2 == 0 { 1.0 } else { -1.0 })),
            (
                "smooth blotches",
                Box::new(|x, y| (x / 9.0).sin() * (y / 7.0).cos() + (0.7 * x / 11.0 + y / 13.0).sin()),
            ),
        ];
        for (name, p) in patterns {
            // A pattern half as strong as the noise: clearly there, though RMSE barely moves.
            let z = z_of(&p, 0.5, 3);
            assert!(z > 3.0 * STRUCTURED_Z, "{name}: z = {z:.1}");
        }
    }

    #[test]
    fn diagonal_and_checkerboard_patterns_escape_the_lag1_axis_metric_but_not_this_one() {
        // A checkerboard of period 2 along the diagonal only: x and y lag-1 autocorrelation are both
        // -1 for a full checkerboard, so take stripes along x - y of period 4 instead: lag (1, 0) and
        // (0, 1) see cos(π/2) = 0 correlation.
        use std::f64::consts::PI;
        let noise = normals((W * H) as usize, 4);
        let img = image(|x, y, i| 0.05 * noise[i] + 0.05 * (PI * (x as f64 - y as f64) / 2.0).cos());
        let (rx, ry) = super::super::autocorrelation(&img, &full());
        assert!(rx.abs() < 0.05 && ry.abs() < 0.05, "axis lag-1 sees nothing: {rx:.3} {ry:.3}");
        assert!(whiteness(&img, &full()).z > 10.0 * STRUCTURED_Z);
    }

    #[test]
    fn masked_pixels_and_constant_errors() {
        let noise = normals((W * H) as usize, 5);
        // Background (mask 0) carries a strong pattern that must be ignored.
        let img = image(|x, _, i| if x < W / 2 { 0.05 * noise[i] } else { (x % 2) as f64 });
        let mask = image(|x, _, _| if x < W / 2 { 1.0 } else { 0.0 });
        assert!(whiteness(&img, &mask).z.abs() < 4.0);
        let flat = image(|_, _, _| 0.25);
        assert_eq!(whiteness(&flat, &full()), Whiteness { q: 0.0, lags: 0, z: 0.0 });
        let none = image(|_, _, _| 0.0);
        assert_eq!(whiteness(&img, &none).z, 0.0);
    }

    #[test]
    fn wilson_hilferty_matches_the_exact_chi2_tail() {
        // z from the exact tail, -Φ⁻¹(P(χ²_k ≥ q)) (statrs), against the closed form, over the range
        // where the tail is representable.
        // With the 40 lags used: within 0.1 up to z = 5 (the structured threshold), within 0.5 to z = 9.
        for q in [15.0, 25.0, 40.0, 55.0, 70.0, 80.0, 100.0, 120.0, 150.0] {
            let exact = -normal_quantile(chi2_p_value(q, lags().len()));
            let wh = wilson_hilferty_z(q, lags().len());
            let tol = if exact.abs() <= 5.0 { 0.1 } else { 0.5 };
            assert!(exact.is_finite() && exact < 9.5, "q {q}: exact z {exact}");
            assert!((wh - exact).abs() < tol, "q {q}: {wh:.3} vs {exact:.3}");
        }
        assert!(wilson_hilferty_z(1e6, 40) > wilson_hilferty_z(1e5, 40));
    }
}
