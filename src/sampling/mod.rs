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
        todo!("sampling helper: sequences + seed modes ({pixel}, {})", out.len())
    }
}
