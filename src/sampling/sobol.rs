//! Owen-scrambled 2-D Sobol' points, hash-based nested uniform scrambling after Burley 2020,
//! "Practical Hash-based Owen Scrambling" (JCGT 9(4)). Written here: it is 30 lines, and the
//! crates that offer it pull in tables for hundreds of dimensions we never use.

use super::hash::{FIX_BITS, fix_add, fix_to_f32, hash};
use super::registry::{PixelSet, PointSequence, SequenceInfo};
use glam::Vec2;

/// Dimension 0 of Sobol' = van der Corput in base 2.
#[inline]
pub fn sobol_x(i: u32) -> u32 {
    i.reverse_bits()
}

/// Dimension 1 of Sobol' (primitive polynomial x + 1): direction numbers v_{k+1} = v_k ^ (v_k >> 1).
/// The generator matrix is linear over GF(2), so the result is the XOR of one table entry per
/// byte of `i` (`SOBOL_Y_BYTES`, made at compile time by `sobol_y_bits`): four loads instead of a
/// loop over `i`'s 32 bits, which ZSobol's full 32-bit indices paid in every point.
#[inline]
pub fn sobol_y(i: u32) -> u32 {
    let t = &SOBOL_Y_BYTES;
    t[0][(i & 0xFF) as usize]
        ^ t[1][(i >> 8 & 0xFF) as usize]
        ^ t[2][(i >> 16 & 0xFF) as usize]
        ^ t[3][(i >> 24) as usize]
}

/// `sobol_y` by its definition, one direction number per set bit of `i`.
pub const fn sobol_y_bits(mut i: u32) -> u32 {
    let mut v = 1u32 << 31;
    let mut r = 0;
    while i != 0 {
        if i & 1 != 0 {
            r ^= v;
        }
        i >>= 1;
        v ^= v >> 1;
    }
    r
}

/// `SOBOL_Y_BYTES[b][v]` = `sobol_y_bits(v << 8b)`.
static SOBOL_Y_BYTES: [[u32; 256]; 4] = {
    let mut t = [[0u32; 256]; 4];
    let mut b = 0;
    while b < 4 {
        let mut v = 0;
        while v < 256 {
            t[b][v] = sobol_y_bits((v as u32) << (8 * b));
            v += 1;
        }
        b += 1;
    }
    t
};

/// Laine–Karras style hash: each bit flips depending only on lower bits (Burley 2020, listing 2).
#[inline]
fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Nested uniform (Owen) scramble: each digit is permuted depending only on the digits above it,
/// which keeps every (0,m,2)-net a net.
#[inline]
pub fn owen_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

/// Fills `out` with points 0.. of Sobol', scrambled by seeds from `key`, shifted by (`dx`, `dy`) mod 1.
pub fn fill(key: u64, dx: u32, dy: u32, out: &mut [Vec2]) {
    let sx = hash(key, 1) as u32;
    let sy = hash(key, 2) as u32;
    for (i, p) in out.iter_mut().enumerate() {
        let i = i as u32;
        let x = owen_scramble(sobol_x(i), sx) >> (32 - FIX_BITS);
        let y = owen_scramble(sobol_y(i), sy) >> (32 - FIX_BITS);
        *p = Vec2::new(fix_to_f32(fix_add(x, dx)), fix_to_f32(fix_add(y, dy)));
    }
}

/// Its seed modes act the common way (`PixelSet::keyed`).
pub struct Sobol;

impl PointSequence for Sobol {
    fn info(&self) -> &SequenceInfo {
        &SequenceInfo {
            name: "sobol",
            label: "Sobol'",
            words: &["sobol'"],
            fresh_per_pixel: false,
            shipped: None,
        }
    }

    fn fill(&self, set: &PixelSet, out: &mut [Vec2]) {
        let (key, dx, dy) = set.keyed();
        fill(key, dx, dy, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unscrambled_sobol_matches_the_pascal_matrix_points_in_index_order() {
        // Index (not Gray-code) order: direction numbers 1/2, 3/4, 5/8 for dimension 1.
        let x: Vec<f64> = (0..8).map(|i| sobol_x(i) as f64 / 2f64.powi(32)).collect();
        let y: Vec<f64> = (0..8).map(|i| sobol_y(i) as f64 / 2f64.powi(32)).collect();
        assert_eq!(x, [0.0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875]);
        assert_eq!(y, [0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875]);
    }

    #[test]
    fn the_byte_tables_give_the_definitions_sobol_y() {
        let mut x = 0x9E37_79B9u32;
        for i in (0..4096).chain([u32::MAX, 1 << 31, 0xDEAD_BEEF]) {
            assert_eq!(sobol_y(i), sobol_y_bits(i), "{i}");
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            assert_eq!(sobol_y(x), sobol_y_bits(x), "{x}");
        }
    }

    #[test]
    fn owen_scramble_is_a_bijection_on_top_bits() {
        let mut seen = [false; 256];
        for i in 0..256u32 {
            seen[(owen_scramble(i << 24, 0xDEAD_BEEF) >> 24) as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
    }
}
