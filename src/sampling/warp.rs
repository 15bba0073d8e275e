//! The paper's three hemisphere distributions (plus the concentric cosine map of pbrt/Mitsuba),
//! pbrt-v4 sampling.h style: per warp `square_to_X`, its solid-angle `X_pdf`, its inverse
//! `X_to_square` and its per-ray AO weight `X_weight` = cos / (pi pdf) in closed form, side by side.
//! Local frame: z is the normal, theta is measured from z, phi = atan2(y, x).
//!
//! Directions leaving here are finite, unit (to f32 rounding), have z >= 0 and no -0.0; inputs
//! outside \[0,1\]^2 (or NaN) are clamped first, so no input can produce a NaN.

use super::frame::canonical;
use super::trig::{sin_cos_quarter, sin_cos_turns};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, PI, TAU};

/// The largest f32 below 1: where an inverse lands when rounding would give exactly 1.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Distribution {
    /// Uniform in the angles: phi = 2 pi u, theta = (pi/2) v.
    Uniform,
    /// Uniform over solid angle: cos theta = 1 - v.
    Sine,
    /// Cosine-weighted: sin theta = sqrt(v).
    SineCosine,
    /// Shirley-Chiu concentric disk + Malley projection.
    ConcentricCosine,
}

/// A direction with its per-ray AO weight cos/(pi pdf).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DirSample {
    pub dir: Vec3,
    pub weight: f32,
}

impl Distribution {
    /// Maps (u, v) in \[0,1\]^2 to a unit direction (z >= 0) and its AO weight.
    #[inline(always)]
    pub fn sample(self, u: Vec2) -> DirSample {
        let u = clamp_unit(u);
        let dir = match self {
            Distribution::Uniform => square_to_uniform_angles(u),
            Distribution::Sine => square_to_sine(u),
            Distribution::SineCosine => square_to_sine_cosine(u),
            Distribution::ConcentricCosine => square_to_concentric_cosine(u),
        };
        DirSample { dir, weight: self.ao_weight(dir) }
    }

    /// Solid-angle density of `dir` (0 below the horizon; +inf only where the weight is 0).
    pub fn pdf(self, dir: Vec3) -> f32 {
        match self {
            Distribution::Uniform => uniform_angles_pdf(dir),
            Distribution::Sine => sine_pdf(dir),
            Distribution::SineCosine => sine_cosine_pdf(dir),
            Distribution::ConcentricCosine => concentric_cosine_pdf(dir),
        }
    }

    /// The (u, v) in [0,1)^2 that `sample` maps to `dir` (unit, z >= 0).
    pub fn invert(self, dir: Vec3) -> Vec2 {
        match self {
            Distribution::Uniform => uniform_angles_to_square(dir),
            Distribution::Sine => sine_to_square(dir),
            Distribution::SineCosine => sine_cosine_to_square(dir),
            Distribution::ConcentricCosine => concentric_cosine_to_square(dir),
        }
    }

    /// True when `ao_weight` is exactly 1 for every direction (the cosine-weighted warps): the
    /// estimator's in-order sum of the blocked rays' weights is then their count, exactly, and
    /// the renderer takes the count instead of walking the rays.
    pub fn unit_weight(self) -> bool {
        matches!(self, Distribution::SineCosine | Distribution::ConcentricCosine)
    }

    /// cos / (pi pdf) in closed form: finite and >= 0 everywhere, including pole and horizon.
    #[inline(always)]
    pub fn ao_weight(self, dir: Vec3) -> f32 {
        match self {
            Distribution::Uniform => uniform_angles_weight(dir),
            Distribution::Sine => sine_weight(dir),
            Distribution::SineCosine => sine_cosine_weight(dir),
            Distribution::ConcentricCosine => concentric_cosine_weight(dir),
        }
    }
}

/// Clamp to [0,1]^2, NaN to 0 (f32::clamp would keep the NaN).
#[inline(always)]
fn clamp_unit(u: Vec2) -> Vec2 {
    let c = |x: f32| if x >= 0.0 { x.min(1.0) } else { 0.0 };
    Vec2::new(c(u.x), c(u.y))
}

/// sqrt that returns 0 instead of NaN for rounding-negative input.
#[inline(always)]
fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

/// sin theta of a unit direction from its xy part (accurate near the pole, unlike acos).
#[inline(always)]
fn sin_theta(d: Vec3) -> f32 {
    (d.x * d.x + d.y * d.y).sqrt().min(1.0)
}

/// Direction from sin/cos theta and u (phi = 2 pi u), clamped into the upper hemisphere.
#[inline(always)]
fn polar(u: f32, sin_t: f32, cos_t: f32) -> Vec3 {
    let (sp, cp) = sin_cos_turns(u);
    canonical(Vec3::new(sin_t * cp, sin_t * sp, cos_t.max(0.0)))
}

/// u = phi / (2 pi) in [0,1).
#[inline(always)]
fn azimuth_to_u(d: Vec3) -> f32 {
    let u = d.y.atan2(d.x) * (0.5 * FRAC_1_PI);
    let u = if u < 0.0 { u + 1.0 } else { u };
    (u + 0.0).min(ONE_MINUS_EPSILON)
}

// ---- uniform in the angles (the paper's "uniform") ----

/// phi = 2 pi u, theta = (pi/2) v (joint pdf 1/pi^2 over the angle rectangle).
#[inline(always)]
pub fn square_to_uniform_angles(u: Vec2) -> Vec3 {
    let (s, c) = sin_cos_quarter(u.y);
    polar(u.x, s.clamp(0.0, 1.0), c)
}

/// 1 / (pi^2 sin theta): infinite at the pole, where the weight is 0.
pub fn uniform_angles_pdf(d: Vec3) -> f32 {
    if d.z < 0.0 { 0.0 } else { 1.0 / (PI * PI * sin_theta(d)) }
}

/// theta = atan2(sin, cos), v = theta / (pi/2).
pub fn uniform_angles_to_square(d: Vec3) -> Vec2 {
    let v = sin_theta(d).atan2(d.z.max(0.0)) / FRAC_PI_2;
    Vec2::new(azimuth_to_u(d), v.min(ONE_MINUS_EPSILON))
}

/// cos / (pi pdf) = pi sin theta cos theta.
#[inline(always)]
pub fn uniform_angles_weight(d: Vec3) -> f32 {
    PI * sin_theta(d) * d.z.max(0.0)
}

// ---- sine (uniform over solid angle) ----

/// cos theta = 1 - v, sin theta = sqrt(v (2 - v)) (accurate near the pole, no acos).
#[inline(always)]
pub fn square_to_sine(u: Vec2) -> Vec3 {
    polar(u.x, safe_sqrt(u.y * (2.0 - u.y)), 1.0 - u.y)
}

/// 1 / (2 pi).
pub fn sine_pdf(d: Vec3) -> f32 {
    if d.z < 0.0 { 0.0 } else { 0.5 * FRAC_1_PI }
}

/// v = 1 - cos theta.
pub fn sine_to_square(d: Vec3) -> Vec2 {
    Vec2::new(azimuth_to_u(d), (1.0 - d.z).clamp(0.0, ONE_MINUS_EPSILON))
}

/// cos / (pi pdf) = 2 cos theta.
#[inline(always)]
pub fn sine_weight(d: Vec3) -> f32 {
    2.0 * d.z.max(0.0)
}

// ---- sine-cosine (cosine-weighted, the paper's polar map) ----

/// sin theta = sqrt(v), cos theta = sqrt(1 - v).
#[inline(always)]
pub fn square_to_sine_cosine(u: Vec2) -> Vec3 {
    polar(u.x, safe_sqrt(u.y), safe_sqrt(1.0 - u.y))
}

/// cos theta / pi.
pub fn sine_cosine_pdf(d: Vec3) -> f32 {
    d.z.max(0.0) * FRAC_1_PI
}

/// v = sin^2 theta = x^2 + y^2.
pub fn sine_cosine_to_square(d: Vec3) -> Vec2 {
    Vec2::new(azimuth_to_u(d), (d.x * d.x + d.y * d.y).min(ONE_MINUS_EPSILON))
}

/// cos / (pi pdf) = 1.
#[inline(always)]
pub fn sine_cosine_weight(_d: Vec3) -> f32 {
    1.0
}

// ---- concentric cosine (Shirley-Chiu disk + Malley projection; pbrt-v4, Mitsuba 3) ----

/// Shirley & Chiu 1997, "A Low Distortion Map Between Disk and Square" (pbrt-v4
/// SampleUniformDiskConcentric): squares of [-1,1]^2 to circles of the unit disk. The angle is
/// carried in quarter turns (theta / (pi/2)), both branches are computed and one is selected, so
/// a loop over points vectorizes.
#[inline(always)]
pub fn square_to_concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    let wide = o.x.abs() > o.y.abs();
    // One division either way: o.y / o.x in the wide octants, o.x / o.y in the others (written as
    // selects of operands, not of whole branches, which the vectorizer would not if-convert).
    let (r, other) = (if wide { o.x } else { o.y }, if wide { o.y } else { o.x });
    let centre = (o.x == 0.0) & (o.y == 0.0);
    let ratio = 0.5 * (other / if centre { 1.0 } else { r });
    let quarter = if wide { ratio } else { 1.0 - ratio };
    let (s, c) = sin_cos_quarter(if centre { 0.0 } else { quarter });
    // Lane by lane (a select of a whole `Vec2` kept the loop scalar: 3x the time per direction).
    let zero = |x: f32| if centre { 0.0 } else { x };
    Vec2::new(zero(r * c), zero(r * s))
}

/// Inverse of `square_to_concentric_disk` (Shirley & Chiu 1997, sec. 3, by octant of phi).
pub fn concentric_disk_to_square(p: Vec2) -> Vec2 {
    let r = p.length().min(1.0);
    let mut phi = p.y.atan2(p.x);
    if phi < -FRAC_PI_4 {
        phi += TAU;
    }
    let (a, b) = if phi < FRAC_PI_4 {
        (r, phi * r / FRAC_PI_4)
    } else if phi < 3.0 * FRAC_PI_4 {
        (-(phi - FRAC_PI_2) * r / FRAC_PI_4, r)
    } else if phi < 5.0 * FRAC_PI_4 {
        (-r, -(phi - PI) * r / FRAC_PI_4)
    } else {
        ((phi - 3.0 * FRAC_PI_2) * r / FRAC_PI_4, -r)
    };
    let u = (Vec2::new(a, b) + Vec2::ONE) * 0.5;
    Vec2::new(u.x.clamp(0.0, ONE_MINUS_EPSILON), u.y.clamp(0.0, ONE_MINUS_EPSILON))
}

/// Malley: lift the concentric disk point to z = sqrt(1 - r^2).
#[inline(always)]
pub fn square_to_concentric_cosine(u: Vec2) -> Vec3 {
    let d = square_to_concentric_disk(u);
    canonical(Vec3::new(d.x, d.y, safe_sqrt(1.0 - d.length_squared())))
}

/// cos theta / pi.
pub fn concentric_cosine_pdf(d: Vec3) -> f32 {
    d.z.max(0.0) * FRAC_1_PI
}

/// Project to the disk, then invert the concentric map.
pub fn concentric_cosine_to_square(d: Vec3) -> Vec2 {
    concentric_disk_to_square(Vec2::new(d.x, d.y))
}

/// cos / (pi pdf) = 1.
#[inline(always)]
pub fn concentric_cosine_weight(_d: Vec3) -> f32 {
    1.0
}
