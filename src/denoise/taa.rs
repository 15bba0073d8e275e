//! TAA-style temporal accumulation with neighbourhood clipping: the warm-started EMA of
//! `accumulate` (α_eff = max(α, 1/n), history read through a `Motion`), whose reprojected history
//! is first clipped to the current frame's 3 × 3 neighbourhood, mean ± γσ over its covered pixels
//! (variance clipping: Salvi 2016, "An Excursion in Temporal Supersampling", GDC; the
//! neighbourhood clamp of Karis 2014, "High Quality Temporal Supersampling"). A history that the
//! current frame's neighbourhood does not support (a disocclusion the motion missed, a moving
//! shadow, a wrong reprojection) is pulled to its bounds instead of ghosting; the price is that
//! real noise outside ±γσ is clipped too, so the clipped EMA converges less far than the plain one.
//!
//! For a scalar (AO), clipping towards the neighbourhood's mean μ is the clamp to [μ − γσ, μ + γσ],
//! written h' = μ + s (h − μ) with s = min(1, γσ / |h − μ|). The joint application of the
//! noise/bias split (`push_pair`) applies that same s, found on the noisy frames, to the
//! reference's history and the reference's neighbourhood mean.

use super::history::{Reprojected, alpha_eff};
use super::motion::Motion;
use crate::image::{Image, covered};

/// γ: how many neighbourhood standard deviations the history may lie from the mean (Salvi's 1).
pub const TAA_GAMMA: f64 = 1.0;

/// The mean and standard deviation (population: Σx²/N − μ²) of the covered pixels of the 3 × 3
/// neighbourhood of each covered pixel of `frame` (background pixels: (value, 0)).
pub fn neighbourhood(frame: &Image, coverage: &Image) -> Vec<(f64, f64)> {
    let (w, h) = (frame.width as i64, frame.height as i64);
    (0..frame.len())
        .map(|i| {
            if !covered(coverage, i) {
                return (frame.data[i] as f64, 0.0);
            }
            let (x, y) = (i as i64 % w, i as i64 / w);
            let (mut s, mut s2, mut k) = (0.0f64, 0.0f64, 0u32);
            for qy in (y - 1).max(0)..=(y + 1).min(h - 1) {
                for qx in (x - 1).max(0)..=(x + 1).min(w - 1) {
                    let q = (qy * w + qx) as usize;
                    if covered(coverage, q) {
                        let v = frame.data[q] as f64;
                        s += v;
                        s2 += v * v;
                        k += 1;
                    }
                }
            }
            let mean = s / k as f64;
            (mean, (s2 / k as f64 - mean * mean).max(0.0).sqrt())
        })
        .collect()
}

/// The clip of history `h` towards `mean` to within `gamma · sd`: (clipped, s) with
/// clipped = mean + s (h − mean), s ∈ [0, 1] (1: inside, untouched): the clamp to
/// [mean − γ sd, mean + γ sd], up to the rounding of that product (the reference's history is
/// clipped by the same expression, so a noise-free pair stays bit-identical).
pub fn clip(h: f64, mean: f64, sd: f64, gamma: f64) -> (f64, f64) {
    let d = h - mean;
    if d.abs() <= gamma * sd {
        (h, 1.0)
    } else {
        let s = gamma * sd / d.abs();
        (blend(h, mean, s), s)
    }
}

/// mean + s (h − mean), and h itself for s = 1.
fn blend(h: f64, mean: f64, s: f64) -> f64 {
    if s == 1.0 { h } else { mean + s * (h - mean) }
}

/// The running state of one TAA run (the history in f64, and the reference's for `push_pair`).
#[derive(Debug, Clone)]
pub struct Taa {
    pub alpha: f64,
    pub gamma: f64,
    frames: u32,
    state: Vec<f64>,
    reference: Option<Vec<f64>>,
    length: Vec<u32>,
}

impl Taa {
    /// α ∈ (0, 1] the EMA's weight, γ the clip's width (`TAA_GAMMA`).
    pub fn new(alpha: f64, gamma: f64) -> Self {
        Self { alpha, gamma, frames: 0, state: Vec::new(), reference: None, length: Vec::new() }
    }

    /// Per pixel the history length n after the last frame (0: background).
    pub fn lengths(&self) -> &[u32] {
        &self.length
    }

    /// The next frame: its covered pixels `coverage`'s, the history read through `motion`. The
    /// output is also the next frame's history; background pixels keep the frame's value.
    pub fn push(&mut self, frame: &Image, coverage: &Image, motion: &Motion) -> Image {
        assert!(
            self.reference.is_none() || self.frames == 0,
            "taa: a run pushes pairs from its first frame or never"
        );
        self.step(frame, None, coverage, motion).0
    }

    /// `push` and its joint application to `reference` (module doc): (output, reference's output).
    /// A run pushes pairs from its first frame or never.
    pub fn push_pair(
        &mut self,
        frame: &Image,
        reference: &Image,
        coverage: &Image,
        motion: &Motion,
    ) -> (Image, Image) {
        assert!(
            self.reference.is_some() || self.frames == 0,
            "taa: a run pushes pairs from its first frame or never"
        );
        let (out, r) = self.step(frame, Some(reference), coverage, motion);
        (out, r.expect("a reference was given"))
    }

    fn step(
        &mut self,
        frame: &Image,
        reference: Option<&Image>,
        coverage: &Image,
        motion: &Motion,
    ) -> (Image, Option<Image>) {
        assert!(frame.same_size(coverage), "taa: frame and coverage differ in size");
        assert!(self.frames == 0 || self.state.len() == frame.len(), "taa: the frame's size changed");
        let r = Reprojected::new(&self.length, coverage, motion);
        let hood = neighbourhood(frame, coverage);
        let hood_ref = reference.map(|rf| {
            assert!(rf.same_size(frame), "taa: the reference and the frame differ in size");
            neighbourhood(rf, coverage)
        });
        let n = frame.len();
        let mut state = vec![0.0f64; n];
        let mut state_ref = reference.map(|_| vec![0.0f64; n]);
        for i in 0..n {
            let x = frame.data[i] as f64;
            let xr = reference.map(|rf| rf.data[i] as f64);
            let (out, s, a) = match (r.length[i], r.gather(&self.state, i)) {
                (0, _) | (_, None) => (x, None, 1.0),
                (len, Some(h)) => {
                    let (mean, sd) = hood[i];
                    let (hc, s) = clip(h, mean, sd, self.gamma);
                    let a = alpha_eff(self.alpha, len);
                    (hc + a * (x - hc), Some(s), a)
                }
            };
            state[i] = out;
            if let (Some(sr), Some(xr)) = (state_ref.as_mut(), xr) {
                sr[i] = match s {
                    None => xr,
                    Some(s) => {
                        let hr = r
                            .gather(self.reference.as_deref().expect("pairs from the first frame"), i)
                            .unwrap();
                        let mr = hood_ref.as_ref().expect("a reference")[i].0;
                        let hc = blend(hr, mr, s);
                        hc + a * (xr - hc)
                    }
                };
            }
        }
        let image =
            |v: &[f64]| Image::from_vec(frame.width, frame.height, v.iter().map(|&x| x as f32).collect());
        let out = image(&state);
        let out_ref = state_ref.as_deref().map(image);
        self.state = state;
        self.reference = state_ref;
        self.length = r.length;
        self.frames += 1;
        (out, out_ref)
    }
}
