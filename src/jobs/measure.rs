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
//! The time of a job (`time_s` and the timing columns) is the CPU time of `render`: every frame it
//! renders (all `frame` frames when the pipeline accumulates, the one last frame when it does not)
//! and accumulating them; the spatial filter in `measure` is not timed (it costs the same for
//! every sampler, so it cannot change which sampler wins at equal time). A single frame rendered
//! by `Frames` would be the same image bit for bit: `SingleFrame` exists so that the paper's path
//! stays one render and one measurement, with nothing of the frames' machinery around it.

use crate::denoise::{Pipeline, Spatial};
use crate::image::Image;
use crate::metrics::{self, ErrorStats, MetricsError};
use crate::plan::Measurement;
use crate::render::{self, GBuffer, RenderJob, RenderOutput};
use crate::scene::Scene;
use std::collections::HashMap;

/// The reference images a measurement compares with, and the guide of its filters.
pub struct Against<'a> {
    pub reference: &'a Image,
    pub coverage: &'a Image,
    /// The scene's G-buffer at the job's size (`None` when no planned pipeline filters).
    pub gbuffer: Option<&'a GBuffer>,
    /// The reference under the measurement's spatial filter (`None`: no spatial part).
    pub filtered_reference: Option<&'a Image>,
}

/// The measured image, its error statistics and its noise RMSE (the RMSE against the equally
/// filtered reference; the RMSE itself without a filter).
pub type Measured = (RenderOutput, ErrorStats, f64);

/// One kind of measurement.
pub trait Measure: Sync {
    /// Renders what the job renders (timed by the caller): `ao` of the output is the image before
    /// any spatial filter, `rays` counts every frame's AO rays.
    fn render(&self, scene: &Scene, rj: &RenderJob, progress: &(dyn Fn(u64) + Sync)) -> RenderOutput;

    /// The image after the measurement's filters, and its errors.
    fn measure(&self, rendered: RenderOutput, against: &Against) -> Result<Measured, MetricsError>;

    /// How many frames `render` renders (for progress and cost).
    fn frames(&self) -> u64;
}

/// One raw frame.
pub struct SingleFrame(pub Measurement);

impl Measure for SingleFrame {
    fn render(&self, scene: &Scene, rj: &RenderJob, progress: &(dyn Fn(u64) + Sync)) -> RenderOutput {
        render::render_integrand(scene, rj, self.0.integrand, progress)
    }

    fn measure(&self, rendered: RenderOutput, against: &Against) -> Result<Measured, MetricsError> {
        let stats = metrics::measure(&rendered.ao, against.reference, against.coverage)?;
        let noise = stats.rmse;
        Ok((rendered, stats, noise))
    }

    fn frames(&self) -> u64 {
        1
    }
}

/// Frames accumulated and filtered by a pipeline.
pub struct Frames(pub Measurement);

impl Measure for Frames {
    fn render(&self, scene: &Scene, rj: &RenderJob, progress: &(dyn Fn(u64) + Sync)) -> RenderOutput {
        let m = &self.0;
        let mut acc = m.pipeline.accumulator();
        let mut last: Option<RenderOutput> = None;
        let (mut rays, mut occluded) = (0u64, 0u64);
        for f in m.frames_rendered() {
            let frame = RenderJob { sampler: rj.sampler.with_frame(f).with_schedule(m.schedule), ..*rj };
            let out = render::render_integrand(scene, &frame, m.integrand, progress);
            rays += out.rays;
            occluded += out.occluded_rays;
            if let Some(a) = acc.as_mut() {
                a.push(&out.ao);
            }
            last = Some(out);
        }
        let mut out = last.expect("a measurement renders at least one frame");
        if let Some(a) = acc {
            out.ao = a.image();
        }
        out.rays = rays;
        out.occluded_rays = occluded;
        out
    }

    fn measure(&self, rendered: RenderOutput, against: &Against) -> Result<Measured, MetricsError> {
        let pipeline = self.0.pipeline;
        let img = match (pipeline.spatial, against.gbuffer) {
            (Some(_), Some(g)) => pipeline.apply_spatial(&rendered.ao, g),
            _ => rendered.ao.clone(),
        };
        let stats = metrics::measure(&img, against.reference, against.coverage)?;
        let noise = match against.filtered_reference {
            Some(f) => metrics::measure(&img, f, against.coverage)?.rmse,
            None => stats.rmse,
        };
        Ok((RenderOutput { ao: img, ..rendered }, stats, noise))
    }

    fn frames(&self) -> u64 {
        self.0.frames_rendered().len() as u64
    }
}

/// The measurement's implementation.
pub fn of(m: &Measurement) -> Box<dyn Measure> {
    if m.is_single_frame() { Box::new(SingleFrame(*m)) } else { Box::new(Frames(*m)) }
}

/// The spatial part of `pipeline` alone (no temporal part): what a converged reference goes through.
pub fn spatial_only(pipeline: Pipeline) -> Pipeline {
    Pipeline { temporal: None, ..pipeline }
}

/// What a plan's filtered measurements are guided by and compared with, made once before any job:
/// per reference (index), the scene's G-buffer at the job's size, and the reference under each
/// spatial filter a planned pipeline applies.
#[derive(Default)]
pub struct Guides {
    gbuffers: HashMap<usize, GBuffer>,
    filtered: HashMap<(usize, Spatial), Image>,
}

impl Guides {
    /// For every (reference `target`, measurement, width, height) of a plan, what its filter needs.
    pub fn new<'a>(
        needs: impl IntoIterator<Item = (usize, &'a Measurement, u32, u32)>,
        scene: impl Fn(usize) -> &'a Scene,
        reference: impl Fn(usize) -> &'a Image,
    ) -> Self {
        let mut g = Guides::default();
        for (t, m, w, h) in needs {
            let Some(spatial) = m.pipeline.spatial else { continue };
            let gbuf = g.gbuffers.entry(t).or_insert_with(|| render::gbuffer(scene(t), w, h));
            let sp = spatial_only(m.pipeline);
            g.filtered.entry((t, spatial)).or_insert_with(|| sp.apply_spatial(reference(t), gbuf));
        }
        g
    }

    /// What a job of reference `target` under `m` is measured against.
    pub fn against<'a>(
        &'a self,
        target: usize,
        m: &Measurement,
        reference: &'a Image,
        coverage: &'a Image,
    ) -> Against<'a> {
        Against {
            reference,
            coverage,
            gbuffer: self.gbuffers.get(&target),
            filtered_reference: m.pipeline.spatial.and_then(|s| self.filtered.get(&(target, s))),
        }
    }
}
