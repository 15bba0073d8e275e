//! Temporal accumulation of a static camera's frames, per pixel: the running mean (every frame the
//! same weight: what converges to the estimator's mean) and the exponential moving average of
//! TAA-style real-time renderers (Karis 2014; Yang et al. 2020, "A Survey of Temporal
//! Antialiasing Techniques"), s_k = s_{k−1} + α (x_k − s_{k−1}) with s_1 = x_1: a noise floor of
//! α/(2−α) of one frame's variance instead of convergence.

use crate::image::Image;

/// How frames are combined.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Temporal {
    /// The running mean of all frames so far.
    Mean,
    /// The exponential moving average with weight α ∈ (0, 1] on the newest frame.
    Ema(f32),
}

/// The accumulated image so far, kept in f64 (a mean over many frames must not drift by f32
/// rounding); `image` rounds it to f32.
#[derive(Debug, Clone)]
pub struct Accumulator {
    pub mode: Temporal,
    frames: u32,
    width: u32,
    height: u32,
    state: Vec<f64>,
}

impl Accumulator {
    pub fn new(mode: Temporal) -> Self {
        Self { mode, frames: 0, width: 0, height: 0, state: Vec::new() }
    }

    /// Frames pushed so far.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Adds the next frame; the first one initializes every pixel. Panics if its size differs from
    /// the first frame's (frames of one camera always agree).
    pub fn push(&mut self, frame: &Image) {
        if self.frames == 0 {
            (self.width, self.height) = (frame.width, frame.height);
            self.state = frame.data.iter().map(|&v| v as f64).collect();
            self.frames = 1;
            return;
        }
        assert!(
            frame.width == self.width && frame.height == self.height,
            "accumulate: a {}x{} frame after {}x{} ones",
            frame.width,
            frame.height,
            self.width,
            self.height
        );
        self.frames += 1;
        let a = match self.mode {
            Temporal::Mean => 1.0 / self.frames as f64,
            Temporal::Ema(alpha) => alpha as f64,
        };
        for (s, &x) in self.state.iter_mut().zip(&frame.data) {
            *s += a * (x as f64 - *s);
        }
    }

    /// The accumulated image (empty 0 × 0 before the first frame).
    pub fn image(&self) -> Image {
        Image::from_vec(self.width, self.height, self.state.iter().map(|&v| v as f32).collect())
    }
}
