//! What the edge-avoiding à-trous filters share (`atrous`, and `svgf`'s spatial part): the
//! 5 × 5 B3-spline kernel with holes (Dammertz et al. 2010), the depth gradient, SVGF's depth and
//! normal edge-stopping weights (Schied et al. 2017, eq. 3-4) and the default number of
//! iterations.
//!
//!   w_z = exp(−|z_p − z_q| / (σ_z |∇z_p · (q − p)| + ε z_p))      depth, scaled by its gradient
//!   w_n = max(0, n_p · n_q)^σ_n                                   normal
//!
//! The depth gradient is the smaller one-sided difference on each axis (so a pixel at a depth step
//! takes its own surface's slope, not the step's); ε z_p (ε = 10⁻³) keeps a fronto-parallel plane,
//! whose gradient is 0, open to its own rounding.
//!
//! **The default iteration count** keeps the filter's footprint a fixed share of the image rather
//! than a fixed number of pixels. Iteration i's taps are 2^i px apart, so k iterations reach
//! 2·(2^k − 1) px either side: a footprint of 4·(2^k − 1) + 1 px. The default is the largest k ≥ 1
//! whose footprint is at most `FOOTPRINT_SHARE` of the image's smaller side. Why a share: the
//! filter's bias is the blur of the AO signal along each surface, and that signal (contact
//! shadows, corners) has the size of the scene's features, which is a share of the image, not a
//! number of pixels. Five iterations (125 px), the papers' count for images of a thousand lines,
//! average whole walls together on a 96 × 72 image, and there the bias, not the noise, was most of
//! the error. Why this share: see `FOOTPRINT_SHARE`.

use crate::render::GBuffer;

/// The B3-spline taps at offsets −2..=2: h = (1, 4, 6, 4, 1)/16.
pub const B3: [f64; 5] = [1.0 / 16.0, 4.0 / 16.0, 6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0];

/// ε: the depth difference relative to the depth itself that is always tolerated.
pub const DEPTH_EPS: f32 = 1e-3;

/// The largest share of the image's smaller side the default à-trous footprint may cover: 1/8.
/// Measured with examples/filter_floor.rs (kitchen, Cornell box, slats; 1 ray per pixel per frame,
/// 16 frames of a static camera under ema0.1 then à-trous): the RMSE at the last frame is least
/// at 2 passes (13 px) at 320x180 and at 1-2 passes at 96x72, i.e. for a share between 13/180 and
/// 29/180 of the smaller side and below 13/72; 1/8 picks 1 pass at 96x72 and 2 at 320x180, and
/// keeps Dammertz's and SVGF's 5 passes (125 px) at 1080 lines. The bias floor
/// RMSE(F(reference), reference) falls from 0.074-0.129 (5 passes at 96x72) to 0.014-0.027.
pub const FOOTPRINT_SHARE: f64 = 1.0 / 8.0;

/// The footprint in pixels of `iterations` à-trous passes: 4·(2^k − 1) + 1.
pub fn footprint(iterations: u32) -> u64 {
    4 * ((1u64 << iterations.min(40)) - 1) + 1
}

/// The default iteration count for a `width` × `height` image: the largest k ≥ 1 with
/// `footprint(k) <= FOOTPRINT_SHARE · min(width, height)` (module doc).
pub fn default_iterations(width: u32, height: u32) -> u32 {
    let limit = FOOTPRINT_SHARE * width.min(height) as f64;
    (1..=30u32).take_while(|&k| footprint(k) as f64 <= limit).last().unwrap_or(1)
}

/// The per-pixel depth gradient (d/dx, d/dy): on each axis the one-sided difference of smaller
/// magnitude among covered neighbours (0 with none).
pub fn depth_gradient(g: &GBuffer) -> Vec<(f32, f32)> {
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

/// One frame's geometric edge-stopping: the G-buffer, its depth gradient and σ_z, σ_n.
pub struct Guide<'a> {
    pub gbuf: &'a GBuffer,
    grad: Vec<(f32, f32)>,
    sigma_depth: f32,
    sigma_normal: f32,
    /// A whole σ_n (SVGF's 128) by repeated squaring: within a few ulp of `powf`, at a fraction of
    /// its cost (it was a third of a real-time run's filtering time).
    normal_power: Option<i32>,
    /// `content_key`, hashed once (each pass of each filter asks for it).
    key: std::sync::OnceLock<u64>,
}

/// At most 25 taps of one à-trous pass: (pixel, weight).
pub type Taps = [(usize, f64); 25];

impl<'a> Guide<'a> {
    pub fn new(gbuf: &'a GBuffer, sigma_depth: f32, sigma_normal: f32) -> Self {
        let normal_power = (sigma_normal.fract() == 0.0 && (0.0..=1024.0).contains(&sigma_normal))
            .then_some(sigma_normal as i32);
        let key = std::sync::OnceLock::new();
        Self { gbuf, grad: depth_gradient(gbuf), sigma_depth, sigma_normal, normal_power, key }
    }

    /// A hash of everything the taps depend on: the G-buffer's size, depth, normals and coverage,
    /// and σ_z, σ_n (`taps::Pass` keeps tables by it). Four independent lanes, so that hashing a
    /// frame costs a small part of filtering it.
    pub fn content_key(&self) -> u64 {
        *self.key.get_or_init(|| self.hash())
    }

    fn hash(&self) -> u64 {
        let g = self.gbuf;
        let mut h = crate::image::WordHash::new([
            g.width as u64,
            g.height as u64,
            self.sigma_depth.to_bits() as u64,
            self.sigma_normal.to_bits() as u64,
        ]);
        h.mix(g.depth.data.iter().map(|v| v.to_bits()));
        h.mix(g.coverage.data.iter().map(|v| v.to_bits()));
        h.mix(g.normal.iter().flat_map(|n| [n.x.to_bits(), n.y.to_bits(), n.z.to_bits()]));
        h.finish()
    }

    pub fn width(&self) -> i64 {
        self.gbuf.width as i64
    }

    pub fn height(&self) -> i64 {
        self.gbuf.height as i64
    }

    pub fn is_covered(&self, i: usize) -> bool {
        self.gbuf.is_covered(i)
    }

    /// `f(x, y, p)` at every covered pixel p = (x, y), in parallel by rows; 0 on background: the
    /// loop SVGF's per-pixel passes (its variance estimate and prefilter) share.
    pub fn per_covered(&self, f: impl Fn(i64, i64, usize) -> f64 + Sync) -> Vec<f64> {
        use rayon::prelude::*;
        let w = self.width();
        let mut out = vec![0.0f64; self.gbuf.width as usize * self.gbuf.height as usize];
        out.par_chunks_mut(w.max(1) as usize).enumerate().for_each(|(y, row)| {
            let y = y as i64;
            for (x, o) in row.iter_mut().enumerate() {
                let p = (y * w + x as i64) as usize;
                if self.is_covered(p) {
                    *o = f(x as i64, y, p);
                }
            }
        });
        out
    }

    /// w_z · w_n between covered pixels p and q = p + (dx, dy).
    #[inline]
    pub fn weight(&self, p: usize, q: usize, dx: i64, dy: i64) -> f64 {
        let (wz, wn) = self.weights(p, q, dx, dy);
        wz * wn
    }

    /// (w_z, w_n) between covered pixels p and q = p + (dx, dy).
    #[inline]
    fn weights(&self, p: usize, q: usize, dx: i64, dy: i64) -> (f64, f64) {
        let z = &self.gbuf.depth.data;
        let n = &self.gbuf.normal;
        let (zp, (gx, gy)) = (z[p], self.grad[p]);
        let dz = (zp - z[q]).abs();
        let scale = self.sigma_depth * (gx * dx as f32 + gy * dy as f32).abs() + DEPTH_EPS * zp;
        let wz = if dz == 0.0 { 1.0 } else { (-(dz / scale.max(f32::MIN_POSITIVE)) as f64).exp() };
        let c = n[p].dot(n[q]).max(0.0) as f64;
        let wn = match self.normal_power {
            Some(k) => c.powi(k),
            None => c.powf(self.sigma_normal as f64),
        };
        (wz, wn)
    }

    /// The taps of à-trous pass `iteration` at covered pixel (x, y): every covered pixel q of the
    /// 5 × 5 B3 kernel with holes 2^iteration px apart inside the image, with its weight
    /// h(kx) h(ky) w_z w_n, in a fixed (row-major) order. Returns how many of `out` are filled.
    pub fn atrous_taps(&self, x: i64, y: i64, iteration: u32, out: &mut Taps) -> usize {
        let (w, h) = (self.width(), self.height());
        let step = 1i64 << iteration.min(30);
        let p = (y * w + x) as usize;
        let mut k = 0;
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
                if qx < 0 || qx >= w || !self.is_covered(q) {
                    continue;
                }
                let (wz, wn) = self.weights(p, q, dx, dy);
                out[k] = (q, hx * hy * wz * wn);
                k += 1;
            }
        }
        k
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn footprints_and_the_default_share() {
        assert_eq!((1..=5).map(footprint).collect::<Vec<_>>(), [5, 13, 29, 61, 125]);
        // 1/8 of 72 = 9: one pass; of 180 = 22.5: two; of 720 = 90: four; of 1080 = 135: five.
        assert_eq!(default_iterations(96, 72), 1);
        assert_eq!(default_iterations(320, 180), 2);
        assert_eq!(default_iterations(1280, 720), 4);
        assert_eq!(default_iterations(1920, 1080), 5);
        assert_eq!(default_iterations(4, 4), 1, "at least one pass");
        for (w, h) in [(96, 72), (320, 180), (1920, 1080), (64, 500)] {
            let k = default_iterations(w, h);
            let side = w.min(h) as f64;
            assert!(footprint(k) as f64 <= FOOTPRINT_SHARE * side);
            assert!(footprint(k + 1) as f64 > FOOTPRINT_SHARE * side);
        }
    }
}
