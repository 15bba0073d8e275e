//! Closed forms shared by the AO tests: Lambert's polygon form factor, and the pooled comparison of
//! rendered floor pixels with it.

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

use glam::Vec2;
use hemilab::render::{PixelRays, pixel_rays, render};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::Scene;

/// One configuration's pooled comparison with the closed form.
#[derive(Debug)]
pub struct Pooling {
    pub what: String,
    pub pixels: usize,
    pub bias: f64,
    pub se: f64,
}

impl Pooling {
    pub fn z(&self) -> f64 {
        self.bias.abs() / self.se
    }
}

/// The covered pixels of a `side` x `side` image of `scene` whose AO `exact` knows: it gets the
/// pixel's AO origin and normal (the renderer's own, camera-relative, as f64) and returns the
/// exact AO (1 - occluded fraction) or None to leave the pixel out.
pub fn exact_pixels(
    scene: &Scene,
    side: u32,
    exact: impl Fn(DVec3, DVec3) -> Option<f64>,
) -> Vec<(usize, f64)> {
    let sampler = SamplerConfig::new(Sequence::Random, SeedMode::Shift, 1, 0).unwrap();
    let job =
        crate::support::jobs::render_job(Distribution::SineCosine, sampler, (side, side), scene.ao_distance);
    let (mut points, mut px, mut out) = (vec![Vec2::ZERO; 1], PixelRays::default(), Vec::new());
    for y in 0..side {
        for x in 0..side {
            let i = (y * side + x) as usize;
            if pixel_rays(scene, &job, x, y, i as u64, &mut points, &mut px)
                && let Some(v) = exact(px.origin.as_dvec3(), px.normal.as_dvec3())
            {
                out.push((i, v));
            }
        }
    }
    out
}

/// Every distribution with pseudo-random and Fibonacci points (per-pixel `shift`, so each pixel's
/// estimate is unbiased), `seeds` renders each of `rays` rays per pixel: the pooled mean signed
/// error over `pixels` and its standard error, per configuration.
pub fn pooled_errors(
    scene: &Scene,
    side: u32,
    rays: u32,
    seeds: u64,
    pixels: &[(usize, f64)],
) -> Vec<Pooling> {
    let mut out = Vec::new();
    for &distribution in Distribution::ALL {
        for sequence in [Sequence::Random, Sequence::Fibonacci] {
            let mut pool = Pooled::new((side * side) as usize);
            for seed in 0..seeds {
                let sampler = SamplerConfig::new(sequence, SeedMode::Shift, rays, 100 + seed).unwrap();
                let job =
                    crate::support::jobs::render_job(distribution, sampler, (side, side), scene.ao_distance);
                pool.add(&render(scene, &job, &|_| {}).ao.data);
            }
            let (bias, se) = pool.bias(pixels);
            out.push(Pooling { what: format!("{distribution} {sequence}"), pixels: pixels.len(), bias, se });
        }
    }
    out
}
