//! How a job's renders become the measured image and its errors, for every kind of measurement
//! (`plan::Measurement`), behind one small interface so that the executor never asks which kind
//! a job is:
//!
//! - `SingleFrame`: one raw frame of the job's integrand, measured against the reference (the
//!   paper's tables).
//! - `Frames`: the frames of a static camera, rendered with `SamplerConfig::with_frame(f)
//!   .with_schedule(s)` and accumulated by the pipeline's temporal part; then its spatial part,
//!   guided by the scene's G-buffer; the error against the reference (what the user sees) and
//!   against the reference under the same spatial filter (the noise part, `noise_rmse`), so a
//!   filter's bias and the sampler's noise stay apart.
//!
//! A series of frames is rendered once, to its last reported frame, and each reported frame's
//! image is taken on the way (`plan::series`). The time of a reported frame's record (`time_s`
//! and the timing columns) is the CPU time of rendering the frames up to it and accumulating
//! them; the spatial filter is not timed (it costs the same for every sampler, so it cannot change
//! which sampler wins at equal time). A single frame's time is that of its whole render. A single
//! frame rendered by `Frames` would be the same image bit for bit: `SingleFrame` exists so that
//! the paper's path stays one render, with nothing of the frames' machinery around it.

use crate::denoise::Motion;
use crate::image::Image;
use crate::metrics::{self, ErrorStats, MetricsError};
use crate::plan::Measurement;
use crate::render::{self, GBuffer, RenderJob, RenderOutput};
use crate::scene::Scene;
use crate::timing::{Time, clock};
use std::collections::HashMap;

/// The reference images a measurement compares with, and the guide of its filters.
pub struct Against<'a> {
    pub reference: &'a Image,
    pub coverage: &'a Image,
    /// The scene's G-buffer at the job's size (`None` for a single frame).
    pub gbuffer: Option<&'a GBuffer>,
}

/// The image of one reported frame: after the whole pipeline, with the rays of every frame so
/// far, the reference under the same filter weights (`denoise::FrameFilter::push_pair`: the noise
/// part of its error is against that), and the render time of those frames (`None`: the caller's
/// time of the whole render).
pub struct FrameImage {
    /// The frame, counted from 1.
    pub frame: u32,
    pub output: RenderOutput,
    pub filtered_reference: Option<Image>,
    pub time: Option<Time>,
}

/// One kind of measurement.
pub trait Measure: Sync {
    /// Renders what the job renders (timed by the caller as a whole) and returns the image at each
    /// of `reported` (ascending frames from 1; a single frame reports `[1]`).
    fn render(
        &self,
        scene: &Scene,
        rj: &RenderJob,
        reported: &[u32],
        against: &Against,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Vec<FrameImage>;

    /// How many frames a render to the job's own frame renders (for progress and cost).
    fn frames(&self) -> u64;
}

/// A reported frame's error statistics against the reference and its noise RMSE: against the
/// reference under the same filter weights, else (no filter) the RMSE itself.
pub fn errors(image: &FrameImage, against: &Against) -> Result<(ErrorStats, f64), MetricsError> {
    let stats = metrics::measure(&image.output.ao, against.reference, against.coverage)?;
    let noise = match &image.filtered_reference {
        Some(f) => metrics::measure(&image.output.ao, f, against.coverage)?.rmse,
        None => stats.rmse,
    };
    Ok((stats, noise))
}

/// One raw frame.
pub struct SingleFrame(pub Measurement);

impl Measure for SingleFrame {
    fn render(
        &self,
        scene: &Scene,
        rj: &RenderJob,
        _reported: &[u32],
        _against: &Against,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Vec<FrameImage> {
        let output = render::render_integrand(scene, rj, self.0.integrand, progress);
        vec![FrameImage { frame: 1, output, filtered_reference: None, time: None }]
    }

    fn frames(&self) -> u64 {
        1
    }
}

/// Frames pushed through a pipeline (`denoise::Pipeline::start`): every frame the pipeline shows
/// is filtered in order, since its history is its own output; the reference is pushed beside them
/// under the same weights, so that the noise part of the error is measured for a non-linear
/// filter too.
pub struct Frames(pub Measurement);

impl Measure for Frames {
    fn render(
        &self,
        scene: &Scene,
        rj: &RenderJob,
        reported: &[u32],
        against: &Against,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Vec<FrameImage> {
        let m = &self.0;
        let last = reported.iter().copied().max().unwrap_or(m.frame).max(1);
        // A pipeline that does not accumulate shows one frame: the last one alone is rendered.
        let rendered: Vec<u32> = if m.pipeline.is_temporal() { (0..last).collect() } else { vec![last - 1] };
        let gbuf = against.gbuffer.expect("a filtered measurement has its G-buffer");
        let motion = Motion::identity(rj.width, rj.height);
        let mut filter = m.pipeline.start(rj.width, rj.height);
        let (mut rays, mut occluded) = (0u64, 0u64);
        let mut spent = Time { cpu_s: 0.0, wall_s: 0.0 };
        let mut out = Vec::with_capacity(reported.len());
        for f in rendered {
            let frame = RenderJob { sampler: rj.sampler.with_frame(f).with_schedule(m.schedule), ..*rj };
            let (c0, w0) = (clock::thread_cpu_s(), clock::wall_s());
            let mut o = render::render_integrand(scene, &frame, m.integrand, progress);
            spent.cpu_s += clock::thread_cpu_s() - c0;
            spent.wall_s += clock::wall_s() - w0;
            rays += o.rays;
            occluded += o.occluded_rays;
            let (shown, filtered_reference) = filter.push_pair(&o.ao, against.reference, gbuf, &motion);
            if !reported.contains(&(f + 1)) {
                continue;
            }
            (o.ao, o.rays, o.occluded_rays) = (shown, rays, occluded);
            out.push(FrameImage {
                frame: f + 1,
                output: o,
                filtered_reference: Some(filtered_reference),
                time: Some(spent),
            });
        }
        out
    }

    fn frames(&self) -> u64 {
        self.0.frames_rendered().len() as u64
    }
}

/// The measurement's implementation.
pub fn of(m: &Measurement) -> Box<dyn Measure> {
    if m.is_single_frame() { Box::new(SingleFrame(*m)) } else { Box::new(Frames(*m)) }
}

/// What a plan's multi-frame measurements are guided by, made once before any job: per reference
/// (index), the scene's G-buffer at the job's size.
#[derive(Default)]
pub struct Guides {
    gbuffers: HashMap<usize, GBuffer>,
}

impl Guides {
    /// For every (reference `target`, measurement, width, height) of a plan, what its filter needs.
    pub fn new<'a>(
        needs: impl IntoIterator<Item = (usize, &'a Measurement, u32, u32)>,
        scene: impl Fn(usize) -> &'a Scene,
    ) -> Self {
        let mut g = Guides::default();
        for (t, m, w, h) in needs {
            if !m.is_single_frame() {
                g.gbuffers.entry(t).or_insert_with(|| render::gbuffer(scene(t), w, h));
            }
        }
        g
    }

    /// What a job of reference `target` is measured against.
    pub fn against<'a>(&'a self, target: usize, reference: &'a Image, coverage: &'a Image) -> Against<'a> {
        Against { reference, coverage, gbuffer: self.gbuffers.get(&target) }
    }
}
