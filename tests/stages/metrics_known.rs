//! Metrics on synthetic images with known answers.

use hemilab::image::Image;
use hemilab::metrics::{MetricsError, autocorrelation, efficiency, error_image, lowpass_rmse, measure};

/// The slope of the least-squares line through (ln x, ln y) (`stats::loglog_fit`, the one log-log
/// fit of the crate).
fn loglog_slope(xs: &[f64], ys: &[f64]) -> Option<f64> {
    hemilab::stats::loglog_fit(xs, ys).map(|f| f.slope)
}

/// Deterministic uniform numbers in [0, 1) (SplitMix64), so no test can flake.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> f32) -> Image {
    Image::from_vec(w, h, (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).map(|(x, y)| f(x, y)).collect())
}

fn full(w: u32, h: u32) -> Image {
    image(w, h, |_, _| 1.0)
}

fn reference(w: u32, h: u32) -> Image {
    image(w, h, |x, y| 0.2 + 0.5 * ((x * 7 + y * 3) % 11) as f32 / 11.0)
}

#[test]
fn constant_offset_gives_rmse_and_bias_of_the_offset() {
    let r = reference(40, 30);
    // Background pixels (x < 5) are wildly off and must not count.
    let mask = image(40, 30, |x, _| if x < 5 { 0.0 } else { 1.0 });
    let img = image(40, 30, |x, y| if x < 5 { 100.0 } else { r.at(x, y) + 0.125 });
    let s = measure(&img, &r, &mask).unwrap();
    assert_eq!(s.covered, 35 * 30);
    assert!((s.rmse - 0.125).abs() < 1e-6, "{s:?}");
    assert!((s.bias - 0.125).abs() < 1e-6, "{s:?}");
    // Constant error: variance 0 → autocorrelation defined as 0, never NaN.
    assert_eq!((s.autocorr_x, s.autocorr_y), (0.0, 0.0));
    // The blur is normalized over covered pixels, so the masked edge does not dilute the offset.
    assert!((s.lowpass_rmse - 0.125).abs() < 1e-6, "{s:?}");

    let neg = image(40, 30, |x, y| r.at(x, y) - 0.25);
    let s = measure(&neg, &r, &full(40, 30)).unwrap();
    assert!((s.rmse - 0.25).abs() < 1e-6 && (s.bias + 0.25).abs() < 1e-6, "{s:?}");
}

#[test]
fn pure_noise_is_uncorrelated_and_blurs_away() {
    let r = reference(128, 128);
    let mut rng = Rng(42);
    let noise: Vec<f32> = (0..128 * 128).map(|_| rng.next() - 0.5).collect();
    let img = image(128, 128, |x, y| r.at(x, y) + noise[(y * 128 + x) as usize]);
    let s = measure(&img, &r, &full(128, 128)).unwrap();
    // Uniform on [-1/2, 1/2]: RMS 1/sqrt(12).
    assert!((s.rmse - (1.0f64 / 12.0).sqrt()).abs() < 0.01, "{s:?}");
    assert!(s.bias.abs() < 0.01, "{s:?}");
    assert!(s.autocorr_x.abs() < 0.03 && s.autocorr_y.abs() < 0.03, "{s:?}");
    // A Gaussian of sigma 1.5 px shrinks white noise by about 1/(2 sqrt(pi) sigma) ≈ 0.19.
    assert!(s.lowpass_rmse < 0.3 * s.rmse, "{s:?}");
}

#[test]
fn bands_are_correlated_and_survive_the_blur() {
    // Constant along x; in y, bands 8 pixels tall with random levels: the static-seed look.
    let r = reference(64, 64);
    let mut rng = Rng(7);
    let levels: Vec<f32> = (0..8).map(|_| rng.next() - 0.5).collect();
    let img = image(64, 64, |x, y| r.at(x, y) + levels[(y / 8) as usize]);
    let s = measure(&img, &r, &full(64, 64)).unwrap();
    assert!(s.autocorr_x > 0.99, "{s:?}");
    assert!(s.autocorr_y > 0.7, "{s:?}");
    assert!(s.lowpass_rmse > 0.8 * s.rmse, "{s:?}");
}

#[test]
fn checkerboard_is_anticorrelated() {
    let r = reference(32, 32);
    let img = image(32, 32, |x, y| r.at(x, y) + if (x + y) % 2 == 0 { 0.1 } else { -0.1 });
    let s = measure(&img, &r, &full(32, 32)).unwrap();
    assert!(s.autocorr_x < -0.99 && s.autocorr_y < -0.99, "{s:?}");
    assert!(s.lowpass_rmse < 0.1 * s.rmse, "{s:?}");
}

#[test]
fn mask_excludes_pixels_from_every_metric() {
    let r = reference(64, 64);
    let mut rng = Rng(3);
    let noise: Vec<f32> = (0..64 * 64).map(|_| rng.next() - 0.5).collect();
    // Every other column is background, holding a smooth (perfectly correlated) error.
    let mask = image(64, 64, |x, _| (x % 2) as f32);
    let img = image(64, 64, |x, y| r.at(x, y) + if x % 2 == 1 { noise[(y * 64 + x) as usize] } else { 5.0 });
    let s = measure(&img, &r, &mask).unwrap();
    assert_eq!(s.covered, 32 * 64);
    assert!(s.bias.abs() < 0.03 && s.rmse < 0.35, "{s:?}");
    // No horizontal pair has both pixels covered.
    assert_eq!(s.autocorr_x, 0.0);
    assert!(s.autocorr_y.abs() < 0.05, "{s:?}");
    // Error only on background: nothing measured.
    let img = image(64, 64, |x, y| if x % 2 == 0 { 9.0 } else { r.at(x, y) });
    let s = measure(&img, &r, &mask).unwrap();
    assert_eq!((s.rmse, s.bias, s.lowpass_rmse), (0.0, 0.0, 0.0));
    let e = error_image(&img, &r, &mask).unwrap();
    assert!(e.data.iter().all(|&v| v == 0.0));
    let (ax, ay) = autocorrelation(&e, &mask);
    assert_eq!((ax, ay), (0.0, 0.0));
    assert_eq!(lowpass_rmse(&e, &mask, 1.5), 0.0);
}

#[test]
fn mismatched_or_empty_inputs_are_errors_not_panics() {
    let r = reference(8, 8);
    let small = reference(8, 4);
    assert!(matches!(measure(&small, &r, &full(8, 4)), Err(MetricsError::SizeMismatch { .. })));
    assert!(matches!(measure(&r, &r, &full(4, 8)), Err(MetricsError::SizeMismatch { .. })));
    let none = image(8, 8, |_, _| 0.0);
    let e = measure(&r, &r, &none).unwrap_err();
    assert_eq!(e, MetricsError::NoCoveredPixels);
    assert!(e.to_string().contains("no pixel"));
}

#[test]
fn loglog_slopes_of_power_laws() {
    let xs: Vec<f64> = (0..=10).map(|k| (1u32 << k) as f64).collect();
    let half: Vec<f64> = xs.iter().map(|x| 0.3 * x.powf(-0.5)).collect();
    assert!((loglog_slope(&xs, &half).unwrap() + 0.5).abs() < 1e-12);
    let three_q: Vec<f64> = xs.iter().map(|x| 2.0 * x.powf(-0.75)).collect();
    assert!((loglog_slope(&xs, &three_q).unwrap() + 0.75).abs() < 1e-12);
    // Zeros (a perfect image) are skipped, not turned into -inf.
    let mut with_zero = half.clone();
    with_zero[3] = 0.0;
    assert!((loglog_slope(&xs, &with_zero).unwrap() + 0.5).abs() < 1e-12);
}

#[test]
fn efficiency_is_inverse_mse_times_time() {
    assert!((efficiency(0.05, 2.0).unwrap() - 1.0 / (0.0025 * 2.0)).abs() < 1e-9);
    assert_eq!(efficiency(0.05, 0.0), None);
}
