//! pmj02bn: the progressive multi-jittered (0,2) sequence with blue-noise selection of
//! Christensen, Kensler & Kilpatrick 2018, "Progressive multi-jittered sample sequences"
//! (Computer Graphics Forum 37(4), EGSR), generated in code (deterministic, no tables shipped).
//!
//! The sequence is built point by point. Point n of the prefix of N = 2^m points (N/2 <= n < N)
//! goes into a sub-stratum that no earlier point occupies in any of the m + 1 elementary-interval
//! shapes of area 1/N (2^k columns × 2^(m−k) rows, k = 0..=m), so every power-of-two prefix is a
//! (0,m,2)-net in base 2: the (0,2)-sequence stratification of pmj02. The valid sub-strata are
//! found as in Pharr 2019, "Efficient generation of points that satisfy two-dimensional
//! elementary intervals" (JCGT 8(1)): fix a free interval of the middle shape k = m/2, then the
//! finer-x shapes constrain only the extra x bits and the finer-y shapes only the extra y bits,
//! so the valid cells are a product of two short lists. Among the valid cells, each with a
//! random position inside it, the candidate farthest (toroidally) from every earlier point is
//! kept: the best-candidate step (Mitchell 1991) that makes pmj02 into pmj02bn.
//!
//! Christensen et al. also pre-assign each new point to a sub-quadrant of an old point's square
//! (diagonally opposite first, then the other two). Tried here, it left at most 16 valid cells
//! per point and gave the first 4..=1024-point prefixes a smaller minimum distance than drawing
//! the candidates from all valid cells (normalized min distance summed over those prefixes 2.79
//! against 3.09), so the candidates come from every valid cell, as Pharr's enumeration allows.
//! The greedy choice never ran out of valid cells for this generator's seed (the net test checks
//! every power-of-two prefix of the table).
//! The first [`TABLE_LEN`] points are made once per process ([`table`]); later indices, which
//! no experiment uses, continue with Owen-scrambled Sobol' points (still uniform, but outside
//! the net property). Per set the table is randomized by a digital (XOR) shift, which maps
//! elementary intervals onto elementary intervals (the stratification is kept exactly) and
//! makes every point uniform; it loosens, but does not undo, the blue-noise spacing.

use super::hash::{FIX_BITS, fix_add, fix_to_f32, hash};
use super::registry::{PixelSet, PointSequence, SHIPS_SHIFTED, SequenceInfo, Shipped};
use super::seed::SeedMode;
use super::sobol::{owen_scramble, sobol_x, sobol_y};
use glam::Vec2;
use std::sync::OnceLock;

/// Points generated once per process: every power-of-two prefix up to this is a (0,m,2)-net.
pub const TABLE_LEN: usize = 4096;
/// Valid cells the blue-noise step compares per point (all of them when there are fewer).
pub const CANDIDATES: usize = 48;
/// The generator's random stream (sub-cell positions and which cells are candidates).
const GEN_KEY: u64 = 0x706D_6A30_3262_6E00;

/// The elementary interval of shape k (2^k columns × 2^(m−k) rows) holding 24-bit point (x, y).
#[inline]
fn interval(k: u32, m: u32, x: u32, y: u32) -> usize {
    (((x >> (FIX_BITS - k)) << (m - k)) | (y >> (FIX_BITS - (m - k)))) as usize
}

/// Which elementary intervals of area 1/2^m the points so far occupy, one bitmap per shape.
struct Strata {
    m: u32,
    occupied: Vec<Vec<bool>>,
}

impl Strata {
    fn new(m: u32, points: &[(u32, u32)]) -> Self {
        let mut s = Strata { m, occupied: vec![vec![false; 1 << m]; m as usize + 1] };
        for &(x, y) in points {
            s.insert(x, y);
        }
        s
    }

    fn insert(&mut self, x: u32, y: u32) {
        for k in 0..=self.m {
            self.occupied[k as usize][interval(k, self.m, x, y)] = true;
        }
    }

    fn free(&self, k: u32, xp: u32, yp: u32) -> bool {
        !self.occupied[k as usize][((xp << (self.m - k)) | yp) as usize]
    }

    /// x prefixes of m bits extending `xp` (k bits) through the shapes k+1..=m, whose y prefixes
    /// are cut from `b`, the m−k0 bits of the middle shape k0.
    fn extend_x(&self, k: u32, xp: u32, k0: u32, b: u32, out: &mut Vec<u32>) {
        if k == self.m {
            out.push(xp);
            return;
        }
        for bit in 0..2 {
            let x2 = (xp << 1) | bit;
            if self.free(k + 1, x2, b >> (k + 1 - k0)) {
                self.extend_x(k + 1, x2, k0, b, out);
            }
        }
    }

    /// y prefixes of m bits extending `yp` (m−k bits) through the shapes k−1..=0, whose x
    /// prefixes are cut from `a`, the k0 bits of the middle shape.
    fn extend_y(&self, k: u32, yp: u32, k0: u32, a: u32, out: &mut Vec<u32>) {
        if k == 0 {
            out.push(yp);
            return;
        }
        for bit in 0..2 {
            let y2 = (yp << 1) | bit;
            if self.free(k - 1, a >> (k0 - (k - 1)), y2) {
                self.extend_y(k - 1, y2, k0, a, out);
            }
        }
    }

    /// Every cell (x, y) of the 2^m × 2^m grid free in all m + 1 shapes (Pharr 2019).
    fn valid_cells(&self, out: &mut Vec<(u32, u32)>) {
        let (m, k0) = (self.m, self.m / 2);
        let (mut xs, mut ys) = (Vec::new(), Vec::new());
        for a in 0..1u32 << k0 {
            for b in 0..1u32 << (m - k0) {
                if !self.free(k0, a, b) {
                    continue;
                }
                xs.clear();
                ys.clear();
                self.extend_x(k0, a, k0, b, &mut xs);
                self.extend_y(k0, b, k0, a, &mut ys);
                out.extend(xs.iter().flat_map(|&x| ys.iter().map(move |&y| (x, y))));
            }
        }
    }
}

/// Squared toroidal distance of two 24-bit points, in units of 2^-24.
#[inline]
fn dist2(a: (u32, u32), b: (u32, u32)) -> u64 {
    let d = |p: u32, q: u32| {
        let t = p.abs_diff(q) as u64;
        t.min((1u64 << FIX_BITS) - t)
    };
    let (u, v) = (d(a.0, b.0), d(a.1, b.1));
    u * u + v * v
}

/// Nearest-neighbour search over the points so far: a 2^g × 2^g bucket grid on the torus.
struct Buckets {
    g: u32,
    cells: Vec<Vec<(u32, u32)>>,
}

impl Buckets {
    fn new(g: u32, points: &[(u32, u32)]) -> Self {
        let mut b = Buckets { g, cells: vec![Vec::new(); 1 << (2 * g)] };
        for &p in points {
            b.insert(p);
        }
        b
    }

    fn cell(&self, p: (u32, u32)) -> (i64, i64) {
        ((p.0 >> (FIX_BITS - self.g)) as i64, (p.1 >> (FIX_BITS - self.g)) as i64)
    }

    fn insert(&mut self, p: (u32, u32)) {
        let (cx, cy) = self.cell(p);
        self.cells[((cx << self.g) | cy) as usize].push(p);
    }

    /// The squared distance from `p` to its nearest point, exact: rings of buckets are searched
    /// until the ring is farther than the best distance found.
    fn nearest2(&self, p: (u32, u32)) -> u64 {
        let side = 1i64 << self.g;
        let size = 1u64 << (FIX_BITS - self.g);
        let (cx, cy) = self.cell(p);
        let mut best = u64::MAX;
        for r in 0..=side / 2 {
            if r > 0 && ((r as u64 - 1) * size).pow(2) >= best {
                break;
            }
            for dx in -r..=r {
                for dy in -r..=r {
                    if dx.abs() != r && dy.abs() != r {
                        continue;
                    }
                    let (bx, by) = ((cx + dx).rem_euclid(side), (cy + dy).rem_euclid(side));
                    for &q in &self.cells[((bx << self.g) | by) as usize] {
                        best = best.min(dist2(p, q));
                    }
                }
            }
        }
        best
    }
}

/// The first `len` points of the unrandomized pmj02bn sequence, 24-bit fixed point.
pub fn generate(len: usize) -> Vec<(u32, u32)> {
    let mut pts: Vec<(u32, u32)> = Vec::with_capacity(len);
    let mut draw = 0u64;
    let mut rand = |bits: u32| {
        draw += 1;
        if bits == 0 { 0 } else { (hash(GEN_KEY, draw) >> (64 - bits)) as u32 }
    };
    let first = (rand(FIX_BITS), rand(FIX_BITS));
    pts.push(first);
    let (mut strata, mut buckets) = (Strata::new(0, &pts), Buckets::new(0, &pts));
    let mut cells = Vec::new();
    for n in 1..len {
        if n.is_power_of_two() {
            // A new level: N = 2n; the strata are finer and the bucket grid is refined.
            let m = n.trailing_zeros() + 1;
            strata = Strata::new(m, &pts);
            buckets = Buckets::new(m.div_ceil(2).min(10), &pts);
        }
        let m = strata.m;
        cells.clear();
        strata.valid_cells(&mut cells);
        assert!(!cells.is_empty(), "pmj02bn: no valid stratum for point {n}");
        // Up to CANDIDATES cells, a random subset (partial Fisher–Yates), a random point in each.
        let k = cells.len().min(CANDIDATES);
        let mut best = (0u64, (0, 0));
        for c in 0..k {
            let j = c + (rand(32) as usize % (cells.len() - c));
            cells.swap(c, j);
            let (cx, cy) = cells[c];
            let p =
                ((cx << (FIX_BITS - m)) | rand(FIX_BITS - m), (cy << (FIX_BITS - m)) | rand(FIX_BITS - m));
            let d = buckets.nearest2(p);
            if d > best.0 || c == 0 {
                best = (d, p);
            }
        }
        pts.push(best.1);
        strata.insert(best.1.0, best.1.1);
        buckets.insert(best.1);
    }
    pts
}

static TABLE: OnceLock<Vec<(u32, u32)>> = OnceLock::new();

/// The first [`TABLE_LEN`] points, generated on first use (`SamplerConfig::prepare` makes them
/// before any timed render).
pub fn table() -> &'static [(u32, u32)] {
    TABLE.get_or_init(|| generate(TABLE_LEN))
}

/// Whether the table has been generated in this process.
pub fn table_ready() -> bool {
    TABLE.get().is_some()
}

/// Point `i` of the unrandomized pmj02bn sequence, 24-bit fixed point.
pub fn pmj02bn_fixed(i: u32) -> (u32, u32) {
    match table().get(i as usize) {
        Some(&p) => p,
        None => (
            owen_scramble(sobol_x(i), GEN_KEY as u32) >> (32 - FIX_BITS),
            owen_scramble(sobol_y(i), (GEN_KEY >> 32) as u32) >> (32 - FIX_BITS),
        ),
    }
}

/// Fills `out` with points 0.. of pmj02bn, digitally shifted by bits from `key`, then shifted by
/// (`dx`, `dy`) mod 1.
pub fn fill(key: u64, dx: u32, dy: u32, out: &mut [Vec2]) {
    let xor_x = (hash(key, 1) >> (64 - FIX_BITS)) as u32;
    let xor_y = (hash(key, 2) >> (64 - FIX_BITS)) as u32;
    for (i, p) in out.iter_mut().enumerate() {
        let (x, y) = pmj02bn_fixed(i as u32);
        *p = Vec2::new(fix_to_f32(fix_add(x ^ xor_x, dx)), fix_to_f32(fix_add(y ^ xor_y, dy)));
    }
}

/// Its seed modes act the common way (`PixelSet::keyed`).
pub struct Pmj02bn;

impl PointSequence for Pmj02bn {
    fn info(&self) -> &SequenceInfo {
        &SequenceInfo {
            name: "pmj02bn",
            label: "pmj02bn",
            words: &["pmj02", "pmj"],
            fresh_per_pixel: false,
            shipped: Some(Shipped { modes: &[SeedMode::Shift], why: SHIPS_SHIFTED, rank: 3 }),
        }
    }

    fn prepare(&self) {
        table();
    }

    fn fill(&self, set: &PixelSet, out: &mut [Vec2]) {
        let (key, dx, dy) = set.keyed();
        fill(key, dx, dy, out)
    }
}
