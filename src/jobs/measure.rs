//! How a job's renders become the measured image and its errors, for every kind of measurement
//! (`plan::Measurement`), behind one small interface so that the executor never asks which kind
//! a job is:
//!
//! - `SingleFrame`: one raw frame of the job's integrand, measured against the reference (the
//!   paper's tables).
//! - `Frames`: the frames of a static camera, rendered with `SamplerConfig::with_frame(f)
//!   .with_schedule(s)` and accumulated by the pipeline's temporal part; then its spatial part,
//!   guided by the scene's G-buffer; the error against the reference (what the user sees). How
//!   much of it is bias and how much noise is measured once every replicate of the configuration
//!   is (`jobs::replicates`), from the images kept.
//!
//! A moving or jittered camera (`plan::CameraId`) renders frame f from its path's view, filtered
//! through the motion from frame f − 1 (`jobs::guides::CameraFrames`); its error is against the
//! reference of that frame.
//!
//! Beside the error, each reported frame's **flicker** (`metrics::flicker`): the RMS over pixels of
//! (o_t − o_{t−1}) − (r_t − r_{t−1}), the change the viewer sees that the converged image does not
//! make. For a pipeline that shows one frame, frame t − 1 is rendered too (untimed) for it.
//! A user's denoiser (`plan::Denoiser`) runs after the pipeline on each reported frame and the one
//! before it; its own wall-clock time is reported apart (`denoise_s`), never in the render's.
//!
//! A series of frames is rendered once, to its last reported frame, and each reported frame's
//! image is taken on the way (`plan::series`). The time of a reported frame's record (`time_s`
//! and the timing columns) is the CPU time of rendering the frames up to it and accumulating
//! them; the spatial filter is not timed (it costs the same for every sampler, so it cannot change
//! which sampler wins at equal time). A single frame's time is that of its whole render. A single
//! frame rendered by `Frames` would be the same image bit for bit: `SingleFrame` exists so that
//! the paper's path stays one render, with nothing of the frames' machinery around it.

use super::guides::Against;
use crate::denoise::Pipeline;
use crate::error::{Error, Result};
use crate::image::Image;
use crate::metrics::{self, ErrorStats, MetricsError};
use crate::plan::Measurement;
use crate::render::{self, GBuffer, RenderJob, RenderOutput, View};
use crate::scene::Scene;
use crate::timing::{Time, clock};

/// The image of one reported frame: after the whole pipeline, with the rays of every frame so
/// far, its flicker, and the render time of those frames (`None`: the caller's time of the whole
/// render).
pub struct FrameImage {
    /// The pipeline it went through.
    pub pipeline: Pipeline,
    /// The frame, counted from 1.
    pub frame: u32,
    pub output: RenderOutput,
    /// `metrics::flicker` against the frame before (NaN for frame 1 and single frames).
    pub flicker: f64,
    /// The user's denoiser's wall-clock time on this frame's image, seconds (0 without one).
    pub denoise_s: f64,
    pub time: Option<Time>,
}

/// One kind of measurement.
pub trait Measure: Sync {
    /// Renders what the job renders (timed by the caller as a whole) and returns the image of each
    /// of `reported` (pipeline, frame from 1): every pipeline that accumulates reads the same
    /// rendered frames (a series, `plan::series`); a single frame reports `[(raw, 1)]`. Fails only
    /// where a user's denoiser command does.
    fn render(
        &self,
        scene: &Scene,
        rj: &RenderJob,
        reported: &[(Pipeline, u32)],
        against: &Against,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<FrameImage>>;

    /// How many frames a render to the job's own frame renders (for progress and cost).
    fn frames(&self) -> u64;
}

/// A reported frame's error statistics against its reference.
pub fn errors(image: &FrameImage, against: &Against) -> Result<ErrorStats, MetricsError> {
    let (reference, coverage) = against.at(image.frame);
    metrics::measure(&image.output.ao, reference, coverage)
}

/// A reported frame's mean LDR-FLIP against its reference over covered pixels
/// (`metrics::flip`), at `ppd` pixels per degree (`Spec::flip_ppd`). Sizes are those `errors` has
/// checked.
pub fn flip(image: &FrameImage, against: &Against, ppd: f64) -> f64 {
    let (reference, coverage) = against.at(image.frame);
    let map = metrics::flip::ldr_flip_map(reference, &image.output.ao, ppd);
    metrics::flip::mean_flip(&map, coverage)
}

/// One raw frame.
pub struct SingleFrame(pub Measurement);

impl Measure for SingleFrame {
    fn render(
        &self,
        scene: &Scene,
        rj: &RenderJob,
        _reported: &[(Pipeline, u32)],
        _against: &Against,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<FrameImage>> {
        let output = render::render_integrand(scene, rj, self.0.integrand, progress);
        Ok(vec![FrameImage {
            pipeline: Pipeline::RAW,
            frame: 1,
            output,
            flicker: f64::NAN,
            denoise_s: 0.0,
            time: None,
        }])
    }

    fn frames(&self) -> u64 {
        1
    }
}

/// Frames pushed through a pipeline (`denoise::Pipeline::start`): every frame the pipeline shows
/// is filtered in order, since its history is its own output.
pub struct Frames(pub Measurement);

/// One frame's guides: its view, G-buffer and motion from the frame before.
struct FrameGuide<'a> {
    view: View,
    gbuffer: &'a GBuffer,
    motion: std::borrow::Cow<'a, crate::denoise::Motion>,
}

impl Frames {
    fn guide<'a>(&self, against: &'a Against, f: u32, width: u32, height: u32) -> FrameGuide<'a> {
        match against.camera {
            Some(c) => FrameGuide {
                view: c.views[f as usize],
                gbuffer: &c.gbuffers[f as usize].gbuffer,
                motion: std::borrow::Cow::Borrowed(&c.motions[f as usize]),
            },
            None => FrameGuide {
                view: View::SCENE,
                gbuffer: against.gbuffer.expect("a filtered measurement has its G-buffer"),
                motion: std::borrow::Cow::Owned(crate::denoise::Motion::identity(width, height)),
            },
        }
    }

    /// Frames (from 1) whose shown image is kept: the reported ones and the frame before each.
    fn kept(reported: &[u32]) -> Vec<u32> {
        let mut k: Vec<u32> =
            reported.iter().flat_map(|&r| [r, r.saturating_sub(1)]).filter(|&f| f > 0).collect();
        k.sort_unstable();
        k.dedup();
        k
    }

    /// The user's denoiser on `shown` (if the measurement has one): the image and its seconds.
    fn denoise(&self, against: &Against, shown: Image, gbuf: &GBuffer) -> Result<(Image, f64)> {
        let Some(d) = self.0.denoiser.get() else { return Ok((shown, 0.0)) };
        let dir = against
            .scratch
            .as_deref()
            .ok_or_else(|| Error::Refused(format!("denoiser '{}': no directory to run it in", d.name)))?;
        let (img, took) = d.command.run(dir, &shown, gbuf)?;
        Ok((img, took.as_secs_f64()))
    }
}

/// One pipeline's run over a series' frames.
struct Shown {
    pipeline: Pipeline,
    filter: Box<dyn crate::denoise::FrameFilter>,
    /// Its reported frames (from 1) and the frames whose image is kept (those and the one before each).
    reported: Vec<u32>,
    kept: Vec<u32>,
    previous: Option<(u32, Image)>,
}

impl Measure for Frames {
    fn render(
        &self,
        scene: &Scene,
        rj: &RenderJob,
        reported: &[(Pipeline, u32)],
        against: &Against,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<FrameImage>> {
        let m = &self.0;
        let mut runs: Vec<Shown> = Vec::new();
        for &(p, f) in reported {
            match runs.iter_mut().find(|r| r.pipeline == p) {
                Some(r) => r.reported.push(f),
                None => runs.push(Shown {
                    pipeline: p,
                    filter: p.start(rj.width, rj.height),
                    reported: vec![f],
                    kept: Vec::new(),
                    previous: None,
                }),
            }
        }
        for r in &mut runs {
            r.reported.sort_unstable();
            r.kept = Self::kept(&r.reported);
        }
        let last = reported.iter().map(|r| r.1).max().unwrap_or(m.frame).max(1);
        // A pipeline that does not accumulate shows one frame: the frames kept alone are rendered
        // (the one before a reported frame for its flicker, untimed). Its series is itself.
        let temporal = m.pipeline.is_temporal();
        let rendered: Vec<u32> =
            if temporal { (0..last).collect() } else { runs[0].kept.iter().map(|f| f - 1).collect() };
        let (mut rays, mut occluded) = (0u64, 0u64);
        let mut spent = Time { cpu_s: 0.0, wall_s: 0.0 };
        let mut out = Vec::with_capacity(reported.len());
        for f in rendered {
            let g = self.guide(against, f, rj.width, rj.height);
            let frame = RenderJob { sampler: rj.sampler.with_frame(f).with_schedule(m.schedule), ..*rj };
            let timed = temporal || runs[0].reported.contains(&(f + 1));
            let (c0, w0) = (clock::thread_cpu_s(), clock::wall_s());
            let o = render::render_view(scene, &frame, m.integrand, &g.view, progress);
            if timed {
                spent.cpu_s += clock::thread_cpu_s() - c0;
                spent.wall_s += clock::wall_s() - w0;
                rays += o.rays;
                occluded += o.occluded_rays;
            }
            for run in &mut runs {
                if temporal && !run.kept.contains(&(f + 1)) {
                    run.filter.advance(&o.ao, None, g.gbuffer, &g.motion);
                    continue;
                }
                let shown = if temporal {
                    run.filter.push(&o.ao, g.gbuffer, &g.motion)
                } else {
                    // Nothing carries over between the frames of a pipeline that shows one: each
                    // is filtered by a run of its own.
                    run.pipeline.start(rj.width, rj.height).push(&o.ao, g.gbuffer, &g.motion)
                };
                if !run.kept.contains(&(f + 1)) {
                    continue;
                }
                let (shown, denoise_s) = self.denoise(against, shown, g.gbuffer)?;
                if run.reported.contains(&(f + 1)) {
                    let flicker = match &run.previous {
                        Some((p, prev)) if *p == f => flicker(against, f + 1, prev, &shown),
                        _ => f64::NAN,
                    };
                    let output = RenderOutput {
                        ao: shown.clone(),
                        coverage: o.coverage.clone(),
                        rays,
                        occluded_rays: occluded,
                    };
                    out.push(FrameImage {
                        pipeline: run.pipeline,
                        frame: f + 1,
                        output,
                        flicker,
                        denoise_s,
                        time: Some(spent),
                    });
                }
                run.previous = Some((f + 1, shown));
            }
        }
        Ok(out)
    }

    fn frames(&self) -> u64 {
        let m = &self.0;
        let extra = u64::from(!m.pipeline.is_temporal() && m.frame >= 2);
        m.frames_rendered().len() as u64 + extra
    }
}

/// The flicker of `shown` at `frame` (from 1) after `prev`, against the references of those
/// frames, over the pixels both references cover.
fn flicker(against: &Against, frame: u32, prev: &Image, shown: &Image) -> f64 {
    let (r, c) = against.at(frame);
    let (r_prev, c_prev) = against.at(frame - 1);
    let mask =
        Image::from_vec(c.width, c.height, c.data.iter().zip(&c_prev.data).map(|(a, b)| a.min(*b)).collect());
    metrics::flicker(prev, shown, r_prev, r, &mask).unwrap_or(f64::NAN)
}

/// The measurement's implementation.
pub fn of(m: &Measurement) -> Box<dyn Measure> {
    if m.is_single_frame() { Box::new(SingleFrame(*m)) } else { Box::new(Frames(*m)) }
}
