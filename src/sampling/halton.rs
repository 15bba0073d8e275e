//! The 2-D Halton sequence (bases 2 and 3), Owen-scrambled per set: x is the base-2 radical
//! inverse (van der Corput), y the base-3 one (Halton 1964). The scramble is nested (Owen 1995):
//! each digit is permuted by a random rotation of {0, 1, 2} chosen by hashing the digits above
//! it, as pbrt-v4's `OwenScrambledRadicalInverse` does (Pharr, Jakob & Humphreys 2023, §8.6).
//! Base 2 reuses [`super::sobol::owen_scramble`] (Burley 2020).

use super::hash::{FIX_BITS, fix_add, fix_to_f32, hash};
use super::registry::{PixelSet, PointSequence, SHIPS_SHIFTED, SequenceInfo, Shipped};
use super::seed::SeedMode;
use super::sobol::owen_scramble;
use glam::Vec2;

/// Base-3 digits kept: 3^21 > 2^32, so every u32 index is inverted exactly.
pub const DIGITS_3: u32 = 21;
/// 3^21: the denominator of [`radical_inverse_3`].
pub const POW3: u64 = 10_460_353_203;

/// The base-3 radical inverse of `i` as the integer r with value r / 3^21 (exact for every u32).
pub fn radical_inverse_3(i: u32) -> u64 {
    owen_radical_inverse_3(i, None)
}

/// Base-3 radical inverse with each digit rotated by hash(seed, depth, digits above) mod 3
/// (None: unscrambled). Digits past the index's own are scrambled too (they are not zero after
/// a scramble), down to 3^-21, below the 24-bit grid.
pub fn owen_radical_inverse_3(mut i: u32, seed: Option<u64>) -> u64 {
    let mut r = 0u64;
    // `above` = the result digits written so far (the more significant ones), as an integer.
    let mut above = 0u64;
    for depth in 0..DIGITS_3 {
        let mut d = (i % 3) as u64;
        i /= 3;
        if let Some(s) = seed {
            d = (d + hash(s, ((depth as u64) << 40) | above) % 3) % 3;
        }
        above = above * 3 + d;
        r = above;
    }
    r
}

/// A base-3 value r / 3^21 on the 24-bit grid (floor, exact integer arithmetic).
#[inline]
pub fn base3_to_fixed(r: u64) -> u32 {
    ((r << FIX_BITS) / POW3) as u32
}

/// Fills `out` with Halton points 0.., Owen-scrambled by seeds from `key`, shifted by (`dx`, `dy`) mod 1.
pub fn fill(key: u64, dx: u32, dy: u32, out: &mut [Vec2]) {
    let sx = hash(key, 1) as u32;
    let sy = hash(key, 2);
    for (i, p) in out.iter_mut().enumerate() {
        let i = i as u32;
        let x = owen_scramble(i.reverse_bits(), sx) >> (32 - FIX_BITS);
        let y = base3_to_fixed(owen_radical_inverse_3(i, Some(sy)));
        *p = Vec2::new(fix_to_f32(fix_add(x, dx)), fix_to_f32(fix_add(y, dy)));
    }
}

/// Its seed modes act the common way (`PixelSet::keyed`).
pub struct Halton;

impl PointSequence for Halton {
    fn info(&self) -> &SequenceInfo {
        &SequenceInfo {
            name: "halton",
            label: "Halton",
            words: &[],
            fresh_per_pixel: false,
            shipped: Some(Shipped { modes: &[SeedMode::Shift], why: SHIPS_SHIFTED, rank: 0 }),
        }
    }

    fn fill(&self, set: &PixelSet, out: &mut [Vec2]) {
        let (key, dx, dy) = set.keyed();
        fill(key, dx, dy, out)
    }
}
