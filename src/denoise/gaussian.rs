//! The Gaussian blur as a normalized convolution over covered pixels (Knutsson & Westin 1993,
//! "Normalized and differential convolution"): Σ_j G_ij m_j v_j / Σ_j G_ij m_j with m the coverage,
//! so background pixels and the image border neither dilute nor leak into a surface's values. The
//! one Gaussian of hemilab: the `gauss` filter here, and the low pass `metrics` measures error with.

use crate::image::{Image, covered};
use rayon::prelude::*;

/// σ of the `gauss` filter, in pixels: the width of the low pass error is measured with
/// (`metrics::LOWPASS_SIGMA`), so that the filter removes what that measure calls noise.
pub const GAUSS_SIGMA: f64 = 1.5;

/// The taps g(k) = exp(−k² / 2σ²), k = −⌈3σ⌉..=⌈3σ⌉, of the separable Gaussian (unnormalized).
pub fn taps(sigma: f64) -> Vec<f64> {
    let radius = (3.0 * sigma).ceil().max(0.0) as isize;
    (-radius..=radius).map(|k| (-((k * k) as f64) / (2.0 * sigma * sigma).max(1e-12)).exp()).collect()
}

/// `src` (w × h, zero outside the image) convolved with `kernel` (odd length, centred) along x, then
/// along y. The 2-D kernel is kernel(kx) · kernel(ky). Rows in parallel; each output is the same
/// in-order sum whatever the thread count.
pub fn separable(src: &[f64], w: usize, h: usize, kernel: &[f64]) -> Vec<f64> {
    let radius = (kernel.len() / 2) as isize;
    let pass = |src: &[f64], horizontal: bool| -> Vec<f64> {
        let mut out = vec![0.0; src.len()];
        out.par_chunks_mut(w.max(1)).enumerate().for_each(|(y, row)| {
            for (x, o) in row.iter_mut().enumerate() {
                let mut acc = 0.0;
                for (ki, k) in (-radius..=radius).enumerate() {
                    let (sx, sy) =
                        if horizontal { (x as isize + k, y as isize) } else { (x as isize, y as isize + k) };
                    if sx >= 0 && sy >= 0 && (sx as usize) < w && (sy as usize) < h {
                        acc += kernel[ki] * src[sy as usize * w + sx as usize];
                    }
                }
                *o = acc;
            }
        });
        out
    };
    pass(&pass(src, true), false)
}

/// The mask as 1 / 0 and the values as f64, zero off the mask.
pub fn masked(img: &Image, mask: &Image) -> (Vec<f64>, Vec<f64>) {
    let m: Vec<f64> = (0..img.len()).map(|i| if covered(mask, i) { 1.0 } else { 0.0 }).collect();
    let v: Vec<f64> = (0..img.len()).map(|i| m[i] * img.data[i] as f64).collect();
    (m, v)
}

/// `img` blurred by a Gaussian of `sigma` pixels over the pixels `coverage` marks; background
/// pixels (coverage 0) are left as they are. A constant surface stays that constant (up to the
/// f32 rounding of a ratio of f64 sums).
pub fn gaussian(img: &Image, coverage: &Image, sigma: f64) -> Image {
    assert!(img.same_size(coverage), "gaussian: image and coverage differ in size");
    let (w, h) = (img.width as usize, img.height as usize);
    let g = taps(sigma);
    let (m, v) = masked(img, coverage);
    let num = separable(&v, w, h, &g);
    let den = separable(&m, w, h, &g);
    let data = (0..img.len())
        .map(|i| if m[i] > 0.0 && den[i] > 0.0 { (num[i] / den[i]) as f32 } else { img.data[i] })
        .collect();
    Image::from_vec(img.width, img.height, data)
}
