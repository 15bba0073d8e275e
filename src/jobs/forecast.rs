//! What `advise` and `render` are about to cost on this machine, said before they start
//! (`plan::forecast`): `calibrate`'s fraction of a second of real renders, then the plan's renders
//! through the timing protocol (`plan::cost`), the references that must be built and the bytes
//! written. `plan` prints the same numbers for a spec.

use super::calibrate::{self, Calibrated};
use crate::error::{Error, Result};
use crate::load::Loaded;
use crate::plan::forecast::Forecast;
use crate::plan::{Geometry, Job, Plan, cost};
use crate::render::{self, RenderJob};
use crate::sampling::Integrand;
use crate::scene::Scene;
use crate::timing;
use std::path::Path;

/// Finalists advise renders again per budget, at most: the six best by the interpolation, the best
/// two unstructured, the best by low-pass RMSE and the paper's default (`advice::answer`) …
pub const FINALIST_ROWS: usize = 10;
/// … each at about two ray counts (the interpolated count rounded down, the sweep's below it; the
/// multiple of 32 below is often one of them).
pub const FINALIST_COUNTS: usize = 2;

/// What advise's finalists will be: per budget, `FINALIST_ROWS` × `FINALIST_COUNTS` configurations
/// of `replicates` renders, each of `frames` frames that fit the budget.
pub struct Finalists {
    pub replicates: u32,
    pub frames: u32,
    /// Given budgets (seconds per frame) …
    pub budgets_s: Vec<f64>,
    /// … and, when none are given, whether advise picks three (`advice::default_budgets`'s quarters
    /// of the paper default's range, taken here from its calibrated line) or answers per ray
    /// budget only (after a real-time pipeline: no finalists).
    pub default_budgets: bool,
    /// The sweep keeps its images (after a real-time pipeline), not only its records.
    pub sweep_images: bool,
}

/// advise's forecast: its reference (if it must be built), the sweep of `todo` (what `plan` still
/// needs, `left`), the finalists; and the calibration, for the cheapest-render check of budgets.
pub fn advise(
    loaded: &Loaded,
    plan: &Plan,
    todo: &Plan,
    reference_dir: &Path,
    finalists: &Finalists,
    workers: usize,
) -> Result<(Forecast, Calibrated)> {
    let builds = calibrate::builds(loaded, plan, reference_dir)?;
    let cal = calibrate::calibrate(loaded, plan, &calibrate::by_scene(loaded, &builds), workers)?;
    let sweep = cost::jobs(
        todo,
        |j| cal.frame_s(loaded, j),
        |j, frames, shown| cal.filter_s(loaded, j, frames, shown),
        |id| cal.overhead_s(loaded, id),
        &cal.model(loaded, workers),
    );
    let refs_s = calibrate::references_s(loaded, &cal, &builds, workers);
    // The paper's default is the sweep's first row; its line gives the default budgets' range.
    let first = plan.jobs.first().ok_or_else(|| Error::Refused("advise: the sweep has no job".into()))?;
    let at = |rays: u32| cal.render_s(loaded, &Job { rays, ..first.clone() });
    let budgets = if finalists.budgets_s.is_empty() && finalists.default_budgets {
        let rays = plan.jobs.iter().map(|j| j.rays);
        let (lo, hi) = (at(rays.clone().min().unwrap_or(1)).ln(), at(rays.max().unwrap_or(1)).ln());
        [0.25, 0.5, 0.75].map(|q| (lo + q * (hi - lo)).exp()).to_vec()
    } else {
        finalists.budgets_s.clone()
    };
    let per_budget = (FINALIST_ROWS.min(rows(plan)) * FINALIST_COUNTS) as f64 * finalists.replicates as f64;
    let final_cpu: f64 = budgets.iter().map(|b| per_budget * b * finalists.frames as f64).sum();
    let final_jobs = (per_budget * budgets.len() as f64).round() as usize;
    let final_wall = final_cpu / workers.max(1) as f64 * cal.contention;
    let geometry = Geometry::of(loaded.spec.resolution, loaded.spec.ao_distance, &loaded.scenes[0]);
    // Under `[tiles]` a job writes the mosaic of its tiles' interiors (`jobs::tiles`).
    let pixels = super::tiles::of_spec(&loaded.spec, 0, &loaded.scenes[0])
        .map_or(geometry.pixels(), |t| t.mosaic_pixels()) as f64;
    // The sweep keeps numbers only; the finalists' images are kept (the winner maps read them).
    let per_pixel = plan.jobs.first().map_or(cal.post.exr_bytes_per_pixel, |j| cal.bytes_per_pixel(j));
    // The sweep keeps its images under a pipeline (the split reads them): mosaic pixels under tiles.
    let bytes = cost::output_bytes(
        todo,
        |_| pixels as u64,
        |j| cal.bytes_per_pixel(j),
        cal.post.record_bytes,
        finalists.sweep_images,
    ) + final_jobs as f64 * (pixels * per_pixel + cal.post.record_bytes)
        + builds.iter().map(|b| b.manifest.image_size().map(f64::from).iter().product::<f64>()).sum::<f64>()
            * cal.post.exr_bytes_per_pixel
            * 1.5;
    let forecast = Forecast {
        references: Some(builds.len()),
        jobs: todo.jobs.len() + final_jobs,
        detail: format!(
            "a sweep of {}{}{}",
            todo.jobs.len(),
            if todo.jobs.len() < plan.jobs.len() {
                format!(
                    " ({} of {} kept from an earlier run)",
                    plan.jobs.len() - todo.jobs.len(),
                    plan.jobs.len()
                )
            } else {
                String::new()
            },
            match budgets.len() {
                0 => ", answered per ray budget".to_string(),
                1 => format!(" and about {final_jobs} finalists' at 1 ms budget"),
                n => format!(" and about {final_jobs} finalists' at {n} ms budgets"),
            }
        ),
        cpu_s: sweep.render_cpu_s
            + sweep.overhead_cpu_s
            + final_cpu
            + refs_s / cal.contention * workers as f64,
        wall_s: sweep.wall_s + final_wall + refs_s,
        threads: workers,
        bytes,
    };
    Ok((forecast, cal))
}

/// The jobs of `plan` no earlier record holds (same configuration, rays, replicate, seed,
/// pipeline and frame): what a resumed command still renders. An estimate: the resume rule itself
/// (`executor::resumed`) needs the reference, which may be what is about to be built.
pub fn left<'a>(plan: &Plan, previous: impl Iterator<Item = &'a crate::results::JobResult>) -> Plan {
    let key =
        |d: &str, s: &str, m: &str, rays: u32, rep: u32, seed: u64, frame: u32, p: &str, view: String| {
            format!("{d}/{s}/{m}/{rays}/{rep}/{seed}/{frame}/{p}/{view}")
        };
    let done: std::collections::HashSet<String> = previous
        .map(|r| {
            let view = format!("{}/{}/{}", r.schedule, r.camera, r.denoiser);
            key(
                &r.distribution,
                &r.sequence,
                &r.seed_mode,
                r.rays,
                r.replicate,
                r.seed,
                r.frame,
                &r.pipeline,
                view,
            )
        })
        .collect();
    let todo = |j: &Job| {
        let row = j.row().canonical();
        let k = key(
            row.distribution.name(),
            row.sequence.name(),
            row.seed_mode.name(),
            j.rays,
            j.replicate,
            j.seed,
            j.measurement.frame,
            &j.measurement.pipeline.to_string(),
            format!(
                "{}/{}/{}",
                j.measurement.schedule.name(),
                j.measurement.camera.name(),
                j.measurement.denoiser.name()
            ),
        );
        !done.contains(&k)
    };
    Plan { jobs: plan.jobs.iter().filter(|j| todo(j)).cloned().collect() }
}

/// Configurations in the plan.
fn rows(plan: &Plan) -> usize {
    let mut r: Vec<_> = plan.jobs.iter().map(|j| j.row().canonical()).collect();
    r.sort_by_key(|r| r.label());
    r.dedup();
    r.len()
}

/// Rays per pixel of the probe beside the 1-ray one, about: enough to dwarf the per-image cost.
const PROBE_RAYS: u64 = 250_000;

/// `render`'s forecast: `job` on `threads` threads, from a 1-ray and a few-ray render of it at the
/// calibration size (`cost::calibration_size`, the same aspect), each the median of three, the
/// line through them scaled to the image's pixels and rays; bytes: its EXR as one probe encoded,
/// and the PNG preview (3 bytes per pixel at most). The sampler's tables must be made first
/// (`SamplerConfig::prepare`), as the render's clock does not count them either.
pub fn render(scene: &Scene, job: &RenderJob, integrand: Integrand, threads: usize) -> Result<Forecast> {
    let (w, h, ratio) = cost::calibration_size(job.width, job.height);
    let probe_rays = (PROBE_RAYS / (w as u64 * h as u64).max(1)).clamp(2, 64) as u32;
    let probe_rays = probe_rays.min(job.sampler.count.max(2));
    let worker = timing::workers(1).map_err(Error::Refused)?.remove(0);
    let at = |rays: u32| -> Result<(f64, u64, Vec<u8>)> {
        let sampler = crate::sampling::SamplerConfig { count: rays, ..job.sampler };
        let probe = RenderJob { width: w, height: h, sampler, ..*job };
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..3 {
            let (out, t) = worker.timed(|| render::render_integrand(scene, &probe, integrand, &|_| {}));
            times.push(t.cpu_s);
            last = Some(out);
        }
        let out = last.expect("three probes");
        let exr = crate::image::encode_exr(&[
            crate::image::Channel { name: "Y", image: &out.ao },
            crate::image::Channel { name: "A", image: &out.coverage },
        ])
        .unwrap_or_default();
        Ok((crate::stats::median(&times), out.rays, exr))
    };
    let (t1, r1, _) = at(1)?;
    let (tk, rk, exr) = at(probe_rays)?;
    let per_ray = if rk > r1 { ((tk - t1) / (rk - r1) as f64).max(0.0) } else { 0.0 };
    let per_image = (t1 - per_ray * r1 as f64).max(0.0) * ratio;
    let covered_per_ray = r1 as f64 * ratio;
    let cpu_s = per_image + per_ray * covered_per_ray * job.sampler.count as f64;
    let pixels = job.width as f64 * job.height as f64;
    let bytes_per_pixel = exr.len() as f64 / (w as f64 * h as f64).max(1.0);
    Ok(Forecast {
        references: None,
        jobs: 1,
        detail: String::new(),
        cpu_s,
        wall_s: cpu_s / threads.max(1) as f64,
        threads,
        bytes: pixels * (bytes_per_pixel + 3.0),
    })
}
