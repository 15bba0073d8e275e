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
static SOBOL_Y_BYTES: [[u32; 256]; 4] = byte_tables(false);

/// `sobol_y_bits(v << 8b)` for every byte value v of every byte b, bit-reversed if `reversed`.
const fn byte_tables(reversed: bool) -> [[u32; 256]; 4] {
    let mut t = [[0u32; 256]; 4];
    let mut b = 0;
    while b < 4 {
        let mut v = 0;
        while v < 256 {
            let y = sobol_y_bits((v as u32) << (8 * b));
            t[b][v] = if reversed { y.reverse_bits() } else { y };
            v += 1;
        }
        b += 1;
    }
    t
}

/// `sobol_y(i).reverse_bits()` from `SOBOL_Y_REVERSED_BYTES` (reversal commutes with XOR).
#[inline(always)]
fn sobol_y_reversed(i: u32) -> u32 {
    let t = &SOBOL_Y_REVERSED_BYTES;
    t[0][(i & 0xFF) as usize]
        ^ t[1][(i >> 8 & 0xFF) as usize]
        ^ t[2][(i >> 16 & 0xFF) as usize]
        ^ t[3][(i >> 24) as usize]
}

/// `SOBOL_Y_BYTES` with every entry bit-reversed.
static SOBOL_Y_REVERSED_BYTES: [[u32; 256]; 4] = byte_tables(true);

/// Laine–Karras style hash: each bit flips depending only on lower bits (Burley 2020, listing 2).
#[inline]
pub fn laine_karras(mut x: u32, seed: u32) -> u32 {
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
    let mut idx = [0u32; CHUNK];
    for (c, chunk) in out.chunks_mut(CHUNK).enumerate() {
        for (k, i) in idx.iter_mut().enumerate() {
            *i = (c * CHUNK + k) as u32;
        }
        scrambled_points(&idx[..chunk.len()], (sx, sy), (dx, dy), chunk);
    }
}

/// Points a call of `scrambled_points` is best given at most (its scratch lives on the stack).
pub const CHUNK: usize = 64;

/// The points of Sobol' indices `idx` (dimensions 0 and 1, Owen-scrambled by seeds `sx`, `sy`,
/// shifted by (`dx`, `dy`) mod 1) into `out`, as long as `idx`: `point_of` of each index, bit for
/// bit, eight lanes at a time. Since `sobol_x` is a bit reversal, `owen_scramble(sobol_x(i), s)` is
/// `laine_karras(i, s)` reversed, and the reversed `sobol_y` comes from reversed byte tables: two
/// reversals a point instead of four, and the hashes vectorize (the table loads are a first,
/// scalar pass).
pub fn scrambled_points(idx: &[u32], (sx, sy): (u32, u32), (dx, dy): (u32, u32), out: &mut [Vec2]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2 (checked just above).
        return unsafe { scrambled_points_avx2(idx, (sx, sy), (dx, dy), out) };
    }
    scrambled_points_in(idx, (sx, sy), (dx, dy), out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn scrambled_points_avx2(idx: &[u32], s: (u32, u32), d: (u32, u32), out: &mut [Vec2]) {
    scrambled_points_in(idx, s, d, out)
}

#[inline(always)]
fn scrambled_points_in(idx: &[u32], (sx, sy): (u32, u32), (dx, dy): (u32, u32), out: &mut [Vec2]) {
    assert_eq!(idx.len(), out.len());
    let mut ry = [0u32; CHUNK];
    for (idx, out) in idx.chunks(CHUNK).zip(out.chunks_mut(CHUNK)) {
        let ry = &mut ry[..idx.len()];
        for (r, &i) in ry.iter_mut().zip(idx) {
            *r = sobol_y_reversed(i);
        }
        for ((p, &i), &r) in out.iter_mut().zip(idx).zip(ry.iter()) {
            let x = laine_karras(i, sx).reverse_bits() >> (32 - FIX_BITS);
            let y = laine_karras(r, sy).reverse_bits() >> (32 - FIX_BITS);
            *p = Vec2::new(fix_to_f32(fix_add(x, dx)), fix_to_f32(fix_add(y, dy)));
        }
    }
}

/// Sobol' point `i` (dimensions 0 and 1), Owen-scrambled by `sx`, `sy`, shifted by (`dx`, `dy`):
/// the definition `scrambled_points` computes in bulk.
pub fn point_of(i: u32, (sx, sy): (u32, u32), (dx, dy): (u32, u32)) -> Vec2 {
    let x = owen_scramble(sobol_x(i), sx) >> (32 - FIX_BITS);
    let y = owen_scramble(sobol_y(i), sy) >> (32 - FIX_BITS);
    Vec2::new(fix_to_f32(fix_add(x, dx)), fix_to_f32(fix_add(y, dy)))
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
    fn scrambled_points_are_point_of_each_index() {
        let mut x = 0x1234_5678u32;
        let mut step = || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x
        };
        for len in [0, 1, 7, 8, 63, 64, 65, 200] {
            let idx: Vec<u32> = (0..len).map(|_| step()).collect();
            let (s, d) = ((step(), step()), (step() >> 8, step() >> 8));
            let mut out = vec![Vec2::ZERO; len];
            scrambled_points(&idx, s, d, &mut out);
            let mut scalar = vec![Vec2::ZERO; len];
            scrambled_points_in(&idx, s, d, &mut scalar);
            for (k, &i) in idx.iter().enumerate() {
                assert_eq!(out[k], point_of(i, s, d), "len {len} k {k}");
                assert_eq!(scalar[k], out[k]);
            }
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
