//! One run of a `Pipeline`, frame by frame: the stateful filter an executor pushes every rendered
//! frame through (`Pipeline::start`), whatever the pipeline, static camera or moving one.
//!
//! **The noise/bias split of a non-linear filter.** For a linear filter F the error of F(noisy)
//! against the reference splits into F(noisy) − F(reference), the noise that survives the filter,
//! and F(reference) − reference, its bias. An edge-stopping filter's weights depend on its input,
//! so "F(reference)" alone is another filter (on a converged input the value weights stop nearly
//! everything). `push_pair` applies the filter *jointly*: it computes every weight (the EMA's
//! α_eff, TAA's clip, à-trous's and SVGF's edge-stopping weights, from the noisy frame, its
//! history and variance) once on the noisy frames and applies those same weights to the
//! reference frames, which keep a history of their own. With F_w that filter,
//! RMSE(F_w(noisy), F_w(reference)) is the noise part and RMSE(F_w(reference), reference) the bias
//! part; for a linear filter F_w(reference) = F(reference), and for a noise-free input
//! (noisy = reference) the noise part is 0.

use super::accumulate::{Accumulator, Temporal};
use super::atrous::{AtrousParams, atrous, atrous_pair};
use super::gaussian::{GAUSS_SIGMA, gaussian};
use super::motion::Motion;
use super::pipeline::{Pipeline, Spatial};
use super::svgf::{Svgf, SvgfParams};
use super::taa::{TAA_GAMMA, Taa};
use crate::image::Image;
use crate::render::GBuffer;

/// A pipeline's state over one run of frames (`Pipeline::start`).
pub trait FrameFilter: Send {
    /// The next frame (its G-buffer, and where its pixels were in the previous frame:
    /// `Motion::identity` for a static camera): the image after the whole pipeline for this frame.
    /// Background pixels (coverage 0) keep the frame's value.
    fn push(&mut self, frame: &Image, gbuf: &GBuffer, motion: &Motion) -> Image;

    /// `push` with the joint application to `reference` (module doc): (the output, the
    /// reference under the same weights). A run pushes pairs from its first frame or never.
    fn push_pair(
        &mut self,
        frame: &Image,
        reference: &Image,
        gbuf: &GBuffer,
        motion: &Motion,
    ) -> (Image, Image);

    /// `push` (with `reference`: `push_pair`) of a frame whose output nobody looks at: the state
    /// advances exactly as theirs does, without the spatial work only a shown image needs (SVGF's
    /// passes after the first, a spatial filter after the accumulation).
    fn advance(&mut self, frame: &Image, reference: Option<&Image>, gbuf: &GBuffer, motion: &Motion);

    /// Frames pushed so far.
    fn frames(&self) -> u32;
}

enum State {
    None,
    /// The accumulator of the frames, and of the reference frames for pairs (the EMA's weights
    /// depend only on the history lengths, so the joint application is the same accumulation).
    Accumulate(Accumulator, Option<Accumulator>),
    Taa(Taa),
    Svgf(Svgf),
}

/// The `FrameFilter` of every pipeline.
pub struct Run {
    pub pipeline: Pipeline,
    width: u32,
    height: u32,
    temporal: State,
    atrous: AtrousParams,
    frames: u32,
    paired: bool,
}

impl Run {
    /// A run of `pipeline` over `width` × `height` frames; default iteration counts settled here.
    pub fn new(pipeline: Pipeline, width: u32, height: u32) -> Self {
        let temporal = match pipeline.temporal {
            None => State::None,
            Some(t @ (Temporal::Mean | Temporal::Ema(_))) => State::Accumulate(Accumulator::new(t), None),
            Some(Temporal::Taa(a)) => State::Taa(Taa::new(a as f64, TAA_GAMMA)),
            Some(Temporal::Svgf(options)) => {
                let params = SvgfParams::of(options);
                let iterations =
                    params.iterations.unwrap_or_else(|| super::edges::default_iterations(width, height));
                State::Svgf(Svgf::new(SvgfParams { iterations: Some(iterations), ..params }))
            }
        };
        let k = match pipeline.spatial {
            Some(Spatial::Atrous(k)) => k,
            _ => None,
        };
        let params = AtrousParams { iterations: k, ..AtrousParams::default() };
        let atrous = params.with_iterations(params.iterations_for(width, height));
        Self { pipeline, width, height, temporal, atrous, frames: 0, paired: false }
    }

    fn check(&self, frame: &Image, gbuf: &GBuffer, motion: &Motion) {
        let (w, h) = (self.width, self.height);
        assert!(
            (frame.width, frame.height) == (w, h)
                && (gbuf.width, gbuf.height) == (w, h)
                && (motion.width, motion.height) == (w, h),
            "{}: a run of {w}x{h} frames got a {}x{} frame, {}x{} G-buffer, {}x{} motion",
            self.pipeline,
            frame.width,
            frame.height,
            gbuf.width,
            gbuf.height,
            motion.width,
            motion.height
        );
    }

    fn spatial(&self, img: Image, gbuf: &GBuffer) -> Image {
        match self.pipeline.spatial {
            None => img,
            Some(Spatial::Gauss) => gaussian(&img, &gbuf.coverage, GAUSS_SIGMA),
            Some(Spatial::Atrous(_)) => atrous(&img, gbuf, &self.atrous),
        }
    }

    fn spatial_pair(&self, img: Image, reference: Image, gbuf: &GBuffer) -> (Image, Image) {
        match self.pipeline.spatial {
            None => (img, reference),
            Some(Spatial::Gauss) => (
                gaussian(&img, &gbuf.coverage, GAUSS_SIGMA),
                gaussian(&reference, &gbuf.coverage, GAUSS_SIGMA),
            ),
            Some(Spatial::Atrous(_)) => atrous_pair(&img, &reference, gbuf, &self.atrous),
        }
    }
}

impl FrameFilter for Run {
    fn push(&mut self, frame: &Image, gbuf: &GBuffer, motion: &Motion) -> Image {
        self.check(frame, gbuf, motion);
        assert!(!self.paired, "{}: a run pushes pairs from its first frame or never", self.pipeline);
        let img = match &mut self.temporal {
            State::None => frame.clone(),
            State::Accumulate(acc, _) => {
                acc.push_through(frame, &gbuf.coverage, motion);
                acc.image()
            }
            State::Taa(t) => t.push(frame, &gbuf.coverage, motion),
            State::Svgf(s) => s.push(frame, gbuf, motion),
        };
        self.frames += 1;
        self.spatial(img, gbuf)
    }

    fn push_pair(
        &mut self,
        frame: &Image,
        reference: &Image,
        gbuf: &GBuffer,
        motion: &Motion,
    ) -> (Image, Image) {
        self.check(frame, gbuf, motion);
        self.check(reference, gbuf, motion);
        assert!(
            self.paired || self.frames == 0,
            "{}: a run pushes pairs from its first frame or never",
            self.pipeline
        );
        self.paired = true;
        let (img, img_ref) = match &mut self.temporal {
            State::None => (frame.clone(), reference.clone()),
            State::Accumulate(acc, acc_ref) => {
                let acc_ref = acc_ref.get_or_insert_with(|| Accumulator::new(acc.mode));
                acc.push_through(frame, &gbuf.coverage, motion);
                acc_ref.push_through(reference, &gbuf.coverage, motion);
                (acc.image(), acc_ref.image())
            }
            State::Taa(t) => t.push_pair(frame, reference, &gbuf.coverage, motion),
            State::Svgf(s) => s.push_pair(frame, reference, gbuf, motion),
        };
        self.frames += 1;
        self.spatial_pair(img, img_ref, gbuf)
    }

    fn advance(&mut self, frame: &Image, reference: Option<&Image>, gbuf: &GBuffer, motion: &Motion) {
        // TAA's history is its output, and a run without state has nothing to advance: no spatial
        // work to spare.
        if !matches!(self.temporal, State::Svgf(_) | State::Accumulate(..)) {
            match reference {
                Some(r) => drop(self.push_pair(frame, r, gbuf, motion)),
                None => drop(self.push(frame, gbuf, motion)),
            }
            return;
        }
        self.check(frame, gbuf, motion);
        assert!(
            self.paired == reference.is_some() || self.frames == 0,
            "{}: a run pushes pairs from its first frame or never",
            self.pipeline
        );
        self.paired = reference.is_some();
        match &mut self.temporal {
            State::Svgf(s) => s.advance(frame, reference, gbuf, motion),
            State::Accumulate(acc, acc_ref) => {
                acc.push_through(frame, &gbuf.coverage, motion);
                if let Some(r) = reference {
                    let acc_ref = acc_ref.get_or_insert_with(|| Accumulator::new(acc.mode));
                    acc_ref.push_through(r, &gbuf.coverage, motion);
                }
            }
            State::None | State::Taa(_) => unreachable!("handled above"),
        }
        self.frames += 1;
    }

    fn frames(&self) -> u32 {
        self.frames
    }
}
