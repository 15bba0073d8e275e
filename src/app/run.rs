//! `hemilab run SPEC`: spec → plan → jobs → images → metrics → results → report. Everything is
//! loaded and validated before the first ray; results are rewritten atomically after every job, so
//! an interrupted run loses nothing and resumes where it stopped.

use crate::cli::RunArgs;
use crate::error::{Error, Result};
use crate::jobs::runner::JobRunner;
use crate::jobs::{Threads, executor, long_run};
use crate::load::load;
use crate::outdir;
use crate::plan;
use crate::reference::store::{self as refs, Policy};
use crate::report;
use crate::shard::manifest as shard;
use std::collections::HashMap;
use std::path::Path;

pub fn run(args: RunArgs) -> Result<()> {
    let loaded = load(&args.spec)?;
    let env = |name: &str| std::env::var(name).ok();
    let shard = args.shard.map(|a| shard::resolve(a, args.shards, &env)).transpose().map_err(Error::Usage)?;
    // `--out`, else `out/<spec name>/`, and a shard's `out/<spec name>/shard-K-of-N/`.
    let default = Path::new("out").join(&loaded.spec.name);
    let out = args.out.clone().unwrap_or(shard.map_or(default.clone(), |s| default.join(s.dir_name())));
    outdir::prepare(&out, true)?;
    let full = plan::plan(&loaded.spec);
    let plan = shard.map_or_else(|| full.clone(), |s| shard::select(&loaded, &full, s));
    let previous = if args.force { HashMap::new() } else { outdir::previous_results(&out)? };
    if let Some(s) = shard {
        // Never a dropped record: another shard's directory, or a whole run's, is refused.
        let images: Vec<&str> = previous.values().map(|r| r.image.as_str()).collect();
        shard::check_out(&out, &loaded.spec.name, &full, &plan, s, &images)?;
    }
    // A resumed run says so first (its closing line counts what it did reuse).
    let kept = plan.jobs.len() - crate::jobs::forecast::left(&plan, previous.values()).jobs.len();
    if kept > 0 && !args.common.quiet {
        eprintln!(
            "resuming from {}: {kept} of {} jobs have their records there and are reused (a changed reference \
             or scene renders them again)",
            out.display(),
            plan.jobs.len()
        );
    }
    let threads = Threads::resolve(args.common.threads);
    let runner = JobRunner::new(threads, args.common.quiet)?;

    let policy = if args.no_build_reference { Policy::ReuseOnly } else { Policy::ReuseOrBuild };
    let ref_dir = refs::dir(args.reference_dir.as_deref(), &loaded.spec);
    let protocol = threads.protocol(args.timing_repeats, &loaded.spec);
    long_run::warn_if_long(&args.spec, protocol, &loaded, &full, &plan, &previous, &ref_dir)?;
    let references = (0..loaded.scenes.len())
        .map(|si| {
            crate::jobs::reference::obtain(&loaded.spec, si, &loaded.scenes[si], &ref_dir, policy, &runner)
        })
        .collect::<Result<Vec<_>>>()?;
    let si_of = |j: &plan::Job| loaded.scene_of(j).0;
    let views = crate::jobs::reference::obtain_views(
        &loaded.spec,
        &plan,
        &loaded.scenes,
        si_of,
        &ref_dir,
        policy,
        &runner,
    )?;

    if let Some(s) = shard {
        shard::Manifest::new(&loaded, &full, s, plan.jobs.len(), protocol).write(&out)?;
    }
    let saver = outdir::Saver::new(&out);
    let write = |s: &executor::Saved| saver.save(s.new, s.so_far);
    // After a signal the message says the finished jobs are here, for a rerun to resume.
    crate::interrupt::saves_to(&out);
    // A signal's message says the finished jobs are saved: results.csv then holds every one.
    let saved = |e: Error| {
        if matches!(e, Error::Interrupted(_)) {
            let _ = outdir::fold_journal(&out);
        }
        e
    };
    let (results, mut session) = executor::run_jobs(&executor::Jobs {
        loaded: &loaded,
        plan: &plan,
        references: &references,
        views: &views,
        previous: &previous,
        out: &out,
        protocol,
        bar: &runner.bar,
        label: "jobs",
        write: &write,
    })
    .map_err(saved)?;
    runner.bar.finish_and_clear();
    outdir::write_results(&out, &results)?;
    if session.renders == 0 {
        session.overhead = outdir::previous_overhead(&out, &loaded.spec);
    }
    let mut timing = session.timing(&loaded.spec, protocol);
    if session.renders == 0
        && let Some(earlier) = outdir::previous_session(&out)
    {
        timing.session = earlier;
    }
    outdir::write_timing(&out, &timing)?;
    // "12 rendered, 428 reused": what the run did, for its closing line.
    let counts =
        format!("{} rendered, {} reused", results.len().saturating_sub(session.reused), session.reused);
    let cost = Some(report::run::quotes::Cost::of(&timing.session, results.len()));
    if let Some(s) = shard {
        // A shard's report would be of a part; `merge` writes the whole one.
        println!(
            "shard {s}: {} of {} jobs: {counts}; results: {}",
            results.len(),
            full.jobs.len(),
            out.display()
        );
        return Ok(());
    }
    let images = |r: &crate::results::JobResult| outdir::record_image(&out, r);
    let run = report::run::Run {
        loaded: &loaded,
        references: &references,
        views: &views,
        results: &results,
        protocol,
        session: &session,
        cost,
        notes: Vec::new(),
        images: &images,
    };
    let report::run::Report { files, summary } = report::run::report(run)?;
    outdir::write_files(&out, &files, &[])?;
    // Under `[tiles]`: each scene's frame with its tiles outlined, `tiles-<scene>.png`.
    for (si, scene) in loaded.scenes.iter().enumerate() {
        let Some(t) = crate::jobs::tiles::of_spec(&loaded.spec, si, scene) else { continue };
        let p = crate::jobs::tiles::preview(&loaded.spec, scene);
        let png =
            report::tiles::tiles_png(&p.ao, &p.coverage, &t.interiors, &t.windows).map_err(Error::Refused)?;
        let name = format!("tiles-{}.png", loaded.spec.scenes[si].name);
        outdir::write_files(&out, &[outdir::File::new(&name, png)], &[])?;
    }
    for w in &summary.warnings {
        eprintln!("{w}");
    }
    print!("{}", summary.text);
    println!("{} jobs: {counts}; report: {}", results.len(), outdir::index(&out).display());
    Ok(())
}
