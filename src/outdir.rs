//! The output directory of `run`, `merge` and `advise`: every file it holds is named here once, and
//! read or written here (through `io`, atomically), so a rerun, a merge and the report agree on
//! what is where.

use crate::error::{Error, Result};
use crate::image::{Channel, Provenance};
use crate::io;
use crate::plan::Job;
use crate::render::RenderOutput;
use crate::results::{self, JobResult};
use crate::spec::Spec;
use crate::timing::{RunTiming, SessionRecord, Summary};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// One record per image, as JSON (the resume source) and CSV.
pub const RESULTS_JSON: &str = "results.json";
/// Records a run has made since results.json was last written whole, one JSON line each.
pub const RESULTS_JOURNAL: &str = "results.journal.jsonl";
pub const RESULTS_CSV: &str = "results.csv";
/// One line per configuration.
pub const AGGREGATES_CSV: &str = "aggregates.csv";
/// Each convergence sweep's configurations at equal time: MSE at every budget, both views.
pub const EQUAL_TIME_CSV: &str = "equal_time.csv";
/// Each convergence sweep's fitted slopes.
pub const SLOPES_JSON: &str = "slopes.json";
/// The numbers the README quotes (`report::run::quotes`).
pub const QUOTES_MD: &str = "quotes.md";
/// How the run was timed.
pub const TIMING_JSON: &str = "timing.json";
/// The report: one offline page, and its Markdown twin.
pub const INDEX_HTML: &str = "index.html";
pub const REPORT_MD: &str = "report.md";
/// `advise`'s answer, for programs and for people.
pub const ADVICE_JSON: &str = "advice.json";
pub const ADVICE_MD: &str = "advice.md";
/// Every measured image, as EXR.
pub const IMAGES: &str = "images";
/// advise's sweep as asked (`advice::setup::Request`): what `advise --from` sets up again, and the
/// mark of a directory advise may replace whole.
pub const ADVISE_REQUEST: &str = "sweep.json";

/// A job's image, relative to the output directory (the record's `image` column).
pub fn image_rel(job: &Job) -> String {
    format!("{IMAGES}/{}.exr", job.file_stem())
}

/// The output directory, and its `images/` when images are written; refused before any work if
/// either cannot be written. The temporary files a killed run left there (`kill -9`: its atomic
/// writes never renamed) are removed, and said so.
pub fn prepare(out: &Path, images: bool) -> Result<()> {
    io::ensure_writable_dir(out)?;
    if images {
        io::ensure_writable_dir(&out.join(IMAGES))?;
    }
    let mut removed = io::remove_stale_temp_files(out)?;
    removed.extend(io::remove_stale_temp_files(&out.join(IMAGES))?);
    if !removed.is_empty() {
        eprintln!(
            "note: removed {} temporary file(s) an interrupted run left in {} (e.g. {})",
            removed.len(),
            out.display(),
            removed[0].display()
        );
    }
    Ok(())
}

/// A measured job's image (AO and coverage) as `images/<job>.exr`, with its provenance in the
/// header; returns its relative path.
pub fn write_image(out: &Path, job: &Job, output: &RenderOutput, provenance: &Provenance) -> Result<String> {
    let image = image_rel(job);
    io::write_exr_with(
        &out.join(&image),
        &[Channel { name: "Y", image: &output.ao }, Channel { name: "A", image: &output.coverage }],
        Some(provenance),
    )?;
    Ok(image)
}

/// The AO channel of an image `write_image` wrote (`image` as the record names it).
pub fn read_image(out: &Path, image: &str) -> Result<crate::image::Image> {
    let path = out.join(image);
    io::read_exr(&path)?
        .into_iter()
        .find(|(name, _)| name == "Y")
        .map(|(_, i)| i)
        .ok_or_else(|| Error::input(&path, "has no Y channel"))
}

/// Whether the image a record names is on disk (a record without its image is not finished). A
/// record that names none (advise's sweep: only its numbers are used) needs none.
pub fn has_image(out: &Path, image: &str) -> bool {
    image.is_empty() || io::exists(&out.join(image))
}

/// `results.json` and `results.csv`, written whole (at the end of a run, and by phases of advise);
/// the journal of the records before them is then removed.
pub fn write_results(out: &Path, results: &[JobResult]) -> Result<()> {
    io::write_atomic(&out.join(RESULTS_JSON), results::to_json(results).as_bytes())?;
    io::write_atomic(&out.join(RESULTS_CSV), results::to_csv(results).as_bytes())?;
    io::remove_file_if_exists(&out.join(RESULTS_JOURNAL))
}

/// Appends records a run has just made to the journal beside `results.json`, one JSON line each:
/// what a killed run keeps. Writing every record again after every job would cost time growing
/// with the square of the records (a 4,000-job real-time run spent most of its wall time so).
pub fn append_results(out: &Path, records: &[JobResult]) -> Result<()> {
    let mut text = String::new();
    for r in records {
        text.push_str(&serde_json::to_string(r).expect("plain records always serialize"));
        text.push('\n');
    }
    io::append(&out.join(RESULTS_JOURNAL), text.as_bytes())
}

/// How a running command saves its records: each render's new ones appended to the journal at
/// once, and `results.json` (with `results.csv`) rewritten whole from every record so far at most
/// every `EVERY` (then the journal starts again), so the files a person opens stay current and a
/// kill loses nothing.
pub struct Saver<'a> {
    out: &'a Path,
    last: std::sync::Mutex<Option<std::time::Instant>>,
}

impl<'a> Saver<'a> {
    /// How often `results.json` is rewritten while jobs finish.
    pub const EVERY: std::time::Duration = std::time::Duration::from_secs(2);

    pub fn new(out: &'a Path) -> Self {
        Self { out, last: std::sync::Mutex::new(None) }
    }

    /// Saves `new`; `so_far` is every record of the run so far (new ones included).
    pub fn save(&self, new: &[JobResult], so_far: &[Option<JobResult>]) -> Result<()> {
        append_results(self.out, new)?;
        let mut last = self.last.lock().unwrap_or_else(|e| e.into_inner());
        if last.is_none_or(|t| t.elapsed() >= Self::EVERY) {
            write_results(self.out, &so_far.iter().flatten().cloned().collect::<Vec<_>>())?;
            *last = Some(std::time::Instant::now());
        }
        Ok(())
    }
}

/// The records in `dir`'s `results.json` and then its journal (a record of the journal replaces
/// the one of the same key), none if neither is there. A results file that cannot be read is an
/// error naming it (`explain` words the parse error), not something to overwrite; a journal's
/// cut-off last line (a run killed mid-write) is dropped.
pub fn read_results(dir: &Path, explain: &dyn Fn(String) -> String) -> Result<Vec<JobResult>> {
    let path = dir.join(RESULTS_JSON);
    let mut list = if io::exists(&path) {
        results::from_json(&io::read_string(&path)?)
            .map_err(|e| Error::input(&path, explain(e.to_string())))?
    } else {
        Vec::new()
    };
    let journal = dir.join(RESULTS_JOURNAL);
    if io::exists(&journal) {
        let text = io::read_string(&journal)?;
        let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
        let mut at: HashMap<String, usize> =
            list.iter().enumerate().map(|(i, r)| (r.key.clone(), i)).collect();
        for (n, line) in lines.iter().enumerate() {
            let r = match results::from_json(&format!("[{line}]")) {
                Ok(mut v) if v.len() == 1 => v.remove(0),
                // The last line of a killed run may be cut off: it is redone.
                _ if n + 1 == lines.len() && !text.ends_with('\n') => break,
                Ok(_) | Err(_) => {
                    return Err(Error::input(&journal, explain(format!("line {} is not a record", n + 1))));
                }
            };
            match at.get(&r.key) {
                Some(&i) => list[i] = r,
                None => {
                    at.insert(r.key.clone(), list.len());
                    list.push(r);
                }
            }
        }
    }
    Ok(list)
}

/// Folds the journal into `results.json` and `results.csv` (written whole, the journal then
/// removed): before a message says the finished jobs are saved, so that the files a person opens
/// hold every one of them, not only those of the last periodic write.
pub fn fold_journal(out: &Path) -> Result<()> {
    if !io::exists(&out.join(RESULTS_JOURNAL)) {
        return Ok(());
    }
    let list = read_results(out, &|e| e)?;
    write_results(out, &list)
}

/// Finished records of an earlier run, by key.
pub fn previous_results(out: &Path) -> Result<HashMap<String, JobResult>> {
    let list = read_results(out, &|e| format!("cannot resume from it ({e}); move it away or pass --force"))?;
    Ok(list.into_iter().map(|r| (r.key.clone(), r)).collect())
}

/// `timing.json`.
pub fn write_timing(out: &Path, timing: &RunTiming) -> Result<()> {
    io::write_atomic(&out.join(TIMING_JSON), timing.to_json().as_bytes())
}

/// A merged run's `timing.json` (its shards' records side by side: `shard::merge::timing_json`).
pub fn write_merged_timing(out: &Path, timing: &serde_json::Value) -> Result<()> {
    let text = serde_json::to_string_pretty(timing).unwrap_or_default();
    io::write_atomic(&out.join(TIMING_JSON), text.as_bytes())
}

/// `dir`'s `timing.json` of a run, if it is there and parses.
pub fn read_timing(dir: &Path) -> Option<RunTiming> {
    RunTiming::from_json(&io::read_string(&dir.join(TIMING_JSON)).ok()?).ok()
}

/// The overhead an earlier session measured (`timing.json`), for a run that rendered nothing.
pub fn previous_overhead(out: &Path, spec: &Spec) -> Vec<Option<Summary>> {
    let v = read_timing(out);
    spec.scenes.iter().map(|s| v.as_ref()?.overhead_of(&s.name)).collect()
}

/// The `session` an earlier run recorded in `timing.json` (what rendering these records cost), for
/// a rerun that rendered nothing: it keeps that record rather than replacing it with its own
/// zero-render session, so the cost a README quotes survives a resume.
pub fn previous_session(out: &Path) -> Option<SessionRecord> {
    let s = read_timing(out)?.session;
    (s.timed_renders > 0).then_some(s)
}

/// A file a report made (`report::run`, `report::advise`): its name in the output directory and
/// its bytes. The report only makes them; [`write_files`] writes them.
#[derive(Debug, Clone, PartialEq)]
pub struct File {
    pub name: String,
    pub bytes: Vec<u8>,
}

impl File {
    pub fn new(name: &str, bytes: impl Into<Vec<u8>>) -> Self {
        Self { name: name.to_string(), bytes: bytes.into() }
    }
}

/// The one door of a report's files: each of `files` written atomically, in order (a report puts
/// its page last, so a page never names a figure not yet there), then each of `stale` removed — a
/// file an earlier run left that this one does not make, which would mislead.
pub fn write_files(out: &Path, files: &[File], stale: &[&str]) -> Result<()> {
    for f in files {
        io::write_atomic(&out.join(&f.name), &f.bytes)?;
    }
    for name in stale {
        io::remove_file_if_exists(&out.join(name))?;
    }
    Ok(())
}

/// A record's kept image (`Y`, what was measured) and its coverage (`A`), read from `out`: what
/// the report's image figures are drawn from.
pub fn record_image(out: &Path, r: &JobResult) -> Result<(crate::image::Image, crate::image::Image)> {
    let path = out.join(&r.image);
    let channels = io::read_exr(&path)?;
    let take = |name: &str| {
        channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, img)| img.clone())
            .ok_or_else(|| Error::input(&path, format!("image lacks channel '{name}'")))
    };
    Ok((take("Y")?, take("A")?))
}

/// The report's entry point, for the closing line.
pub fn index(out: &Path) -> PathBuf {
    out.join(INDEX_HTML)
}

/// advise's default output directory for a scene file's stem and a pipeline: `out/advise-room`
/// for raw frames (the paper's question), `out/advise-room-svgf` after a pipeline, so that one
/// pipeline's advice never replaces another's.
pub fn advise_default(stem: &str, pipeline: &str) -> PathBuf {
    let name = if pipeline == crate::denoise::Pipeline::RAW.to_string() {
        format!("advise-{stem}")
    } else {
        format!("advise-{stem}-{pipeline}")
    };
    Path::new("out").join(name)
}

/// Where advise builds its output set before the set replaces `out` in one step
/// ([`commit_advise_stage`]): a hidden sibling, `.<name>.partial`, on the same filesystem. A run
/// killed before the end leaves it, and the next run resumes from its records.
pub fn advise_stage(out: &Path) -> Result<PathBuf> {
    let abs = std::path::absolute(out).map_err(|e| Error::io(out, e))?;
    match (abs.parent(), abs.file_name()) {
        (Some(parent), Some(name)) => Ok(parent.join(format!(".{}.partial", name.to_string_lossy()))),
        _ => Err(Error::Usage(format!("--out {}: name a directory below another one", out.display()))),
    }
}

/// Refuses, before any work, an `out` that advise may not replace whole: it must be absent, empty,
/// or an earlier advise's (its `ADVISE_REQUEST` is there), and its parent writable.
pub fn check_advise_out(out: &Path) -> Result<()> {
    io::ensure_writable_dir(out)?;
    let entries = io::list_dir(out)?;
    if !entries.is_empty() && !io::exists(&out.join(ADVISE_REQUEST)) {
        return Err(Error::input(
            out,
            format!(
                "holds files advise did not write (no {ADVISE_REQUEST}); advise replaces its output directory \
                 whole, so name a new or empty one, or an earlier advise's"
            ),
        ));
    }
    Ok(())
}

/// The stage, created if missing (a killed run's is kept: its records resume), with every image
/// under `sources`' `images/` linked in where the stage lacks it, so that their records resume.
pub fn begin_advise_stage(out: &Path, sources: &[&Path]) -> Result<PathBuf> {
    let stage = advise_stage(out)?;
    io::create_dir_all(&stage.join(IMAGES))?;
    for dir in sources {
        for image in io::list_dir(&dir.join(IMAGES))? {
            let Some(name) = image.file_name() else { continue };
            let to = stage.join(IMAGES).join(name);
            if !io::exists(&to) && image.extension().is_some_and(|e| e == "exr") {
                io::link_or_copy(&image, &to)?;
            }
        }
    }
    Ok(stage)
}

/// Puts the finished stage in place of `out` in one step (`io::exchange_dirs`), then removes the
/// old set (now at the stage's path); a reader sees the old set or the new one, never a mix.
pub fn commit_advise_stage(stage: &Path, out: &Path) -> Result<()> {
    if io::exists(out) {
        io::exchange_dirs(stage, out)?;
        io::remove_dir_all_if_exists(stage)
    } else {
        io::rename(stage, out)
    }
}

/// `ADVISE_REQUEST`'s text in `dir`.
pub fn read_advise_request(dir: &Path) -> Result<String> {
    io::read_string(&dir.join(ADVISE_REQUEST))
}

/// `ADVISE_REQUEST` in `dir`.
pub fn write_advise_request(dir: &Path, text: &str) -> Result<()> {
    io::write_atomic(&dir.join(ADVISE_REQUEST), text.as_bytes())
}
