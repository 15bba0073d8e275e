//! `run --shard`: which shard this process is (given, or from the batch scheduler's environment),
//! and the `shard.json` a shard leaves in its output directory so that `merge` can check what it
//! was: which spec and plan, which hemilab, which shard of how many, and on which machine.

use super::ShardArg;
use crate::error::{Error, Result};
use crate::io;
use crate::load::Loaded;
use crate::plan::{self, Plan};
use crate::shard::{self, Shard};
use crate::timing::Protocol;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The file name of a shard's manifest in its output directory.
pub const MANIFEST: &str = "shard.json";

/// `--shard K/N` as given, or `auto`: Slurm's array variables first, then a Kubernetes Indexed
/// Job's `JOB_COMPLETION_INDEX` with `--shards N`. `env` reads a variable (injected for tests).
pub fn resolve(
    arg: ShardArg,
    shards: Option<u32>,
    env: &dyn Fn(&str) -> Option<String>,
) -> Result<Shard, String> {
    let fixed = match arg {
        ShardArg::Fixed(s) => Some(s),
        ShardArg::Auto => None,
    };
    if let (Some(s), Some(n)) = (fixed, shards)
        && s.count != n
    {
        return Err(format!("--shard {s} and --shards {n} disagree about the number of shards"));
    }
    if let Some(s) = fixed {
        return Ok(s);
    }
    let num = |name: &str| -> Result<Option<u32>, String> {
        match env(name) {
            None => Ok(None),
            Some(v) => v
                .trim()
                .parse::<u32>()
                .map(Some)
                .map_err(|_| format!("--shard auto: {name}={v:?} is not a whole number")),
        }
    };
    if let Some(id) = num("SLURM_ARRAY_TASK_ID")? {
        let count = num("SLURM_ARRAY_TASK_COUNT")?.ok_or(
            "--shard auto: SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not (submit with \
             sbatch --array=0-(N-1))",
        )?;
        let min = num("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
        let k = id.checked_sub(min).filter(|k| *k < count).ok_or_else(|| {
            format!(
                "--shard auto: SLURM_ARRAY_TASK_ID={id} is not one of {count} consecutive tasks from \
                 SLURM_ARRAY_TASK_MIN={min}; submit the array as sbatch --array=0-{}",
                count.saturating_sub(1)
            )
        })?;
        if let Some(n) = shards.filter(|n| *n != count) {
            return Err(format!("--shards {n} disagrees with SLURM_ARRAY_TASK_COUNT={count}"));
        }
        return Shard::new(k, count).map_err(|e| format!("--shard auto: {e}"));
    }
    if let Some(k) = num("JOB_COMPLETION_INDEX")? {
        let n = shards.ok_or(
            "--shard auto: JOB_COMPLETION_INDEX is set (a Kubernetes Indexed Job) but the number of \
             shards is not: add --shards N, N being the Job's `completions`",
        )?;
        return Shard::new(k, n).map_err(|e| format!("--shard auto with JOB_COMPLETION_INDEX={k}: {e}"));
    }
    Err("--shard auto: neither a Slurm job array (SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_COUNT) nor a \
         Kubernetes Indexed Job (JOB_COMPLETION_INDEX) is set; outside a scheduler write --shard K/N"
        .into())
}

/// Fingerprint of what a spec asks for: its name, every planned job, the reference settings and
/// the timing settings. Shards of one spec have the same; `merge` refuses any other.
pub fn fingerprint(loaded: &Loaded, plan: &Plan) -> String {
    let spec = &loaded.spec;
    let r = &spec.reference;
    let rays = match r.rays {
        crate::spec::ReferenceRays::Auto => "auto".to_string(),
        crate::spec::ReferenceRays::Fixed(n) => n.to_string(),
    };
    let mut text = format!(
        "{};reference:rays={rays},replicates={},seed={},estimator={},adaptive={};timing:repeats={},seed={}",
        spec.name,
        r.replicates,
        r.seed,
        r.estimator.label(),
        r.adaptive,
        spec.timing.repeats,
        spec.timing.seed
    );
    for job in &plan.jobs {
        text.push(';');
        text.push_str(&job.canonical());
    }
    format!("{:016x}", plan::fnv1a64(text.as_bytes()))
}

/// The shard of every job of the spec's plan, as `run --shard` deals them.
pub fn partition(loaded: &Loaded, plan: &Plan, count: u32) -> Vec<u32> {
    shard::partition(plan, count, |job| resolution_of(loaded, job), loaded.spec.timing.repeats)
}

/// The jobs of one shard, in plan order.
pub fn select(loaded: &Loaded, plan: &Plan, s: Shard) -> Plan {
    shard::select(plan, s, |job| resolution_of(loaded, job), loaded.spec.timing.repeats)
}

fn resolution_of(loaded: &Loaded, job: &plan::Job) -> [u32; 2] {
    let (_, scene) = loaded.scene_of(job);
    [scene.resolution.0, scene.resolution.1]
}

/// Refuses, before any work, to run shard `s` (`mine`: its jobs of the whole plan `full`) into an
/// output directory whose records it would drop: one holding another shard's `shard.json`, or
/// records of jobs of the plan that are not this shard's (a whole run's, another shard's). A run
/// keeps only its own plan's records, so a second shard into one `--out` once kept only its own,
/// the first shard's gone. Each shard has its own directory (`Shard::dir_name`); `merge` puts them
/// together. A rerun of the same shard resumes as any run does.
pub fn check_out(
    out: &Path,
    spec: &str,
    full: &Plan,
    mine: &Plan,
    s: Shard,
    previous: &[&str],
) -> Result<()> {
    let what = "give each shard its own --out (by default out/NAME/shard-K-of-N) and put them together \
                with `hemilab merge`";
    if io::exists(&out.join(MANIFEST))
        && let Ok(m) = Manifest::read(out)
        && (m.spec != spec || m.shard != s.index || m.shards != s.count)
    {
        return Err(Error::input(
            out,
            format!(
                "holds shard {}/{} of spec '{}' ({MANIFEST}); shard {s} of spec '{spec}' would keep only its \
                 own records there and drop the others: {what}",
                m.shard, m.shards, m.spec
            ),
        ));
    }
    let image = |j: &plan::Job| crate::outdir::image_rel(j);
    let own: std::collections::HashSet<String> = mine.jobs.iter().map(image).collect();
    let others: std::collections::HashSet<String> =
        full.jobs.iter().map(image).filter(|i| !own.contains(i)).collect();
    let foreign: Vec<&str> = previous.iter().copied().filter(|i| others.contains(*i)).collect();
    if let Some(first) = foreign.first() {
        return Err(Error::input(
            out,
            format!(
                "holds records of jobs of other shards ({} of them, e.g. {first}: a whole run's or another \
                 shard's); shard {s} would keep only its own and drop them: {what}",
                foreign.len()
            ),
        ));
    }
    Ok(())
}

/// How a shard's renders were timed, as the report needs it back.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TimingOf {
    pub repeats: u32,
    pub seed: u64,
    pub workers: usize,
}

/// `shard.json`: written when a shard starts (so an unfinished one is recognised too).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    pub hemilab_version: String,
    /// The spec's name and the path it was run from (for messages only).
    pub spec: String,
    pub spec_path: String,
    /// `fingerprint` of the spec and its plan.
    pub plan: String,
    pub shard: u32,
    pub shards: u32,
    /// Jobs of this shard, and of the whole plan.
    pub jobs: usize,
    pub planned_jobs: usize,
    /// The machine: timings of different machines are not comparable, so the merged report says
    /// which shard ran where.
    pub host: String,
    pub cpu: String,
    pub timing: TimingOf,
}

impl Manifest {
    pub fn new(loaded: &Loaded, plan: &Plan, s: Shard, jobs: usize, protocol: Protocol) -> Self {
        Self {
            hemilab_version: env!("CARGO_PKG_VERSION").into(),
            spec: loaded.spec.name.clone(),
            spec_path: loaded.spec.path.display().to_string(),
            plan: fingerprint(loaded, plan),
            shard: s.index,
            shards: s.count,
            jobs,
            planned_jobs: plan.jobs.len(),
            host: io::hostname(),
            cpu: io::cpu_model(),
            timing: TimingOf { repeats: protocol.repeats, seed: protocol.seed, workers: protocol.workers },
        }
    }

    /// The machine, as the report names it.
    pub fn machine(&self) -> String {
        format!("{} ({})", self.host, self.cpu)
    }

    pub fn write(&self, dir: &Path) -> Result<()> {
        let text = serde_json::to_string_pretty(self).unwrap_or_default() + "\n";
        io::write_atomic(&dir.join(MANIFEST), text.as_bytes())
    }

    /// The manifest of the shard output directory `dir`.
    pub fn read(dir: &Path) -> Result<Self> {
        let path = dir.join(MANIFEST);
        if !io::exists(&path) {
            let what = if io::exists(dir) {
                "not found: is this the output directory of `hemilab run --shard K/N`?"
            } else {
                "not found: the shard directory does not exist"
            };
            return Err(Error::input(&path, what));
        }
        serde_json::from_str(&io::read_string(&path)?)
            .map_err(|e| Error::input(&path, format!("not a shard manifest ({e})")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |name| vars.iter().find(|(k, _)| *k == name).map(|(_, v)| v.to_string())
    }

    fn auto(vars: &[(&str, &str)], shards: Option<u32>) -> Result<Shard, String> {
        resolve(ShardArg::Auto, shards, &env(vars))
    }

    #[test]
    fn slurm_array() {
        let s = auto(&[("SLURM_ARRAY_TASK_ID", "1"), ("SLURM_ARRAY_TASK_COUNT", "3")], None);
        assert_eq!(s, Ok(Shard { index: 1, count: 3 }));
        // An array numbered from 1 is shifted by its minimum.
        let vars =
            [("SLURM_ARRAY_TASK_ID", "3"), ("SLURM_ARRAY_TASK_COUNT", "3"), ("SLURM_ARRAY_TASK_MIN", "1")];
        assert_eq!(auto(&vars, None), Ok(Shard { index: 2, count: 3 }));
        let e = auto(&[("SLURM_ARRAY_TASK_ID", "3"), ("SLURM_ARRAY_TASK_COUNT", "3")], None).unwrap_err();
        assert!(e.contains("--array=0-2"), "{e}");
        let e = auto(&[("SLURM_ARRAY_TASK_ID", "0")], None).unwrap_err();
        assert!(e.contains("SLURM_ARRAY_TASK_COUNT is not"), "{e}");
        let e = auto(&[("SLURM_ARRAY_TASK_ID", "x"), ("SLURM_ARRAY_TASK_COUNT", "3")], None).unwrap_err();
        assert!(e.contains("not a whole number"), "{e}");
        let e = auto(&[("SLURM_ARRAY_TASK_ID", "0"), ("SLURM_ARRAY_TASK_COUNT", "3")], Some(4)).unwrap_err();
        assert!(e.contains("disagrees"), "{e}");
    }

    #[test]
    fn kubernetes_indexed_job() {
        assert_eq!(auto(&[("JOB_COMPLETION_INDEX", "4")], Some(5)), Ok(Shard { index: 4, count: 5 }));
        assert!(auto(&[("JOB_COMPLETION_INDEX", "4")], None).unwrap_err().contains("--shards N"));
        assert!(auto(&[("JOB_COMPLETION_INDEX", "5")], Some(5)).unwrap_err().contains("0 to 4"));
    }

    #[test]
    fn neither_scheduler_is_a_clear_error() {
        let e = auto(&[], None).unwrap_err();
        assert!(e.contains("SLURM_ARRAY_TASK_ID") && e.contains("JOB_COMPLETION_INDEX") && e.contains("K/N"));
    }

    #[test]
    fn fixed_shard_wins_but_must_agree_with_shards() {
        let s = Shard::new(0, 2).unwrap();
        let slurm = [("SLURM_ARRAY_TASK_ID", "1"), ("SLURM_ARRAY_TASK_COUNT", "3")];
        assert_eq!(resolve(ShardArg::Fixed(s), None, &env(&slurm)), Ok(s));
        assert!(resolve(ShardArg::Fixed(s), Some(3), &env(&[])).unwrap_err().contains("disagree"));
    }
}
