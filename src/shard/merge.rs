//! Merging the shards of `run --shard K/N`: each directory read and checked against the spec (same
//! name and plan fingerprint, this hemilab version, one split), every record matched to its
//! planned job by run key, duplicates checked, the missing named; and the merged timing record.
//!
//! Timings: a shard holds whole configurations (`shard`), so each configuration's time samples,
//! and the overhead its AO time is taken from, come from one shard on one machine; the records keep
//! them as their shard measured them. Across configurations, though, times may come from different
//! machines: the report and `timing.json` say which shard ran where, and warn when that is more
//! than one machine.

use super::manifest::Manifest;
use crate::error::{Error, Result};
use crate::io;
use crate::outdir;
use crate::plan;
use crate::results::JobResult;
use crate::timing::{self, Protocol, Summary};
use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One shard directory, read and checked.
pub struct ShardDir {
    pub dir: PathBuf,
    pub manifest: Manifest,
    pub records: Vec<JobResult>,
    /// `timing.json`, if the shard got that far.
    pub timing: Option<timing::RunTiming>,
}

/// Every record to its planned job (by run key); the first directory given wins among identical
/// duplicates. A record of no planned job, or a job in two directories with different results, is an
/// error; a record whose image is missing (an unfinished write) counts as missing.
pub fn match_records<'a>(
    shards: &'a [ShardDir],
    keys: &[String],
    plan: &plan::Plan,
    spec_path: &Path,
    ref_dir: &Path,
) -> Result<Vec<Option<(usize, &'a JobResult)>>> {
    let index: HashMap<&str, usize> = keys.iter().enumerate().map(|(i, k)| (k.as_str(), i)).collect();

    let mut found: Vec<Option<(usize, &JobResult)>> = vec![None; plan.jobs.len()];
    for (si, s) in shards.iter().enumerate() {
        for r in &s.records {
            let Some(&j) = index.get(r.key.as_str()) else {
                return Err(Error::input(
                    &s.dir.join(outdir::RESULTS_JSON),
                    format!(
                        "record {} is not a job of {} as measured against the references in {} (another \
                         reference, scene file or hemilab version?)",
                        r.image,
                        spec_path.display(),
                        ref_dir.display()
                    ),
                ));
            };
            if !io::exists(&s.dir.join(&r.image)) {
                continue; // an unfinished write: the job counts as missing, as a resumed run would redo it
            }
            match found[j] {
                None => found[j] = Some((si, r)),
                Some((first, kept)) => {
                    if kept.without_times() != r.without_times() {
                        return Err(Error::Refused(format!(
                            "job {} is in {} and in {} with different results; a job must be merged once",
                            plan.jobs[j].file_stem(),
                            shards[first].dir.display(),
                            s.dir.display()
                        )));
                    }
                }
            }
        }
    }
    Ok(found)
}

pub fn read_shard(dir: &Path) -> Result<ShardDir> {
    let manifest = Manifest::read(dir)?;
    // None yet: started, nothing finished.
    let records = outdir::read_results(dir, &|e| format!("not a results file ({e})"))?;
    let tpath = dir.join(outdir::TIMING_JSON);
    let timing =
        if io::exists(&tpath) { timing::RunTiming::from_json(&io::read_string(&tpath)?).ok() } else { None };
    Ok(ShardDir { dir: dir.to_path_buf(), manifest, records, timing })
}

/// Same spec, same plan, this hemilab, one split.
pub fn check_manifests(shards: &[ShardDir], spec_path: &Path, name: &str, fingerprint: &str) -> Result<()> {
    let version = env!("CARGO_PKG_VERSION");
    for s in shards {
        let m = &s.manifest;
        let file = s.dir.join(super::manifest::MANIFEST);
        if m.spec != name || m.plan != fingerprint {
            let what = if m.spec != name {
                format!("spec '{}' ({})", m.spec, m.spec_path)
            } else {
                format!(
                    "another version of spec '{}' ({}: its jobs, reference or timing differ)",
                    m.spec, m.spec_path
                )
            };
            return Err(Error::input(
                &file,
                format!("this shard ran {what}, not {}; merge shards of one spec only", spec_path.display()),
            ));
        }
        if m.hemilab_version != version {
            return Err(Error::input(
                &file,
                format!("this shard ran hemilab {}, this is hemilab {version}; rerun it", m.hemilab_version),
            ));
        }
    }
    let first = &shards[0];
    if let Some(other) = shards.iter().find(|s| s.manifest.shards != first.manifest.shards) {
        return Err(Error::Refused(format!(
            "{} is shard {}/{} but {} is shard {}/{}: merge the shards of one split (one N)",
            first.dir.display(),
            first.manifest.shard,
            first.manifest.shards,
            other.dir.display(),
            other.manifest.shard,
            other.manifest.shards
        )));
    }
    Ok(())
}

/// "12 of 40 planned jobs are missing: shard 1/3 (12 jobs; no directory given) …"
pub fn missing_message(
    loaded: &crate::load::Loaded,
    plan: &plan::Plan,
    shards: &[ShardDir],
    missing: &[usize],
) -> String {
    let n = shards[0].manifest.shards;
    let of = super::manifest::partition(loaded, plan, n);
    let mut by_shard: BTreeMap<u32, usize> = BTreeMap::new();
    for &j in missing {
        *by_shard.entry(of[j]).or_default() += 1;
    }
    let total = |k: u32| of.iter().filter(|&&s| s == k).count();
    let parts: Vec<String> = by_shard
        .iter()
        .map(|(&k, &count)| {
            let dirs: Vec<String> = shards
                .iter()
                .filter(|s| s.manifest.shard == k)
                .map(|s| s.dir.display().to_string())
                .collect();
            let where_ = if dirs.is_empty() {
                "no directory of it given".to_string()
            } else {
                format!("unfinished in {}; rerun it there to resume", dirs.join(", "))
            };
            format!("shard {k}/{n} ({count} of its {} jobs; {where_})", total(k))
        })
        .collect();
    format!(
        "{} of {} planned jobs are missing: {}; nothing was written",
        missing.len(),
        plan.jobs.len(),
        parts.join(", ")
    )
}

pub fn same_dir(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// The session a shard recorded (nothing, if it has no `timing.json`).
pub fn session_of(s: &ShardDir) -> timing::SessionRecord {
    s.timing.as_ref().map(|t| t.session).unwrap_or_default()
}

/// The overhead each shard measured for scene `name`.
pub fn shard_overhead(s: &ShardDir, name: &str) -> Option<Summary> {
    s.timing.as_ref()?.overhead_of(name)
}

/// Per scene, the overhead for the report's figures and text: one shard's as it is; several
/// shards' as the median of their medians, their overall min and max, the widest interval, and
/// all their renders (each record keeps the overhead of its own shard).
pub fn merged_overhead(spec: &crate::spec::Spec, shards: &[ShardDir]) -> Vec<Option<Summary>> {
    spec.scenes
        .iter()
        .map(|scene| {
            let all: Vec<Summary> = shards.iter().filter_map(|s| shard_overhead(s, &scene.name)).collect();
            match all.len() {
                0 => None,
                1 => Some(all[0]),
                _ => {
                    let medians: Vec<f64> = all.iter().map(|o| o.median).collect();
                    Some(Summary {
                        median: crate::stats::median(&medians),
                        min: all.iter().map(|o| o.min).fold(f64::INFINITY, f64::min),
                        max: all.iter().map(|o| o.max).fold(f64::NEG_INFINITY, f64::max),
                        n: all.iter().map(|o| o.n).sum(),
                        // The widest: no interval is claimed narrower than a shard's own.
                        ci_low: all.iter().map(|o| o.ci_low).fold(f64::INFINITY, f64::min),
                        ci_high: all.iter().map(|o| o.ci_high).fold(f64::NEG_INFINITY, f64::max),
                    })
                }
            }
        })
        .collect()
}

/// Which shard ran where, for the page, the summary and `timing.json`.
pub fn provenance(shards: &[ShardDir]) -> String {
    let mut machines: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for s in shards {
        let m = &s.manifest;
        machines.entry(m.machine()).or_default().push(format!("{}/{}", m.shard, m.shards));
    }
    let list: Vec<String> =
        machines.iter().map(|(machine, ks)| format!("{} on {machine}", ks.join(", "))).collect();
    let mut s = format!(
        "Shards. Merged from {} shard directories of a {}-way split: {}. A shard holds whole \
         configurations, so each configuration's timing samples come from one machine and one \
         session, and its AO time is taken from that session's own per-image overhead.",
        shards.len(),
        shards[0].manifest.shards,
        list.join("; ")
    );
    let workers: std::collections::BTreeSet<usize> =
        shards.iter().map(|s| s.manifest.timing.workers).collect();
    if workers.len() > 1 {
        let w: Vec<String> = workers.iter().map(|w| w.to_string()).collect();
        let _ = write!(s, " The shards ran with different numbers of workers ({}).", w.join(", "));
    }
    if machines.len() > 1 {
        let _ = write!(
            s,
            " Warning: the timings come from {} different machines, so times, AO times, efficiencies and \
             slopes against time compare configurations measured on different machines; compare times \
             only within one shard, or run the spec on one machine for timing claims.",
            machines.len()
        );
    } else {
        s.push_str(
            " All shards ran on one machine, in separate sessions (which may have met different loads).",
        );
    }
    s
}

/// The merged `timing.json`: the protocol, and per shard its machine, overhead and session, and
/// the keys of the records taken from it (so each record's time can be traced to its machine).
pub fn timing_json(
    shards: &[ShardDir],
    found: &[Option<(usize, &JobResult)>],
    protocol: Protocol,
    note: &str,
) -> serde_json::Value {
    let per_shard: Vec<serde_json::Value> = shards
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let m = &s.manifest;
            let keys: Vec<&str> =
                found.iter().flatten().filter(|(si, _)| *si == i).map(|(_, r)| r.key.as_str()).collect();
            serde_json::json!({
                "dir": s.dir.display().to_string(),
                "shard": m.shard,
                "shards": m.shards,
                "host": m.host,
                "cpu": m.cpu,
                "timing": m.timing,
                "overhead": s.timing.as_ref().map(|t| &t.overhead),
                "session": s.timing.as_ref().map(|t| t.session),
                "records": keys,
            })
        })
        .collect();
    let machines: std::collections::BTreeSet<String> = shards.iter().map(|s| s.manifest.machine()).collect();
    let v = serde_json::json!({
        "clock": timing::clock::NAME,
        "time_includes": timing::TIME_INCLUDES,
        "protocol": protocol,
        "machines": machines.len(),
        "note": note,
        "shards": per_shard,
    });
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shard::manifest::TimingOf;

    fn shard(k: u32, host: &str, workers: usize) -> ShardDir {
        let manifest = Manifest {
            hemilab_version: "0".into(),
            spec: "s".into(),
            spec_path: "s.toml".into(),
            plan: "p".into(),
            shard: k,
            shards: 3,
            jobs: 1,
            planned_jobs: 3,
            host: host.into(),
            cpu: "CPU X (8 CPUs)".into(),
            timing: TimingOf { repeats: 3, seed: 1, workers },
        };
        ShardDir { dir: PathBuf::from(format!("d{k}")), manifest, records: Vec::new(), timing: None }
    }

    #[test]
    fn provenance_names_machines_and_warns_when_several() {
        let one = provenance(&[shard(0, "a", 2), shard(1, "a", 2), shard(2, "a", 2)]);
        assert!(one.contains("0/3, 1/3, 2/3 on a (CPU X (8 CPUs))"), "{one}");
        assert!(one.contains("All shards ran on one machine") && !one.contains("Warning"), "{one}");
        let two = provenance(&[shard(0, "a", 2), shard(1, "b", 4), shard(2, "a", 2)]);
        assert!(two.contains("0/3, 2/3 on a (CPU X (8 CPUs)); 1/3 on b (CPU X (8 CPUs))"), "{two}");
        assert!(two.contains("Warning: the timings come from 2 different machines"), "{two}");
        assert!(two.contains("different numbers of workers (2, 4)"), "{two}");
    }
}
