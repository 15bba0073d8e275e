//! How a pixel's randomization changes from frame to frame (a static camera rendered for several
//! frames, whose images are accumulated): the per-frame randomization schedule.
//!
//! | schedule | every seed mode but `stbn` | `stbn` |
//! |---|---|---|
//! | `independent` | frame f draws everything from a fresh run seed keyed by (seed, f); frame 0 keeps the seed, so its points are today's. For `blue-noise` that is a new toroidal mask shift per frame. | the mask's own time axis for f mod depth; a fresh run seed (new toroidal shift) per full cycle of depth frames |
//! | `r1` | the run seed stays; the offsets the mode applies advance by f golden-ratio steps: R1 (1/phi) for the scalar x offset of `rotation`, R2 (1/g, 1/g², g the plastic number) for the 2-D Cranley–Patterson offsets of every other mode (for `static`, the whole set moves; for `blue-noise`, the usual engine practice of a fixed mask plus R2 per frame) | the mask's time axis for f mod depth; + R2 once per full cycle |
//!
//! The engines' patterns (`ign`, `bayer`, `magic-square`, `r2-dither`) and textures follow the same
//! rows: a pattern is a rotation, so `r1` steps it by R1 — except IGN, which under `r1` steps by its
//! own pixel offset 5.588238 f (frame mod 64, [`super::engine`]) with no R1 added; a texture of D
//! slices is read like `stbn` (slice f mod D, the schedule once per cycle; for one slice, as
//! `blue-noise`), and a vector texture's R2 step per cycle moves its texels, not its directions.
//!
//! R1 and R2 are Roberts' additive recurrences ("The unreasonable effectiveness of quasirandom
//! sequences", 2018): frac(f α) for α = 1/phi (R1), and the pair α = (1/g, 1/g²) with g the real
//! root of g³ = g + 1 (R2), the 2-D sequence of lowest discrepancy among additive recurrences.
//! Each step is f·α mod 1 computed from a 64-bit constant (f · floor(2^64 α) mod 2^64, top 24
//! bits), exact for every u32 frame, then added mod 1 in the 24-bit fixed point (`fix_add`), so
//! frame f's offsets are exactly (base + f α) mod 1 and frame 0 changes no bit.
//!
//! Why R1 for a rotation and R2 for a shift: the rotation moves x only, so its sequence is the
//! scalar one; a shift moves x and y, and stepping both by R1 would move every offset along the
//! diagonal. `random` × `rotation` is `random` × `shift` (the same fresh numbers), so both take R2.

use super::hash::{FIX_BITS, hash};

/// How the randomization of frame f relates to frame 0's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub enum Schedule {
    /// A fresh run seed per frame.
    #[default]
    Independent,
    /// The same run seed, offsets advanced by golden-ratio (R1 / R2) steps per frame.
    R1,
}

/// floor(2^64 / phi), phi the golden ratio: R1's step.
pub const R1_ALPHA: u64 = 0x9E37_79B9_7F4A_7C15;
/// floor(2^64 / g) and floor(2^64 / g²), g = 1.3247… the plastic number: R2's steps.
pub const R2_ALPHA: [u64; 2] = [0xC13F_A9A9_02A6_328F, 0x91E1_0DA5_C79E_7B1C];

/// frac(k α) in 24-bit fixed point, for α = `alpha` / 2^64: exact (64-bit modular product).
#[inline]
pub fn step(k: u64, alpha: u64) -> u32 {
    (k.wrapping_mul(alpha) >> (64 - FIX_BITS)) as u32
}

/// k steps of R1, in 24-bit fixed point.
#[inline]
pub fn r1(k: u64) -> u32 {
    step(k, R1_ALPHA)
}

/// k steps of R2, in 24-bit fixed point.
#[inline]
pub fn r2(k: u64) -> (u32, u32) {
    (step(k, R2_ALPHA[0]), step(k, R2_ALPHA[1]))
}

/// The run seed of epoch `k` under `independent` (an epoch is a frame, or one cycle of the
/// `stbn` mask): keyed by (seed, k); epoch 0 keeps `seed`, so a single frame is today's image.
#[inline]
pub fn epoch_seed(seed: u64, k: u64) -> u64 {
    if k == 0 { seed } else { hash(seed ^ 0x6672_616D_6573_6564, k) }
}

/// What a schedule makes of epoch `k`: the run seed to derive the pixel keys from, and the
/// fixed-point offsets added to the mode's own (x only when `scalar`, the rotation's case).
#[inline]
pub fn epoch(schedule: Schedule, seed: u64, k: u64, scalar: bool) -> (u64, (u32, u32)) {
    match schedule {
        Schedule::Independent => (epoch_seed(seed, k), (0, 0)),
        Schedule::R1 if scalar => (seed, (r1(k), 0)),
        Schedule::R1 => (seed, r2(k)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constants_are_the_inverse_golden_and_plastic_numbers() {
        let g = 1.324_717_957_244_746_f64;
        assert!((g * g * g - g - 1.0).abs() < 1e-15);
        let phi = (1.0 + 5f64.sqrt()) / 2.0;
        for (c, want) in [(R1_ALPHA, 1.0 / phi), (R2_ALPHA[0], 1.0 / g), (R2_ALPHA[1], 1.0 / (g * g))] {
            assert!((c as f64 / 2f64.powi(64) - want).abs() < 1e-15, "{c:#x} {want}");
        }
    }

    #[test]
    fn epoch_zero_changes_nothing() {
        for s in [Schedule::Independent, Schedule::R1] {
            for scalar in [false, true] {
                assert_eq!(epoch(s, 12345, 0, scalar), (12345, (0, 0)));
            }
        }
        assert_ne!(epoch_seed(12345, 1), 12345);
        assert_ne!(epoch_seed(12345, 1), epoch_seed(12345, 2));
    }
}
