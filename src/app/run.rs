//! `hemilab run`, `plan` and `reference`: spec → plan → jobs → images → metrics → results.
//! Everything is loaded and validated before the first ray; results are rewritten atomically after
//! every job, so an interrupted run loses nothing and resumes where it stopped.

use super::jobs::{Geometry, JobRunner};
use super::reference::{self as refs, Policy, Reference};
use crate::app::render::{MAX_PIXELS, dropped_warning, load_scene};
use crate::cli::{PlanArgs, ReferenceArgs, RunArgs};
use crate::error::{Error, Result};
use crate::image::Channel;
use crate::io;
use crate::metrics;
use crate::plan::{self, Job, Plan};
use crate::reference as refmath;
use crate::results::{self, JobResult};
use crate::scene::Scene;
use crate::spec::{self, SceneRef, Spec};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Assumed throughput for `hemilab plan`'s time estimate (measure yours with `hemilab bench`).
pub const ASSUMED_RAYS_PER_S: f64 = 8.0e6;

/// A spec with every scene it names loaded: all bad input is found here, before any work.
pub struct Loaded {
    pub spec: Spec,
    pub scenes: Vec<Scene>,
}

impl Loaded {
    pub fn scene_of(&self, job: &Job) -> (usize, &Scene) {
        let i =
            self.spec.scenes.iter().position(|s| s.id == job.scene_id).expect("planned scene is in the spec");
        (i, &self.scenes[i])
    }
}

pub fn load(spec_path: &Path) -> Result<Loaded> {
    let text = io::read_string(spec_path)?;
    let spec = spec::parse_spec(&text, spec_path)?;
    let scenes = spec.scenes.iter().map(|s| load_named_scene(&spec, s)).collect::<Result<Vec<_>>>()?;
    for w in scenes.iter().filter_map(dropped_warning) {
        eprintln!("{w}");
    }
    Ok(Loaded { spec, scenes })
}

/// A scene the spec names: a missing file is the spec's mistake, so the message points at its key;
/// an image too large to hold in memory is refused here rather than by the allocator mid-run.
fn load_named_scene(spec: &Spec, s: &SceneRef) -> Result<Scene> {
    if !io::exists(&s.path) {
        return Err(Error::input(
            &spec.path,
            format!("key `scenes`: scene file '{}' not found (looked for {})", s.id, s.path.display()),
        ));
    }
    let scene = load_scene(&s.path)?;
    let g = Geometry::of(spec.resolution, spec.ao_distance, &scene);
    if g.pixels() > MAX_PIXELS {
        return Err(Error::input(
            &spec.path,
            format!(
                "key `resolution`: {}x{} for scene '{}' has more than {MAX_PIXELS} pixels; too large to hold \
                 in memory",
                g.width, g.height, s.name
            ),
        ));
    }
    Ok(scene)
}

pub fn run_plan(args: PlanArgs) -> Result<()> {
    let loaded = load(&args.spec)?;
    let plan = plan::plan(&loaded.spec);
    let est = plan::estimate(
        &plan,
        |job| {
            let (_, s) = loaded.scene_of(job);
            [s.resolution.0, s.resolution.1]
        },
        ASSUMED_RAYS_PER_S,
    );
    print!("{}", plan::format_plan(&args.spec, &plan, &est, ASSUMED_RAYS_PER_S));
    Ok(())
}

pub fn run_reference(args: ReferenceArgs) -> Result<()> {
    let loaded = load(&args.spec)?;
    io::ensure_writable_dir(&args.reference_dir)?;
    let runner = JobRunner::new(args.common.threads, args.common.quiet)?;
    for (si, scene) in loaded.scenes.iter().enumerate() {
        let r = refs::obtain(&loaded.spec, si, scene, &args.reference_dir, Policy::Rebuild, &runner)?;
        println!(
            "{}: noise floor {:.3e} ({} x {} rays)",
            r.exr.display(),
            r.noise_floor(),
            r.manifest.replicates,
            r.manifest.rays
        );
    }
    runner.bar.finish_and_clear();
    Ok(())
}

/// Output directory: `--out`, else `out/<spec name>/`.
pub fn out_dir(args: &RunArgs, spec: &Spec) -> PathBuf {
    args.out.clone().unwrap_or_else(|| Path::new("out").join(&spec.name))
}

pub fn run_run(args: RunArgs) -> Result<()> {
    let loaded = load(&args.spec)?;
    let out = out_dir(&args, &loaded.spec);
    io::ensure_writable_dir(&out)?;
    io::ensure_writable_dir(&out.join("images"))?;
    let plan = plan::plan(&loaded.spec);
    let previous = if args.force { HashMap::new() } else { previous_results(&out)? };
    let runner = JobRunner::new(args.common.threads, args.common.quiet)?;

    let policy = if args.no_build_reference { Policy::ReuseOnly } else { Policy::ReuseOrBuild };
    let references = (0..loaded.scenes.len())
        .map(|si| refs::obtain(&loaded.spec, si, &loaded.scenes[si], &args.reference_dir, policy, &runner))
        .collect::<Result<Vec<_>>>()?;

    let results = run_jobs(&loaded, &plan, &references, &previous, &out, &runner)?;
    runner.bar.finish_and_clear();
    let summary = summarize(&loaded, &references, &results, &out)?;
    super::figures::write_all(&loaded, &plan, &references, &results, &out)?;
    print!("{summary}");
    Ok(())
}

/// Finished records of an earlier run, by key. A results file that cannot be read is an error, not
/// something to overwrite silently.
fn previous_results(out: &Path) -> Result<HashMap<String, JobResult>> {
    let path = out.join("results.json");
    if !io::exists(&path) {
        return Ok(HashMap::new());
    }
    let list = results::from_json(&io::read_string(&path)?).map_err(|e| {
        Error::input(&path, format!("cannot resume from it ({e}); move it away or pass --force"))
    })?;
    Ok(list.into_iter().map(|r| (r.key.clone(), r)).collect())
}

/// The resume key: the job, and everything outside the job that its numbers depend on (scene
/// content, reference, hemilab version). The reference's measured fields (its render time, noise
/// floor) are left out: a rebuilt identical reference must not invalidate finished jobs.
fn run_key(job: &Job, scene: &Scene, reference: &Reference) -> String {
    let manifest = refmath::Manifest { noise_floor: None, time_s: None, ..reference.manifest.clone() };
    let what = format!(
        "{};{};{};{}",
        job.canonical(),
        scene.content_hash,
        manifest.to_json(),
        env!("CARGO_PKG_VERSION")
    );
    format!("{:016x}", plan::fnv1a64(what.as_bytes()))
}

fn run_jobs(
    loaded: &Loaded,
    plan: &Plan,
    references: &[Reference],
    previous: &HashMap<String, JobResult>,
    out: &Path,
    runner: &JobRunner,
) -> Result<Vec<JobResult>> {
    let total: u64 = plan
        .jobs
        .iter()
        .map(|j| Geometry::of(j.resolution, j.ao_distance, loaded.scene_of(j).1).pixels() * j.rays as u64)
        .sum();
    runner.stage("jobs", total);
    let mut results: Vec<JobResult> = Vec::with_capacity(plan.jobs.len());
    for (i, job) in plan.jobs.iter().enumerate() {
        let (si, scene) = loaded.scene_of(job);
        let reference = &references[si];
        let key = run_key(job, scene, reference);
        let image_rel = format!("images/{}.exr", job.file_stem());
        if let Some(done) = previous.get(&key).filter(|_| io::exists(&out.join(&image_rel))) {
            runner.bar.inc(Geometry::of(job.resolution, job.ao_distance, scene).pixels() * job.rays as u64);
            results.push(done.clone());
            continue;
        }
        let label = format!("job {}/{}", i + 1, plan.jobs.len());
        let r = runner.render(job, scene, &label)?;
        let stats = metrics::measure(&r.output.ao, &reference.mean, &reference.coverage)
            .map_err(|e| Error::Refused(format!("job {}: {e}", job.file_stem())))?;
        io::write_exr(
            &out.join(&image_rel),
            &[Channel { name: "Y", image: &r.output.ao }, Channel { name: "A", image: &r.output.coverage }],
        )?;
        let mut record = JobResult::new(job, &stats, r.time_s, r.output.rays, image_rel);
        record.key = key;
        results.push(record);
        write_results(out, &results)?;
    }
    write_results(out, &results)?;
    Ok(results)
}

fn write_results(out: &Path, results: &[JobResult]) -> Result<()> {
    io::write_atomic(&out.join("results.json"), results::to_json(results).as_bytes())?;
    io::write_atomic(&out.join("results.csv"), results::to_csv(results).as_bytes())
}

/// The slopes of one `[[convergence]]` sweep.
#[derive(serde::Serialize)]
struct SweepSlopes<'a> {
    group: &'a str,
    slopes: Vec<results::Slope>,
}

/// Per sweep, per row and scene, over the sweep's own ray counts only: a table that shares a row
/// must not add its points to the fit.
fn sweep_slopes<'a>(spec: &'a Spec, aggs: &[results::Aggregate]) -> Vec<SweepSlopes<'a>> {
    let sweeps = spec.groups.iter().filter(|g| g.kind == spec::GroupKind::Convergence);
    sweeps
        .map(|g| {
            let in_sweep = |a: &results::Aggregate| {
                g.scenes.iter().any(|&si| spec.scenes[si].name == a.scene)
                    && g.rows.iter().any(|r| {
                        a.distribution == r.distribution.name()
                            && a.sequence == r.sequence.name()
                            && a.seed_mode == r.seed_mode.name()
                    })
            };
            let pts: Vec<results::Aggregate> = aggs.iter().filter(|a| in_sweep(a)).cloned().collect();
            SweepSlopes { group: &g.name, slopes: results::convergence_slopes(&pts, &g.rays) }
        })
        .collect()
}

/// Aggregates and slopes to files, the noise-floor check, and the text printed at the end.
fn summarize(loaded: &Loaded, references: &[Reference], results: &[JobResult], out: &Path) -> Result<String> {
    use std::fmt::Write;
    let aggs = results::aggregate(results);
    io::write_atomic(&out.join("aggregates.csv"), results::aggregates_to_csv(&aggs).as_bytes())?;
    let slopes_json = serde_json::to_string_pretty(&sweep_slopes(&loaded.spec, &aggs)).unwrap_or_default();
    io::write_atomic(&out.join("slopes.json"), slopes_json.as_bytes())?;

    let mut s = String::new();
    let _ = writeln!(s, "{} jobs → {}", results.len(), out.display());
    for (si, r) in references.iter().enumerate() {
        // The spec's scene name (the file stem) is the results' `scene` column; the scene file's own
        // `name` may differ.
        let name = &loaded.spec.scenes[si].name;
        let smallest =
            aggs.iter().filter(|a| &a.scene == name).map(|a| a.rmse.mean).fold(f64::INFINITY, f64::min);
        let floor = r.noise_floor();
        let target = refmath::target_floor(smallest);
        let _ = writeln!(s, "reference '{name}': noise floor {floor:.2e}, smallest RMSE {smallest:.2e}");
        if smallest.is_finite() && floor > target {
            let need = refmath::rays_needed(floor, r.manifest.rays, target);
            eprintln!(
                "warning: reference noise floor {floor:.2e} of '{name}' is above a tenth of the smallest RMSE \
                 ({smallest:.2e}); about {need} rays per replicate are needed (set [reference] rays)"
            );
        }
    }
    for a in &aggs {
        let _ = writeln!(
            s,
            "  {:<12} {:<18} {:<10} {:<8} {:>5} rays  RMSE {:.4} ± {:.4}  ρ {:+.2}/{:+.2}  {:.1} Mrays/s",
            a.scene,
            a.distribution,
            a.sequence,
            a.seed_mode,
            a.rays,
            a.rmse.mean,
            a.rmse.sd,
            a.autocorr_x.mean,
            a.autocorr_y.mean,
            a.rays_per_s.mean / 1e6
        );
    }
    Ok(s)
}
