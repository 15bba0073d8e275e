//! The split of a configuration's error into bias and noise, measured from its replicates (R images
//! of one configuration that differ only in the seed), over the covered pixels of the reference:
//!
//! - bias² = mean over pixels of (x̄ − ref)² − s²/R, x̄ the pixel's mean over the replicates and s²
//!   its unbiased sample variance: (x̄ − ref)² overstates the squared bias by the variance of the
//!   mean, s²/R, which is taken off, so the estimate is unbiased (it may come out below 0 on an
//!   unbiased estimator; `bias_rmse` clips it there);
//! - noise² = mean over pixels of s²: what a new seed changes;
//! - bias² + noise² is exactly the mean over the replicates of their MSE (both sides expand to
//!   mean_px (x̄ − ref)² + (R − 1)/R · s²), so the two parts always add up to what RMSE measures;
//! - the standard error of bias² by the jackknife over replicates: θ₋ᵢ the estimate without
//!   replicate i, se² = (R − 1)/R · Σ (θ₋ᵢ − θ̄)² (Efron & Stein 1981). It needs R ≥ 3 (each
//!   leave-one-out estimate needs a variance of its own).
//!
//! Unlike the joint application (the reference pushed through the same filter weights), this needs
//! nothing of the filter: it is what the field means by a filter's bias, E\[F(x)\] − ref, for any
//! filter, linear or not, and for a user's denoiser. With one replicate nothing is measured (NaN).
//! Pure: images in, numbers out.

use crate::image::{Image, covered};

/// A configuration's bias and noise (module doc). Squared values, unclipped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Split {
    pub replicates: usize,
    /// bias² (unclipped: may be slightly below 0); NaN with one replicate.
    pub bias2: f64,
    /// noise² = mean s²; NaN with one replicate.
    pub noise2: f64,
    /// The jackknife standard error of `bias2`; NaN below three replicates.
    pub bias2_se: f64,
}

impl Split {
    /// √max(bias², 0).
    pub fn bias_rmse(&self) -> f64 {
        if self.bias2.is_nan() { f64::NAN } else { self.bias2.max(0.0).sqrt() }
    }

    /// √noise².
    pub fn noise_rmse(&self) -> f64 {
        self.noise2.sqrt()
    }

    /// The standard error of `bias_rmse` by the delta method, se(bias²) / (2 bias); NaN where bias
    /// is 0 (the interval of bias² says more there: `bias2_se`).
    pub fn bias_rmse_se(&self) -> f64 {
        let b = self.bias_rmse();
        if b > 0.0 { self.bias2_se / (2.0 * b) } else { f64::NAN }
    }
}

/// (bias², noise²) of `images` (each covered pixel's values at `pixels`).
fn parts(images: &[&Image], reference: &Image, pixels: &[usize]) -> (f64, f64) {
    let r = images.len() as f64;
    let (mut bias2, mut noise2) = (0.0f64, 0.0f64);
    for &i in pixels {
        let mean = images.iter().map(|im| im.data[i] as f64).sum::<f64>() / r;
        let s2 = images.iter().map(|im| (im.data[i] as f64 - mean).powi(2)).sum::<f64>() / (r - 1.0);
        let d = mean - reference.data[i] as f64;
        bias2 += d * d - s2 / r;
        noise2 += s2;
    }
    let n = pixels.len() as f64;
    (bias2 / n, noise2 / n)
}

/// The split of `images` (the replicates, in any order) against `reference` over the pixels
/// `mask` covers; `None` when an image's size differs from the reference's or the mask's, or no
/// pixel is covered (nothing to measure; `metrics::measure` has refused such an image already).
pub fn split(images: &[&Image], reference: &Image, mask: &Image) -> Option<Split> {
    if !reference.same_size(mask) || images.iter().any(|im| !im.same_size(reference)) {
        return None;
    }
    let pixels: Vec<usize> = (0..mask.len()).filter(|&i| covered(mask, i)).collect();
    if pixels.is_empty() {
        return None;
    }
    let r = images.len();
    if r < 2 {
        return Some(Split { replicates: r, bias2: f64::NAN, noise2: f64::NAN, bias2_se: f64::NAN });
    }
    let (bias2, noise2) = parts(images, reference, &pixels);
    let bias2_se = if r < 3 {
        f64::NAN
    } else {
        let loo: Vec<f64> = (0..r)
            .map(|k| {
                let rest: Vec<&Image> =
                    images.iter().enumerate().filter(|(j, _)| *j != k).map(|(_, im)| *im).collect();
                parts(&rest, reference, &pixels).0
            })
            .collect();
        let m = loo.iter().sum::<f64>() / r as f64;
        ((r as f64 - 1.0) / r as f64 * loo.iter().map(|t| (t - m).powi(2)).sum::<f64>()).sqrt()
    };
    Some(Split { replicates: r, bias2, noise2, bias2_se })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn img(v: &[f32]) -> Image {
        Image::from_vec(v.len() as u32, 1, v.to_vec())
    }

    #[test]
    fn parts_add_up_to_the_mean_mse_and_one_replicate_measures_nothing() {
        let reference = img(&[0.5, 0.2, 0.9, 0.0]);
        let mask = img(&[1.0, 1.0, 1.0, 0.0]);
        let a = img(&[0.6, 0.1, 0.7, 5.0]);
        let b = img(&[0.3, 0.4, 0.8, -5.0]);
        let c = img(&[0.7, 0.2, 1.0, 2.0]);
        let s = split(&[&a, &b, &c], &reference, &mask).unwrap();
        let mse = |x: &Image| {
            (0..3).map(|i| (x.data[i] as f64 - reference.data[i] as f64).powi(2)).sum::<f64>() / 3.0
        };
        let mean_mse = (mse(&a) + mse(&b) + mse(&c)) / 3.0;
        assert!((s.bias2 + s.noise2 - mean_mse).abs() < 1e-12, "{s:?} {mean_mse}");
        assert!(s.bias2_se.is_finite());
        let one = split(&[&a], &reference, &mask).unwrap();
        assert!(one.bias2.is_nan() && one.noise2.is_nan() && one.bias_rmse().is_nan());
        assert!(split(&[&a, &b], &reference, &mask).unwrap().bias2_se.is_nan(), "jackknife needs 3");
    }
}
