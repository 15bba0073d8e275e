//! The paper's three hemisphere distributions (plus the concentric cosine map of pbrt/Mitsuba).
//! Local frame: z is the normal, theta is measured from z.

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, PI, TAU};

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
    /// Maps (u, v) in [0,1]^2 to a unit direction (z >= 0) and its AO weight.
    pub fn sample(self, u: Vec2) -> DirSample {
        match self {
            Distribution::Uniform => {
                let (s, c) = (FRAC_PI_2 * u.y).sin_cos();
                let (sp, cp) = (TAU * u.x).sin_cos();
                DirSample { dir: Vec3::new(s * cp, s * sp, c), weight: PI * s * c }
            }
            Distribution::Sine => {
                let c = 1.0 - u.y;
                let s = (u.y * (2.0 - u.y)).max(0.0).sqrt();
                let (sp, cp) = (TAU * u.x).sin_cos();
                DirSample { dir: Vec3::new(s * cp, s * sp, c), weight: 2.0 * c }
            }
            Distribution::SineCosine | Distribution::ConcentricCosine => {
                let s = u.y.max(0.0).sqrt();
                let c = (1.0 - u.y).max(0.0).sqrt();
                let (sp, cp) = (TAU * u.x).sin_cos();
                DirSample { dir: Vec3::new(s * cp, s * sp, c), weight: 1.0 }
            }
        }
    }
}
