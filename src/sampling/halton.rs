//! The 2-D Halton sequence (bases 2 and 3), Owen-scrambled per set: x is the base-2 radical
//! inverse (van der Corput), y the base-3 one (Halton 1964). The scramble is nested (Owen 1995):
//! each digit is permuted by a random rotation of {0, 1, 2} chosen by hashing the digits above
//! it, as pbrt-v4's `OwenScrambledRadicalInverse` does (Pharr, Jakob & Humphreys 2023, §8.6).
//! Base 2 reuses [`super::sobol::owen_scramble`] (Burley 2020). A set hashes each node of its
//! digit tree once and draws the digits below its own in one hash (`owen_scramble_3`).

use super::hash::{FIX_BITS, fix_add, fix_to_f32, hash};
use super::registry::{PixelSet, PointSequence, SHIPS_SHIFTED, SequenceInfo, Shipped};
use super::seed::SeedMode;
use super::sobol::laine_karras;
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

/// Fills `out` with the first points of a `count`-point Halton set, Owen-scrambled by seeds from
/// `key`, shifted by (`dx`, `dy`) mod 1. The base-3 scramble is `owen_scramble_3`'s.
pub fn fill(key: u64, count: u32, dx: u32, dy: u32, out: &mut [Vec2]) {
    let sx = hash(key, 1) as u32;
    let sy = hash(key, 2);
    SCRATCH.with_borrow_mut(|scratch| {
        owen_scramble_3(count, sy, out.len(), scratch);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2 (checked just above).
            return unsafe { points_avx2(scratch, sx, (dx, dy), out) };
        }
        points(scratch, sx, (dx, dy), out)
    });
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn points_avx2(ys: &[u64], sx: u32, d: (u32, u32), out: &mut [Vec2]) {
    points(ys, sx, d, out)
}

/// The points from their scrambled base-3 integers `ys`: x in a first pass that vectorizes (eight
/// 32-bit hashes and bit reversals at a time), y (64-bit products) in a second.
#[inline(always)]
fn points(ys: &[u64], sx: u32, (dx, dy): (u32, u32), out: &mut [Vec2]) {
    const CHUNK: usize = 64;
    let mut xs = [0.0f32; CHUNK];
    for (c, (out, ys)) in out.chunks_mut(CHUNK).zip(ys.chunks(CHUNK)).enumerate() {
        let xs = &mut xs[..out.len()];
        for (k, x) in xs.iter_mut().enumerate() {
            // owen_scramble(reverse(i), sx), with the two reversals that cancel left out.
            let i = (c * CHUNK + k) as u32;
            *x = fix_to_f32(fix_add(laine_karras(i, sx).reverse_bits() >> (32 - FIX_BITS), dx));
        }
        for ((p, &x), &y) in out.iter_mut().zip(xs.iter()).zip(ys) {
            *p = Vec2::new(x, fix_to_f32(fix_add(base3_to_fixed(y), dy)));
        }
    }
}

std::thread_local! {
    /// `fill`'s working list, kept per thread so that a render allocates it once.
    static SCRATCH: std::cell::RefCell<Vec<u64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Base-3 digits a `count`-point set's indices use: the least k with 3^k >= count.
pub fn set_digits(count: u32) -> u32 {
    let (mut k, mut p) = (0, 1u64);
    while p < count as u64 {
        p *= 3;
        k += 1;
    }
    k
}

/// The Owen-scrambled base-3 radical inverses (integers r, value r / 3^21) of points 0..`len` of a
/// `count`-point set, into `out`. Its k = `set_digits(count)` leading digits are those of
/// `owen_radical_inverse_3(i, Some(seed))` (each digit rotated by the same hash of the digits above
/// it), found once per node of the digit tree: 3^j nodes at depth j, (3^k - 1) / 2 hashes for the
/// set instead of 21 a point, which made Halton renders cost ×4.1–4.6 the lattice's.
/// Below depth k every index's digits are 0 and no two points of the set share a node, so in a
/// nested uniform scramble (Owen 1995) the remaining 21 - k digits of each point are independent
/// uniform digits: one hash of the point's node draws them together, uniform on 0..3^(21-k). The
/// set is thus Owen-scrambled in distribution exactly as before, but its points differ from
/// `owen_radical_inverse_3`'s below 3^-k (and they depend on `count`, as a scramble's tail may).
pub fn owen_scramble_3(count: u32, seed: u64, len: usize, out: &mut Vec<u64>) {
    let k = set_digits(count.max(len as u32));
    out.clear();
    out.push(0);
    // out[p], p < 3^j: the scrambled leading j digits (as an integer) of every index = p mod 3^j.
    let mut size = 1usize;
    for depth in 0..k {
        // The last depth makes only the nodes of the points asked for.
        let next = if depth + 1 == k { len.max(1) } else { size * 3 };
        out.resize(next.max(size), 0);
        for p in 0..size.min(next) {
            let above = out[p];
            let rot = hash(seed, ((depth as u64) << 40) | above) % 3;
            for c in (0..3u64).rev() {
                let child = p + c as usize * size;
                if child < next {
                    out[child] = above * 3 + (c + rot) % 3;
                }
            }
        }
        out.truncate(next);
        size = next;
    }
    let tail = 3u64.pow(DIGITS_3 - k);
    out.truncate(len);
    for a in out.iter_mut() {
        let h = hash(seed, ((k as u64) << 40) | *a);
        *a = *a * tail + ((h as u128 * tail as u128) >> 64) as u64;
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
        fill(key, set.count.max(1), dx, dy, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sets_leading_digits_are_the_per_digit_scrambles() {
        let mut out = Vec::new();
        for count in [1u32, 2, 3, 4, 9, 10, 36, 64, 100, 729, 1024] {
            let k = set_digits(count);
            let below = 3u64.pow(DIGITS_3 - k);
            for seed in [1u64, 0xDEAD_BEEF, u64::MAX] {
                for len in [count as usize, (count as usize).div_ceil(2)] {
                    owen_scramble_3(count, seed, len, &mut out);
                    assert_eq!(out.len(), len);
                    for (i, &r) in out.iter().enumerate() {
                        assert!(r < POW3);
                        let want = owen_radical_inverse_3(i as u32, Some(seed)) / below;
                        assert_eq!(r / below, want, "count {count} seed {seed} point {i}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_drawn_tail_is_uniform_in_its_cell() {
        // Chi-square over 27 sub-cells of each point's cell (3^-k wide), 64-point sets, many seeds.
        let (mut hist, mut out) = ([0u64; 27], Vec::new());
        let below = 3u64.pow(DIGITS_3 - set_digits(64));
        for seed in 0..400u64 {
            owen_scramble_3(64, seed, 64, &mut out);
            for &r in &out {
                hist[((r % below) * 27 / below) as usize] += 1;
            }
        }
        let expected = 400.0 * 64.0 / 27.0;
        let chi2: f64 = hist.iter().map(|&h| (h as f64 - expected).powi(2) / expected).sum();
        // 26 degrees of freedom: P(chi2 > 54.05) = 0.001.
        assert!(chi2 < 54.05, "chi-square {chi2:.1}: {hist:?}");
    }
}
