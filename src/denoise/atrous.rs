//! The edge-avoiding à-trous wavelet filter (Dammertz, Sewtz, Hanika & Lensch 2010, "Edge-Avoiding
//! À-Trous Wavelet Transform for fast Global Illumination Filtering"), with the edge-stopping
//! functions of SVGF's spatial filter (Schied et al. 2017, "Spatiotemporal Variance-Guided
//! Filtering", eq. 3-5): iteration i convolves with the 5 × 5 B3-spline kernel h(kx)·h(ky),
//! h = (1, 4, 6, 4, 1)/16, its taps 2^i pixels apart ("with holes"), each tap also weighted by
//!
//!   w_z = exp(−|z_p − z_q| / (σ_z |∇z_p · (q − p)| + ε z_p))      depth, scaled by its gradient
//!   w_n = max(0, n_p · n_q)^σ_n                                   normal
//!   w_l = exp(−(l_p − l_q)² / (σ_l² 2^−i))                        value (optional, Dammertz's)
//!
//! and normalized by the weights' sum, over covered pixels inside the image only. The depth
//! gradient is the smaller one-sided difference on each axis (so a pixel at a depth step takes its
//! own surface's slope, not the step's); ε z_p (ε = 10⁻³) keeps a fronto-parallel plane, whose
//! gradient is 0, open to its own rounding. The value weight is Dammertz's (σ halved each
//! iteration) rather than SVGF's variance-scaled one, since one frame has no variance estimate;
//! it is off by default: at a few AO rays per pixel the noise is as large as any edge in the value.

use crate::image::Image;
use crate::render::GBuffer;
use rayon::prelude::*;

/// The filter's parameters; `Default` is SVGF's σ_z = 1, σ_n = 128 and Dammertz's five iterations
/// (taps 1…16 pixels apart: a 125 × 125 footprint), no value weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AtrousParams {
    pub iterations: u32,
    /// σ_z: how many depth gradients' worth of difference weighs e⁻¹.
    pub sigma_depth: f32,
    /// σ_n: the exponent on the normals' cosine.
    pub sigma_normal: f32,
    /// σ_l in the image's units (AO: 0…1), or None for no value weight.
    pub sigma_value: Option<f32>,
}

impl Default for AtrousParams {
    fn default() -> Self {
        Self { iterations: 5, sigma_depth: 1.0, sigma_normal: 128.0, sigma_value: None }
    }
}

/// ε: the depth difference relative to the depth itself that is always tolerated.
const DEPTH_EPS: f32 = 1e-3;

/// The B3-spline taps at offsets −2..=2.
const B3: [f64; 5] = [1.0 / 16.0, 4.0 / 16.0, 6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0];

/// The per-pixel depth gradient (d/dx, d/dy): on each axis the one-sided difference of smaller
/// magnitude among covered neighbours (0 with none).
fn depth_gradient(g: &GBuffer) -> Vec<(f32, f32)> {
    let (w, h) = (g.width as i64, g.height as i64);
    let z = &g.depth.data;
    let at = |x: i64, y: i64| -> Option<f32> {
        let i = (y * w + x) as usize;
        (x >= 0 && y >= 0 && x < w && y < h && g.is_covered(i)).then(|| z[i])
    };
    let axis = |c: f32, a: Option<f32>, b: Option<f32>| -> f32 {
        match (a.map(|a| c - a), b.map(|b| b - c)) {
            (Some(d0), Some(d1)) => {
                if d0.abs() <= d1.abs() {
                    d0
                } else {
                    d1
                }
            }
            (Some(d), None) | (None, Some(d)) => d,
            (None, None) => 0.0,
        }
    };
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let c = z[i as usize];
            (axis(c, at(x - 1, y), at(x + 1, y)), axis(c, at(x, y - 1), at(x, y + 1)))
        })
        .collect()
}

/// `img` filtered by the edge-avoiding à-trous transform guided by `gbuf` (module doc). Background
/// pixels are left as they are and never contribute. Rows in parallel, every sum in a fixed
/// order: bit-identical for any thread count.
pub fn atrous(img: &Image, gbuf: &GBuffer, params: &AtrousParams) -> Image {
    assert!(
        img.width == gbuf.width && img.height == gbuf.height,
        "atrous: the image is {}x{}, its G-buffer {}x{}",
        img.width,
        img.height,
        gbuf.width,
        gbuf.height
    );
    let (w, h) = (img.width as i64, img.height as i64);
    let grad = depth_gradient(gbuf);
    let z = &gbuf.depth.data;
    let n = &gbuf.normal;
    let mut cur = img.data.clone();
    // A whole σ_n (SVGF's 128) by repeated squaring: within a few ulp of `powf`, at a fraction of
    // its cost (it was a third of a real-time run's filtering time).
    let normal_power = (params.sigma_normal.fract() == 0.0 && (0.0..=1024.0).contains(&params.sigma_normal))
        .then_some(params.sigma_normal as i32);
    for it in 0..params.iterations {
        let step = 1i64 << it.min(30);
        let value_scale = params.sigma_value.map(|s| 1.0 / ((s as f64).powi(2) * 0.5f64.powi(it as i32)));
        let src = &cur;
        let mut next = vec![0.0f32; src.len()];
        next.par_chunks_mut(w.max(1) as usize).enumerate().for_each(|(y, row)| {
            let y = y as i64;
            for (x, out) in row.iter_mut().enumerate() {
                let x = x as i64;
                let p = (y * w + x) as usize;
                if !gbuf.is_covered(p) {
                    *out = src[p];
                    continue;
                }
                let (zp, np, lp, (gx, gy)) = (z[p], n[p], src[p] as f64, grad[p]);
                let (mut sum, mut wsum) = (0.0f64, 0.0f64);
                for (ky, hy) in B3.iter().enumerate() {
                    let dy = (ky as i64 - 2) * step;
                    let qy = y + dy;
                    if qy < 0 || qy >= h {
                        continue;
                    }
                    for (kx, hx) in B3.iter().enumerate() {
                        let dx = (kx as i64 - 2) * step;
                        let qx = x + dx;
                        let q = (qy * w + qx) as usize;
                        if qx < 0 || qx >= w || !gbuf.is_covered(q) {
                            continue;
                        }
                        let dz = (zp - z[q]).abs();
                        let scale =
                            params.sigma_depth * (gx * dx as f32 + gy * dy as f32).abs() + DEPTH_EPS * zp;
                        let wz =
                            if dz == 0.0 { 1.0 } else { (-(dz / scale.max(f32::MIN_POSITIVE)) as f64).exp() };
                        let c = np.dot(n[q]).max(0.0) as f64;
                        let wn = match normal_power {
                            Some(k) => c.powi(k),
                            None => c.powf(params.sigma_normal as f64),
                        };
                        let lq = src[q] as f64;
                        let wl = value_scale.map_or(1.0, |s| (-(lp - lq) * (lp - lq) * s).exp());
                        let wgt = hx * hy * wz * wn * wl;
                        sum += wgt * lq;
                        wsum += wgt;
                    }
                }
                *out = if wsum > 0.0 { (sum / wsum) as f32 } else { src[p] };
            }
        });
        cur = next;
    }
    Image::from_vec(img.width, img.height, cur)
}
