//! A real-time job (`Job::is_single_frame` false): the frames of a static camera the job measures,
//! rendered with `SamplerConfig::with_frame(f).with_schedule(s)` and accumulated by the
//! pipeline's temporal part; then its spatial part, guided by the scene's G-buffer, and the error
//! against the reference (what the user sees) and against the reference under the same spatial
//! filter (the noise part, `noise_rmse`), so a filter's bias and the sampler's noise stay apart.
//!
//! The time of such a job (`time_s` and the timing columns) is the CPU time of rendering every
//! frame it renders — all `frame` frames when the pipeline accumulates, the one last frame when it
//! does not — and accumulating them; the spatial filter is not timed (it costs the same for every
//! sampler, so it cannot change which sampler wins at equal time).

use crate::denoise::Pipeline;
use crate::image::Image;
use crate::metrics::{self, ErrorStats, MetricsError};
use crate::plan::Job;
use crate::render::{self, GBuffer, RenderJob, RenderOutput};
use crate::scene::Scene;

/// The frame indices (from 0) that job `job` renders.
pub fn frames_rendered(job: &Job) -> Vec<u32> {
    if job.pipeline.is_temporal() { (0..job.frame).collect() } else { vec![job.frame - 1] }
}

/// Renders the job's frames and accumulates them (`frames_rendered`); `ao` of the output is the
/// accumulated image (before the spatial part), `rays` counts every frame's AO rays.
pub fn render_frames(
    scene: &Scene,
    rj: &RenderJob,
    job: &Job,
    progress: &(dyn Fn(u64) + Sync),
) -> RenderOutput {
    let mut acc = job.pipeline.accumulator();
    let mut last: Option<RenderOutput> = None;
    let (mut rays, mut occluded) = (0u64, 0u64);
    for f in frames_rendered(job) {
        let frame = RenderJob { sampler: rj.sampler.with_frame(f).with_schedule(job.schedule), ..*rj };
        let out = render::render_integrand(scene, &frame, job.integrand, progress);
        rays += out.rays;
        occluded += out.occluded_rays;
        if let Some(a) = acc.as_mut() {
            a.push(&out.ao);
        }
        last = Some(out);
    }
    let mut out = last.expect("a job renders at least one frame");
    if let Some(a) = acc {
        out.ao = a.image();
    }
    out.rays = rays;
    out.occluded_rays = occluded;
    out
}

/// The spatial part of `pipeline` alone (no temporal part): what a converged reference goes through.
pub fn spatial_only(pipeline: Pipeline) -> Pipeline {
    Pipeline { temporal: None, ..pipeline }
}

/// The image after the spatial part, its error statistics against `reference`, and its noise RMSE
/// against `filtered_reference` (the reference under the same spatial filter; `None`: no spatial
/// part, the noise RMSE is the RMSE).
pub fn measure(
    accumulated: &Image,
    pipeline: Pipeline,
    gbuf: Option<&GBuffer>,
    reference: &Image,
    filtered_reference: Option<&Image>,
    coverage: &Image,
) -> Result<(Image, ErrorStats, f64), MetricsError> {
    let img = match (pipeline.spatial, gbuf) {
        (Some(_), Some(g)) => pipeline.apply_spatial(accumulated, g),
        _ => accumulated.clone(),
    };
    let stats = metrics::measure(&img, reference, coverage)?;
    let noise = match filtered_reference {
        Some(f) => metrics::measure(&img, f, coverage)?.rmse,
        None => stats.rmse,
    };
    Ok((img, stats, noise))
}
