//! pmj02bn: a progressive multi-jittered (0,2) sequence with blue-noise selection, after
//! Christensen, Kensler & Kilpatrick 2018, "Progressive multi-jittered sample sequences" (EGSR).
//! Generated in code, deterministic, no tables. The pmj02 stratification (every power-of-two
//! prefix of N points has one point in every elementary interval of area 1/N) is exactly that of
//! a base-2 (0,2)-sequence; Helmer, Christensen & Kensler 2021 ("Stochastic generation of (t,s)
//! sample sequences") show pmj02 is such a sequence and that Owen scrambling of Sobol' draws one.
//! So the base sequence here is Owen-scrambled Sobol' (Burley 2020), and the blue-noise
//! selection is a best-candidate choice (Mitchell 1991) among [`CANDIDATES`] scrambles: the one
//! whose prefixes of 4..=256 points have the largest normalized minimum toroidal distance.
//! Per set it is randomized by a digital (XOR) shift, which maps elementary intervals onto
//! elementary intervals (the stratification is kept exactly) and makes every point uniform.
//! Not Christensen et al.'s point-by-point construction: their blue-noise choice is made per
//! point, this one per sequence.

use super::hash::{FIX_BITS, fix_add, fix_to_f32, hash};
use super::sobol::{owen_scramble, sobol_x, sobol_y};
use glam::Vec2;
use std::sync::OnceLock;

/// Scrambles the best-candidate selection considers.
pub const CANDIDATES: u64 = 32;

/// Minimum toroidal distance of the first `n` points, times sqrt(n) (1 for a perfect hexagonal-ish set, order).
fn min_distance(points: &[(u32, u32)]) -> f64 {
    let mut best = f64::MAX;
    let d = |a: u32, b: u32| {
        let t = (a as f64 - b as f64).abs() / (1u64 << FIX_BITS) as f64;
        t.min(1.0 - t)
    };
    for (i, a) in points.iter().enumerate() {
        for b in &points[..i] {
            let (u, v) = (d(a.0, b.0), d(a.1, b.1));
            best = best.min(u * u + v * v);
        }
    }
    best.sqrt() * (points.len() as f64).sqrt()
}

/// Point `i` of the base sequence scrambled by (`sx`, `sy`), 24-bit fixed point.
#[inline]
fn base_point(i: u32, sx: u32, sy: u32) -> (u32, u32) {
    (owen_scramble(sobol_x(i), sx) >> (32 - FIX_BITS), owen_scramble(sobol_y(i), sy) >> (32 - FIX_BITS))
}

/// The scramble seeds of the blue-noise-selected base sequence (computed once, deterministic).
pub fn base_seeds() -> (u32, u32) {
    static SEEDS: OnceLock<(u32, u32)> = OnceLock::new();
    *SEEDS.get_or_init(|| {
        let mut best = (f64::MIN, (0, 0));
        for c in 0..CANDIDATES {
            let (sx, sy) =
                (hash(0x706D_6A30_3262_6E00, 2 * c) as u32, hash(0x706D_6A30_3262_6E00, 2 * c + 1) as u32);
            let pts: Vec<(u32, u32)> = (0..256).map(|i| base_point(i, sx, sy)).collect();
            let score: f64 = (2..=8).map(|m| min_distance(&pts[..1 << m])).sum();
            if score > best.0 {
                best = (score, (sx, sy));
            }
        }
        best.1
    })
}

/// Point `i` of the unrandomized pmj02bn sequence, 24-bit fixed point.
pub fn pmj02bn_fixed(i: u32) -> (u32, u32) {
    let (sx, sy) = base_seeds();
    base_point(i, sx, sy)
}

/// Fills `out` with points 0.. of pmj02bn, digitally shifted by bits from `key`, then shifted by
/// (`dx`, `dy`) mod 1.
pub fn fill(key: u64, dx: u32, dy: u32, out: &mut [Vec2]) {
    let (sx, sy) = base_seeds();
    let xor_x = (hash(key, 1) >> (64 - FIX_BITS)) as u32;
    let xor_y = (hash(key, 2) >> (64 - FIX_BITS)) as u32;
    for (i, p) in out.iter_mut().enumerate() {
        let (x, y) = base_point(i as u32, sx, sy);
        *p = Vec2::new(fix_to_f32(fix_add(x ^ xor_x, dx)), fix_to_f32(fix_add(y ^ xor_y, dy)));
    }
}
