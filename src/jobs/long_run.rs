//! `run`'s warning before a long run: what is left of it, estimated first roughly (no rendering)
//! and, if that may be long, as `plan` estimates it (`calibrate::estimate_s`, a fraction of a second
//! of calibration renders), so that an 8000x8000 spec does not start for hours unannounced.

use crate::error::Result;
use crate::load::Loaded;
use crate::outdir;
use crate::plan::Geometry;
use crate::plan::{self, Job, Plan, cost};
use crate::reference::store as refs;
use crate::results::JobResult;
use crate::timing;
use std::collections::HashMap;
use std::path::Path;

/// Runs estimated to take longer than this (in wall seconds) are announced before they start.
const LONG_RUN_S: f64 = 3600.0;

/// Says before the first render when what is left of the run (references included) will take over
/// `LONG_RUN_S`, as `plan` estimates it. A rough estimate comes first, without rendering, so that
/// only a run that may be long pays for `plan`'s calibration (a fraction of a second).
pub fn warn_if_long(
    spec_path: &Path,
    p: timing::Protocol,
    loaded: &Loaded,
    full: &Plan,
    plan: &Plan,
    previous: &HashMap<String, JobResult>,
    ref_dir: &Path,
) -> Result<()> {
    // What is left to render, by image: the resume rule (`executor::resumed`) needs the run keys,
    // and they need the references, which may take hours to build; this is an estimate.
    let done: std::collections::HashSet<&str> = previous.values().map(|r| r.image.as_str()).collect();
    let left = plan.jobs.iter().filter(|j| !done.contains(outdir::image_rel(j).as_str()));
    let todo = Plan { jobs: left.cloned().collect() };
    let rough = rough_run_s(loaded, &todo, ref_dir, p, LONG_RUN_S / 4.0)?;
    if todo.jobs.is_empty() || rough <= LONG_RUN_S / 4.0 {
        return Ok(());
    }
    let s = crate::jobs::calibrate::estimate_s(loaded, full, &todo, ref_dir, p.workers)?;
    if s > LONG_RUN_S {
        eprintln!(
            "warning: this run will take about {} on this machine (as `hemilab plan {}` estimates it); it can \
             be stopped at any time and resumes where it stopped, and `--shard K/N` splits it over machines",
            plan::format_duration(s),
            spec_path.display()
        );
    }
    Ok(())
}

/// AO-ray equivalents per CPU second of one thread, typical of this project's scenes (20 M AO rays
/// per second per thread on the kitchen; a pixel costs about 10 AO rays besides its own, as in the
/// shard balance): the rough estimate, so that a short run never pays for a calibration.
const TYPICAL_RAYS_PER_S: f64 = 20e6;

/// A rough wall time of a run, without rendering anything: the protocol's renders of `selected`
/// (`plan::cost`) and the references it would build, at `TYPICAL_RAYS_PER_S` on every worker.
/// Below `threshold_s` it may count references that are in fact stored (not worth reading them).
fn rough_run_s(
    loaded: &Loaded,
    selected: &Plan,
    reference_dir: &std::path::Path,
    protocol: timing::Protocol,
    threshold_s: f64,
) -> Result<f64> {
    let pixels = |j: &Job| {
        let (_, scene) = loaded.scene_of(j);
        Geometry::of(j.resolution, j.ao_distance, scene).pixels() as f64
    };
    let overhead = |id: &str| {
        let j = selected.jobs.iter().find(|j| j.scene_id == id).expect("a planned scene");
        pixels(j) * 10.0 / TYPICAL_RAYS_PER_S
    };
    let model = cost::Model {
        protocol,
        overhead_renders: timing::OVERHEAD_REPEATS,
        post_s: 0.0,
        rewrite_s: 0.0,
        rewrite_every_s: 0.0,
        contention: 1.0,
    };
    let render_s = |j: &Job| pixels(j) * (j.rays as f64 + 10.0) / TYPICAL_RAYS_PER_S;
    let jobs_s = cost::jobs(selected, render_s, |_, _, _| 0.0, overhead, &model).wall_s;
    // The references, if they must be built: looked up (reading each image) only if they matter.
    let spec = &loaded.spec;
    let used = |si: usize| selected.jobs.iter().any(|j| loaded.scene_of(j).0 == si);
    let reference_s = |si: usize, rays: u32| {
        let jobs = plan::reference_jobs(spec, si, rays);
        jobs.iter().map(render_s).sum::<f64>() / protocol.workers.max(1) as f64
    };
    let wanted = |si: usize| {
        let g = Geometry::of(spec.resolution, spec.ao_distance, &loaded.scenes[si]);
        refs::wanted_manifest(spec, si, &loaded.scenes[si], g).rays
    };
    let at_most: f64 =
        (0..loaded.scenes.len()).filter(|&si| used(si)).map(|si| reference_s(si, wanted(si))).sum();
    if jobs_s + at_most <= threshold_s {
        return Ok(jobs_s + at_most);
    }
    let mut wall = jobs_s;
    for si in (0..loaded.scenes.len()).filter(|&si| used(si)) {
        if let Some(m) = refs::missing(spec, si, &loaded.scenes[si], reference_dir)? {
            wall += reference_s(si, m.rays);
        }
    }
    Ok(wall)
}
