//! The order in which a pixel's AO rays are traced: grouped by direction, whatever order the
//! sampler produced them in.
//!
//! The tracer walks the BVH with packets of 32 rays (`scene::packet`), and a packet costs about
//! what its widest ray cone costs: rays that point the same way visit the same nodes. A sequence's
//! index order says nothing about that. The Fibonacci lattice's consecutive points lie in one band
//! of elevation, while Sobol', Halton, ZSobol and pseudo-random numbers put consecutive points far
//! apart on purpose (every prefix is spread out), so with the rays traced in index order part of
//! what their renders cost over the lattice's was the tracer's order, not the sequence
//! (docs/performance.md). Every sequence is therefore traced in the same order: its points sorted
//! into bands of elevation, one packet's worth a band (a counting sort, as in the ray sorting of
//! coherent ray tracing: Pharr et al. 1997 "Rendering complex scenes with memory-coherent ray
//! tracing"; Garanzha and Loop 2010 "Fast ray sorting and breadth-first packet traversal").
//!
//! The answers are handed back in the caller's order, so a pixel's estimate, including the order of
//! its weighted sum, is bit for bit what tracing in index order gives: only the time changes.

use crate::scene::packet::PACKET;
use glam::Vec2;

/// A pixel's points in traced order, with what it takes to answer in the sampler's order (kept per
/// thread: no allocation per pixel).
#[derive(Debug, Default)]
pub struct RayOrder {
    /// Each point's cell (Morton code of its cell of the unit square).
    cell: Vec<u16>,
    /// Points per cell, then each cell's next slot.
    start: Vec<u32>,
    /// Traced slot j holds the sampler's point `perm[j]`.
    perm: Vec<u32>,
    /// The points in traced order.
    points: Vec<Vec2>,
}

/// Points a band holds on average: one packet's worth.
const BAND: usize = PACKET;

/// Interleaved streams of the counting sort.
const WAYS: usize = 4;

impl RayOrder {
    pub fn new() -> Self {
        Self::default()
    }

    /// Sorts `points` (in [0, 1)^2, before the warp) into bands of v, stably, and returns them in
    /// traced order; None when they already are, or are in band order started part-way (then
    /// nothing moved and `unsort` is not needed).
    /// Every warp maps v to the elevation (the concentric one to the disk's rows), so a band of
    /// 32 points is a packet of rays that share their angle to the normal, as the Fibonacci
    /// lattice's consecutive points do ((i + 0.5)/n is its v): its order is kept at no cost but
    /// the check, and every other sequence is traced as coherently. (Square cells in Morton order
    /// were tried: no faster for Sobol', and they move the lattice's points too.)
    pub fn sort(&mut self, points: &[Vec2]) -> Option<&[Vec2]> {
        let n = points.len();
        let bands = (n / BAND).max(1);
        let scale = bands as f32;
        let last = bands as u32 - 1;
        self.cell.resize(n, 0);
        for (c, p) in self.cell.iter_mut().zip(points) {
            *c = ((p.y * scale) as u32).min(last) as u16;
        }
        // In band order already, or that order started part-way (a shift of v mod 1 rotates the
        // bands): as coherent as sorted, so nothing moves.
        let mut descents = 0;
        for w in self.cell.windows(2) {
            descents += (w[0] > w[1]) as u32;
            if descents > 1 {
                break;
            }
        }
        if descents <= 1 {
            return None;
        }
        // A counting sort in WAYS interleaved streams, each over its own part of the points with its
        // own counts and cursors: a count or cursor bumped twice in a row waits for its own store,
        // so one stream of points that mostly share a band runs at the store's latency, and
        // independent streams overlap. Stable: each part's points follow the earlier parts' in
        // their band, in order.
        let part = n.div_ceil(WAYS);
        self.start.clear();
        self.start.resize(WAYS * bands, 0);
        for i in 0..part {
            for w in 0..WAYS {
                if let Some(&c) = self.cell.get(w * part + i) {
                    self.start[w * bands + c as usize] += 1;
                }
            }
        }
        let mut next = 0;
        for b in 0..bands {
            for w in 0..WAYS {
                let count = self.start[w * bands + b];
                self.start[w * bands + b] = next;
                next += count;
            }
        }
        self.perm.resize(n, 0);
        self.points.resize(n, Vec2::ZERO);
        for i in 0..part {
            for w in 0..WAYS {
                let k = w * part + i;
                if let Some(&c) = self.cell.get(k) {
                    let slot = &mut self.start[w * bands + c as usize];
                    self.perm[*slot as usize] = k as u32;
                    self.points[*slot as usize] = points[k];
                    *slot += 1;
                }
            }
        }
        Some(&self.points)
    }

    /// Answers in traced order (one bit per ray, 32 a mask) back in the sampler's order.
    pub fn unsort(&self, sorted: &[u32], masks: &mut [u32]) {
        masks.fill(0);
        for (k, &m) in sorted.iter().enumerate() {
            let mut m = m;
            while m != 0 {
                let i = self.perm[k * PACKET + m.trailing_zeros() as usize] as usize;
                masks[i / PACKET] |= 1 << (i % PACKET);
                m &= m - 1;
            }
        }
    }

    /// Values in traced order (e.g. weights) back in the sampler's order.
    pub fn unsort_values(&self, sorted: &[f32], out: &mut [f32]) {
        for (&i, &v) in self.perm.iter().zip(sorted) {
            out[i as usize] = v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lattice_is_traced_in_its_own_order() {
        use crate::sampling::{SamplerConfig, SeedMode, Sequence};
        let mut o = RayOrder::new();
        for (n, mode) in [33, 64, 100, 256, 1024].into_iter().flat_map(|n| {
            [SeedMode::Rotation, SeedMode::Static, SeedMode::Shift, SeedMode::BlueNoise].map(|m| (n, m))
        }) {
            let sampler = SamplerConfig::new(Sequence::Fibonacci, mode, n, 7).unwrap();
            let mut points = vec![Vec2::ZERO; n as usize];
            for pixel in 0..50u32 {
                sampler.fill_pixel(pixel % 10, pixel / 10, pixel as u64, &mut points);
                assert!(o.sort(&points).is_none(), "{n} points, {mode:?}, pixel {pixel}");
            }
        }
    }

    #[test]
    fn sorting_is_a_stable_permutation_and_unsort_inverts_it() {
        let n = 200;
        let points: Vec<Vec2> = (0..n)
            .map(|i| Vec2::new((i as f32 * 0.618_034).fract(), ((i * 37 % n) as f32 + 0.5) / n as f32))
            .collect();
        let mut o = RayOrder::new();
        let sorted = o.sort(&points).expect("not in band order").to_vec();
        for w in o.perm.windows(2) {
            let (c0, c1) = (o.cell[w[0] as usize], o.cell[w[1] as usize]);
            assert!(c0 < c1 || (c0 == c1 && w[0] < w[1]), "cells ascend, ties in the sampler's order");
        }
        let mut seen = vec![false; n];
        for (j, &i) in o.perm.iter().enumerate() {
            assert!(!seen[i as usize]);
            seen[i as usize] = true;
            assert_eq!(sorted[j], points[i as usize]);
        }
        // Answer "blocked" for every point with x < 0.3, in traced order; unsort gives them back.
        let mut answers = vec![0u32; n.div_ceil(PACKET)];
        for (j, p) in sorted.iter().enumerate() {
            if p.x < 0.3 {
                answers[j / PACKET] |= 1 << (j % PACKET);
            }
        }
        let mut masks = vec![u32::MAX; n.div_ceil(PACKET)];
        o.unsort(&answers, &mut masks);
        for (i, p) in points.iter().enumerate() {
            assert_eq!((masks[i / PACKET] >> (i % PACKET)) & 1 == 1, p.x < 0.3, "point {i}");
        }
        let mut back = vec![0.0; n];
        o.unsort_values(&sorted.iter().map(|p| p.y).collect::<Vec<_>>(), &mut back);
        assert!(back.iter().zip(&points).all(|(b, p)| *b == p.y));
    }
}
