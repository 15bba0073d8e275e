//! The R2 sequence: the 2-D Kronecker (additive recurrence) sequence of the plastic number
//! g (g^3 = g + 1), x_i = frac(s + i/g), y_i = frac(s + i/g^2) (Roberts 2018, "The unreasonable
//! effectiveness of quasirandom sequences"). Carried as 64-bit Weyl sums, so it is exact mod 1
//! at any index; the start offset s is a Cranley–Patterson shift (Cranley & Patterson 1976) drawn
//! per set.

use super::hash::{FIX_BITS, fix_add, fix_to_f32, hash};
use super::registry::{PixelSet, PointSequence, SHIPS_SHIFTED, SequenceInfo, Shipped};
use super::seed::SeedMode;
use glam::Vec2;

/// round(2^64 / g) and round(2^64 / g^2), g the plastic number 1.32471795724474602596...
pub const ALPHA: [u64; 2] = [0xc13f_a9a9_02a6_328f, 0x91e1_0da5_c79e_7b1c];

/// Point `i` of R2 started at (`ox`, `oy`) (64-bit fractions), on the 24-bit grid.
#[inline]
pub fn r2_fixed(i: u64, ox: u64, oy: u64) -> (u32, u32) {
    let x = ox.wrapping_add(i.wrapping_mul(ALPHA[0]));
    let y = oy.wrapping_add(i.wrapping_mul(ALPHA[1]));
    ((x >> (64 - FIX_BITS)) as u32, (y >> (64 - FIX_BITS)) as u32)
}

/// Fills `out` with R2 points 0.., Cranley–Patterson shifted by offsets from `key`, then by (`dx`, `dy`).
pub fn fill(key: u64, dx: u32, dy: u32, out: &mut [Vec2]) {
    let (ox, oy) = (hash(key, 1), hash(key, 2));
    for (i, p) in out.iter_mut().enumerate() {
        let (x, y) = r2_fixed(i as u64, ox, oy);
        *p = Vec2::new(fix_to_f32(fix_add(x, dx)), fix_to_f32(fix_add(y, dy)));
    }
}

/// Its seed modes act the common way (`PixelSet::keyed`).
pub struct R2;

impl PointSequence for R2 {
    fn info(&self) -> &SequenceInfo {
        &SequenceInfo {
            name: "r2",
            label: "R2",
            words: &["kronecker"],
            fresh_per_pixel: false,
            shipped: Some(Shipped { modes: &[SeedMode::Shift], why: SHIPS_SHIFTED, rank: 1 }),
        }
    }

    fn fill(&self, set: &PixelSet, out: &mut [Vec2]) {
        let (key, dx, dy) = set.keyed();
        fill(key, dx, dy, out)
    }
}
