//! The paper's 2-D Fibonacci lattice ( frac((i+1)/phi_g), (i+0.5)/n ).
//!
//! frac((i+1)/phi_g) is computed in 64-bit fixed point: index * round(2^64/phi_g) mod 2^64.
//! The constant is 0.048 units of 2^-64 off, so at index 2^40 the fraction is off by 0.05 of an
//! f32 step (2^-24): the f32 is the true fraction truncated, or, for the ~5 % of indices that lie
//! that close to a step boundary, the neighbouring step. An f32 division loses every fractional
//! bit past 2^24; this stays within one f32 step up to index 2^44.

use super::seed::{FIX_BITS, fix_add, fix_to_f32};
use glam::Vec2;

/// round(2^64 / phi_g) = round(2^64 * (phi_g - 1)).
pub const INV_GOLDEN_FIXED: u64 = 0x9E37_79B9_7F4A_7C16;

/// x of lattice index `index` (the paper's i + 1 plus any seed offset), as 24-bit fixed point.
#[inline]
pub fn fibonacci_x_fixed(index: u64) -> u32 {
    (index.wrapping_mul(INV_GOLDEN_FIXED) >> (64 - FIX_BITS)) as u32
}

/// y = (i + 0.5) / n floored to the 24-bit grid: inside stratum i exactly for n <= 2^23.
#[inline]
pub fn fibonacci_y_fixed(i: u32, n: u32) -> u32 {
    (((2 * i as u64 + 1) << (FIX_BITS - 1)) / n.max(1) as u64) as u32
}

/// Point `i` of the n-point lattice with the paper's seed `index_offset` added to the indices.
pub fn fibonacci_point(i: u32, n: u32, index_offset: u64) -> Vec2 {
    let x = fibonacci_x_fixed((i as u64 + 1).wrapping_add(index_offset));
    Vec2::new(fix_to_f32(x), fix_to_f32(fibonacci_y_fixed(i, n)))
}

/// Fills `out` with points 0.. of the n-point lattice, index offset `index_offset`, then
/// shifted by the fixed-point offsets (dx, dy) mod 1.
/// Both coordinates are stepped, not recomputed: x by adding the constant mod 2^64 (the same
/// bits as the product), y = floor((2i+1) 2^23 / n) by quotient and remainder (no division).
pub fn fill(n: u32, index_offset: u64, dx: u32, dy: u32, out: &mut [Vec2]) {
    let n = n.max(1) as u64;
    let mut x64 = 1u64.wrapping_add(index_offset).wrapping_mul(INV_GOLDEN_FIXED);
    let half = 1u64 << (FIX_BITS - 1);
    let (mut q, mut r) = (half / n, half % n);
    let (step_q, step_r) = ((2 * half) / n, (2 * half) % n);
    for p in out.iter_mut() {
        let x = fix_add((x64 >> (64 - FIX_BITS)) as u32, dx);
        let y = fix_add(q as u32, dy);
        *p = Vec2::new(fix_to_f32(x), fix_to_f32(y));
        x64 = x64.wrapping_add(INV_GOLDEN_FIXED);
        q += step_q;
        r += step_r;
        if r >= n {
            r -= n;
            q += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stepped_fill_equals_direct_formula() {
        for n in [1u32, 2, 3, 7, 16, 100, 1000, 65_537] {
            for offset in [0u64, 5, 1 << 40, u64::MAX - 2] {
                let mut out = vec![Vec2::ZERO; n as usize];
                fill(n, offset, 0, 0, &mut out);
                for (i, p) in out.iter().enumerate() {
                    assert_eq!(*p, fibonacci_point(i as u32, n, offset), "n={n} offset={offset} i={i}");
                }
            }
        }
    }

    #[test]
    fn constant_is_round_of_two_pow_64_over_golden_ratio() {
        // 2^128 / phi_g in hex (60-digit decimal arithmetic), rounded to its top 64 bits.
        let wide: u128 = 0x9e3779b97f4a7c15f39cc0605cedc834;
        assert_eq!(((wide + (1u128 << 63)) >> 64) as u64, INV_GOLDEN_FIXED);
    }
}
