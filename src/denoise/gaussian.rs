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
/// in-order sum whatever the thread count: 0 + k₀s₀ + k₁s₁ + … over the taps inside the image, in
/// tap order. Where every tap is inside, the sums are made tap by tap over a whole run of outputs
/// (each output's own sum still in tap order, so the same bits), a loop the compiler vectorizes:
/// with a bounds test per tap, the low-pass metrics built on this took 9.1 of the 12.5 ms that
/// `metrics::measure` spent on a 320x180 frame (one thread), 2.5 ms now.
pub fn separable(src: &[f64], w: usize, h: usize, kernel: &[f64]) -> Vec<f64> {
    let r = kernel.len() / 2;
    // Outputs i with every tap inside 0..n: r..n − r.
    let inner = |n: usize| r.min(n)..n.saturating_sub(r).max(r.min(n));
    let edge = |n: usize, i: usize, at: &dyn Fn(usize) -> f64| -> f64 {
        let mut acc = 0.0;
        for (ki, k) in kernel.iter().enumerate() {
            // Source index i + ki − r, when inside 0..n.
            if let Some(j) = (i + ki).checked_sub(r).filter(|&j| j < n) {
                acc += k * at(j);
            }
        }
        acc
    };
    let mut across = vec![0.0; src.len()];
    across.par_chunks_mut(w.max(1)).zip(src.par_chunks(w.max(1))).for_each(|(row, s)| {
        let mid = inner(w);
        for x in (0..mid.start).chain(mid.end..w) {
            row[x] = edge(w, x, &|j| s[j]);
        }
        if mid.is_empty() {
            return;
        }
        let out = &mut row[mid.clone()];
        for (ki, k) in kernel.iter().enumerate() {
            let from = &s[mid.start + ki - r..mid.end + ki - r];
            for (o, v) in out.iter_mut().zip(from) {
                *o += k * v;
            }
        }
    });
    let mut out = vec![0.0; src.len()];
    let mid = inner(h);
    out.par_chunks_mut(w.max(1)).enumerate().for_each(|(y, row)| {
        if mid.contains(&y) {
            for (ki, k) in kernel.iter().enumerate() {
                let sy = y + ki - r;
                for (o, v) in row.iter_mut().zip(&across[sy * w..sy * w + w]) {
                    *o += k * v;
                }
            }
        } else {
            for (x, o) in row.iter_mut().enumerate() {
                *o = edge(h, y, &|j| across[j * w + x]);
            }
        }
    });
    out
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The definition: each output's sum over its taps inside the image, in tap order.
    fn by_definition(src: &[f64], w: usize, h: usize, kernel: &[f64]) -> Vec<f64> {
        let r = (kernel.len() / 2) as isize;
        let pass = |src: &[f64], horizontal: bool| -> Vec<f64> {
            (0..w * h)
                .map(|i| {
                    let (x, y) = ((i % w) as isize, (i / w) as isize);
                    let mut acc = 0.0;
                    for (ki, k) in (-r..=r).enumerate() {
                        let (sx, sy) = if horizontal { (x + k, y) } else { (x, y + k) };
                        if sx >= 0 && sy >= 0 && (sx as usize) < w && (sy as usize) < h {
                            acc += kernel[ki] * src[sy as usize * w + sx as usize];
                        }
                    }
                    acc
                })
                .collect()
        };
        pass(&pass(src, true), false)
    }

    #[test]
    fn the_separable_blur_sums_as_its_definition_bit_for_bit() {
        for sigma in [0.0, 0.5, 1.5, 3.0] {
            let kernel = taps(sigma);
            for (w, h) in [(1, 1), (3, 2), (2, 13), (11, 11), (12, 5), (37, 23)] {
                let src: Vec<f64> = (0..w * h)
                    .map(|i| {
                        let v = ((i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11) as f64
                            / (1u64 << 53) as f64;
                        if i % 5 == 0 { 0.0 } else { v - 0.3 }
                    })
                    .collect();
                let (a, b) = (separable(&src, w, h, &kernel), by_definition(&src, w, h, &kernel));
                assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()), "sigma {sigma}, {w}x{h}");
            }
        }
    }
}
