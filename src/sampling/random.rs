//! The paper's pseudo-random pairs, counter-based: point i of a pixel is a hash of
//! (run seed, pixel, i, dimension), so it never depends on thread scheduling or on other pixels.

use super::hash::{fix_add, fix_from_bits, fix_to_f32, hash};
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
