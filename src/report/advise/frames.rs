//! advise's images after a real-time pipeline, drawn by the run page's own code
//! (`report::run::realtime_figures::final_frames`, `report::run::viewer::section`), not a copy:
//! the final frames of the top configurations beside the reference for each camera, cropped where
//! the two best differ most, with their signed-error and FLIP maps, and the comparison viewer.
//! The top configurations are every ray budget's and camera's winners by RMSE and by FLIP, its
//! near-ties (at most `TOP` of them) and the paper's default.

use crate::advice::analysis::{Analysis, Measured};
use crate::compare::PAPER_DEFAULT;
use crate::error::Result;
use crate::load::Loaded;
use crate::outdir::File;
use crate::report::Figure;
use crate::report::run::data::{Flip, ReportInput};
use crate::spec::{Group, GroupKind, Row};

/// Near-ties per ray budget and camera shown besides the winners.
pub const TOP: usize = 3;

/// The rows the images show: per ray budget and camera, the winner by RMSE, by FLIP and the
/// first `TOP` near-ties, then the paper's default; in that order, each once.
pub fn top_rows(a: &Analysis) -> Vec<Row> {
    let mut rows: Vec<Row> = Vec::new();
    let mut add = |r: Row| {
        if !rows.contains(&r) {
            rows.push(r);
        }
    };
    for x in &a.per_ray {
        x.best().into_iter().chain(x.best_flip()).for_each(|e| add(e.row));
        x.near_ties().take(TOP).for_each(|e| add(e.row));
    }
    add(PAPER_DEFAULT);
    rows
}

/// The figures (crop grids) and the viewer's section (HTML; empty for none), their files added to
/// `files`. Nothing after the paper's raw image (advise keeps no sweep image there).
pub fn images(m: &Measured, a: &Analysis, files: &mut Vec<File>) -> Result<(Vec<Figure>, String)> {
    let setup = m.setup;
    if setup.pipeline == crate::denoise::Pipeline::RAW || m.stored.iter().all(|r| r.image.is_empty()) {
        return Ok((Vec::new(), String::new()));
    }
    let spec = &setup.loaded.spec;
    let Some(first) = spec.groups.first() else { return Ok((Vec::new(), String::new())) };
    // One group of the top rows under every schedule swept: what the run page's code draws from.
    let mut schedules: Vec<crate::sampling::Schedule> = Vec::new();
    for g in &spec.groups {
        schedules.extend(g.schedules.iter().copied().filter(|s| !schedules.contains(s)).collect::<Vec<_>>());
    }
    let group = Group {
        kind: GroupKind::Table,
        name: "advise".into(),
        rows: top_rows(a),
        schedules,
        ..first.clone()
    };
    let loaded = Loaded {
        spec: crate::spec::Spec { groups: vec![group], ..spec.clone() },
        scenes: setup.loaded.scenes.clone(),
    };
    let references = std::slice::from_ref(m.reference);
    let data = ReportInput {
        loaded: &loaded,
        references,
        views: m.views,
        results: &m.stored,
        aggs: Vec::new(),
        protocol: m.protocol,
        overhead: m.session.overhead.clone(),
        notes: Vec::new(),
        images: m.images,
        flip: Some(Flip {
            ppd: crate::metrics::DEFAULT_PPD,
            map: &crate::metrics::ldr_flip_map,
            mean: &crate::metrics::mean_flip,
        }),
    };
    let figures = crate::report::run::realtime_figures::final_frames(&data, files)?;
    let viewer = crate::report::run::viewer::section(&data, files)?.unwrap_or_default();
    Ok((figures, viewer))
}
