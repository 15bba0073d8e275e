//! Turning a planned job into an image on all threads (the references; `executor` renders the
//! measured jobs): its geometry on its scene, the sampler, the thread pool.

use crate::error::{Error, Result};
use crate::plan::{Geometry, Job};
use crate::progress;
use crate::render::{self, RenderJob, RenderOutput};
use crate::sampling::SamplerConfig;
use crate::scene::Scene;
use indicatif::ProgressBar;

pub struct Rendered {
    pub output: RenderOutput,
}

/// Renders jobs on one thread pool and advances one progress bar counted in rays
/// (an upper bound: background pixels cast none, so the bar is topped up after each job).
pub struct JobRunner {
    pool: rayon::ThreadPool,
    pub bar: ProgressBar,
}

impl JobRunner {
    /// On a pool of `threads.pool_threads`.
    pub fn new(threads: super::Threads, quiet: bool) -> Result<Self> {
        Ok(Self { pool: threads.pool()?, bar: progress::bar(0, "", quiet) })
    }

    /// `job` with `counts[i]` rays in pixel i instead of `job.rays` (adaptive references), as a
    /// pass of its own: the bar goes from 0 to 100 % by the rays cast.
    pub fn render_counts(&self, job: &Job, scene: &Scene, counts: &[u32], label: &str) -> Result<Rendered> {
        let rj = render_job(job, scene, job.rays)?;
        self.start_pass(counts.iter().map(|&n| n as u64).sum(), label);
        let output = self.pool.install(|| {
            crate::render::adaptive::render_counts_of(scene, &rj, job.measurement.integrand, counts, &|n| {
                self.bar.inc(n)
            })
        });
        Ok(Rendered { output })
    }

    /// `render` as a pass of its own (a reference's replicate or pilot): the bar shows this render
    /// alone, from 0 to 100 %, so a long reference shows its progress and not a full bar.
    pub fn render_pass(&self, job: &Job, scene: &Scene, label: &str) -> Result<Rendered> {
        let g = Geometry::of(job.resolution, job.ao_distance, scene);
        self.start_pass(g.pixels() * job.rays as u64, label);
        self.render(job, scene, label)
    }

    /// `render_pass` from another view (a camera path's frame, a jitter offset), its sampler at
    /// frame `frame` (fresh numbers for each of a reference's views), of `window` of the image
    /// alone if given (a tile's reference, `render::render_window`).
    pub fn render_view_pass(
        &self,
        job: &Job,
        scene: &Scene,
        view: &render::View,
        window: Option<render::Window>,
        frame: u32,
        label: &str,
    ) -> Result<Rendered> {
        let g = Geometry::of(job.resolution, job.ao_distance, scene);
        let window = window.unwrap_or(render::Window::full(g.width, g.height));
        self.start_pass(window.pixels() * job.rays as u64, label);
        let mut rj = render_job(job, scene, job.rays)?;
        rj.sampler = rj.sampler.with_frame(frame);
        let rays = job.rays as u64;
        let integrand = job.measurement.integrand;
        let output = self.pool.install(|| {
            render::render_window(scene, &rj, integrand, view, &window, &|px| self.bar.inc(px * rays))
        });
        Ok(Rendered { output })
    }

    fn start_pass(&self, length: u64, label: &str) {
        self.bar.reset();
        self.bar.set_length(length);
        self.bar.set_message(label.to_string());
    }

    /// `job`, advancing the bar by its rays (the caller sets the bar's length for a series).
    pub fn render(&self, job: &Job, scene: &Scene, label: &str) -> Result<Rendered> {
        let g = Geometry::of(job.resolution, job.ao_distance, scene);
        let rj = render_job(job, scene, job.rays)?;
        self.bar.set_message(label.to_string());
        let before = self.bar.position();
        let rays = job.rays as u64;
        let output = self.pool.install(|| {
            render::render_integrand(scene, &rj, job.measurement.integrand, &|px| self.bar.inc(px * rays))
        });
        self.bar.set_position(before + g.pixels() * rays);
        Ok(Rendered { output })
    }
}

/// What the renderer needs to know of a planned job, with `rays` AO rays per pixel (the job's own,
/// or fewer for warm-up and overhead renders).
pub fn render_job(job: &Job, scene: &Scene, rays: u32) -> Result<RenderJob> {
    let g = Geometry::of(job.resolution, job.ao_distance, scene);
    let sampler = SamplerConfig::new(job.sequence, job.seed_mode, rays, job.seed)
        .map_err(|e| Error::Refused(format!("job {}: {e}", job.file_stem())))?;
    Ok(RenderJob {
        distribution: job.distribution,
        sampler,
        width: g.width,
        height: g.height,
        ao_distance: g.distance.as_f32(),
    })
}
