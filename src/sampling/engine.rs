//! The per-pixel patterns real-time engines ship, as seed modes: each gives a pixel one
//! scalar in [0, 1), used as a **rotation** — the x offset (mod 1) of the static set, a rotation
//! about the normal through the sine and sine-cosine warps, as `rotation` is. All four are scalar
//! masks by definition (one number per pixel), so a 2-D offset from them would put every pixel's
//! offset on a line; engines use them to rotate a kernel, and so does hemilab.
//!
//! | mode | the pattern at pixel (x, y), frame f | source |
//! |---|---|---|
//! | `ign` | frac(52.9829189 · frac(0.06711056 x' + 0.00583715 y')), x' = x + 5.588238 (f mod 64), y' likewise | Jimenez 2014, "Next Generation Post Processing in Call of Duty: Advanced Warfare" (SIGGRAPH course); the per-frame offset and its reset every 64 frames as Wolfe 2022 animates it ("Interleaved Gradient Noise: A Different Kind of Low Discrepancy Sequence") |
//! | `bayer` | B(x mod 4, y mod 4) / 16, B the 4 × 4 ordered-dither matrix | Bayer 1973, "An optimum method for two-level rendition of continuous-tone pictures" (ICC) |
//! | `magic-square` | M(x mod 5, y mod 5) / 25, M(x, y) = 5 ((4x + 3y) mod 5) + ((x + 3y) mod 5) | a pandiagonal (Nasik) magic square of order 5 by the linear construction of de la Hire (1705); the coefficients are, of all pandiagonal linear squares, one with the largest least circular difference between 8-neighbours (3/25) |
//! | `r2-dither` | frac(x / g + y / g²), g the plastic number (g³ = g + 1) | Roberts 2018, "The unreasonable effectiveness of quasirandom sequences" (its dither mask) |
//!
//! Every neighbourhood holds all the rotations: each 4 × 4 window of `bayer` holds its 16 values
//! and each 5 × 5 window of `magic-square` its 25 (both are periodic tiles), and every row, column
//! and diagonal of the magic square holds each of the five coarse and five fine digits once.
//!
//! **A run's seed** ([`EngineShift`]): the pattern is shifted toroidally by a per-run integer
//! offset (uniform over the period: 4 or 5, or over 2^16 pixels for the aperiodic IGN and R2
//! dither), so replicates see different phases, and a per-run Cranley–Patterson offset u, uniform
//! on the 24-bit grid, is added mod 1. Then a fixed pixel's x offset over runs is exactly uniform
//! whatever the pattern (pattern + an independent uniform, mod 1). Only x moves, so, as for
//! `rotation`, the per-pixel estimate is unbiased only where the static set itself is random over
//! runs (`random`); for the lattice, a scramble or a jitter, a fixed pattern gives each pixel a fixed
//! θ set and no per-pixel randomization (tests/stages/sampling_engine_noise.rs measures both).
//!
//! **Frames** ([`super::schedule`]): `independent` draws every frame from a fresh run seed (a new
//! shift and offset), as for every mode. `r1` keeps the run seed and steps the pattern as engines
//! do: IGN by its own pixel offset 5.588238 f (frame mod 64), the other three by the golden-ratio
//! R1 step of a scalar rotation (frac(u + f / φ)), which is the schedule's step of `rotation`.

use super::hash::{FIX_BITS, FIX_ONE, fix_add, hash};
use super::schedule::R2_ALPHA;

/// The four engine patterns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Pattern {
    Ign,
    Bayer,
    MagicSquare,
    R2Dither,
}

/// Bayer's 4 × 4 ordered-dither matrix, row-major (row = y).
pub const BAYER4: [u32; 16] = [0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5];

/// The order-5 pandiagonal magic square's entry at (x, y), 0..25.
#[inline]
pub const fn magic5(x: u32, y: u32) -> u32 {
    5 * ((4 * x + 3 * y) % 5) + (x + 3 * y) % 5
}

/// Frames after which IGN's per-frame offset starts again (Wolfe 2022: keeps x' small).
pub const IGN_PERIOD: u32 = 64;
/// IGN's per-frame pixel offset (Wolfe 2022).
pub const IGN_FRAME_STEP: f64 = 5.588238;

/// Interleaved gradient noise at real pixel coordinates (x, y) (Jimenez 2014), in f64: exact IEEE
/// operations (no fused multiply-add), so the same on every machine.
#[inline]
pub fn ign(x: f64, y: f64) -> f64 {
    let inner = 0.06711056 * x + 0.00583715 * y;
    let v = 52.9829189 * (inner - inner.floor());
    v - v.floor()
}

/// [0, 1) to the 24-bit grid (floor; a value that rounds to 1 stays below it).
#[inline]
pub fn to_fixed(v: f64) -> u32 {
    ((v * FIX_ONE as f64) as u32).min(FIX_ONE - 1)
}

impl Pattern {
    /// The pattern's period in pixels, if it tiles.
    pub fn period(self) -> Option<u32> {
        match self {
            Pattern::Bayer => Some(4),
            Pattern::MagicSquare => Some(5),
            Pattern::Ign | Pattern::R2Dither => None,
        }
    }

    /// The pattern's value at pixel (x, y) in frame `t` (only IGN reads `t`), 24-bit fixed point.
    #[inline]
    pub fn value(self, x: u32, y: u32, t: u32) -> u32 {
        match self {
            Pattern::Ign => {
                let f = (t % IGN_PERIOD) as f64 * IGN_FRAME_STEP;
                to_fixed(ign(x as f64 + f, y as f64 + f))
            }
            Pattern::Bayer => BAYER4[((y % 4) * 4 + x % 4) as usize] << (FIX_BITS - 4),
            // floor(M 2^24 / 25): the 25 values equally spaced to the grid's resolution.
            Pattern::MagicSquare => ((magic5(x % 5, y % 5) as u64 * FIX_ONE as u64) / 25) as u32,
            // frac(x / g + y / g²) from the 64-bit Weyl constants: exact mod 1 at any pixel.
            Pattern::R2Dither => {
                let v =
                    (x as u64).wrapping_mul(R2_ALPHA[0]).wrapping_add((y as u64).wrapping_mul(R2_ALPHA[1]));
                (v >> (64 - FIX_BITS)) as u32
            }
        }
    }
}

/// One run's randomization of a pattern: a toroidal shift (which pixel reads which phase) and a
/// Cranley–Patterson offset added mod 1, the same for every pixel; see the module's doc.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EngineShift {
    shift: (u32, u32),
    offset: u32,
}

impl EngineShift {
    /// Derived from the run key only.
    #[inline]
    pub fn new(pattern: Pattern, run_key: u64) -> Self {
        let h = hash(run_key, 0xE9_61_4E);
        // 2^16 is no multiple of 5: the magic square's shift comes from 32 bits (bias < 2^-29).
        let (sx, sy) = match pattern.period() {
            Some(p) => ((h as u32) % p, ((h >> 32) as u32) % p),
            None => (h as u32 & 0xFFFF, (h >> 16) as u32 & 0xFFFF),
        };
        let offset = (hash(run_key, 0xE9_61_4F) >> (64 - FIX_BITS)) as u32;
        Self { shift: (sx, sy), offset }
    }

    /// Pixel (x, y)'s x offset in frame `t` of the pattern, 24-bit fixed point.
    #[inline]
    pub fn offset(&self, pattern: Pattern, x: u32, y: u32, t: u32) -> u32 {
        let (x, y) = match pattern.period() {
            Some(p) => (x % p + self.shift.0, y % p + self.shift.1),
            None => (x.wrapping_add(self.shift.0), y.wrapping_add(self.shift.1)),
        };
        fix_add(pattern.value(x, y, t), self.offset)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ign_matches_jimenez_at_known_pixels() {
        // By hand: 0.06711056 · 1 = 0.06711056; × 52.9829189 = 3.5557134; frac = 0.5557134.
        assert!((ign(1.0, 0.0) - 0.555_713_4).abs() < 1e-7, "{}", ign(1.0, 0.0));
        assert_eq!(ign(0.0, 0.0), 0.0);
    }

    #[test]
    fn bayer_and_magic_square_windows_hold_every_value() {
        for (p, n) in [(Pattern::Bayer, 4u32), (Pattern::MagicSquare, 5)] {
            for (ox, oy) in [(0, 0), (3, 1), (7, 11)] {
                let mut v: Vec<u32> = (0..n * n).map(|i| p.value(ox + i % n, oy + i / n, 0)).collect();
                v.sort_unstable();
                v.dedup();
                assert_eq!(v.len() as u32, n * n, "{p:?} at ({ox}, {oy})");
            }
        }
    }
}
