//! The hemisphere sampling core: pure math, no IO, imports glam only.
//!
//! A point set is made in three steps, each in its own file:
//! `sequence` numbers in [0,1)^2 (random, Fibonacci, stratified, Sobol') →
//! `seed` randomization across pixels (static, rotation, shift) →
//! `warp` to a direction on the hemisphere (uniform, sine, sine-cosine, concentric-cosine),
//! which `frame` rotates around the surface normal.

pub mod frame;
mod names;
pub mod warp;

pub use frame::Frame;
pub use warp::Distribution;

use glam::Vec2;
use std::fmt;

/// Why a sampling request cannot be honoured (never a panic).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SamplingError {
    /// A point set of zero points has no estimate.
    ZeroCount,
}

impl fmt::Display for SamplingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SamplingError::ZeroCount => write!(f, "a point set needs at least one point (count = 0)"),
        }
    }
}

impl std::error::Error for SamplingError {}

/// Which numbers feed the warp.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Sequence {
    Random,
    Fibonacci,
    Stratified,
    Sobol,
}

/// How the point set differs from pixel to pixel (the paper's "seed").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SeedMode {
    Static,
    Rotation,
    Shift,
}

/// Everything that determines the points of every pixel of one image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SamplerConfig {
    pub sequence: Sequence,
    pub seed_mode: SeedMode,
    pub count: u32,
    pub seed: u64,
}

impl SamplerConfig {
    pub fn new(
        sequence: Sequence,
        seed_mode: SeedMode,
        count: u32,
        seed: u64,
    ) -> Result<Self, SamplingError> {
        if count == 0 {
            return Err(SamplingError::ZeroCount);
        }
        Ok(Self { sequence, seed_mode, count, seed })
    }

    /// Writes pixel `pixel`'s `count` points into `out` (`out.len() == count`).
    /// Depends only on (config, pixel), never on which thread or which other pixels ran.
    pub fn fill_pixel(&self, pixel: u64, out: &mut [Vec2]) {
        // Baseline (random + Fibonacci only); the sampling issue replaces this with the full set.
        let n = self.count as usize;
        let per_pixel = self.seed_mode != SeedMode::Static;
        let key = if per_pixel { hash(self.seed, pixel) } else { hash(self.seed, u64::MAX) };
        let offset = match self.seed_mode {
            SeedMode::Static => Vec2::ZERO,
            SeedMode::Rotation => Vec2::new(unit(hash(key, 1)), 0.0),
            SeedMode::Shift => Vec2::new(unit(hash(key, 1)), unit(hash(key, 2))),
        };
        for (i, p) in out.iter_mut().enumerate().take(n) {
            let base = match self.sequence {
                Sequence::Fibonacci => {
                    let x = ((i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40) as f32
                        / (1u64 << 24) as f32;
                    Vec2::new(x, (i as f32 + 0.5) / n as f32)
                }
                _ => Vec2::new(unit(hash(key, 2 * i as u64 + 3)), unit(hash(key, 2 * i as u64 + 4))),
            };
            let q = if self.sequence == Sequence::Random { base } else { base + offset };
            *p = Vec2::new(q.x.fract(), q.y.fract());
        }
    }
}

fn hash(a: u64, b: u64) -> u64 {
    let mut z = a ^ b.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn unit(h: u64) -> f32 {
    (h >> 40) as f32 / (1u64 << 24) as f32
}
