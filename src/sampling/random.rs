//! The paper's pseudo-random pairs, counter-based: point i of a pixel is a hash of
//! (run seed, pixel, i, dimension), so it never depends on thread scheduling or on other pixels.

use super::hash::{fix_add, fix_from_bits, fix_to_f32, hash};
use super::registry::{PixelSet, PointSequence, SequenceInfo};
use super::seed::SeedMode;
use glam::Vec2;

/// Fills `out` with points 0.. of the stream `key` (key = hash of run seed, and of the pixel unless
/// static), shifted by the fixed-point offsets (dx, dy) mod 1 (0 except for `blue-noise`, which
/// shifts the run's static set per pixel).
pub fn fill(key: u64, dx: u32, dy: u32, out: &mut [Vec2]) {
    for (i, p) in out.iter_mut().enumerate() {
        let (x, y) = (hash(key, 2 * i as u64 + 1), hash(key, 2 * i as u64 + 2));
        let (x, y) = (fix_add(fix_from_bits(x), dx), fix_add(fix_from_bits(y), dy));
        *p = Vec2::new(fix_to_f32(x), fix_to_f32(y));
    }
}

/// The paper's pseudo-random numbers: fresh per pixel under every seed mode but `static`; under
/// `blue-noise`, `stbn`, the engine patterns and textures the run's one set, shifted by their
/// offsets.
pub struct Random;

impl PointSequence for Random {
    fn info(&self) -> &SequenceInfo {
        &SequenceInfo {
            name: "random",
            label: "pseudo-random",
            words: &["pseudo-random", "pseudorandom"],
            fresh_per_pixel: true,
            shipped: None,
        }
    }

    fn fill(&self, set: &PixelSet, out: &mut [Vec2]) {
        let (fx, fy) = set.frame_offsets;
        match set.seed_mode {
            m if m.carries_offsets() => fill(set.seed.run_key, set.offsets.0, set.offsets.1, out),
            m => fill(set.seed.set_key(m != SeedMode::Static), fx, fy, out),
        }
    }
}
