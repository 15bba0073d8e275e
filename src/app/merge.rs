//! `hemilab merge SPEC SHARD_DIR...`: the shards of `run --shard K/N` back into one run — the full
//! results and the whole report, as a plain run of the spec would have written them. Everything is
//! checked before anything is written (`shard::merge`); a missing job stops the merge with exit
//! status 2, naming how many are missing and from which shards, and nothing is written.

use crate::cli::MergeArgs;
use crate::error::{Error, Result};
use crate::io;
use crate::jobs::executor::{Session, run_key};
use crate::jobs::runner::JobRunner;
use crate::load::load;
use crate::outdir;
use crate::plan;
use crate::reference::store::{self as refs, Policy};
use crate::report;
use crate::results::JobResult;
use crate::shard::manifest;
use crate::shard::merge::{
    check_manifests, match_records, merged_overhead, missing_message, provenance, read_shard, same_dir,
    session_of, timing_json,
};
use crate::timing::Protocol;
use std::path::Path;

pub fn run(args: MergeArgs) -> Result<()> {
    let loaded = load(&args.spec)?;
    let spec = &loaded.spec;
    let plan = plan::plan(spec);
    let fingerprint = manifest::fingerprint(&loaded, &plan);
    let out = args.out.clone().unwrap_or_else(|| Path::new("out").join(&spec.name));

    let shards = args.shard_dirs.iter().map(|d| read_shard(d)).collect::<Result<Vec<_>>>()?;
    check_manifests(&shards, &args.spec, &spec.name, &fingerprint)?;
    for s in &shards {
        if same_dir(&s.dir, &out) {
            return Err(Error::Usage(format!(
                "--out {} is shard directory {}; merge into another directory",
                out.display(),
                s.dir.display()
            )));
        }
    }

    let ref_dir = refs::dir(args.reference_dir.as_deref(), spec);
    for (si, scene) in loaded.scenes.iter().enumerate() {
        if let Some(m) = refs::missing(spec, si, scene, &ref_dir)? {
            return Err(Error::Refused(format!(
                "no usable reference for scene '{}' in {}: {} x {} rays wanted; pass the --reference-dir \
                 the shards used",
                spec.scenes[si].name,
                ref_dir.display(),
                m.replicates,
                m.rays
            )));
        }
    }
    let runner = JobRunner::new(crate::jobs::Threads::resolve(None), args.quiet)?;
    let references = (0..loaded.scenes.len())
        .map(|si| {
            crate::jobs::reference::obtain(spec, si, &loaded.scenes[si], &ref_dir, Policy::ReuseOnly, &runner)
        })
        .collect::<Result<Vec<_>>>()?;
    let keys: Vec<String> = plan
        .jobs
        .iter()
        .map(|j| {
            let (si, scene) = loaded.scene_of(j);
            run_key(j, scene, &references[si], loaded.spec.flip_ppd)
        })
        .collect();
    let found = match_records(&shards, &keys, &plan, &args.spec, &ref_dir)?;
    let missing: Vec<usize> = (0..plan.jobs.len()).filter(|&j| found[j].is_none()).collect();
    if !missing.is_empty() {
        return Err(Error::Refused(missing_message(&loaded, &plan, &shards, &missing)));
    }

    // Every shard's image is read whole where it is, so a truncated one is named in its shard's
    // directory (not as the merged copy, after the results were written).
    for (si, r) in found.iter().flatten() {
        outdir::record_image(&shards[*si].dir, r)?;
    }

    // Checked: now write.
    outdir::prepare(&out, true)?;
    let mut merged: Vec<JobResult> = Vec::with_capacity(plan.jobs.len());
    let bar = crate::progress::bar(plan.jobs.len() as u64, "images", args.quiet);
    for (si, r) in found.iter().flatten() {
        io::link_or_copy(&shards[*si].dir.join(&r.image), &out.join(&r.image))?;
        merged.push((*r).clone());
        bar.inc(1);
    }
    bar.finish_and_clear();
    // A place's floor may be a configuration another shard measured.
    crate::jobs::replicates::floors(&mut merged, &plan.jobs);
    outdir::write_results(&out, &merged)?;

    let overhead = merged_overhead(&loaded.spec, &shards);
    let session = Session {
        overhead: overhead.clone(),
        renders: shards.iter().map(|s| session_of(s).timed_renders).sum(),
        cpu_s: shards.iter().map(|s| session_of(s).timed_cpu_s).sum(),
        wall_s: shards.iter().map(|s| session_of(s).wall_s).sum(),
        reused: 0,
    };
    let m0 = &shards[0].manifest;
    let protocol = Protocol::new(m0.timing.repeats, m0.timing.seed, m0.timing.workers);
    let note = provenance(&shards);
    let timing = timing_json(&shards, &found, protocol, &note);
    outdir::write_merged_timing(&out, &timing)?;
    // A merged run's cost is its shards' (each shard's own timing.json); the whole has none.
    let cost = None;
    let images = |r: &JobResult| outdir::record_image(&out, r);
    // The camera paths' frame references, for the report's viewer only: where the directory lacks
    // them, the viewer leaves those cameras out rather than the merge failing.
    let si_of = |j: &plan::Job| loaded.scene_of(j).0;
    let views = crate::jobs::reference::obtain_views(
        spec,
        &plan,
        &loaded.scenes,
        si_of,
        &ref_dir,
        Policy::ReuseOnly,
        &runner,
    )
    .unwrap_or_default();
    let run = report::run::Run {
        loaded: &loaded,
        references: &references,
        views: &views,
        results: &merged,
        protocol,
        session: &session,
        cost,
        notes: vec![note.clone()],
        images: &images,
    };
    let report::run::Report { files, summary } = report::run::report(run)?;
    outdir::write_files(&out, &files, &[])?;
    for w in &summary.warnings {
        eprintln!("{w}");
    }
    println!("{note}");
    print!("{}", summary.text);
    println!(
        "merged {} shard directories ({} jobs; times summed over the shards); report: {}",
        shards.len(),
        merged.len(),
        outdir::index(&out).display()
    );
    Ok(())
}
