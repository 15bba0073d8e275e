//! `hemilab run`'s report: what it is drawn from (`data`), the answer, the claims' verdicts, the
//! figures and the page — one exporter, like hyperfine's `export/`: it receives the records and
//! `compare`'s comparisons and returns bytes (`Report::files`), which `outdir::write_files` writes.

pub mod answer;
pub mod data;
pub mod draw;
pub mod equal_time;
pub mod figures;
pub mod integrands;
pub mod page;
pub mod quotes;
pub mod rays;
pub mod realtime;
pub mod realtime_figures;
pub mod summary;
pub mod verdicts;
pub mod viewer;

use crate::error::Result;
use crate::image::Image;
use crate::jobs::executor::Session;
use crate::jobs::reference::ViewReferences;
use crate::load::Loaded;
use crate::outdir::{self, File};
use crate::reference::store::Reference;
use crate::results::{self, JobResult};
use crate::timing::Protocol;

/// What a run's report is made of: the spec and scenes, their references, the records, how they
/// were timed (the session as `timing.json` records it, and its `cost` for `quotes.md`), paragraphs
/// the page adds after its timing text (`merge`: which shard ran where), and how a record's kept
/// image is read (`outdir::record_image`, by the command that owns the files).
pub struct Run<'a> {
    pub loaded: &'a Loaded,
    pub references: &'a [Reference],
    /// The camera paths' frames' references (`jobs::reference::obtain_views`; empty without paths).
    pub views: &'a ViewReferences,
    pub results: &'a [JobResult],
    pub protocol: Protocol,
    pub session: &'a Session,
    pub cost: Option<quotes::Cost>,
    pub notes: Vec<String>,
    pub images: &'a (dyn Fn(&JobResult) -> Result<(Image, Image)> + Sync),
}

/// The report's files, in the order to write them (the page last), and what to print.
pub struct Report {
    pub files: Vec<File>,
    pub summary: summary::Summary,
}

/// The whole run's outputs after its records: `quotes.md`, `aggregates.csv`, `slopes.json`, the
/// figures, `equal_time.csv` and the page. `run` and `merge` both end here.
pub fn report(run: Run) -> Result<Report> {
    let spec = &run.loaded.spec;
    let mut files = vec![File::new(outdir::QUOTES_MD, quotes::quotes(spec, run.results, run.cost))];
    let aggs = results::aggregate(run.results);
    files.push(File::new(outdir::AGGREGATES_CSV, results::aggregates_to_csv(&aggs)));
    let slopes = serde_json::to_string_pretty(&results::sweep_slopes(spec, &aggs)).unwrap_or_default();
    files.push(File::new(outdir::SLOPES_JSON, slopes));
    let summary = summary::summary(spec, run.references, run.results, &aggs, run.session);
    let data = data::ReportInput {
        loaded: run.loaded,
        references: run.references,
        views: run.views,
        results: run.results,
        aggs,
        protocol: run.protocol,
        overhead: run.session.overhead.clone(),
        notes: run.notes,
        images: run.images,
        flip: Some(data::Flip {
            ppd: spec.flip_ppd,
            map: &crate::metrics::ldr_flip_map,
            mean: &crate::metrics::mean_flip,
        }),
    };
    let mut figures = figures::all(&data, &mut files)?;
    figures.other.extend(realtime_figures::all(&data, &mut files)?);
    let viewer = viewer::section(&data, &mut files)?;
    page::page(&data, &figures, viewer.as_deref().unwrap_or(""), &mut files);
    Ok(Report { files, summary })
}
