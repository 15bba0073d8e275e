//! `hemilab run`'s report: what it is drawn from (`data`), the answer, the claims' verdicts, the
//! figures and the page — one exporter, like hyperfine's `export/`.

pub mod answer;
pub mod data;
pub mod draw;
pub mod equal_time;
pub mod figures;
pub mod page;
pub mod quotes;
pub mod rays;
pub mod realtime;
pub mod realtime_figures;
pub mod summary;
pub mod verdicts;

use crate::error::Result;
use crate::jobs::executor::Session;
use crate::load::Loaded;
use crate::outdir;
use crate::reference::store::Reference;
use crate::results::{self, JobResult};
use crate::timing::Protocol;
use std::path::Path;

/// The whole run's outputs after its records: `aggregates.csv`, `slopes.json`, `quotes.md` (with
/// `cost`, the session as `timing.json` records it), the figures and the
/// page (with `notes` after its timing text), in `out`; returns what to print. `run` and `merge`
/// both end here.
#[allow(clippy::too_many_arguments)]
pub fn write(
    loaded: &Loaded,
    references: &[Reference],
    results: &[JobResult],
    protocol: Protocol,
    session: &Session,
    cost: Option<quotes::Cost>,
    notes: Vec<String>,
    out: &Path,
) -> Result<summary::Summary> {
    outdir::write_file(out, outdir::QUOTES_MD, quotes::quotes(&loaded.spec, results, cost).as_bytes())?;
    let aggs = results::aggregate(results);
    outdir::write_aggregates(out, &loaded.spec, &aggs)?;
    let summary = summary::summary(&loaded.spec, references, &aggs, session);
    let mut data =
        data::ReportInput::new(loaded, references, results, aggs, protocol, session.overhead.clone());
    data.notes = notes;
    let mut figures = figures::write_all(&data, out)?;
    figures.other.extend(realtime_figures::write_all(&data, out)?);
    page::write(&data, &figures, out)?;
    Ok(summary)
}
