//! The counter-based hashing every sequence draws its randomness from (SplitMix64, keyed by run
//! seed, pixel and index), and the 24-bit fixed point every sequence carries its coordinates in.
//! A leaf: it imports nothing of the crate.
//!
//! Coordinates are carried as 24-bit fixed point (`k / 2^24`, k < 2^24): every f32 in [0,1)
//! of that grid is exact, offsets wrap mod 1 exactly (no `x + offset` rounding to 1.0), and
//! strata boundaries can be honoured exactly.

/// Fractional bits of the fixed-point coordinates: all an f32 in [0,1) can hold uniformly.
pub const FIX_BITS: u32 = 24;
pub const FIX_ONE: u32 = 1 << FIX_BITS;
const FIX_MASK: u32 = FIX_ONE - 1;
/// 2^64 / phi_g, the Weyl increment of SplitMix64.
const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;

/// Fixed point (mod 1) to f32; exact, so always < 1.
#[inline]
pub fn fix_to_f32(k: u32) -> f32 {
    (k & FIX_MASK) as f32 * (1.0 / FIX_ONE as f32)
}

/// `a + b` mod 1 in fixed point.
#[inline]
pub fn fix_add(a: u32, b: u32) -> u32 {
    a.wrapping_add(b) & FIX_MASK
}

/// Top 24 bits of a 64-bit hash as a fixed-point coordinate.
#[inline]
pub fn fix_from_bits(h: u64) -> u32 {
    (h >> (64 - FIX_BITS)) as u32
}

/// SplitMix64's finalizer (Steele, Lea, Flood 2014): a bijective 64-bit avalanche mix.
#[inline]
pub fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Keyed counter hash: `mix64(key + counter * golden)` is SplitMix64's stream `key`, element `counter`.
#[inline]
pub fn hash(key: u64, counter: u64) -> u64 {
    mix64(key.wrapping_add(counter.wrapping_mul(GOLDEN)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fix_add_wraps_mod_one_and_stays_below_one() {
        assert_eq!(fix_add(FIX_ONE - 1, 1), 0);
        assert!(fix_to_f32(FIX_ONE - 1) < 1.0);
        assert_eq!(fix_to_f32(FIX_ONE), 0.0);
    }
}
