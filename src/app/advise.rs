//! `hemilab advise SCENE.toml`: which configuration to ship for this scene at a time budget.
//!
//! The same stages as `run`, from an in-memory spec instead of a file (`advice::setup`): `plan` →
//! the scene's reference (`reference::store::obtain`, the same manifest rules) → the jobs under the
//! timing protocol (`jobs::executor`) → metrics → `advice` (equal-time ranking, paired gains, the
//! winner map) → advice.json, advice.md, index.html, figures. No image is written: each job's error
//! image stays in memory for the winner map. Nothing is written before every input has been
//! checked, and the outputs are written at the end, each atomically; advise does not resume (its
//! default run is about a minute).

use crate::cli::AdviseArgs;
use hemilab::advice::analysis::{self, Measured};
use hemilab::advice::setup::{Request, map_jobs, setup};
use hemilab::error::{Error, Result};
use hemilab::jobs::executor;
use hemilab::jobs::runner::{Geometry, JobRunner};
use hemilab::metrics;
use hemilab::plan::Job;
use hemilab::reference::store::{self as refs, Policy, Reference};
use hemilab::render::RenderOutput;
use hemilab::scene::Scene;
use hemilab::spec::Row;
use hemilab::timing::Protocol;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Mutex;

pub fn run(args: AdviseArgs) -> Result<()> {
    let setup = setup(&Request {
        scene: args.scene.clone(),
        rays: args.rays.clone(),
        only: args.only.clone(),
        replicates: args.replicates,
        resolution: args.resolution,
        reference_dir: args.reference_dir.clone(),
    })?;
    let out = args.out.clone().unwrap_or_else(|| Path::new("out").join(format!("advise-{}", setup.stem)));
    hemilab::outdir::prepare(&out, false)?;
    let runner = JobRunner::new(args.common.threads, args.common.quiet)?;
    let (spec, scene) = (&setup.loaded.spec, &setup.loaded.scenes[0]);
    let reference = refs::obtain(spec, 0, scene, &setup.reference_dir, Policy::ReuseOrBuild, &runner)?;
    let workers = match args.common.threads {
        Some(t) => t as usize,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let protocol = Protocol::new(spec.timing.repeats, spec.timing.seed, workers);

    let n = setup.plan.jobs.len();
    let errors: Mutex<Vec<Option<Vec<f32>>>> = Mutex::new(vec![None; n]);
    let keep = |i: usize, job: &Job, output: &RenderOutput| -> Result<String> {
        let e = error_of(job, output, &reference)?;
        errors.lock().map_err(|_| Error::Refused("a render worker failed".into()))?[i] = Some(e);
        Ok(String::new())
    };
    let none = HashMap::new();
    let (results, session) = executor::measure_jobs(
        &setup.loaded,
        &setup.plan,
        std::slice::from_ref(&reference),
        &none,
        &out,
        protocol,
        &runner.bar,
        &|_| Ok(()),
        &keep,
    )?;
    let errors = errors.into_inner().map_err(|_| Error::Refused("a render worker failed".into()))?;
    let errors = setup
        .plan
        .jobs
        .iter()
        .zip(errors)
        .filter_map(|(j, e)| Some(((j.row().canonical(), j.rays, j.replicate), e?)))
        .collect();
    let map_replicates = spec.replicates.max(analysis::MAP_REPLICATES);
    let mut measured =
        Measured { setup: &setup, reference: &reference, results, errors, map_replicates, session, protocol };
    let analysis = analysis::analyse(&measured, &args.budget_ms);
    let extra = map_jobs(spec, &analysis::map_needs(&analysis), map_replicates);
    render_extra(&extra, scene, &reference, &runner, &mut measured.errors)?;
    runner.bar.finish_and_clear();
    let summary = hemilab::report::advise::write(&measured, analysis, &out)?;
    print!("{summary}");
    Ok(())
}

/// image − reference on covered pixels.
fn error_of(job: &Job, output: &RenderOutput, reference: &Reference) -> Result<Vec<f32>> {
    metrics::error_image(&output.ao, &reference.mean, &reference.coverage)
        .map(|e| e.data)
        .map_err(|e| Error::Refused(format!("job {}: {e}", job.file_stem())))
}

/// Renders `jobs` on every thread (untimed: only their error images are used) into `errors`.
fn render_extra(
    jobs: &[Job],
    scene: &Scene,
    reference: &Reference,
    runner: &JobRunner,
    errors: &mut HashMap<(Row, u32, u32), Vec<f32>>,
) -> Result<()> {
    let g = |j: &Job| Geometry::of(j.resolution, j.ao_distance, scene).pixels() * j.rays as u64;
    runner.bar.reset();
    runner.bar.set_length(jobs.iter().map(g).sum());
    for job in jobs {
        let done = runner.render(job, scene, "winner map")?;
        errors.insert(
            (job.row().canonical(), job.rays, job.replicate),
            error_of(job, &done.output, reference)?,
        );
    }
    Ok(())
}
