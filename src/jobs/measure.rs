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
//! Under `[tiles]` (`jobs::tiles`) each frame is rendered as the tiles' windows, each pushed through
//! a run of the pipeline of its own (with the whole image's iteration counts, `Pipeline::at_size`)
//! and the user's denoiser; the measured image is the mosaic of the windows' interiors, and the
//! references are the same mosaics, so every metric below reads it as it reads a whole frame.
//!
//! Beside the error, each reported frame's **flicker** (`metrics::flicker`): the RMS over pixels of
//! (o_t − o_{t−1}) − (r_t − r_{t−1}), the change the viewer sees that the converged image does not
//! make. For a pipeline that shows one frame, frame t − 1 is rendered too (untimed) for it.
//! A user's denoiser (`plan::Denoiser`) runs after the pipeline on each reported frame and the one
//! before it; its own wall-clock time is reported apart (`denoise_s`), never in the render's.
//!
//! A series of frames is rendered once, to its last reported frame, and each reported frame's
//! image is taken on the way (`plan::series`); SVGF runs of a series that differ only in their
//! number of passes (`svgf`, `svgf:5`) share one state per part (`Svgf::push_passes`, `SvgfGroup`).
//! The time of a reported frame's record (`time_s` and the timing columns) is the CPU time of
//! rendering the frames up to it; each frame's primary hits are its G-buffer's, and the time of
//! tracing them, measured once per frame and window on one thread (`jobs::guides`), is added to
//! each render of it. The filters are not timed (they cost the same for every sampler, so they
//! cannot change which sampler wins at equal time). A single frame's time is that of its whole render. A single
//! frame rendered by `Frames` would be the same image bit for bit: `SingleFrame` exists so that
//! the paper's path stays one render, with nothing of the frames' machinery around it.

use super::guides::{Against, Traced};
use crate::denoise::{Motion, Pipeline, Svgf, SvgfOptions, SvgfParams, Temporal, default_iterations};
use crate::error::{Error, Result};
use crate::image::Image;
use crate::metrics::{self, ErrorStats, MetricsError};
use crate::plan::Measurement;
use crate::render::{self, GBuffer, Primaries, RenderJob, RenderOutput, View, Window};
use crate::scene::Scene;
use crate::timing::{Time, clock};
use std::borrow::Cow;

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
    let map = super::flip_refs::flip_map(reference, &image.output.ao, ppd);
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
        against: &Against,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<FrameImage>> {
        let output = match against.tiles {
            None => render::render_integrand(scene, rj, self.0.integrand, progress),
            // Each tile's window (as a frame of a pipeline renders it), measured on its interior.
            Some(t) => {
                let o: Vec<RenderOutput> = t
                    .windows
                    .iter()
                    .map(|w| render::render_window(scene, rj, self.0.integrand, &View::SCENE, w, progress))
                    .collect();
                RenderOutput {
                    ao: t.mosaic_of_windows(&o.iter().map(|o| o.ao.clone()).collect::<Vec<_>>(), 1.0),
                    coverage: t
                        .mosaic_of_windows(&o.iter().map(|o| o.coverage.clone()).collect::<Vec<_>>(), 0.0),
                    rays: o.iter().map(|o| o.rays).sum(),
                    occluded_rays: o.iter().map(|o| o.occluded_rays).sum(),
                }
            }
        };
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

/// One frame's guides: its view, and per part (`Against::parts`) its G-buffer, primary hits and
/// their time, and motion from the frame before.
struct FrameGuide<'a> {
    view: View,
    gbuffers: Vec<&'a GBuffer>,
    primaries: Vec<(&'a Primaries, Time)>,
    motions: Vec<Cow<'a, Motion>>,
}

/// Per part, its G-buffer and its primary hits and their time.
fn kept(traced: &[Traced]) -> (Vec<&GBuffer>, Vec<(&Primaries, Time)>) {
    traced.iter().map(|t| (&t.frame.gbuffer, (&t.frame.primaries, t.primary))).unzip()
}

impl Frames {
    fn guide<'a>(&self, against: &'a Against, f: u32, parts: &[Window]) -> FrameGuide<'a> {
        match against.camera {
            Some(c) => {
                let (gbuffers, primaries) = kept(&c.gbuffers[f as usize]);
                FrameGuide {
                    view: c.views[f as usize],
                    gbuffers,
                    primaries,
                    motions: c.motions[f as usize].iter().map(Cow::Borrowed).collect(),
                }
            }
            None => {
                let (gbuffers, primaries) =
                    kept(against.gbuffer.expect("a filtered measurement has its G-buffer"));
                FrameGuide {
                    view: View::SCENE,
                    gbuffers,
                    primaries,
                    motions: parts.iter().map(|w| Cow::Owned(Motion::identity(w.width, w.height))).collect(),
                }
            }
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

/// One pipeline's run over a series' frames: a run of its filter per part.
struct Shown {
    pipeline: Pipeline,
    filters: Vec<Box<dyn crate::denoise::FrameFilter>>,
    /// Its reported frames (from 1) and the frames whose image is kept (those and the one before each).
    reported: Vec<u32>,
    kept: Vec<u32>,
    previous: Option<(u32, Image)>,
    /// The `SvgfGroup` whose states it reads its images from (an SVGF run), instead of `filters`.
    svgf: Option<usize>,
}

/// The SVGF runs of a series that differ only in their number of passes (`svgf`, `svgf:5`): one
/// state per part for all (`Svgf::push_passes`, the same images bit for bit).
struct SvgfGroup {
    options: SvgfOptions,
    /// One per part.
    states: Vec<Svgf>,
    /// (run, its passes).
    members: Vec<(usize, u32)>,
}

/// A run of `pipeline` over the frames of `part` of a `width` × `height` image, with the whole
/// image's default iteration counts (`Pipeline::at_size`; the pipeline itself for the whole image).
fn start(pipeline: Pipeline, width: u32, height: u32, part: &Window) -> Box<dyn crate::denoise::FrameFilter> {
    pipeline.at_size(width, height).start(part.width, part.height)
}

/// The measured image of the parts' images (each its window's size): the mosaic of the tiles'
/// interiors (`jobs::tiles`), or the whole frame itself.
fn measured(against: &Against, mut parts: Vec<Image>, fill: f32) -> Image {
    match against.tiles {
        Some(t) => t.mosaic_of_windows(&parts, fill),
        None => parts.pop().expect("one part: the whole frame"),
    }
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
        let parts = against.parts(rj.width, rj.height);
        let mut runs: Vec<Shown> = Vec::new();
        for &(p, f) in reported {
            match runs.iter_mut().find(|r| r.pipeline == p) {
                Some(r) => r.reported.push(f),
                None => runs.push(Shown {
                    pipeline: p,
                    filters: parts.iter().map(|w| start(p, rj.width, rj.height, w)).collect(),
                    reported: vec![f],
                    kept: Vec::new(),
                    previous: None,
                    svgf: None,
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
        let mut groups: Vec<SvgfGroup> = Vec::new();
        for (i, r) in runs.iter_mut().enumerate() {
            let Some(Temporal::Svgf(o)) = r.pipeline.temporal else { continue };
            // The whole image's pass count on every part (`Pipeline::at_size`).
            let passes = o.iterations.unwrap_or_else(|| default_iterations(rj.width, rj.height));
            let options = SvgfOptions { iterations: None, ..o };
            let g = match groups.iter().position(|g| g.options == options) {
                Some(g) => g,
                None => {
                    let states = parts.iter().map(|_| Svgf::new(SvgfParams::of(options))).collect();
                    groups.push(SvgfGroup { options, states, members: Vec::new() });
                    groups.len() - 1
                }
            };
            groups[g].members.push((i, passes));
            r.svgf = Some(g);
        }
        // A steady-state series starts at its first frame (`Measurement::first_frame`).
        let first = m.first_frame.clamp(1, last) - 1;
        let rendered: Vec<u32> =
            if temporal { (first..last).collect() } else { runs[0].kept.iter().map(|f| f - 1).collect() };
        let (mut rays, mut occluded) = (0u64, 0u64);
        let mut spent = Time { cpu_s: 0.0, wall_s: 0.0 };
        let mut out = Vec::with_capacity(reported.len());
        for f in rendered {
            let g = self.guide(against, f, &parts);
            let frame = RenderJob { sampler: rj.sampler.with_frame(f).with_schedule(m.schedule), ..*rj };
            let timed = temporal || runs[0].reported.contains(&(f + 1));
            let (c0, w0) = (clock::thread_cpu_s(), clock::wall_s());
            let o: Vec<RenderOutput> = parts
                .iter()
                .zip(&g.primaries)
                .map(|(w, p)| {
                    render::render_window_from(scene, &frame, m.integrand, &g.view, w, Some(p.0), progress)
                })
                .collect();
            if timed {
                // The primary rays' time, measured when they were traced (`jobs::guides`).
                let primary =
                    g.primaries.iter().fold((0.0, 0.0), |(c, w), p| (c + p.1.cpu_s, w + p.1.wall_s));
                spent.cpu_s += clock::thread_cpu_s() - c0 + primary.0;
                spent.wall_s += clock::wall_s() - w0 + primary.1;
                rays += o.iter().map(|o| o.rays).sum::<u64>();
                occluded += o.iter().map(|o| o.occluded_rays).sum::<u64>();
            }
            if against.timing_only {
                // Only the time is wanted: the filters (untimed) and the images are left out.
                for run in &runs {
                    if run.reported.contains(&(f + 1)) {
                        let empty = Image::from_vec(0, 0, Vec::new());
                        out.push(FrameImage {
                            pipeline: run.pipeline,
                            frame: f + 1,
                            output: RenderOutput {
                                ao: empty.clone(),
                                coverage: empty,
                                rays,
                                occluded_rays: occluded,
                            },
                            flicker: f64::NAN,
                            denoise_s: 0.0,
                            time: Some(spent),
                        });
                    }
                }
                continue;
            }
            // Each SVGF group's kept runs' images per part; the group advances if none is kept.
            let mut shared: Vec<Option<Vec<Image>>> = vec![None; runs.len()];
            for group in &mut groups {
                let kept: Vec<(usize, u32)> =
                    group.members.iter().copied().filter(|&(i, _)| runs[i].kept.contains(&(f + 1))).collect();
                if kept.is_empty() {
                    for (k, state) in group.states.iter_mut().enumerate() {
                        state.advance(&o[k].ao, None, g.gbuffers[k], &g.motions[k]);
                    }
                    continue;
                }
                let passes: Vec<u32> = kept.iter().map(|k| k.1).collect();
                let mut images: Vec<Vec<Image>> = vec![Vec::with_capacity(parts.len()); kept.len()];
                for (k, state) in group.states.iter_mut().enumerate() {
                    let part = state.push_passes(&o[k].ao, g.gbuffers[k], &g.motions[k], &passes);
                    for (run, img) in images.iter_mut().zip(part) {
                        run.push(img);
                    }
                }
                for ((i, _), imgs) in kept.into_iter().zip(images) {
                    shared[i] = Some(imgs);
                }
            }
            for (i, run) in runs.iter_mut().enumerate() {
                if run.svgf.is_some() && shared[i].is_none() {
                    continue;
                }
                if run.svgf.is_none() && temporal && !run.kept.contains(&(f + 1)) {
                    for (k, filter) in run.filters.iter_mut().enumerate() {
                        filter.advance(&o[k].ao, None, g.gbuffers[k], &g.motions[k]);
                    }
                    continue;
                }
                let shown: Vec<Image> = match shared[i].take() {
                    Some(imgs) => imgs,
                    None => (0..parts.len())
                        .map(|k| {
                            if temporal {
                                run.filters[k].push(&o[k].ao, g.gbuffers[k], &g.motions[k])
                            } else {
                                // Nothing carries over between the frames of a pipeline that shows one:
                                // each is filtered by a run of its own.
                                start(run.pipeline, rj.width, rj.height, &parts[k]).push(
                                    &o[k].ao,
                                    g.gbuffers[k],
                                    &g.motions[k],
                                )
                            }
                        })
                        .collect(),
                };
                if !run.kept.contains(&(f + 1)) {
                    continue;
                }
                let mut denoise_s = 0.0;
                let mut done = Vec::with_capacity(shown.len());
                for (k, img) in shown.into_iter().enumerate() {
                    let (img, s) = self.denoise(against, img, g.gbuffers[k])?;
                    denoise_s += s;
                    done.push(img);
                }
                let shown = measured(against, done, 1.0);
                if run.reported.contains(&(f + 1)) {
                    let flicker = match &run.previous {
                        Some((p, prev)) if *p == f => flicker(against, f + 1, prev, &shown),
                        _ => f64::NAN,
                    };
                    let coverage = measured(against, o.iter().map(|o| o.coverage.clone()).collect(), 0.0);
                    let output = RenderOutput { ao: shown.clone(), coverage, rays, occluded_rays: occluded };
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
