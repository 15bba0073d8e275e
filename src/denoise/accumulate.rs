//! Temporal accumulation of frames, per pixel: the running mean (every frame the same weight: what
//! converges to the estimator's mean) and the exponential moving average of TAA-style real-time
//! renderers (Karis 2014; Yang et al. 2020, "A Survey of Temporal Antialiasing Techniques"),
//! s_n = s_{n−1} + α_eff (x_n − s_{n−1}) with the warm start α_eff = max(α, 1/n) of a per-pixel
//! history of n frames (`history`; Schied et al. 2017 §4.1): the running mean of a pixel's first
//! 1/α frames, then a noise floor of α/(2−α) of one frame's variance instead of convergence. A
//! constant α from s_1 = x_1 on would weigh the first frame (1−α)^(n−1), far more than the others,
//! for dozens of frames. The history is read through a `Motion` (a static camera: `push`).

use super::history::{Reprojected, alpha_eff};
use super::motion::Motion;
use super::svgf::SvgfOptions;
use crate::image::Image;

/// How frames are combined.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Temporal {
    /// The running mean of all frames of a pixel's history.
    Mean,
    /// The warm-started exponential moving average: weight max(α, 1/n) on the newest frame,
    /// α ∈ (0, 1].
    Ema(f32),
    /// `Ema` with the reprojected history clipped to the current frame's neighbourhood (`taa`).
    Taa(f32),
    /// SVGF's own temporal accumulation and à-trous filter, with its iteration count (None: the
    /// share-of-image default) and options (`svgf`). Its history is its first à-trous pass, so it
    /// is no accumulation of frames alone.
    Svgf(SvgfOptions),
}

/// The weight below which a pipeline's history is said to have forgotten a frame: `memory_frames`.
pub const FORGOTTEN: f64 = 0.01;

impl Temporal {
    /// How many of the newest frames hold all but `FORGOTTEN` of the weight of a long history at
    /// steady state: the least W with (1 − α)^W ≤ `FORGOTTEN` (SVGF: α = 0.2 for colour and
    /// moments, W = 21; an EMA or TAA of α 0.1: W = 44); `None` for the mean, which never forgets.
    /// Why: a run started W frames before the frame it measures (`plan::Measurement::first_frame`)
    /// shows that frame as a long run does, the frames before weighing at most 1 % together (and
    /// the warm start α_eff = max(α, 1/n) gives its first frames the running mean's weights).
    /// TAA's clipping only shortens its memory.
    pub fn memory_frames(self) -> Option<u32> {
        let alpha = match self {
            Temporal::Mean => return None,
            Temporal::Ema(a) | Temporal::Taa(a) => a as f64,
            Temporal::Svgf(o) => {
                let p = super::svgf::SvgfParams::of(o);
                p.alpha_color.min(p.alpha_moments)
            }
        };
        if alpha >= 1.0 {
            return Some(1);
        }
        Some((FORGOTTEN.ln() / (1.0 - alpha).ln()).ceil().max(1.0) as u32)
    }

    /// The α of α_eff = max(α, 1/n) (0 for the mean), for the modes `Accumulator` runs.
    fn alpha(self) -> f64 {
        match self {
            Temporal::Mean => 0.0,
            Temporal::Ema(a) => a as f64,
            Temporal::Taa(_) | Temporal::Svgf(_) => {
                panic!("accumulate: {self:?} is no plain accumulation (run it through Pipeline::start)")
            }
        }
    }
}

/// The accumulated image so far, kept in f64 (a mean over many frames must not drift by f32
/// rounding); `image` rounds it to f32. Background pixels (coverage 0) hold the newest frame's
/// value and have no history.
#[derive(Debug, Clone)]
pub struct Accumulator {
    pub mode: Temporal,
    frames: u32,
    width: u32,
    height: u32,
    state: Vec<f64>,
    length: Vec<u32>,
}

impl Accumulator {
    /// A fresh accumulator; panics for `Taa` and `Svgf`, which are not plain accumulations.
    pub fn new(mode: Temporal) -> Self {
        mode.alpha();
        Self { mode, frames: 0, width: 0, height: 0, state: Vec::new(), length: Vec::new() }
    }

    /// Frames pushed so far.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Per pixel the history length n after the last frame (0: background).
    pub fn lengths(&self) -> &[u32] {
        &self.length
    }

    /// The accumulated values in f64.
    pub fn state(&self) -> &[f64] {
        &self.state
    }

    /// Adds the next frame of a static camera, every pixel covered. Panics if its size differs
    /// from the first frame's (frames of one camera always agree).
    pub fn push(&mut self, frame: &Image) {
        let all = Image::from_vec(frame.width, frame.height, vec![1.0; frame.len()]);
        self.push_through(frame, &all, &Motion::identity(frame.width, frame.height));
    }

    /// Adds the next frame, whose covered pixels are `coverage`'s, reading the history through
    /// `motion`: a pixel without taps (or the first frame) starts again at its value.
    pub fn push_through(&mut self, frame: &Image, coverage: &Image, motion: &Motion) {
        if self.frames > 0 {
            assert!(
                frame.width == self.width && frame.height == self.height,
                "accumulate: a {}x{} frame after {}x{} ones",
                frame.width,
                frame.height,
                self.width,
                self.height
            );
        }
        assert!(frame.same_size(coverage), "accumulate: frame and coverage differ in size");
        let r = Reprojected::new(&self.length, coverage, motion);
        let alpha = self.mode.alpha();
        let state: Vec<f64> = (0..frame.len())
            .map(|i| {
                let x = frame.data[i] as f64;
                match (r.length[i], r.gather(&self.state, i)) {
                    (0, _) | (_, None) => x,
                    (n, Some(h)) => h + alpha_eff(alpha, n) * (x - h),
                }
            })
            .collect();
        (self.width, self.height) = (frame.width, frame.height);
        self.state = state;
        self.length = r.length;
        self.frames += 1;
    }

    /// The accumulated image (empty 0 × 0 before the first frame).
    pub fn image(&self) -> Image {
        Image::from_vec(self.width, self.height, self.state.iter().map(|&v| v as f32).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_history_forgets_all_but_one_percent_after_its_memory_frames() {
        let svgf = Temporal::Svgf(SvgfOptions::default());
        assert_eq!(svgf.memory_frames(), Some(21));
        assert_eq!(Temporal::Taa(0.1).memory_frames(), Some(44));
        assert_eq!(Temporal::Ema(1.0).memory_frames(), Some(1));
        assert_eq!(Temporal::Mean.memory_frames(), None);
        for a in [0.05f32, 0.1, 0.2, 0.5] {
            let w = Temporal::Ema(a).memory_frames().unwrap() as i32;
            let kept = |n: i32| (1.0 - a as f64).powi(n);
            assert!(kept(w) <= FORGOTTEN && kept(w - 1) > FORGOTTEN, "{a}");
        }
    }
}
