//! The edge-avoiding à-trous wavelet filter (Dammertz, Sewtz, Hanika & Lensch 2010, "Edge-Avoiding
//! À-Trous Wavelet Transform for fast Global Illumination Filtering"), with the edge-stopping
//! functions of SVGF's spatial filter (Schied et al. 2017, "Spatiotemporal Variance-Guided
//! Filtering", eq. 3-5): iteration i convolves with the 5 × 5 B3-spline kernel h(kx)·h(ky),
//! h = (1, 4, 6, 4, 1)/16, its taps 2^i pixels apart ("with holes"), each tap also weighted by
//! the depth and normal weights of `edges` (w_z, w_n) and by
//!
//!   w_l = exp(−(l_p − l_q)² / (σ_l² 2^−i))                        value (optional, Dammertz's)
//!
//! and normalized by the weights' sum, over covered pixels inside the image only. The value weight
//! is Dammertz's (σ halved each iteration) rather than SVGF's variance-scaled one (`svgf`), since
//! one frame has no variance estimate; it is off by default: at a few AO rays per pixel the noise
//! is as large as any edge in the value. The number of iterations defaults to a share of the
//! image (`edges::default_iterations`).
//!
//! `atrous_pair` is the joint application of the noise/bias split: the weights computed on the
//! (noisy) image applied to a second one, the reference, so that RMSE(F_w(noisy), F_w(reference))
//! is the filtered noise and RMSE(F_w(reference), reference) the filter's bias. Without a value
//! weight the weights do not depend on the image and it is `atrous` applied to each.

use super::edges::{Guide, Taps, default_iterations};
use super::taps::Pass;
use crate::image::Image;
use crate::render::GBuffer;
use rayon::prelude::*;

/// The filter's parameters; `Default` is SVGF's σ_z = 1, σ_n = 128, the share-of-image iteration
/// count (`edges::default_iterations`) and no value weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AtrousParams {
    /// The number of passes; None: `edges::default_iterations` of the image's size.
    pub iterations: Option<u32>,
    /// σ_z: how many depth gradients' worth of difference weighs e⁻¹.
    pub sigma_depth: f32,
    /// σ_n: the exponent on the normals' cosine.
    pub sigma_normal: f32,
    /// σ_l in the image's units (AO: 0…1), or None for no value weight.
    pub sigma_value: Option<f32>,
}

impl Default for AtrousParams {
    fn default() -> Self {
        Self { iterations: None, sigma_depth: 1.0, sigma_normal: 128.0, sigma_value: None }
    }
}

impl AtrousParams {
    /// `params` with `iterations` passes.
    pub fn with_iterations(self, iterations: u32) -> Self {
        Self { iterations: Some(iterations), ..self }
    }

    /// The number of passes on a `width` × `height` image.
    pub fn iterations_for(&self, width: u32, height: u32) -> u32 {
        self.iterations.unwrap_or_else(|| default_iterations(width, height))
    }
}

/// `img` filtered by the edge-avoiding à-trous transform guided by `gbuf` (module doc). Background
/// pixels are left as they are and never contribute. Rows in parallel, every sum in a fixed
/// order: bit-identical for any thread count.
pub fn atrous(img: &Image, gbuf: &GBuffer, params: &AtrousParams) -> Image {
    run(img, None, gbuf, params).0
}

/// The joint application (module doc): `img` filtered as by `atrous`, and `reference` filtered
/// with the weights computed on `img` (each pass's weights from that pass's `img`).
pub fn atrous_pair(img: &Image, reference: &Image, gbuf: &GBuffer, params: &AtrousParams) -> (Image, Image) {
    let (out, r) = run(img, Some(reference), gbuf, params);
    (out, r.expect("a reference was given"))
}

fn run(
    img: &Image,
    reference: Option<&Image>,
    gbuf: &GBuffer,
    params: &AtrousParams,
) -> (Image, Option<Image>) {
    assert!(
        img.width == gbuf.width && img.height == gbuf.height,
        "atrous: the image is {}x{}, its G-buffer {}x{}",
        img.width,
        img.height,
        gbuf.width,
        gbuf.height
    );
    if let Some(r) = reference {
        assert!(
            r.same_size(img),
            "atrous: the reference is {}x{}, the image {}x{}",
            r.width,
            r.height,
            img.width,
            img.height
        );
    }
    let guide = Guide::new(gbuf, params.sigma_depth, params.sigma_normal);
    let w = img.width as usize;
    let mut cur = img.data.clone();
    let mut cur_ref = reference.map(|r| r.data.clone());
    for it in 0..params.iterations_for(img.width, img.height) {
        let value_scale = params.sigma_value.map(|s| 1.0 / ((s as f64).powi(2) * 0.5f64.powi(it as i32)));
        let (src, src_ref) = (&cur, cur_ref.as_deref());
        let mut next = vec![0.0f32; src.len()];
        let mut next_ref = vec![0.0f32; if src_ref.is_some() { src.len() } else { 0 }];
        let taps_of = Pass::new(&guide, it);
        let pass = |y: usize, row: &mut [f32], row_ref: Option<&mut [f32]>| {
            let mut taps: Taps = [(0, 0.0); 25];
            let mut row_ref = row_ref;
            for x in 0..row.len() {
                let p = y * w + x;
                if !guide.is_covered(p) {
                    row[x] = src[p];
                    if let (Some(rr), Some(sr)) = (row_ref.as_deref_mut(), src_ref) {
                        rr[x] = sr[p];
                    }
                    continue;
                }
                let k = taps_of.taps(x as i64, y as i64, &mut taps);
                let lp = src[p] as f64;
                let (mut sum, mut sum_ref, mut wsum) = (0.0f64, 0.0f64, 0.0f64);
                for &(q, g) in &taps[..k] {
                    let lq = src[q] as f64;
                    let wl = value_scale.map_or(1.0, |s| (-(lp - lq) * (lp - lq) * s).exp());
                    let wgt = g * wl;
                    sum += wgt * lq;
                    if let Some(sr) = src_ref {
                        sum_ref += wgt * sr[q] as f64;
                    }
                    wsum += wgt;
                }
                row[x] = if wsum > 0.0 { (sum / wsum) as f32 } else { src[p] };
                if let (Some(rr), Some(sr)) = (row_ref.as_deref_mut(), src_ref) {
                    rr[x] = if wsum > 0.0 { (sum_ref / wsum) as f32 } else { sr[p] };
                }
            }
        };
        if src_ref.is_some() {
            next.par_chunks_mut(w.max(1))
                .zip(next_ref.par_chunks_mut(w.max(1)))
                .enumerate()
                .for_each(|(y, (row, row_ref))| pass(y, row, Some(row_ref)));
            cur_ref = Some(next_ref);
        } else {
            next.par_chunks_mut(w.max(1)).enumerate().for_each(|(y, row)| pass(y, row, None));
        }
        cur = next;
    }
    (Image::from_vec(img.width, img.height, cur), cur_ref.map(|d| Image::from_vec(img.width, img.height, d)))
}
