//! ZSobol': Sobol' points indexed through the pixel's Morton (Z-order) code with random base-4
//! digit permutations chosen by the digits above, so neighbouring pixels receive complementary
//! blocks of one Sobol' sequence and the error is distributed as blue noise across the screen
//! (Ahmed & Wonka 2020, "Screen-space blue-noise diffusion of Monte Carlo sampling error via
//! hierarchical ordering of pixels"; pbrt-v4's `ZSobolSampler`). The pixel's 2^L indices form an
//! aligned block, so its points are a (0, L, 2)-net of Sobol', Owen-scrambled (Burley 2020).

use super::hash::hash;
use super::registry::{PixelSet, PointSequence, SequenceInfo, Shipped};
use super::seed::SeedMode;
use super::sobol::scrambled_points;
use glam::Vec2;

/// The 24 permutations of {0, 1, 2, 3}.
const PERMS: [[u8; 4]; 24] = [
    [0, 1, 2, 3],
    [0, 1, 3, 2],
    [0, 2, 1, 3],
    [0, 2, 3, 1],
    [0, 3, 1, 2],
    [0, 3, 2, 1],
    [1, 0, 2, 3],
    [1, 0, 3, 2],
    [1, 2, 0, 3],
    [1, 2, 3, 0],
    [1, 3, 0, 2],
    [1, 3, 2, 0],
    [2, 0, 1, 3],
    [2, 0, 3, 1],
    [2, 1, 0, 3],
    [2, 1, 3, 0],
    [2, 3, 0, 1],
    [2, 3, 1, 0],
    [3, 0, 1, 2],
    [3, 0, 2, 1],
    [3, 1, 0, 2],
    [3, 1, 2, 0],
    [3, 2, 0, 1],
    [3, 2, 1, 0],
];

/// Bits of the Morton code: 16 per axis (images up to 65536 pixels wide and high).
pub const MORTON_BITS: u32 = 32;

/// Interleaves the low 16 bits of x (even bits) and y (odd bits).
pub fn morton(x: u32, y: u32) -> u64 {
    let spread = |v: u32| {
        let mut v = (v & 0xFFFF) as u64;
        v = (v | (v << 8)) & 0x00FF_00FF;
        v = (v | (v << 4)) & 0x0F0F_0F0F;
        v = (v | (v << 2)) & 0x3333_3333;
        (v | (v << 1)) & 0x5555_5555
    };
    spread(x) | (spread(y) << 1)
}

/// log2 of the smallest power of two >= n.
pub fn log2_ceil(n: u32) -> u32 {
    n.max(1).next_power_of_two().trailing_zeros()
}

/// The permuted index of sample `j` of the pixel with Morton code `m` when each pixel has 2^`l`
/// samples: every base-4 digit of (m << l | j) from the top is permuted by one of 24 permutations
/// chosen by hashing the original digits above it; with an odd bit count the last (base-2) digit
/// is flipped by a hash of the digits above it (as pbrt-v4 does).
pub fn permuted_index(m: u64, j: u32, l: u32, key: u64) -> u64 {
    let idx = (m << l) | j as u64;
    let bits = MORTON_BITS + l;
    let odd = (bits & 1) as u64;
    let mut out = 0u64;
    for k in (0..bits / 2).rev() {
        let shift = 2 * k as u64 + odd;
        let digit = ((idx >> shift) & 3) as usize;
        let above = idx >> (shift + 2);
        let perm = PERMS[(hash(key, above ^ (shift << 58)) % 24) as usize];
        out |= (perm[digit] as u64) << shift;
    }
    if odd == 1 {
        out |= (idx & 1) ^ (hash(key ^ 0xB17, idx >> 1) & 1);
    }
    out
}

/// A pixel's permuted indices: the numbers `permuted_index` gives, with each hash made once per
/// distinct value it hashes rather than once per point (hashing all 16 + l/2 digits of every point
/// made ZSobol renders cost ×3.3–3.8 the lattice's). The digits from the Morton code (those at or
/// above bit l) are the pixel's: permuted once. A digit of j is permuted by a hash of the digits
/// above it, which change only every 4^k points for the k-th digit from the bottom (`all`). The odd
/// last bit's hash reads idx >> 1, shared by two points.
pub struct PixelIndices {
    idx_high: u64,
    /// The permuted digits at or above bit l, those below bit 32 (all that `all` reads).
    high: u64,
    digits: usize,
    odd: u32,
    key: u64,
}

impl PixelIndices {
    pub fn new(m: u64, l: u32, key: u64) -> PixelIndices {
        let idx_high = m << l;
        let bits = MORTON_BITS + l;
        let odd = bits & 1;
        // Digits at shifts 2k + odd; those below l are j's.
        let digits = ((l - odd) / 2) as usize;
        // Only the digits below bit 32 reach the indices `all` gives (Sobol' dimensions 0 and 1
        // read the low 32 bits); each is permuted by a hash of the digits above it, which
        // neighbouring pixels share for all but their lowest levels, so the last pixel's
        // permutation of each level is kept per thread and reused while its prefix is the same.
        let mut high = 0u64;
        let top = (bits / 2).min(16);
        LEVELS.with_borrow_mut(|levels| {
            for k in (digits as u32..top).rev() {
                let shift = 2 * k as u64 + odd as u64;
                let digit = ((idx_high >> shift) & 3) as usize;
                let above = idx_high >> (shift + 2);
                let level = &mut levels[k as usize];
                if (level.0, level.1) != (key, above) {
                    *level = (key, above, (hash(key, above ^ (shift << 58)) % 24) as u8);
                }
                high |= (PERMS[level.2 as usize][digit] as u64) << shift;
            }
        });
        PixelIndices { idx_high, high, digits, odd, key }
    }

    /// The low 32 bits of `permuted_index(m, j, l, key)` for j = 0..out.len() (all a pixel's
    /// points need: Sobol' dimensions 0 and 1 read only them), level by level rather than point by
    /// point: one hash per distinct prefix and level, then a table look-up per point and level in
    /// straight loops, about half the cost of `get` in turn.
    pub fn all(&self, out: &mut [u32]) {
        out.fill(self.high as u32);
        for k in 0..self.digits {
            let s = 2 * k as u64 + self.odd as u64;
            let span = 1usize << (s + 2);
            for (g, chunk) in out.chunks_mut(span).enumerate() {
                let above = (self.idx_high >> (s + 2)) | g as u64;
                let perm = PERMS[(hash(self.key, above ^ (s << 58)) % 24) as usize];
                // The digit is constant over runs of 2^s points: one value OR-ed over each run.
                for (run, &d) in chunk.chunks_mut(1 << s).zip(perm.iter()) {
                    let v = (d as u32) << s;
                    run.iter_mut().for_each(|o| *o |= v);
                }
            }
        }
        if self.odd == 1 {
            // l >= 1 here, so a pair's indices differ in bit 0 alone and share idx >> 1.
            for (h, pair) in out.chunks_mut(2).enumerate() {
                let flip = (hash(self.key ^ 0xB17, (self.idx_high >> 1) | h as u64) & 1) as u32;
                for (bit, o) in pair.iter_mut().enumerate() {
                    *o |= bit as u32 ^ flip;
                }
            }
        }
    }
}

/// Fills `out` with the first points of pixel (`x`, `y`)'s block of 2^ceil(log2 n) ZSobol' points,
/// permuted and Owen-scrambled by seeds from `key`, shifted by (`dx`, `dy`) mod 1.
pub fn fill(n: u32, x: u32, y: u32, key: u64, dx: u32, dy: u32, out: &mut [Vec2]) {
    let indices = PixelIndices::new(morton(x, y), log2_ceil(n), hash(key, 3));
    let seeds = (hash(key, 1) as u32, hash(key, 2) as u32);
    INDICES.with_borrow_mut(|idx| {
        idx.resize(out.len(), 0);
        // Sobol' dimensions 0 and 1 depend on the index's low 32 bits only.
        indices.all(idx);
        scrambled_points(idx, seeds, (dx, dy), out);
    });
}

std::thread_local! {
    /// Per level of a pixel's digits above its points': the last (key, digits above, permutation)
    /// `PixelIndices::new` hashed (a cache: the permutations are the hash's whatever is in it).
    static LEVELS: std::cell::RefCell<[(u64, u64, u8); 32]> = const { std::cell::RefCell::new([(0, u64::MAX, 0); 32]) };
    /// `fill`'s permuted indices, kept per thread so that a render allocates them once.
    static INDICES: std::cell::RefCell<Vec<u32>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Its seed modes act the common way (`PixelSet::keyed`).
pub struct ZSobol;

impl PointSequence for ZSobol {
    fn info(&self) -> &SequenceInfo {
        &SequenceInfo {
            name: "zsobol",
            label: "ZSobol'",
            words: &["z-sobol", "zsobol'"],
            fresh_per_pixel: false,
            shipped: Some(Shipped {
                modes: &[SeedMode::Static, SeedMode::Shift],
                why: "ZSobol runs as it ships: `static` (its Morton blocks) and `shift`",
                rank: 2,
            }),
        }
    }

    fn fill(&self, set: &PixelSet, out: &mut [Vec2]) {
        let (key, dx, dy) = set.keyed();
        fill(set.count.max(1), set.x, set.y, key, dx, dy, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixels_indices_are_permuted_index() {
        for l in [0, 1, 2, 5, 6, 9, 10] {
            for (x, y, key) in [(0, 0, 1), (7, 5, 0xDEAD_BEEF), (65535, 65535, u64::MAX)] {
                let p = PixelIndices::new(morton(x, y), l, key);
                // A whole block, and a first part of one (a count that is not a power of two).
                for len in [1usize << l, ((1usize << l) * 2 / 3).max(1)] {
                    let mut all = vec![0u32; len];
                    p.all(&mut all);
                    for (j, &i) in all.iter().enumerate() {
                        let want = permuted_index(morton(x, y), j as u32, l, key) as u32;
                        assert_eq!(i, want, "l {l} ({x},{y}) j {j}");
                    }
                }
            }
        }
    }
}
