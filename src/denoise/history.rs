//! The per-pixel history every temporal filter here keeps (`accumulate`, `taa`, `svgf`): its
//! length n (frames since the pixel's history last started) and the weight of the newest frame,
//! α_eff = max(α, 1/n) (Schied et al. 2017, §4.1; Karis 2014's TAA starts the same way), so that
//! a fresh history is the running mean of its frames until 1/n falls to α, then the exponential
//! moving average of weight α. α = 0 is the running mean throughout.
//!
//! The history is read through a `Motion` (identity for a static camera): a pixel's taps into the
//! previous frame, of which only those onto pixels that had a history (covered in the previous
//! frame) are kept, their weights renormalized; with none the pixel restarts (n = 1). Its new
//! length is one more than that of its largest-weight tap (the previous pixel it mostly came from,
//! as SVGF's reprojection reads it). Background pixels have no history (n = 0) and are never read.

use super::motion::Motion;
use crate::image::{Image, covered};

/// α_eff = max(α, 1/n) for a history of n ≥ 1 frames (the newest included).
pub fn alpha_eff(alpha: f64, n: u32) -> f64 {
    alpha.max(1.0 / n.max(1) as f64)
}

/// What SVGF's reprojection may do beyond the bilinear taps every temporal filter reads (both off
/// for the others, and by default).
#[derive(Debug, Clone, Copy, Default)]
pub struct Extra<'a> {
    /// A pixel with no valid bilinear tap reads its `Motion::fallback` neighbours, each with the
    /// same weight (Falcor's 3 × 3 cross-bilateral fallback), before it restarts.
    pub fallback: bool,
    /// (previous frame's ids, this frame's ids), `GBuffer::primitive`: a tap onto another
    /// primitive than the pixel's is not kept (Schied et al. 2017 §4.1's mesh-ID test).
    pub ids: Option<(&'a [u32], &'a [u32])>,
}

/// One frame's reprojection of the history: per pixel its valid taps into the previous frame and
/// its new history length.
#[derive(Debug, Clone)]
pub struct Reprojected {
    /// Pixel i's taps are `taps[start[i] as usize..start[i + 1] as usize]`.
    start: Vec<u32>,
    taps: Vec<(u32, f64)>,
    /// Per pixel the history length after this frame: 0 on background, 1 for a restart.
    pub length: Vec<u32>,
}

impl Reprojected {
    /// The frame's pixels (`coverage`) through `motion` onto a previous frame whose history
    /// lengths were `prev` (empty: there was no previous frame, every pixel starts).
    pub fn new(prev: &[u32], coverage: &Image, motion: &Motion) -> Self {
        Self::with(prev, coverage, motion, Extra::default())
    }

    /// `new`, with SVGF's `extra` tests and fallback.
    pub fn with(prev: &[u32], coverage: &Image, motion: &Motion, extra: Extra) -> Self {
        let n = coverage.len();
        assert!(
            motion.width == coverage.width && motion.height == coverage.height,
            "temporal filter: the motion is {}x{}, the frame {}x{}",
            motion.width,
            motion.height,
            coverage.width,
            coverage.height
        );
        assert!(
            prev.is_empty() || prev.len() == n,
            "temporal filter: a {}-pixel history for a {n}-pixel frame",
            prev.len()
        );
        if let Some((a, b)) = extra.ids {
            assert!(
                (prev.is_empty() || a.len() == n) && b.len() == n,
                "svgf: the primitive-ID test needs ids in both frames' G-buffers"
            );
        }
        let same = |i: usize, q: u32| extra.ids.is_none_or(|(a, b)| a[q as usize] == b[i]);
        let mut start = Vec::with_capacity(n + 1);
        let mut taps = Vec::with_capacity(n);
        let mut length = vec![0u32; n];
        for (i, len) in length.iter_mut().enumerate() {
            start.push(taps.len() as u32);
            if !covered(coverage, i) {
                continue;
            }
            let first = taps.len();
            let (mut sum, mut best) = (0.0f64, (0.0f32, 0u32));
            if !prev.is_empty() {
                for t in motion.taps(i) {
                    let had = prev[t.index as usize];
                    if had == 0 || !same(i, t.index) {
                        continue;
                    }
                    taps.push((t.index, t.weight as f64));
                    sum += t.weight as f64;
                    if t.weight > best.0 {
                        best = (t.weight, had);
                    }
                }
                if taps.len() == first && extra.fallback {
                    for &q in motion.fallback(i) {
                        let had = prev[q as usize];
                        if had == 0 || !same(i, q) {
                            continue;
                        }
                        taps.push((q, 1.0));
                        sum += 1.0;
                        best.1 = best.1.max(had);
                    }
                }
            }
            for t in &mut taps[first..] {
                t.1 /= sum;
            }
            *len = if taps.len() == first { 1 } else { best.1.saturating_add(1) };
        }
        start.push(taps.len() as u32);
        Self { start, taps, length }
    }

    /// Every covered pixel starts (the first frame of a run).
    pub fn start(coverage: &Image) -> Self {
        Self::new(&[], coverage, &Motion::identity(coverage.width, coverage.height))
    }

    /// The valid taps of pixel `i` (empty: its history restarts), weights summing to 1.
    pub fn taps(&self, i: usize) -> &[(u32, f64)] {
        &self.taps[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// The previous frame's values `prev` resampled at pixel `i` (None: no history), in tap order.
    pub fn gather(&self, prev: &[f64], i: usize) -> Option<f64> {
        let taps = self.taps(i);
        (!taps.is_empty()).then(|| taps.iter().map(|&(q, w)| w * prev[q as usize]).sum())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_grow_restart_and_skip_taps_onto_background() {
        let cov = Image::from_vec(3, 1, vec![1.0, 1.0, 0.0]);
        let first = Reprojected::start(&cov);
        assert_eq!(first.length, [1, 1, 0]);
        let again = Reprojected::new(&first.length, &cov, &Motion::identity(3, 1));
        assert_eq!(again.length, [2, 2, 0]);
        // Pixel 0 reads 3/4 of pixel 1 and 1/4 of the background pixel 2: the latter is dropped.
        let m = Motion::from_taps(3, 1, vec![vec![(1, 0.75), (2, 0.25)], vec![], vec![(0, 1.0)]]);
        let moved = Reprojected::new(&again.length, &cov, &m);
        assert_eq!(moved.taps(0), &[(1, 1.0)]);
        assert_eq!(moved.length, [3, 1, 0], "pixel 1 disoccluded: a restart");
        assert_eq!(moved.gather(&[5.0, 7.0, 9.0], 0), Some(7.0));
        assert_eq!(moved.gather(&[5.0, 7.0, 9.0], 1), None);
        assert_eq!(alpha_eff(0.1, 3), 1.0 / 3.0);
        assert_eq!(alpha_eff(0.5, 3), 0.5);
        assert_eq!(alpha_eff(0.0, 7), 1.0 / 7.0);
    }
}
