//! Randomization across pixels (the paper's "seed"); the hashing and the fixed-point arithmetic
//! every sequence shares are in [`super::hash`] (re-exported here).
//!
//! | seed mode | random | fibonacci | stratified | sobol |
//! |---|---|---|---|---|
//! | `static` — the same point set in every pixel, keyed by the run seed only | one set of counter-based pseudo-random numbers per run | the paper's lattice with index offset = hash(run seed) (the paper's "static seed") | one jitter per run | one Owen scramble per run |
//! | `rotation` — the paper's "random seed per pixel": the static set with x offset per pixel (mod 1) = a rotation about the normal | fresh independent numbers per pixel (bit-identical to `shift`) | a per-pixel random index offset (< 2^40) added to the indices: x moves by frac(offset / phi_g) | static jitter, per-pixel x offset | static scramble, per-pixel x offset |
//! | `shift` — per-pixel randomization that makes each pixel's estimate unbiased | fresh independent numbers per pixel (bit-identical to `rotation`) | static lattice + Cranley–Patterson shift of x and y (mod 1) | fresh independent jitter per pixel | per-pixel Owen scrambling (Burley 2020) |
//! | `blue-noise` — the static set + a Cranley–Patterson shift of x and y whose per-pixel offsets come from two blue-noise masks ([`super::blue_noise`]), toroidally shifted per run: unbiased per pixel, error pushed to high frequencies | static numbers, shifted | static lattice, shifted (like `shift`, offsets blue instead of white) | static jitter, shifted | static scramble, shifted |
//! | `stbn` — as `blue-noise`, the two masks spatiotemporal ([`super::stbn`], Wolfe et al. 2022): frame f reads slice f mod depth, so each frame is blue in space and each pixel's offsets over frames are blue in time; toroidally shifted per run: unbiased per pixel in every frame. At frame 0 it is a 2-D blue-noise mask like `blue-noise`'s (another one); it differs across frames | static numbers, shifted | static lattice, shifted | static jitter, shifted | static scramble, shifted |
//!
//! How the modes change from frame to frame (`independent`, `r1`): [`super::schedule`].
//!
//! The four sequences after them — `halton` (Owen-scrambled radical inverses), `pmj02bn`
//! (digitally shifted), `zsobol` (Morton-indexed, digit-permuted, Owen-scrambled) and `r2`
//! (Cranley–Patterson offset) — share one column, as `stratified` and `sobol` do:
//!
//! | seed mode | halton | pmj02bn | zsobol | r2 |
//! |---|---|---|---|---|
//! | `static` | one Owen scramble per run: the same set in every pixel | one XOR shift per run | one set of digit permutations and one scramble per run; each pixel reads its own Morton block of the one sequence (Ahmed & Wonka's sampler: the sets differ, the error is blue) | one start offset per run |
//! | `rotation` | static scramble, per-pixel x offset | static shift, per-pixel x offset | static permutations, per-pixel x offset | static offset, per-pixel x offset |
//! | `shift` (unbiased per pixel) | per-pixel Owen scramble | per-pixel XOR shift (keeps every elementary interval) | per-pixel permutations and scramble (still a Sobol' net per pixel, but no longer one sequence across pixels) | per-pixel Cranley–Patterson offset |
//! | `blue-noise` | static scramble, shifted | static shift, shifted | static permutations, shifted | static offset, shifted |
//!
//! `rotation` leaves y (hence theta) as in the static set, so it does not make the per-pixel
//! estimate unbiased for the lattice sequences (tests/stages/sampling_estimators.rs measures it).
//!
//! The engines' patterns and noise textures act on every sequence alike, as `blue-noise` does: the run's static set
//! (for `random`, the run's one set of numbers) plus the mode's per-pixel offsets:
//!
//! | seed mode | offset added to the static set | randomized per run by | unbiased per pixel |
//! |---|---|---|---|
//! | `ign`, `bayer`, `magic-square`, `r2-dither` — the engines' patterns ([`super::engine`]) | x only (a rotation): the pattern's value at the pixel | a toroidal shift of the pattern + a Cranley–Patterson offset of x | as `rotation`: only for `random` (the static set is random over runs); never for the lattice, a scramble or a jitter |
//! | `texture`, use `offset` ([`super::texture`]) | x and y from the texture's channels 0 and 1 | the built-in masks' toroidal shift and cell jitter | when its slices are exactly uniform (measured at load; else one warning) |
//! | `texture`, use `rotation` | x only, from channel 0 | as `offset` | as `rotation` |
//! | `texture`, use `vector` | none: the texel is the direction (any sequence names the same images; `random` is kept) | a toroidal shift | never (a finite set of directions) |

use super::blue_noise::MaskShift;
use super::engine::{EngineShift, Pattern};
pub use super::hash::{FIX_BITS, FIX_ONE, fix_add, fix_from_bits, fix_to_f32, hash, mix64};
use super::stbn::StbnShift;
use super::texture::{TextureId, TextureUse};

/// How the point set differs from pixel to pixel (the paper's "seed").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SeedMode {
    Static,
    Rotation,
    Shift,
    /// The static set shifted per pixel by a blue-noise mask (Georgiev & Fajardo 2016).
    BlueNoise,
    /// As `BlueNoise`, the masks spatiotemporal: one slice per frame (Wolfe et al. 2022).
    Stbn,
    /// Interleaved gradient noise as a per-pixel rotation (Jimenez 2014; [`super::engine`]).
    Ign,
    /// Bayer's 4 × 4 ordered-dither matrix as a per-pixel rotation.
    Bayer,
    /// A 5 × 5 pandiagonal magic square as a per-pixel rotation.
    MagicSquare,
    /// Roberts' R2 dither mask as a per-pixel rotation.
    R2Dither,
    /// A noise texture the user named, read by the loader ([`super::texture`]).
    Texture(TextureId),
}

impl SeedMode {
    /// The engine pattern behind the mode, if it is one.
    pub fn pattern(self) -> Option<Pattern> {
        match self {
            SeedMode::Ign => Some(Pattern::Ign),
            SeedMode::Bayer => Some(Pattern::Bayer),
            SeedMode::MagicSquare => Some(Pattern::MagicSquare),
            SeedMode::R2Dither => Some(Pattern::R2Dither),
            _ => None,
        }
    }

    /// The texture's use, if the mode is a texture.
    pub fn texture_use(self) -> Option<TextureUse> {
        match self {
            SeedMode::Texture(t) => Some(t.get().use_()),
            _ => None,
        }
    }

    /// Whether the mode adds per-pixel offsets (`offsets_at`) to the run's static set: the masks,
    /// the engine patterns and offset or rotation textures (not `rotation` and `shift`, whose
    /// randomization some sequences make their own way, nor a vector texture, which gives the
    /// points itself).
    pub fn carries_offsets(self) -> bool {
        match self {
            SeedMode::BlueNoise | SeedMode::Stbn => true,
            SeedMode::Ign | SeedMode::Bayer | SeedMode::MagicSquare | SeedMode::R2Dither => true,
            SeedMode::Texture(t) => t.get().use_() != TextureUse::Vector,
            SeedMode::Static | SeedMode::Rotation | SeedMode::Shift => false,
        }
    }

    /// Whether the mode moves x alone (a rotation about the normal), so that the `r1` schedule
    /// steps it by R1, not R2: `rotation` of a set that is not fresh per pixel (`fresh`), the
    /// engine patterns and rotation textures.
    pub fn is_scalar(self, fresh: bool) -> bool {
        match self {
            SeedMode::Rotation => !fresh,
            SeedMode::Texture(t) => t.get().use_() == TextureUse::Rotation,
            m => m.pattern().is_some(),
        }
    }

    /// Whether each pixel's estimate is unbiased over runs (the tables above): `shift`, `blue-noise`
    /// and `stbn` for every sequence (a Cranley–Patterson shift uniform over runs); `static`,
    /// `rotation` and the engine patterns only when the set itself is pseudo-random
    /// (`pseudo_random`: the `random` sequence, whose static set is random over runs); a texture
    /// never by this rule (its uniformity is measured at load, not known here).
    pub fn unbiased_per_pixel(self, pseudo_random: bool) -> bool {
        match self {
            SeedMode::Shift | SeedMode::BlueNoise | SeedMode::Stbn => true,
            SeedMode::Static | SeedMode::Rotation => pseudo_random,
            m if m.pattern().is_some() => pseudo_random,
            _ => false,
        }
    }

    /// Slices of the mode's spatiotemporal mask (frame f reads slice f mod depth, and the schedule
    /// acts once per cycle): `stbn`'s and a texture's; 1 for every other mode.
    pub fn depth(self) -> u32 {
        match self {
            SeedMode::Stbn => super::stbn::STBN_DEPTH,
            SeedMode::Texture(t) => t.get().size().2,
            _ => 1,
        }
    }

    /// Whether the per-frame schedule (`independent`, `r1`) changes any of the first `frames`
    /// frames (0..frames): a schedule acts once per full cycle of the mode's mask
    /// ([`Self::depth`] frames; IGN under `r1` steps every frame), so over at most one cycle —
    /// `stbn` up to 32 frames — both schedules draw the same points in every frame, and are one
    /// configuration (measured once, not twice).
    pub fn schedule_matters(self, frames: u32) -> bool {
        frames > self.depth()
    }
}

/// One pixel's randomization, derived once per pixel (three mixes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelSeed {
    /// Keyed by the run seed only: what `static` uses.
    pub run_key: u64,
    /// Keyed by run seed and pixel: fresh numbers / jitter / scramble for this pixel.
    pub pixel_key: u64,
    /// Per-pixel offsets in fixed point (x for `rotation`, x and y for `shift`).
    pub x_offset: u32,
    pub y_offset: u32,
}

impl PixelSeed {
    #[inline]
    pub fn new(seed: u64, pixel: u64) -> Self {
        let run_key = hash(seed, 0x6865_6D69_6C61_6231);
        let pixel_key = hash(run_key, pixel.wrapping_add(1));
        let offsets = mix64(pixel_key ^ 0x5EED);
        Self { run_key, pixel_key, x_offset: fix_from_bits(offsets), y_offset: fix_from_bits(offsets << 24) }
    }

    /// The key of the set's own randomness: per pixel only where the mode asks for fresh numbers.
    #[inline]
    pub fn set_key(&self, fresh_per_pixel: bool) -> u64 {
        if fresh_per_pixel { self.pixel_key } else { self.run_key }
    }

    /// The offsets the mode applies on top of the set (x for rotation, x and y for shift and
    /// blue-noise) at pixel (x, y): white noise keyed by the pixel for shift, the run's shifted
    /// blue-noise masks for blue-noise.
    #[inline]
    pub fn offsets(&self, mode: SeedMode, x: u32, y: u32) -> (u32, u32) {
        self.offsets_at(mode, x, y, 0)
    }

    /// As `offsets`, in slice `t` of the `stbn` masks (the other modes ignore `t`).
    #[inline]
    pub fn offsets_at(&self, mode: SeedMode, x: u32, y: u32, t: u32) -> (u32, u32) {
        match mode {
            SeedMode::Static => (0, 0),
            SeedMode::Rotation => (self.x_offset, 0),
            SeedMode::Shift => (self.x_offset, self.y_offset),
            SeedMode::BlueNoise => MaskShift::new(self.run_key).offsets(x, y),
            SeedMode::Stbn => StbnShift::new(self.run_key).offsets(x, y, t),
            SeedMode::Ign | SeedMode::Bayer | SeedMode::MagicSquare | SeedMode::R2Dither => {
                let p = self_pattern(mode);
                (EngineShift::new(p, self.run_key).offset(p, x, y, t), 0)
            }
            SeedMode::Texture(id) => match id.get().use_() {
                TextureUse::Vector => (0, 0),
                _ => id.get().offsets(self.run_key, x, y, t),
            },
        }
    }
}

#[inline]
fn self_pattern(mode: SeedMode) -> Pattern {
    mode.pattern().unwrap_or(Pattern::Ign)
}

/// Walks the n equal strata of [0,1) on the 24-bit grid without a division per point.
/// Stratum s holds the grid points [lo(s), lo(s+1)) with lo(s) = ceil(s 2^24 / n), kept as
/// quotient and remainder, so a point placed there satisfies floor(k n / 2^24) == s exactly
/// (for n <= 2^24) and its f32 lies in [s/n, (s+1)/n).
#[derive(Debug, Clone, Copy)]
pub struct StrataWalk {
    q: u32,
    r: u32,
    step_q: u32,
    step_r: u32,
    n: u32,
}

impl StrataWalk {
    #[inline]
    pub fn new(n: u32) -> Self {
        let n = n.max(1);
        Self { q: 0, r: 0, step_q: FIX_ONE / n, step_r: FIX_ONE % n, n }
    }

    #[inline]
    fn lo(q: u32, r: u32) -> u32 {
        q + (r != 0) as u32
    }

    /// The point at position `j` in [0, 2^24) of the current stratum.
    #[inline]
    pub fn at(&self, j: u32) -> u32 {
        let (mut q, mut r) = (self.q + self.step_q, self.r + self.step_r);
        if r >= self.n {
            r -= self.n;
            q += 1;
        }
        let lo = Self::lo(self.q, self.r);
        let width = Self::lo(q, r) - lo;
        lo + ((j as u64 * width as u64) >> FIX_BITS) as u32
    }

    /// Moves to the next stratum.
    #[inline]
    pub fn advance(&mut self) {
        self.q += self.step_q;
        self.r += self.step_r;
        if self.r >= self.n {
            self.r -= self.n;
            self.q += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strata_walk_stays_in_each_stratum_at_both_ends() {
        for strata in [1u32, 2, 3, 7, 10, 17, 1000, 12345, 1 << 20, 3_000_017] {
            for j in [0, 1, FIX_ONE / 2, FIX_ONE - 1] {
                let mut w = StrataWalk::new(strata);
                for s in 0..strata {
                    let k = w.at(j);
                    assert_eq!((k as u64 * strata as u64) >> FIX_BITS, s as u64, "{strata} {s} {j}");
                    w.advance();
                }
            }
        }
    }
}
