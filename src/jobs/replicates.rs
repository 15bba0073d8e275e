//! The post-pass that splits each configuration's error into bias and noise from its replicates
//! (`metrics::replicates`), once every replicate of it is measured, and sets each record's
//! `bias_rmse`, `bias_se` and `noise_rmse` and its place's `floor`. It reads the images the run
//! kept (EXR under `images/`, bit-exact), so a resumed run, which re-reads them all, gets the same
//! numbers as an uninterrupted one. A configuration is everything of its job but the replicate and
//! seed; where any of its images is not on disk (`advise` keeps none) nothing is split (NaN).
//!
//! **The floor** of a place (scene, rays, size, integrand, pipeline, frame, camera, denoiser) is the
//! pipeline's bias measured this way on input that is unbiased in every pixel
//! (`SeedMode::unbiased_per_pixel`), so the bias is the filter's own, not a sampler's: of the
//! configurations measured there, the first by seed mode `shift` (the white Cranley–Patterson
//! shift, the textbook unbiased estimator), then `blue-noise`, then `stbn`, then a per-pixel
//! pseudo-random one; the independent schedule and sine-cosine before others. It replaces
//! RMSE(F(reference), reference), which is 0 for a filter (SVGF) whose weights stop on a
//! noise-free input although it is biased on the noisy frames it actually filters. No such
//! configuration measured, or one replicate: no floor.

use crate::error::Result;
use crate::image::Image;
use crate::metrics::{self, Split};
use crate::plan::{Job, Measurement};
use crate::results::JobResult;
use crate::sampling::{Distribution, Schedule, SeedMode, Sequence};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Everything of `job` but the replicate and seed.
fn configuration(job: &Job) -> String {
    Job { replicate: 0, seed: 0, ..job.clone() }.canonical()
}

/// Everything of `job` but the estimator (distribution, sequence, seed mode, schedule) and the
/// replicate: where a floor is.
fn place(job: &Job) -> String {
    let measurement = Measurement { schedule: Schedule::Independent, ..job.measurement };
    Job {
        replicate: 0,
        seed: 0,
        distribution: Distribution::SineCosine,
        sequence: Sequence::Random,
        seed_mode: SeedMode::Rotation,
        measurement,
        ..job.clone()
    }
    .canonical()
}

/// How much a configuration is preferred as a place's floor (less first); `None`: its input is
/// not unbiased per pixel.
fn floor_rank(job: &Job) -> Option<(u8, bool, bool)> {
    if !job.seed_mode.unbiased_per_pixel(job.sequence == Sequence::Random) {
        return None;
    }
    let mode = match job.seed_mode {
        SeedMode::Shift => 0,
        SeedMode::BlueNoise => 1,
        SeedMode::Stbn => 2,
        _ => 3,
    };
    Some((
        mode,
        job.measurement.schedule != Schedule::Independent,
        job.distribution != Distribution::SineCosine,
    ))
}

/// Splits every configuration of `records` (by plan position: `jobs[i]` made `records[i]`).
/// `against(i)` is record i's reference and coverage (those its RMSE was measured against);
/// `image(r)` reads a record's image (`None`: not kept).
pub fn split(
    records: &mut [JobResult],
    jobs: &[Job],
    against: &(dyn Fn(usize) -> (Image, Image) + Sync),
    image: &(dyn Fn(&JobResult) -> Result<Option<Image>> + Sync),
) -> Result<()> {
    let mut configs: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (i, job) in jobs.iter().enumerate() {
        configs.entry(configuration(job)).or_default().push(i);
    }
    // Each configuration reads its own images and splits them on its own: on the run's threads,
    // one configuration a task (experiments/realtime.toml's 1,650, all jobs resumed: the run
    // 65.7 -> 56.1 s on 2 cores, the same records). The first error in configuration order is
    // the one reported, as on one thread.
    let records_ro: &[JobResult] = records;
    let per_config: Vec<Result<Option<Split>>> = configs
        .values()
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(|members| {
            let mut images = Vec::with_capacity(members.len());
            for &i in members {
                match image(&records_ro[i])? {
                    Some(img) => images.push(img),
                    None => return Ok(None),
                }
            }
            let (reference, coverage) = against(members[0]);
            let refs: Vec<&Image> = images.iter().collect();
            Ok(metrics::split(&refs, &reference, &coverage))
        })
        .collect();
    let mut splits: Vec<Option<Split>> = vec![None; records.len()];
    for (members, s) in configs.values().zip(per_config) {
        let s = s?;
        for &i in members {
            splits[i] = s;
        }
    }
    for (r, s) in records.iter_mut().zip(&splits) {
        let s = s.unwrap_or(Split { replicates: 0, bias2: f64::NAN, noise2: f64::NAN, bias2_se: f64::NAN });
        r.bias_rmse = s.bias_rmse();
        r.bias_se = s.bias_rmse_se();
        r.noise_rmse = s.noise_rmse();
    }
    floors(records, jobs);
    Ok(())
}

/// Sets every record's `floor` from the records' own `bias_rmse` (module doc): by `split`, and by
/// `merge`, whose shards each saw only their own configurations (a configuration's replicates are
/// in one shard, `plan::unit_key`, so its split is whole; a place's configurations may not be).
pub fn floors(records: &mut [JobResult], jobs: &[Job]) {
    // Per place, the preferred unbiased configuration's bias.
    let mut best: BTreeMap<String, ((u8, bool, bool), usize)> = BTreeMap::new();
    for (i, job) in jobs.iter().enumerate() {
        let Some(rank) = floor_rank(job).filter(|_| records[i].bias_rmse.is_finite()) else { continue };
        let e = best.entry(place(job)).or_insert((rank, i));
        if rank < e.0 {
            *e = (rank, i);
        }
    }
    for (i, job) in jobs.iter().enumerate() {
        records[i].floor = best.get(&place(job)).map(|&(_, k)| records[k].bias_rmse);
    }
}
