//! Closed forms shared by the AO tests: Lambert's polygon form factor, and the pooled comparison of
//! rendered floor pixels with it.
#![allow(dead_code)]

use glam::DVec3;
use std::f64::consts::PI;

/// Lambert's form factor from a point `p` with unit normal `n` to a planar polygon (vertices in
/// order) that lies wholly on the normal's side of p's tangent plane:
/// F = (1/2π) Σ_edges γ_e n · (r_i × r_{i+1}) / |r_i × r_{i+1}|, γ_e the angle the edge subtends at
/// p. It equals the occluded fraction of AO at p with d infinite, when nothing else is in view.
pub fn form_factor(p: DVec3, n: DVec3, polygon: &[DVec3]) -> f64 {
    let r: Vec<DVec3> = polygon.iter().map(|v| *v - p).collect();
    let mut sum = 0.0;
    for i in 0..r.len() {
        let (a, b) = (r[i], r[(i + 1) % r.len()]);
        let cross = a.cross(b);
        let cos = a.dot(b) / (a.length() * b.length());
        sum += cos.clamp(-1.0, 1.0).acos() * n.dot(cross) / cross.length();
    }
    (sum / (2.0 * PI)).abs()
}

/// Per-pixel sums over independent renders, for means and standard errors.
pub struct Pooled {
    pub sum: Vec<f64>,
    pub sum2: Vec<f64>,
    pub renders: u32,
}

impl Pooled {
    pub fn new(pixels: usize) -> Self {
        Self { sum: vec![0.0; pixels], sum2: vec![0.0; pixels], renders: 0 }
    }

    pub fn add(&mut self, ao: &[f32]) {
        for (i, &v) in ao.iter().enumerate() {
            self.sum[i] += v as f64;
            self.sum2[i] += (v as f64) * (v as f64);
        }
        self.renders += 1;
    }

    /// Over `pixels` = (index, exact AO): the mean signed error and its standard error (pixels
    /// and renders independent, as with per-pixel `shift` randomization), i.e. the pooled bias test.
    pub fn bias(&self, pixels: &[(usize, f64)]) -> (f64, f64) {
        let s = self.renders as f64;
        let (mut signed, mut var) = (0.0, 0.0);
        for &(i, exact) in pixels {
            let mean = self.sum[i] / s;
            signed += mean - exact;
            var += ((self.sum2[i] - s * mean * mean) / (s - 1.0)).max(0.0) / s;
        }
        let k = pixels.len() as f64;
        (signed / k, var.sqrt() / k)
    }
}
