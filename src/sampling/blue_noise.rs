//! Tileable blue-noise masks for the `blue-noise` seed mode: ranks by the void-and-cluster method
//! (Ulichney 1993, "The void-and-cluster method for dither array generation", Proc. SPIE 1913),
//! used as per-pixel Cranley–Patterson offsets as in Georgiev & Fajardo 2016, "Blue-noise dithered
//! sampling" (SIGGRAPH Talks), so that neighbouring pixels get dissimilar offsets and the image's
//! error moves to high spatial frequencies, where any blur or denoiser removes it.
//!
//! Written here rather than taken from the `blue-noise` crate: `sampling` imports glam only (that
//! crate brings image IO), its floating-point FFT blur takes seconds for 64², and the mask must be
//! the same bit for bit on every run. Here the energy is an integer sum of a quantized Gaussian
//! (the only floating point is the ~200 kernel taps, each rounded once), so incremental updates
//! are exact (no drift, no order dependence) and ties are broken by the lowest index; the
//! generator (`void_cluster`) is shared with the spatiotemporal masks of [`super::stbn`].
//!
//! Two independent masks (different initial patterns) give the x and y offsets, not one mask for
//! both: the same mask for both would put every pixel's offset on the diagonal x = y (+ const),
//! while two independent void-and-cluster masks are each an exact permutation of the ranks (a
//! stratified marginal) and blue, and are uncorrelated with each other, so neighbouring pixels
//! differ in both offsets. A mask optimized jointly in x and y (Georgiev & Fajardo's energy on
//! pixel distance and toroidal offset distance, tried as swaps of whole (x, y) pairs, which keep
//! both marginals exact) gave the same low-pass RMSE on the kitchen for every sequence, so the
//! simpler pair is kept.

use super::hash::{FIX_ONE, hash};
use super::void_cluster::VoidAndCluster;
use std::sync::OnceLock;

/// Side of the shipped masks: 4096 ranks, tiled toroidally over the image.
pub const MASK_SIZE: u32 = 64;
/// Standard deviation, in pixels, of the Gaussian energy filter (Ulichney's choice).
pub const MASK_SIGMA: f64 = 1.5;
/// Initial-pattern seeds of the x and y masks.
const MASK_SEEDS: [u64; 2] = [0x626C_7565_2D78, 0x626C_7565_2D79];

/// A size × size toroidal dither array: `ranks` (row-major) is a permutation of 0..size².
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BlueNoiseMask {
    size: u32,
    ranks: Vec<u32>,
}

impl BlueNoiseMask {
    /// Void-and-cluster with a Gaussian energy filter of `sigma` pixels, initial pattern from `seed`.
    /// `size` in 2..=2048.
    pub fn void_and_cluster(size: u32, sigma: f64, seed: u64) -> Self {
        assert!((2..=2048).contains(&size), "mask size {size} outside 2..=2048");
        let s = size as usize;
        Self { size, ranks: VoidAndCluster::new([s, s, 1], sigma, sigma).ranks(seed) }
    }

    pub fn size(&self) -> u32 {
        self.size
    }

    /// Row-major ranks, a permutation of 0..size².
    pub fn ranks(&self) -> &[u32] {
        &self.ranks
    }

    /// The rank at (x, y), wrapping toroidally.
    #[inline]
    pub fn rank(&self, x: u32, y: u32) -> u32 {
        self.ranks[((y % self.size) * self.size + x % self.size) as usize]
    }
}

static MASKS: OnceLock<[BlueNoiseMask; 2]> = OnceLock::new();

/// The shipped x and y masks, generated on first use (a few milliseconds; `SamplerConfig::prepare`
/// makes them before any timed render) and kept for the process.
pub fn masks() -> &'static [BlueNoiseMask; 2] {
    MASKS.get_or_init(|| MASK_SEEDS.map(|s| BlueNoiseMask::void_and_cluster(MASK_SIZE, MASK_SIGMA, s)))
}

/// Whether the masks have been generated in this process.
pub fn masks_ready() -> bool {
    MASKS.get().is_some()
}

/// Width of one rank's cell [rank/N, (rank+1)/N) of [0,1) in 24-bit fixed point (N = 4096 ranks).
const CELL: u32 = FIX_ONE / (MASK_SIZE * MASK_SIZE);
const _: () = assert!(CELL * MASK_SIZE * MASK_SIZE == FIX_ONE, "the ranks must tile the 24-bit grid");

/// One run's randomization of the two masks: a toroidal shift of each (which pixel reads which
/// rank) and a jitter within one rank's cell, the same for every pixel:
/// offset = (rank at the shifted position + jitter) / N, jitter uniform in [0, 1).
///
/// Why each pixel's estimate is unbiased over runs: the shift is uniform over the M² positions, and
/// the mask is a permutation, so the rank a fixed pixel reads is uniform over 0..N; with the
/// independent jitter, the offset is exactly uniform over the 24-bit grid of [0,1). The x and y
/// masks get independent shifts and jitters, so (x, y) is uniform on [0,1)² and the
/// Cranley–Patterson-shifted set is unbiased in every pixel (tests/stages/sampling_blue_noise.rs checks
/// both). The usual alternative, a Cranley–Patterson rotation of the mask values by a uniform
/// amount mod 1, is as unbiased and measured the same on the kitchen (low-pass RMSE within 2 % at
/// 8–32 rays, inside the run-to-run spread): a shifted point set is a periodic function of its
/// offset, so a rotation mod 1 moves no pixel's offset away from its neighbours' on the torus. The
/// jitter is kept because it leaves a run's offsets equal to the mask itself (plus a constant below
/// 1/N), so the mask's spectral test is a test of what the renderer uses; a rotation cuts the
/// values where they wrap, which on the line (not the torus) lets 7× more through the low-pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MaskShift {
    shift: [(u32, u32); 2],
    jitter: [u32; 2],
}

impl MaskShift {
    /// Derived from the run key only: the same for every pixel of a run.
    #[inline]
    pub fn new(run_key: u64) -> Self {
        let h = [hash(run_key, 0xB1_0E_5E), hash(run_key, 0xB1_0E_5F)];
        // Low 32 bits pick the shift (2^16 is a multiple of 64: uniform), the top bits the jitter:
        // disjoint bits of one hash.
        let shift = h.map(|h| ((h as u32 & 0xFFFF) % MASK_SIZE, ((h >> 16) as u32 & 0xFFFF) % MASK_SIZE));
        Self { shift, jitter: h.map(|h| (h >> 40) as u32 % CELL) }
    }

    /// Pixel (x, y)'s (x, y) offsets in 24-bit fixed point.
    #[inline]
    pub fn offsets(&self, x: u32, y: u32) -> (u32, u32) {
        let m = masks();
        let at = |c: usize| {
            let (sx, sy) = self.shift[c];
            m[c].rank(x % MASK_SIZE + sx, y % MASK_SIZE + sy) * CELL + self.jitter[c]
        };
        (at(0), at(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kernel_keeps_exactly_the_taps_within_r_squared_65() {
        // exp(-r²/4.5) 2^20 rounds to 0 exactly when r² > 4.5 ln 2^21 = 65.5.
        let g = VoidAndCluster::new([64, 64, 1], 1.5, 1.5);
        let mut want = 0;
        for dy in 0..64usize {
            for dx in 0..64usize {
                let (x, y) = (dx.min(64 - dx), dy.min(64 - dy));
                want += (x * x + y * y <= 65) as usize;
            }
        }
        assert_eq!(g.taps().len(), want);
        assert_eq!(g.taps()[0], ([0, 0, 0], 1 << 20));
    }
}
