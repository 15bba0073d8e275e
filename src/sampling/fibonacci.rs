//! The paper's 2-D Fibonacci lattice ( frac((i+1)/phi_g), (i+0.5)/n ).
//!
//! frac((i+1)/phi_g) is computed in 128-bit fixed point: index * floor(2^128/phi_g) mod 2^128.
//! A 64-bit constant is 0.048 units of 2^-64 off, which at index 2^40 already moves ~5 % of the
//! points by one f32 step (2^-24); the 128-bit constant's error, under 2^-128 per unit of index,
//! cannot reach a 24-bit boundary for any u64 index in practice, so the f32 is the true fraction
//! truncated. (An f32 division loses every fractional bit past index 2^24.)

use super::hash::{FIX_BITS, fix_add, fix_to_f32};
use super::registry::{PixelSet, PointSequence, SequenceInfo};
use super::seed::SeedMode;
use glam::Vec2;

/// floor(2^128 / phi_g) = floor(2^128 * (phi_g - 1)).
pub const INV_GOLDEN_FIXED: u128 = 0x9E37_79B9_7F4A_7C15_F39C_C060_5CED_C834;

/// x of lattice index `index` (the paper's i + 1 plus any seed offset), as 24-bit fixed point.
#[inline]
pub fn fibonacci_x_fixed(index: u64) -> u32 {
    x_fixed_wide(index as u128)
}

/// As `fibonacci_x_fixed`, for an index past u64 (index + offset does not wrap at 2^64).
#[inline]
fn x_fixed_wide(index: u128) -> u32 {
    (index.wrapping_mul(INV_GOLDEN_FIXED) >> (128 - FIX_BITS)) as u32
}

/// y = (i + 0.5) / n floored to the 24-bit grid: inside stratum i exactly for n <= 2^23.
#[inline]
pub fn fibonacci_y_fixed(i: u32, n: u32) -> u32 {
    (((2 * i as u64 + 1) << (FIX_BITS - 1)) / n.max(1) as u64) as u32
}

/// Point `i` of the n-point lattice with the paper's seed `index_offset` added to the indices.
pub fn fibonacci_point(i: u32, n: u32, index_offset: u64) -> Vec2 {
    let x = x_fixed_wide(i as u128 + 1 + index_offset as u128);
    Vec2::new(fix_to_f32(x), fix_to_f32(fibonacci_y_fixed(i, n)))
}

/// Fills `out` with points 0.. of the n-point lattice, index offset `index_offset`, then
/// shifted by the fixed-point offsets (dx, dy) mod 1.
/// x is stepped eight points at a time: point j + k's is x_j + k·C mod 2^128 (the same bits as
/// the product), added in two 64-bit halves with the carry, independent across the eight, so the
/// loop vectorizes (AVX2 where the CPU has it). y = floor((2i+1) 2^23 / n) depends on n only: it is
/// worked out once per thread and n (`y_fixed`, quotient and remainder, no division) and reused by
/// every pixel. The same bits as stepping one point at a time (`fill_stepped`, tested); the kitchen's
/// 32-point sets went from 1.55 to 0.92 ns per point (`profile_render … points`).
pub fn fill(n: u32, index_offset: u64, dx: u32, dy: u32, out: &mut [Vec2]) {
    thread_local! {
        /// The last lattice's y (fixed point, before any shift): it depends only on n, the same
        /// for every pixel of a render.
        static Y: std::cell::RefCell<(u32, Vec<u32>)> = const { std::cell::RefCell::new((0, Vec::new())) };
    }
    Y.with(|cell| {
        let mut cached = cell.borrow_mut();
        if cached.0 != n || cached.1.len() < out.len() {
            *cached = (n, y_fixed(n, out.len()));
        }
        let y = &cached.1;
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2 (checked just above).
            return unsafe { fill_avx2(index_offset, dx, dy, y, out) };
        }
        fill_with_y(index_offset, dx, dy, y, out);
    })
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn fill_avx2(index_offset: u64, dx: u32, dy: u32, y: &[u32], out: &mut [Vec2]) {
    fill_with_y(index_offset, dx, dy, y, out);
}

/// k · INV_GOLDEN_FIXED mod 2^128 for k = 0..8, as (high, low) 64-bit halves.
const STEPS: [(u64, u64); 8] = {
    let mut t = [(0u64, 0u64); 8];
    let mut k = 0;
    while k < 8 {
        let v = (k as u128).wrapping_mul(INV_GOLDEN_FIXED);
        t[k] = ((v >> 64) as u64, v as u64);
        k += 1;
    }
    t
};

/// floor((2i+1) 2^23 / n) for i < len, by quotient and remainder (no division per point).
fn y_fixed(n: u32, len: usize) -> Vec<u32> {
    let n = n.max(1) as u64;
    let half = 1u64 << (FIX_BITS - 1);
    let (mut q, mut r) = (half / n, half % n);
    let (step_q, step_r) = ((2 * half) / n, (2 * half) % n);
    (0..len)
        .map(|_| {
            let y = q as u32;
            q += step_q;
            r += step_r;
            if r >= n {
                r -= n;
                q += 1;
            }
            y
        })
        .collect()
}

/// `fill` given the lattice's y (`y_fixed`, at least as long as `out`).
#[inline(always)]
fn fill_with_y(index_offset: u64, dx: u32, dy: u32, y: &[u32], out: &mut [Vec2]) {
    let mut x128 = (1 + index_offset as u128).wrapping_mul(INV_GOLDEN_FIXED);
    for (chunk, ys) in out.chunks_mut(8).zip(y.chunks(8)) {
        let (hi, lo) = ((x128 >> 64) as u64, x128 as u64);
        let mut xs = [0u32; 8];
        for (x, &(sh, sl)) in xs.iter_mut().zip(&STEPS) {
            let l = lo.wrapping_add(sl);
            let h = hi.wrapping_add(sh).wrapping_add((l < lo) as u64);
            *x = fix_add((h >> (64 - FIX_BITS)) as u32, dx);
        }
        for (p, (&x, &y)) in chunk.iter_mut().zip(xs.iter().zip(ys)) {
            *p = Vec2::new(fix_to_f32(x), fix_to_f32(fix_add(y, dy)));
        }
        x128 = x128.wrapping_add(8u128.wrapping_mul(INV_GOLDEN_FIXED));
    }
}

/// `fill` one point at a time: the definition the blocks must match.
/// The paper's lattice. Its seed is an index offset: `static` one per run, `rotation` plus one per
/// pixel (x moves by frac(offset / phi)); `shift`, `blue-noise` and `stbn` add their offsets to
/// the run's lattice (a Cranley–Patterson shift).
pub struct Fibonacci;

impl PointSequence for Fibonacci {
    fn info(&self) -> &SequenceInfo {
        &SequenceInfo {
            name: "fibonacci",
            label: "Fibonacci",
            words: &["lattice", "fibonacci lattice"],
            fresh_per_pixel: false,
            shipped: None,
        }
    }

    fn fill(&self, set: &PixelSet, out: &mut [Vec2]) {
        let n = set.count.max(1);
        let run_offset = set.seed.run_key >> 24;
        let (fx, fy) = set.frame_offsets;
        match set.seed_mode {
            SeedMode::Static => fill(n, run_offset, fx, fy, out),
            SeedMode::Rotation => fill(n, run_offset + (set.seed.pixel_key >> 24), fx, fy, out),
            // `shift`, the masks, the engine patterns and textures: offsets on the run's lattice.
            _ => fill(n, run_offset, set.offsets.0, set.offsets.1, out),
        }
    }
}

#[cfg(test)]
fn fill_stepped(n: u32, index_offset: u64, dx: u32, dy: u32, out: &mut [Vec2]) {
    let n = n.max(1) as u64;
    let mut x128 = (1 + index_offset as u128).wrapping_mul(INV_GOLDEN_FIXED);
    let half = 1u64 << (FIX_BITS - 1);
    let (mut q, mut r) = (half / n, half % n);
    let (step_q, step_r) = ((2 * half) / n, (2 * half) % n);
    for p in out.iter_mut() {
        let x = fix_add((x128 >> (128 - FIX_BITS)) as u32, dx);
        let y = fix_add(q as u32, dy);
        *p = Vec2::new(fix_to_f32(x), fix_to_f32(y));
        x128 = x128.wrapping_add(INV_GOLDEN_FIXED);
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

    /// Eight at a time (AVX2 or not) equals one at a time, for every length mod 8, offsets near
    /// 2^64 (the carry between the halves) and shifts.
    #[test]
    fn blocks_equal_stepping() {
        for n in [1u32, 5, 8, 31, 32, 33, 64, 1000, 65_537] {
            for offset in [0u64, 7, 1 << 40, u64::MAX - 3, 0x9E37_79B9_7F4A_7C15] {
                for (dx, dy) in [(0, 0), (12_345, 16_777_000), (16_777_215, 1)] {
                    let (mut a, mut b) = (vec![Vec2::ZERO; n as usize], vec![Vec2::ZERO; n as usize]);
                    fill(n, offset, dx, dy, &mut a);
                    fill_stepped(n, offset, dx, dy, &mut b);
                    let bits =
                        |v: &[Vec2]| v.iter().map(|p| (p.x.to_bits(), p.y.to_bits())).collect::<Vec<_>>();
                    assert_eq!(bits(&a), bits(&b), "n={n} offset={offset} d=({dx}, {dy})");
                    fill_with_y(offset, dx, dy, &y_fixed(n, n as usize), &mut a);
                    assert_eq!(bits(&a), bits(&b), "n={n} offset={offset}: portable blocks");
                }
            }
        }
    }

    #[test]
    fn constant_is_floor_of_two_pow_128_over_golden_ratio() {
        // Its top 64 bits are the well-known 64-bit golden-ratio hash constant 0x9E3779B97F4A7C15.
        assert_eq!((INV_GOLDEN_FIXED >> 64) as u64, 0x9E37_79B9_7F4A_7C15);
        // frac(1/phi_g) = 0.6180339887498949 to 16 digits.
        let x = (INV_GOLDEN_FIXED >> 75) as f64 / (1u64 << 53) as f64;
        assert!((x - 0.618_033_988_749_894_9).abs() < 1e-15, "{x}");
    }
}
