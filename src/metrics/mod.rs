//! Error statistics of an image against a reference, over covered pixels only (imports only
//! `crate::image`, `denoise`'s Gaussian for the low pass, and `stats` for distributions). RMSE and bias say how far off; the low-frequency
//! ratio (`lowfreq`: low-pass energy against white noise's, with a sign: < 1 blue, > 1 clumped), the
//! whiteness z-score (`whiteness`: a test of any correlation, every short lag, every direction), the
//! lag-1 autocorrelation and the low-pass RMSE say whether the error is *structured* — the paper's
//! Table 3 banding, which RMSE alone cannot see. `flicker` is a sequence's temporal stability.

pub mod flicker;
pub mod flip;
pub mod lowfreq;
pub mod whiteness;

pub use flicker::{flicker, flicker_sequence};
pub use flip::{DEFAULT_PPD, ldr_flip_map, mean_flip};
pub use lowfreq::{STRUCTURED_RATIO, lowfreq_ratio, lowpass_rmse};

use crate::image::Image;
use std::fmt;

pub use crate::image::covered;

#[derive(Debug, Clone, PartialEq)]
pub enum MetricsError {
    SizeMismatch { what: &'static str, expected: (u32, u32), got: (u32, u32) },
    NoCoveredPixels,
}

impl fmt::Display for MetricsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MetricsError::SizeMismatch { what, expected, got } => write!(
                f,
                "{what} is {}x{} but the image is {}x{}; mismatched images are never compared",
                got.0, got.1, expected.0, expected.1
            ),
            MetricsError::NoCoveredPixels => {
                write!(f, "no pixel is covered by the scene; nothing to measure")
            }
        }
    }
}

impl std::error::Error for MetricsError {}

/// Everything measured for one image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorStats {
    pub covered: usize,
    pub rmse: f64,
    /// Mean signed error (image − reference).
    pub bias: f64,
    pub autocorr_x: f64,
    pub autocorr_y: f64,
    pub lowpass_rmse: f64,
    /// z-score of the 2-D portmanteau statistic against white noise (`whiteness`): ~N(0, 1) for
    /// independent per-pixel noise, above `whiteness::STRUCTURED_Z` when *any* correlation is
    /// significant, negative (blue noise) or positive — a test, which grows with the pixel count.
    pub whiteness_z: f64,
    /// Low-pass energy of the error over that of independent errors of the same magnitudes
    /// (`lowfreq`): 1 = white, < 1 = blue, above `STRUCTURED_RATIO` = clumped or banded; the same
    /// at any image size. The structure verdict of the report and of `advise`.
    pub lowfreq_ratio: f64,
}

/// Width of the low-pass, in pixels: wide enough to average pixel noise away, narrow enough to keep
/// bands. A property of the error measure, set here; that the `gauss` filter has the same width
/// (`denoise::GAUSS_SIGMA`) is the filter's choice.
pub const LOWPASS_SIGMA: f64 = 1.5;

fn check(image: &Image, other: &Image, what: &'static str) -> Result<(), MetricsError> {
    if image.same_size(other) {
        Ok(())
    } else {
        Err(MetricsError::SizeMismatch {
            what,
            expected: (image.width, image.height),
            got: (other.width, other.height),
        })
    }
}

/// image − reference on covered pixels, 0 elsewhere.
pub fn error_image(image: &Image, reference: &Image, mask: &Image) -> Result<Image, MetricsError> {
    check(image, reference, "the reference")?;
    check(image, mask, "the coverage mask")?;
    let data = (0..image.len())
        .map(|i| if covered(mask, i) { image.data[i] - reference.data[i] } else { 0.0 })
        .collect();
    Ok(Image::from_vec(image.width, image.height, data))
}

/// All metrics of one image at once.
pub fn measure(image: &Image, reference: &Image, mask: &Image) -> Result<ErrorStats, MetricsError> {
    let err = error_image(image, reference, mask)?;
    let n = (0..mask.len()).filter(|&i| covered(mask, i)).count();
    if n == 0 {
        return Err(MetricsError::NoCoveredPixels);
    }
    let (rmse, bias) = rmse_bias(&err, mask);
    let (autocorr_x, autocorr_y) = autocorrelation(&err, mask);
    Ok(ErrorStats {
        covered: n,
        rmse,
        bias,
        autocorr_x,
        autocorr_y,
        lowpass_rmse: lowpass_rmse(&err, mask, LOWPASS_SIGMA),
        whiteness_z: whiteness::whiteness(&err, mask).z,
        lowfreq_ratio: lowfreq_ratio(&err, mask, LOWPASS_SIGMA),
    })
}

/// (RMS, mean) of an error image over covered pixels; (0, 0) when nothing is covered.
pub fn rmse_bias(err: &Image, mask: &Image) -> (f64, f64) {
    let (mut n, mut sum, mut sq) = (0usize, 0.0f64, 0.0f64);
    for i in (0..err.len()).filter(|&i| covered(mask, i)) {
        let e = err.data[i] as f64;
        n += 1;
        sum += e;
        sq += e * e;
    }
    if n == 0 { (0.0, 0.0) } else { ((sq / n as f64).sqrt(), sum / n as f64) }
}

/// Error spread below this counts as a constant error (AO lies in [0, 1]; f32 resolves ~6e-8).
pub const CONSTANT_SD: f64 = 1e-6;

/// Lag-1 autocorrelation of the error (minus its mean) along x and along y, over pairs of covered
/// neighbours, normalized by the variance. A constant error (sd ≤ `CONSTANT_SD`) or no pairs gives 0.
pub fn autocorrelation(err: &Image, mask: &Image) -> (f64, f64) {
    let (w, h) = (err.width as usize, err.height as usize);
    let (_, mean) = rmse_bias(err, mask);
    let (mut n, mut var) = (0usize, 0.0f64);
    for i in (0..err.len()).filter(|&i| covered(mask, i)) {
        let d = err.data[i] as f64 - mean;
        var += d * d;
        n += 1;
    }
    if n == 0 {
        return (0.0, 0.0);
    }
    var /= n as f64;
    // A constant error stored in f32 still carries rounding noise (~1e-7 for AO values in [0, 1]);
    // that must read as "no structure", not as a correlation of rounding.
    if var.sqrt() <= CONSTANT_SD {
        return (0.0, 0.0);
    }
    let lag = |step: usize, ok: &dyn Fn(usize) -> bool| {
        let (mut pairs, mut sum) = (0usize, 0.0f64);
        for i in 0..err.len() {
            if ok(i) && covered(mask, i) && covered(mask, i + step) {
                sum += (err.data[i] as f64 - mean) * (err.data[i + step] as f64 - mean);
                pairs += 1;
            }
        }
        if pairs == 0 { 0.0 } else { sum / pairs as f64 / var }
    };
    let x = lag(1, &|i| i % w + 1 < w);
    let y = lag(w, &|i| i / w + 1 < h);
    (x, y)
}

/// Error per unit of work: 1 / (MSE · time). `None` when MSE · time is 0 or not finite (a perfect
/// or unmeasured run has no meaningful efficiency).
pub fn efficiency(rmse: f64, time_s: f64) -> Option<f64> {
    let p = rmse * rmse * time_s;
    (p > 0.0 && p.is_finite()).then(|| 1.0 / p)
}

/// Mean and sample standard deviation (n − 1; 0 for a single value) of the finite values.
pub fn mean_sd(values: &[f64]) -> (f64, f64) {
    let v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let sd = if v.len() < 2 {
        0.0
    } else {
        (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    };
    (mean, sd)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn efficiency_and_mean_sd() {
        assert!((efficiency(0.1, 2.0).unwrap() - 50.0).abs() < 1e-9);
        assert_eq!(efficiency(0.0, 2.0), None);
        assert_eq!(efficiency(0.1, 0.0), None);
        let (m, s) = mean_sd(&[1.0, 2.0, 3.0]);
        assert!((m - 2.0).abs() < 1e-12 && (s - 1.0).abs() < 1e-12);
        assert_eq!(mean_sd(&[5.0]), (5.0, 0.0));
    }
}
