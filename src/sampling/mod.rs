//! The hemisphere sampling core: pure math, no IO, imports glam only.
//!
//! A point set is made in three steps, each in its own file:
//! a sequence of numbers in [0,1)^2 (`random`, `fibonacci`, `stratified`, `sobol`,
//! `halton`, `pmj02bn`, `zsobol`, `r2`, or a file's points held by `point_file`) →
//! `seed` randomization across pixels (static, rotation, shift, blue-noise from `blue_noise`'s
//! masks, stbn from `stbn`'s spatiotemporal masks, both made by `void_cluster`; the engines'
//! rotation patterns of `engine`; a user's noise texture from `texture`'s table), changing from
//! frame to frame by a `schedule` →
//! `warp` to a direction on the hemisphere (uniform, sine, sine-cosine, concentric-cosine),
//! which `frame` rotates around the surface normal.
//! All of them draw their randomness from `hash` (counter-based hashing and the 24-bit fixed
//! point), a leaf that imports nothing of the crate.

pub mod batch;
pub mod blue_noise;
pub mod engine;
pub mod fibonacci;
pub mod frame;
pub mod halton;
pub mod hash;
pub mod integrand;
mod names;
pub mod pmj02;
pub mod point_file;
pub mod r2;
pub mod random;
pub mod registry;
pub mod schedule;
pub mod seed;
pub mod sobol;
pub mod stbn;
pub mod stratified;
pub mod texture;
pub mod trig;
mod void_cluster;
pub mod warp;
pub mod zsobol;

pub use fibonacci::fibonacci_point;
pub use frame::{Frame, canonical};
pub use integrand::Integrand;
pub use registry::{
    PixelSet, PointSequence, RegisterError, Sequence, SequenceInfo, Shipped, register, register_file,
};
pub use schedule::Schedule;
pub use seed::SeedMode;
pub use warp::{DirSample, Distribution};

use hash::fix_add;
use seed::PixelSeed;

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

/// Everything that determines the points of every pixel of one image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SamplerConfig {
    pub sequence: Sequence,
    pub seed_mode: SeedMode,
    pub count: u32,
    pub seed: u64,
    /// Which frame of a static camera's sequence of frames (0 = the single image of today).
    pub frame: u32,
    /// How the randomization changes from frame to frame ([`schedule`]).
    pub schedule: Schedule,
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
        Ok(Self { sequence, seed_mode, count, seed, frame: 0, schedule: Schedule::Independent })
    }

    /// The same configuration at frame `frame`.
    pub fn with_frame(self, frame: u32) -> Self {
        Self { frame, ..self }
    }

    /// The same configuration under `schedule`.
    pub fn with_schedule(self, schedule: Schedule) -> Self {
        Self { schedule, ..self }
    }

    /// Makes every process-wide table this configuration reads (the sequence's own, e.g. pmj02bn's
    /// points, and the seed mode's blue-noise or spatiotemporal masks), so that no timed render
    /// pays for generating them: the executor calls it for every job before the first timed
    /// render (the spatiotemporal masks take seconds, half of it on a second thread that a
    /// render's thread clock would not even count).
    pub fn prepare(&self) {
        self.sequence.imp().prepare();
        match self.seed_mode {
            SeedMode::BlueNoise => {
                blue_noise::masks();
            }
            SeedMode::Stbn => {
                stbn::stbn_masks();
            }
            // The engine patterns are closed forms; a texture was decoded and registered by the
            // loader before any configuration could name it.
            _ => {}
        }
    }

    /// Writes the points of pixel (`x`, `y`), index `pixel` (= y · width + x, which keys its
    /// fresh numbers), into `out`: the first `min(count, out.len())` points of the `count`-point
    /// set (strata and lattice spacing follow `count`). Depends only on (config, x, y, pixel), never
    /// on which thread or which other pixels ran. No allocation (Halton's working list is kept per
    /// thread, made once). (x, y) matters only for
    /// `blue-noise` and `stbn`, whose offsets are read from masks tiled over the image.
    /// `frame` and `schedule` say how frame f's points follow from frame 0's ([`schedule`]).
    /// What each (sequence, seed mode) pair means: see [`seed`].
    pub fn fill_pixel(&self, x: u32, y: u32, pixel: u64, out: &mut [Vec2]) {
        let n = self.count.max(1);
        let len = (self.count as usize).min(out.len());
        let out = &mut out[..len];
        // The frame's run seed and the schedule's offsets on top of the mode's (all 0 at frame 0).
        // `stbn` and a texture read slice frame mod depth; the schedule acts once per full cycle of
        // the mask. IGN under `r1` steps itself (its pixel offset per frame, `engine`).
        let (epoch, slice) = match (self.seed_mode, self.schedule) {
            (SeedMode::Ign, Schedule::R1) => (0, self.frame),
            (m, _) => (self.frame / m.depth(), self.frame % m.depth()),
        };
        // A rotation moves x only, unless the numbers are fresh per pixel anyway (then it is a shift).
        let scalar = self.seed_mode.is_scalar(self.sequence.info().fresh_per_pixel);
        let (seed, (fx, fy)) = schedule::epoch(self.schedule, self.seed, epoch as u64, scalar);
        let ps = PixelSeed::new(seed, pixel);
        if let SeedMode::Texture(t) = self.seed_mode
            && t.get().use_() == texture::TextureUse::Vector
        {
            // The texture gives the directions itself: the sequence is not read.
            return t.get().fill_vector(ps.run_key, (x, y, slice), (fx, fy), out);
        }
        let (dx, dy) = ps.offsets_at(self.seed_mode, x, y, slice);
        let set = PixelSet {
            count: n,
            x,
            y,
            pixel,
            seed_mode: self.seed_mode,
            seed: ps,
            offsets: (fix_add(dx, fx), fix_add(dy, fy)),
            frame_offsets: (fx, fy),
        };
        self.sequence.imp().fill(&set, out);
    }
}
