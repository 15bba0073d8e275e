//! `hemilab run`, `plan` and `reference`: spec → plan → jobs → images → metrics → results.
//! Everything is loaded and validated before the first ray; results are rewritten atomically after
//! every job, so an interrupted run loses nothing and resumes where it stopped.

use super::data::{Data, agg_label};
use super::jobs::JobRunner;
use super::load::{Loaded, load};
use super::reference::{self as refs, Policy, Reference};
use super::shard;
use super::timed::{self, Session};
use crate::cli::{ReferenceArgs, RunArgs};
use crate::error::{Error, Result};
use crate::io;
use crate::plan::{self, shard::Shard};
use crate::reference as refmath;
use crate::results::{self, JobResult};
use crate::spec::{self, Spec};
use crate::timing::{self, Protocol, Summary};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

pub fn run_reference(args: ReferenceArgs) -> Result<()> {
    let loaded = load(&args.spec)?;
    let dir = refs::dir(args.reference_dir.as_deref(), &loaded.spec);
    io::ensure_writable_dir(&dir)?;
    let runner = JobRunner::new(args.common.threads, args.common.quiet)?;
    // A stored reference that serves the spec is kept: for `rays = "auto"` it may hold far more
    // rays than this spec asks (the paper's, shared with a smaller spec), and rebuilding it would
    // throw them away.
    let policy = if args.force { Policy::Rebuild } else { Policy::ReuseOrBuild };
    for (si, scene) in loaded.scenes.iter().enumerate() {
        let kept = policy == Policy::ReuseOrBuild && refs::missing(&loaded.spec, si, scene, &dir)?.is_none();
        let r = refs::obtain(&loaded.spec, si, scene, &dir, policy, &runner)?;
        println!(
            "{}: noise floor {:.3e} ({} x {} rays){}",
            r.exr.display(),
            r.noise_floor(),
            r.manifest.replicates,
            r.manifest.rays,
            if kept { "; kept, it serves this spec (--force rebuilds it)" } else { "" }
        );
    }
    runner.bar.finish_and_clear();
    Ok(())
}

/// Output directory: `--out`, else `out/<spec name>/`, and a shard's `out/<spec name>/shard-K-of-N/`.
pub fn out_dir(args: &RunArgs, spec: &Spec, shard: Option<Shard>) -> PathBuf {
    let default = Path::new("out").join(&spec.name);
    let default = shard.map_or(default.clone(), |s| default.join(s.dir_name()));
    args.out.clone().unwrap_or(default)
}

pub fn run_run(args: RunArgs) -> Result<()> {
    let loaded = load(&args.spec)?;
    let env = |name: &str| std::env::var(name).ok();
    let shard = args.shard.map(|a| shard::resolve(a, args.shards, &env)).transpose().map_err(Error::Usage)?;
    let out = out_dir(&args, &loaded.spec, shard);
    io::ensure_writable_dir(&out)?;
    io::ensure_writable_dir(&out.join("images"))?;
    let full = plan::plan(&loaded.spec);
    let plan = shard.map_or_else(|| full.clone(), |s| shard::select(&loaded, &full, s));
    let previous = if args.force { HashMap::new() } else { previous_results(&out)? };
    let runner = JobRunner::new(args.common.threads, args.common.quiet)?;

    let policy = if args.no_build_reference { Policy::ReuseOnly } else { Policy::ReuseOrBuild };
    let ref_dir = refs::dir(args.reference_dir.as_deref(), &loaded.spec);
    super::long_run::warn_if_long(&args, &loaded, &full, &plan, &previous, &ref_dir)?;
    let references = (0..loaded.scenes.len())
        .map(|si| refs::obtain(&loaded.spec, si, &loaded.scenes[si], &ref_dir, policy, &runner))
        .collect::<Result<Vec<_>>>()?;

    let protocol = protocol(&args, &loaded.spec);
    let reused = reused_jobs(&loaded, &plan, &references, &previous, &out);
    if let Some(s) = shard {
        shard::Manifest::new(&loaded, &full, s, plan.jobs.len(), protocol).write(&out)?;
    }
    let write = |r: &[JobResult]| write_results(&out, r);
    let (results, mut session) =
        timed::run_jobs(&loaded, &plan, &references, &previous, &out, protocol, &runner.bar, &write)?;
    runner.bar.finish_and_clear();
    if session.renders == 0 {
        session.overhead = previous_overhead(&out, &loaded.spec);
    }
    write_timing(&out, &loaded.spec, protocol, &session)?;
    if let Some(s) = shard {
        // A shard's report would be of a part; `merge` writes the whole one.
        println!(
            "shard {s}: {} of {} jobs: {}; results: {}",
            results.len(),
            full.jobs.len(),
            counts(results.len(), reused),
            out.display()
        );
        return Ok(());
    }
    let summary = summarize(&loaded, &references, &results, &session, &out)?;
    let data = Data::new(&loaded, &references, &results, protocol, session.overhead.clone());
    let figures = super::figures::write_all(&data, &out)?;
    super::page::write(&data, &figures, &out)?;
    print!("{summary}");
    let index = out.join("index.html");
    println!("{} jobs: {}; report: {}", results.len(), counts(results.len(), reused), index.display());
    Ok(())
}

/// "12 rendered, 428 reused": what a run did, for its closing line.
pub(super) fn counts(jobs: usize, reused: usize) -> String {
    format!("{} rendered, {reused} reused", jobs.saturating_sub(reused))
}

/// Jobs whose finished record (same key, image on disk) an earlier run left: `timed::run_jobs`
/// reuses exactly these.
fn reused_jobs(
    loaded: &Loaded,
    plan: &plan::Plan,
    references: &[Reference],
    previous: &HashMap<String, JobResult>,
    out: &Path,
) -> usize {
    plan.jobs
        .iter()
        .filter(|j| {
            let (si, scene) = loaded.scene_of(j);
            let key = timed::run_key(j, scene, &references[si]);
            previous.get(&key).is_some_and(|r| io::exists(&out.join(&r.image)))
        })
        .count()
}

/// The spec's timing settings, `--timing-repeats` over `[timing] repeats`; one worker per thread.
pub(super) fn protocol(args: &RunArgs, spec: &Spec) -> Protocol {
    let workers = match args.common.threads {
        Some(t) => t as usize,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    Protocol::new(args.timing_repeats.unwrap_or(spec.timing.repeats), spec.timing.seed, workers)
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

pub(super) fn write_results(out: &Path, results: &[JobResult]) -> Result<()> {
    io::write_atomic(&out.join("results.json"), results::to_json(results).as_bytes())?;
    io::write_atomic(&out.join("results.csv"), results::to_csv(results).as_bytes())
}

/// `timing.json`: how the run was timed, what a time includes, each scene's overhead, and the
/// session's totals (a resumed run's older records keep the times of the session that made them).
fn write_timing(out: &Path, spec: &Spec, protocol: Protocol, session: &Session) -> Result<()> {
    let overhead: Vec<serde_json::Value> = spec
        .scenes
        .iter()
        .zip(&session.overhead)
        .map(|(s, o)| serde_json::json!({ "scene": s.name, "overhead_s": o }))
        .collect();
    let v = serde_json::json!({
        "clock": timing::clock::NAME,
        "time_includes": timing::TIME_INCLUDES,
        "protocol": protocol,
        "overhead": overhead,
        "session": {
            "timed_renders": session.renders,
            "timed_cpu_s": session.cpu_s,
            "wall_s": session.wall_s,
        },
    });
    let text = serde_json::to_string_pretty(&v).unwrap_or_default();
    io::write_atomic(&out.join("timing.json"), text.as_bytes())
}

/// The overhead an earlier session measured (`timing.json`), for a run that rendered nothing.
fn previous_overhead(out: &Path, spec: &Spec) -> Vec<Option<Summary>> {
    let read = || -> Option<serde_json::Value> {
        serde_json::from_str(&io::read_string(&out.join("timing.json")).ok()?).ok()
    };
    let v = read();
    spec.scenes
        .iter()
        .map(|s| {
            let list = v.as_ref()?.get("overhead")?.as_array()?;
            let e = list.iter().find(|e| e.get("scene").and_then(|n| n.as_str()) == Some(s.name.as_str()))?;
            serde_json::from_value(e.get("overhead_s")?.clone()).ok()
        })
        .collect()
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

/// More configurations than this are not listed at the end of a run: the report has them all.
const MAX_PRINTED_CONFIGURATIONS: usize = 24;

/// Aggregates and slopes to files, the noise-floor check, and the text printed at the end.
pub(super) fn summarize(
    loaded: &Loaded,
    references: &[Reference],
    results: &[JobResult],
    session: &Session,
    out: &Path,
) -> Result<String> {
    use std::fmt::Write;
    let aggs = results::aggregate(results);
    io::write_atomic(&out.join("aggregates.csv"), results::aggregates_to_csv(&aggs).as_bytes())?;
    let slopes_json = serde_json::to_string_pretty(&sweep_slopes(&loaded.spec, &aggs)).unwrap_or_default();
    io::write_atomic(&out.join("slopes.json"), slopes_json.as_bytes())?;

    let mut s = String::new();
    let _ = writeln!(
        s,
        "timing: {} timed renders, {:.1} s of render CPU time in {:.1} s of wall time",
        session.renders, session.cpu_s, session.wall_s
    );
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
    if aggs.len() > MAX_PRINTED_CONFIGURATIONS {
        let _ = writeln!(
            s,
            "{} configurations: RMSE, times and efficiency of each in aggregates.csv and the report",
            aggs.len()
        );
        return Ok(s);
    }
    let width = aggs.iter().map(|a| agg_label(a).chars().count()).max().unwrap_or(0);
    let _ = writeln!(
        s,
        "per configuration: RMSE mean ± sd over replicates, lag-1 error autocorrelation ρ x/y, median render \
         time, ns per AO ray"
    );
    for a in &aggs {
        let _ = writeln!(
            s,
            "  {:<12} {:<width$} {:>5} rays  RMSE {:.4} ± {:.4}  ρ {:+.2}/{:+.2}  {:.2} ms  {:.1} ns/ray",
            a.scene,
            agg_label(a),
            a.rays,
            a.rmse.mean,
            a.rmse.sd,
            a.autocorr_x.mean,
            a.autocorr_y.mean,
            a.time.map_or(f64::NAN, |t| t.median * 1e3),
            a.ns_per_ray
        );
    }
    Ok(s)
}
