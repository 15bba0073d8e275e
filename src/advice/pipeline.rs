//! `advise --pipeline P [--frames K]`: advice for the image a real-time renderer shows — K frames
//! accumulated by P's temporal part, then P's spatial filter — instead of one raw frame.
//! The sweep's jobs are real-time jobs measured at frame K alone; the analysis, the finalists and
//! the report read them as the images they rank (`as_ranked`), with the time of *one frame*, since a
//! real-time budget is a frame's: a configuration fits a budget of B ms when each of its frames
//! renders in B ms, and its error is that of the image after K such frames and the filter. The
//! stored records keep their real labels (pipeline, frame, the time of all K frames). After a
//! spatial filter the structure rule is not applied (see `as_ranked`).

use crate::denoise::Pipeline;
use crate::plan::Measurement;
use crate::results::{self, JobResult};

/// The records as the paper-table images advise ranks: pipeline `raw`, frame 1 (the schedule, the
/// camera and the denoiser kept: a ranking is per camera, of configurations under a schedule), every time (and the rays cast) divided by the frames rendered, the timing split and
/// efficiency recomputed from those per-frame times with the record's own overhead. Records that
/// are already single frames come back unchanged. A record whose pipeline, schedule or integrand
/// this version cannot read is refused (the message names it), never read as raw.
pub fn as_ranked(records: &[JobResult]) -> Result<Vec<JobResult>, String> {
    let mut out: Vec<JobResult> = records
        .iter()
        .map(|r| {
            let m: Measurement = r.measurement().ok_or_else(|| {
                format!(
                    "record {} names a pipeline '{}', schedule '{}', integrand '{}', camera '{}' or denoiser '{}' \
                     this version or this advise does not know",
                    r.key, r.pipeline, r.schedule, r.integrand, r.camera, r.denoiser
                )
            })?;
            if m.is_single_frame() {
                return Ok(r.clone());
            }
            let p = m.pipeline;
            let k = m.frames_rendered().len() as f64;
            // A spatial filter makes every error low-frequency, white noise's too, so the
            // low-frequency ratio of a filtered image says nothing about the sampler: not measured
            // (advise's structure rule then holds nothing back; the report's crops show the image).
            let lowfreq_ratio = if p.spatial.is_some() { f64::NAN } else { r.lowfreq_ratio };
            Ok(JobResult {
                lowfreq_ratio,
                pipeline: Pipeline::RAW.to_string(),
                frame: 1,
                time_s: r.time_s / k,
                wall_s: r.wall_s / k,
                times: r.times.iter().map(|t| t / k).collect(),
                walls: r.walls.iter().map(|t| t / k).collect(),
                rays_cast: (r.rays_cast as f64 / k).round() as u64,
                ..r.clone()
            })
        })
        .collect::<Result<_, String>>()?;
    let overhead = |scene: &str| {
        records.iter().find(|r| r.scene == scene && r.overhead_s.is_finite()).map(|r| r.overhead_s)
    };
    if records.iter().any(|r| !r.is_single_frame()) {
        results::fill_timing(&mut out, &overhead);
    }
    Ok(out)
}

/// The ranked records (`as_ranked`) of the scene's still camera under the independent schedule, as
/// single frames (the denoiser's name dropped): what a budget in ms ranks at equal time
/// (`compare::budget`), as it ranks the paper's single frames. The other cameras and the `r1`
/// schedule are answered per ray budget (`compare::per_ray`).
pub fn still_independent(ranked: &[JobResult]) -> Vec<JobResult> {
    ranked
        .iter()
        .filter(|r| {
            r.camera == crate::plan::CameraId::STATIC_NAME
                && r.schedule == crate::sampling::Schedule::Independent.name()
        })
        .map(|r| JobResult { denoiser: String::new(), ..r.clone() })
        .collect()
}
