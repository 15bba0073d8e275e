//! advise's analysis: the sweep's records → each configuration's ladder (`compare::equal_time::curve`,
//! the ladders `run` compares too) → the budgets' interpolated rankings (`compare::budget::rank`) →
//! the finalists to measure → the answers from their records (`advice::answer`) → the winner maps.
//! `report::advise` formats what it finds.

use crate::advice::answer::{self, Answer};
use crate::advice::setup::Setup;
use crate::advice::winner::{self, Pixel};
use crate::compare::PAPER_DEFAULT;
use crate::compare::budget::{Curve, Metric, rank};
use crate::compare::equal_time::{TimeView, curve};
use crate::compare::per_ray::{self, AtRays};
use crate::jobs::executor::Session;
use crate::metrics::covered;
use crate::reference::store::Reference;
use crate::results::JobResult;
use crate::spec::Row;
use crate::timing::{Protocol, Summary};
use std::collections::HashMap;
use std::path::PathBuf;

/// What advise measured.
pub struct Measured<'a> {
    pub setup: &'a Setup,
    pub reference: &'a Reference,
    /// The sweep's records, by plan index.
    pub results: Vec<JobResult>,
    /// The camera paths' frames' references (empty without a moving or jittered camera).
    pub views: &'a crate::jobs::reference::ViewReferences,
    /// A kept record's image and its coverage (the sweep's after a real-time pipeline, the
    /// finalists'), read from where advise writes them (`outdir::record_image`).
    pub images:
        &'a (dyn Fn(&JobResult) -> crate::error::Result<(crate::image::Image, crate::image::Image)> + Sync),
    /// The sweep's records as stored (each with its real pipeline, frame and camera), for the
    /// page's final frames and viewer.
    pub stored: Vec<JobResult>,
    /// The finalists' records (`setup::verify_jobs`), every budget's.
    pub verified: Vec<JobResult>,
    /// By (configuration, rays, replicate): a finalist's image − reference on covered pixels (0
    /// elsewhere), for the winner map.
    pub errors: HashMap<(Row, u32, u32), Vec<f32>>,
    /// Replicates of every finalist (`verify_replicates`).
    pub replicates: u32,
    /// The sweep's session and the finalists' (`None`: nothing rendered for them).
    pub session: Session,
    pub verify_session: Option<Session>,
    pub protocol: Protocol,
    /// Jobs rendered and reused (an earlier run's records, `jobs::executor::resumed`).
    pub rendered: usize,
    pub reused: usize,
    /// Re-analysed from this directory's records without rendering (`advise --from`).
    pub from: Option<PathBuf>,
    /// Under tiles (an engine's resolution, `plan::tiles::auto`): the frame with its tiles and
    /// aprons outlined, a PNG of the output set (`report::tiles::tiles_png`), shown first on the
    /// page so that the reader sees which parts of the image the answer was measured on.
    pub tiles: Option<crate::outdir::File>,
}

/// Replicates of each finalist at least: the winner map's per-pixel test splits them in halves
/// (one picks, one tests), and its power grows with them — on the kitchen at 64x48 the map resolved
/// 6, 0 and 0 % of the pixels at the three default budgets with 16, 14, 7 and 51 % with 32, for
/// 2.5 and 7 s more render CPU time than the sweep alone (20 s) — while the shipped numbers' σ
/// shrinks too. The sweep's replicates count when they are more.
pub const VERIFY_REPLICATES: u32 = 24;

/// The finalists' replicates for a sweep of `replicates`.
pub fn verify_replicates(replicates: u32) -> u32 {
    replicates.max(VERIFY_REPLICATES)
}

/// The winner map at one budget.
pub struct Map {
    pub budget_s: f64,
    /// The compared configurations, least MSE first; `Pixel::Won(i)` indexes this.
    pub rows: Vec<Row>,
    pub pixels: Vec<Pixel>,
}

/// Everything the page and advice.json are made from.
pub struct Analysis {
    pub curves: Vec<Curve>,
    pub budgets_s: Vec<f64>,
    /// The budgets were chosen by advise (`advice::default_budgets`), not given.
    pub default_budgets: bool,
    /// Per budget.
    pub answers: Vec<Answer>,
    /// Per measured budget, the winner map (`winner_maps`).
    pub maps: Vec<Map>,
    /// The finalists' session's median times over the sweep's at the counts both measured
    /// (geometric mean): how much slower (> 1) the machine ran then. `None`: nothing in common.
    pub session_ratio: Option<f64>,
    /// After a real-time pipeline: the answer per ray budget (rays per pixel per frame), every
    /// configuration ranked at each swept ray count (`compare::per_ray`); empty for raw images.
    pub per_ray: Vec<AtRays>,
    /// Each configuration's sampler cost per point on this machine at each ray count, ns
    /// (`jobs::sampler_cost`), filled in by the command that measures it.
    pub sampler_ns: Vec<(Row, u32, f64)>,
    /// After an accumulating pipeline, the configurations measured under one schedule only, since
    /// both would draw the same points (`advice::schedules_for`); empty otherwise.
    pub one_schedule: Vec<Row>,
    /// Whether each candidate is named with its schedule (after an accumulating pipeline).
    pub temporal: bool,
}

impl Analysis {
    /// `row`'s sampler cost per point at `rays`, ns (NaN if not measured).
    pub fn sampler_ns(&self, row: Row, rays: u32) -> f64 {
        self.sampler_ns.iter().find(|(r, n, _)| *r == row && *n == rays).map_or(f64::NAN, |x| x.2)
    }
}

/// Ladders, budgets, rankings and the sweep's (interpolated) answers; no maps yet.
pub fn analyse(setup: &Setup, results: &[JobResult], budgets_ms: &[f64]) -> Analysis {
    let curves = curves(setup, &crate::advice::pipeline::still_independent(results));
    let default = curves.iter().find(|c| c.row == PAPER_DEFAULT).expect("the paper default is always run");
    // After a real-time pipeline the budgets an engine has are rays per pixel per frame; a budget
    // in ms of this machine's CPU time only when asked for.
    let per_ray: Vec<AtRays> = if setup.pipeline == crate::denoise::Pipeline::RAW {
        Vec::new()
    } else {
        // Per ray budget and, within it, per camera (the scene's still one first).
        let candidates = setup.candidates();
        let cameras = setup.cameras();
        let mut out = Vec::new();
        for &r in &setup.rays {
            for c in &cameras {
                out.push(per_ray::rank(results, &candidates, r, &c.name()));
            }
        }
        out
    };
    let (budgets_s, defaulted) = if budgets_ms.is_empty() && !per_ray.is_empty() {
        (Vec::new(), false)
    } else if budgets_ms.is_empty() {
        (crate::advice::default_budgets(default), true)
    } else {
        (budgets_ms.iter().map(|b| b * 1e-3).collect(), false)
    };
    let answers = budgets_s
        .iter()
        .map(|&b| Answer::interpolated(rank(&curves, b, Metric::Rmse), rank(&curves, b, Metric::Lowpass)))
        .collect();
    Analysis {
        curves,
        budgets_s,
        default_budgets: defaulted,
        answers,
        maps: vec![],
        session_ratio: None,
        per_ray,
        sampler_ns: Vec::new(),
        one_schedule: setup.rows.iter().copied().filter(|&r| setup.schedule_free(r)).collect(),
        temporal: setup.pipeline.is_temporal(),
    }
}

/// Every (configuration, ray count) some budget's answer measures (`answer::counts`), each once.
pub fn finalists(a: &Analysis) -> Vec<(Row, u32)> {
    let mut out = Vec::new();
    for ans in &a.answers {
        for f in answer::finalists(&ans.ranking, &ans.lowpass) {
            for n in answer::counts(f) {
                if !out.contains(&(f.row, n)) {
                    out.push((f.row, n));
                }
            }
        }
    }
    out
}

/// Each budget's answer from the finalists' records, where they are all there (`Answer::measure`).
pub fn measure(a: &mut Analysis, verified: &[JobResult], replicates: u32) {
    let records = |row: Row, rays: u32| -> Vec<&JobResult> {
        let mut v: Vec<&JobResult> = verified.iter().filter(|r| r.rays == rays && r.is_row(row)).collect();
        v.sort_by_key(|r| r.replicate);
        v
    };
    let mut logs = Vec::new();
    for c in &a.curves {
        for p in &c.points {
            let times: Vec<f64> =
                records(c.row, p.rays).iter().flat_map(|r| r.times.iter().copied()).collect();
            if let Some(t) = Summary::of(&times) {
                logs.push((t.median / p.time_s).ln());
            }
        }
    }
    a.session_ratio = (!logs.is_empty()).then(|| mean(&logs).exp());
    let ratio = a.session_ratio.unwrap_or(1.0);
    a.answers = std::mem::take(&mut a.answers)
        .into_iter()
        .map(|x| x.measure(&records, replicates as usize, ratio))
        .collect();
}

/// Each configuration's ladder from the sweep's records (`compare::equal_time::curve`, by total
/// render time): per ray count, the median of every timed render of it and that median's σ, and
/// each replicate's MSE, low-pass MSE and structure.
fn curves(setup: &Setup, results: &[JobResult]) -> Vec<Curve> {
    let scene = &setup.loaded.spec.scenes[0].name;
    setup.rows.iter().map(|&row| curve(results, scene, row, &setup.rays, TimeView::Total)).collect()
}

/// Per measured budget: every pixel's winner by MSE among its finalists, each at its own ray
/// count, over their replicates (see `advice::winner`). A budget answered by interpolation has no
/// per-pixel measurement, and so no map.
pub fn winner_maps(m: &Measured, a: &Analysis) -> Vec<Map> {
    let reference = &m.reference.coverage;
    let cov: Vec<bool> = (0..reference.len()).map(|i| covered(reference, i)).collect();
    let width = reference.width as usize;
    let mut maps = Vec::new();
    for ans in a.answers.iter().filter(|x| x.measured && x.finalists.len() >= 2) {
        let mse: Vec<Vec<Vec<f64>>> = ans
            .finalists
            .iter()
            .map(|c| {
                (0..m.replicates)
                    .map(|rep| match m.errors.get(&(c.row, c.rays, rep)) {
                        Some(err) => winner::pooled_squared_error(err, &cov, width),
                        None => vec![f64::NAN; cov.len()], // not measured: no winner from it
                    })
                    .collect()
            })
            .collect();
        let pixels = winner::winners(&mse, &cov, winner::FDR);
        maps.push(Map {
            budget_s: ans.budget_s,
            rows: ans.finalists.iter().map(|c| c.row).collect(),
            pixels,
        });
    }
    maps
}

pub fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}
