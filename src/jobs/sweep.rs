//! `advise`'s records on disk: what a sweep left (for a resume and for `--from`), the finalists'
//! error images read back for the winner map, and the stage's results.json rewritten while jobs
//! finish (`Store`). The resume rule is `executor::resumed`'s, the same as `run`'s.

use super::executor::{self, Session};
use crate::error::{Error, Result};
use crate::load::Loaded;
use crate::plan::Plan;
use crate::reference::store::Reference;
use crate::results::JobResult;
use crate::spec::Row;
use crate::{metrics, outdir};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// `--from`: the sweep's records from `dir` (by run key, as a resume would take them); refused
/// unless every job is there.
pub fn stored(
    loaded: &Loaded,
    plan: &Plan,
    reference: &Reference,
    previous: &HashMap<String, JobResult>,
    stage: &Path,
    dir: &Path,
) -> Result<(Vec<JobResult>, Session)> {
    let found: Vec<Option<JobResult>> = present(loaded, plan, reference, previous, stage);
    let have = found.iter().flatten().count();
    if have < found.len() {
        return Err(Error::input(
            dir,
            format!(
                "its sweep is unfinished or of other settings: {have} of {} jobs have records for this scene, \
                 reference and version; run `hemilab advise` with --out {} to finish it",
                found.len(),
                dir.display()
            ),
        ));
    }
    let overhead = vec![None; loaded.spec.scenes.len()];
    let session = Session { overhead, renders: 0, cpu_s: 0.0, wall_s: 0.0, reused: have };
    Ok((found.into_iter().flatten().collect(), session))
}

/// The records `previous` holds for `plan`'s jobs, in plan order (`None`: not there).
pub fn present(
    loaded: &Loaded,
    plan: &Plan,
    reference: &Reference,
    previous: &HashMap<String, JobResult>,
    stage: &Path,
) -> Vec<Option<JobResult>> {
    let scene = &loaded.scenes[0];
    plan.jobs
        .iter()
        .map(|j| {
            executor::resumed(previous, &executor::run_key(j, scene, reference, loaded.spec.flip_ppd), stage)
                .cloned()
        })
        .collect()
}

/// Each finalist record's image − reference on covered pixels, by (configuration, rays,
/// replicate), read back from the images the finalists' renders wrote.
pub fn error_images(
    plan: &Plan,
    records: &[Option<JobResult>],
    reference: &Reference,
    stage: &Path,
) -> Result<HashMap<(Row, u32, u32), Vec<f32>>> {
    let mut out = HashMap::new();
    for (job, record) in plan.jobs.iter().zip(records) {
        let Some(r) = record else { continue };
        let ao = outdir::read_image(stage, &r.image)?;
        let e = metrics::error_image(&ao, &reference.mean, &reference.coverage)
            .map_err(|e| Error::Refused(format!("job {}: {e}", job.file_stem())))?;
        out.insert((job.row().canonical(), job.rays, job.replicate), e.data);
    }
    Ok(out)
}

/// How often the records are rewritten while jobs finish: rewriting every record after every one
/// of a sweep's ~1,500 jobs would cost more than the renders; a killed run loses at most this. As
/// often as `run` rewrites its results (`outdir::Saver`).
const WRITE_EVERY: Duration = crate::outdir::Saver::EVERY;

/// The stage's results.json: every earlier record and this run's, rewritten every `WRITE_EVERY`.
pub struct Store<'a> {
    dir: &'a Path,
    /// Finished phases' records, then the earlier ones they do not replace.
    kept: Mutex<Vec<JobResult>>,
    /// The running phase's records so far.
    current: Mutex<Vec<JobResult>>,
    last: Mutex<Instant>,
}

impl<'a> Store<'a> {
    pub fn new(dir: &'a Path, previous: &HashMap<String, JobResult>) -> Self {
        let mut kept: Vec<JobResult> = previous.values().cloned().collect();
        kept.sort_by(|a, b| a.key.cmp(&b.key));
        Self {
            dir,
            kept: Mutex::new(kept),
            current: Mutex::new(Vec::new()),
            last: Mutex::new(Instant::now()),
        }
    }

    fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
        m.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A running phase's new records join its earlier ones; those and the kept ones are written if
    /// `now` or it is time.
    pub fn write(&self, new: &[JobResult], now: bool) -> Result<()> {
        let mut current = Self::lock(&self.current);
        current.extend_from_slice(new);
        let mut last = Self::lock(&self.last);
        if !now && last.elapsed() < WRITE_EVERY {
            return Ok(());
        }
        let kept = Self::lock(&self.kept);
        let mine: std::collections::HashSet<&str> = current.iter().map(|r| r.key.as_str()).collect();
        let all: Vec<JobResult> =
            current.iter().chain(kept.iter().filter(|r| !mine.contains(r.key.as_str()))).cloned().collect();
        outdir::write_results(self.dir, &all)?;
        *last = Instant::now();
        Ok(())
    }

    /// A finished phase's records join the kept ones (replacing theirs), and all are written.
    pub fn add(&self, done: &[JobResult]) -> Result<()> {
        Self::lock(&self.current).clear();
        {
            let mut kept = Self::lock(&self.kept);
            let mine: std::collections::HashSet<&str> = done.iter().map(|r| r.key.as_str()).collect();
            let rest: Vec<JobResult> =
                kept.iter().filter(|r| !mine.contains(r.key.as_str())).cloned().collect();
            *kept = done.iter().cloned().chain(rest).collect();
        }
        self.write(&[], true)
    }
}
