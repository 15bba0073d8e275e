//! Where each pixel of the current frame was in the previous one: the reprojection a temporal
//! filter reads its history through, as plain data. A moving camera's reprojection (each pixel's
//! world position projected into the previous frame's camera, bilinear taps validated by depth and
//! normal) is made from the two frames' G-buffers by the code that owns cameras; the temporal
//! filters here only consume it, so a static camera and a moving one run the same filter code.

/// One history tap: a pixel of the previous frame (row-major index) and its weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tap {
    pub index: u32,
    pub weight: f32,
}

/// Per pixel of the current frame, up to four taps into the previous frame whose weights sum to 1,
/// or none: the pixel is disoccluded (or newly covered) and its history starts again.
///
/// Beside them, for a pixel with no tap, the previous pixels of the 3 × 3 neighbourhood around
/// where it projects that pass the same consistency tests: the cross-bilateral fallback of
/// Falcor's SVGFPass (tried there before a pixel is declared disoccluded). Only a filter that asks
/// for it reads them (`fallback`); for every other the pixel is disoccluded, as before.
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    pub width: u32,
    pub height: u32,
    taps: Vec<[Tap; 4]>,
    count: Vec<u8>,
    /// (pixel, its consistent 3 × 3 neighbours in the previous frame), by pixel, for pixels
    /// without taps.
    fallback: Vec<(u32, Vec<u32>)>,
}

const NO_TAP: Tap = Tap { index: 0, weight: 0.0 };

impl Motion {
    /// A static camera: every pixel reads its own history with weight 1.
    pub fn identity(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        let taps = (0..n).map(|i| [Tap { index: i as u32, weight: 1.0 }, NO_TAP, NO_TAP, NO_TAP]).collect();
        Self { width, height, taps, count: vec![1; n], fallback: Vec::new() }
    }

    /// From each pixel's valid taps (at most four; an empty list is a disocclusion). Weights are
    /// normalized to sum to 1; taps of zero weight are dropped.
    pub fn from_taps(width: u32, height: u32, per_pixel: Vec<Vec<(u32, f32)>>) -> Self {
        let n = width as usize * height as usize;
        assert_eq!(
            per_pixel.len(),
            n,
            "motion: {} pixels' taps for a {width}x{height} frame",
            per_pixel.len()
        );
        let mut taps = Vec::with_capacity(n);
        let mut count = Vec::with_capacity(n);
        for list in per_pixel {
            let kept: Vec<(u32, f32)> = list.into_iter().filter(|&(_, w)| w > 0.0).collect();
            assert!(kept.len() <= 4, "motion: a pixel has {} history taps (at most 4)", kept.len());
            let sum: f32 = kept.iter().map(|&(_, w)| w).sum();
            let mut t = [NO_TAP; 4];
            for (slot, &(index, w)) in t.iter_mut().zip(&kept) {
                assert!((index as usize) < n, "motion: tap {index} outside a {width}x{height} frame");
                *slot = Tap { index, weight: w / sum };
            }
            taps.push(t);
            count.push(kept.len() as u8);
        }
        Self { width, height, taps, count, fallback: Vec::new() }
    }

    /// This motion with `fallback`: per pixel without taps, its consistent previous pixels of
    /// the 3 × 3 neighbourhood around where it projects (a pixel with taps, an empty list or a
    /// pixel outside the frame panics).
    pub fn with_fallback(mut self, mut fallback: Vec<(u32, Vec<u32>)>) -> Self {
        let n = self.width as usize * self.height as usize;
        fallback.sort_by_key(|&(i, _)| i);
        for (i, list) in &fallback {
            let i = *i as usize;
            assert!(i < n && self.count[i] == 0, "motion: a fallback for pixel {i}, which has taps");
            assert!(!list.is_empty() && list.len() <= 9, "motion: {} fallback taps", list.len());
            assert!(list.iter().all(|&q| (q as usize) < n), "motion: a fallback tap outside the frame");
        }
        self.fallback = fallback;
        self
    }

    /// Pixel `i`'s fallback neighbours (empty for a pixel with taps or with none that is
    /// consistent): each is read with the same weight, as Falcor's SVGFPass does.
    pub fn fallback(&self, i: usize) -> &[u32] {
        match self.fallback.binary_search_by_key(&(i as u32), |&(p, _)| p) {
            Ok(k) => &self.fallback[k].1,
            Err(_) => &[],
        }
    }

    /// The taps of pixel `i` (empty: disoccluded).
    pub fn taps(&self, i: usize) -> &[Tap] {
        &self.taps[i][..self.count[i] as usize]
    }

    /// Whether pixel `i` has any history.
    pub fn has_history(&self, i: usize) -> bool {
        self.count[i] > 0
    }

    /// The previous frame's values `prev` resampled at pixel `i` (None: disoccluded).
    pub fn gather(&self, prev: &[f64], i: usize) -> Option<f64> {
        let taps = self.taps(i);
        (!taps.is_empty()).then(|| taps.iter().map(|t| t.weight as f64 * prev[t.index as usize]).sum())
    }
}
