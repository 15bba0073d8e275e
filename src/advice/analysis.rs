//! advise's analysis: the measured records → each configuration's ladder (`Curve`) → the budgets'
//! rankings (`advice`) → the winner maps. `report::advise` draws and writes what it finds.

use crate::advice::setup::Setup;
use crate::advice::winner::{self, Pixel};
use crate::advice::{self, AtBudget, Curve, Metric, PAPER_DEFAULT, Point, Ranking};
use crate::jobs::executor::Session;
use crate::metrics::covered;
use crate::reference::store::Reference;
use crate::results::JobResult;
use crate::spec::Row;
use crate::timing::{Protocol, Summary};
use std::collections::HashMap;

/// What advise measured.
pub struct Measured<'a> {
    pub setup: &'a Setup,
    pub reference: &'a Reference,
    /// By plan index.
    pub results: Vec<JobResult>,
    /// By (configuration, rays, replicate): image − reference on covered pixels (0 elsewhere), for
    /// every timed job and every extra replicate rendered for the winner map.
    pub errors: HashMap<(Row, u32, u32), Vec<f32>>,
    /// Replicates the winner map uses (the timed ones and extra ones, `MAP_REPLICATES` at least).
    pub map_replicates: u32,
    pub session: Session,
    pub protocol: Protocol,
}

/// The winner map compares, per budget, this many of the best configurations (and the paper's
/// default): beyond them the image-level gap is large, and a legend of 50 colours unreadable.
pub const MAP_CANDIDATES: usize = 6;
/// Replicates per pixel comparison, at least: with a handful, a pixel's MSE is too noisy to order
/// anything (the timed replicates are reused; the rest are rendered untimed, for the map only).
pub const MAP_REPLICATES: u32 = 16;

/// The winner map at one budget.
pub struct Map {
    pub budget_s: f64,
    /// The compared configurations, in ranking order; `Pixel::Won(i)` indexes this.
    pub rows: Vec<Row>,
    pub pixels: Vec<Pixel>,
}

/// Everything the page and advice.json are made from.
pub struct Analysis {
    pub curves: Vec<Curve>,
    pub budgets_s: Vec<f64>,
    /// The budgets were chosen by advise (`advice::default_budgets`), not given.
    pub default_budgets: bool,
    /// Per budget: by RMSE and by low-pass RMSE.
    pub rankings: Vec<(Ranking, Ranking)>,
    pub maps: Vec<Map>,
    /// Configurations coloured in the winner map, most pixels first, with their colours.
    pub colours: Vec<(Row, [u8; 3])>,
    /// Paired standard errors a pixel's win must exceed.
    pub threshold: f64,
}

/// Ladders, budgets and rankings (no maps yet).
pub fn analyse(m: &Measured, budgets_ms: &[f64]) -> Analysis {
    let curves = curves(m);
    let default = curves.iter().find(|c| c.row == PAPER_DEFAULT).expect("the paper default is always run");
    let (budgets_s, defaulted) = if budgets_ms.is_empty() {
        (advice::default_budgets(default), true)
    } else {
        (budgets_ms.iter().map(|b| b * 1e-3).collect(), false)
    };
    let rankings: Vec<(Ranking, Ranking)> = budgets_s
        .iter()
        .map(|&b| (advice::rank(&curves, b, Metric::Rmse), advice::rank(&curves, b, Metric::Lowpass)))
        .collect();
    let threshold = winner::threshold(m.map_replicates as usize);
    Analysis {
        curves,
        budgets_s,
        default_budgets: defaulted,
        rankings,
        maps: vec![],
        colours: vec![],
        threshold,
    }
}

/// The configurations a budget's map compares: its `MAP_CANDIDATES` best by RMSE, and the paper's
/// default; none when fewer than two are inside their measured times.
fn candidates(r: &Ranking) -> Vec<&AtBudget> {
    if r.ranked.len() < 2 {
        return Vec::new();
    }
    let mut c: Vec<&AtBudget> = r.ranked.iter().take(MAP_CANDIDATES).collect();
    if let Some(d) = r.ranked.iter().skip(MAP_CANDIDATES).find(|a| a.row == PAPER_DEFAULT) {
        c.push(d);
    }
    c
}

/// (configuration, rays) the maps need at `MAP_REPLICATES` replicates: the two measured ray counts
/// around each budget of each candidate.
pub fn map_needs(a: &Analysis) -> Vec<(Row, u32)> {
    let mut out = Vec::new();
    for (r, _) in &a.rankings {
        for c in candidates(r) {
            let curve = a.curves.iter().find(|x| x.row == c.row).expect("ranked rows have curves");
            for p in [&curve.points[c.lo], &curve.points[c.lo + 1]] {
                if !out.contains(&(c.row, p.rays)) {
                    out.push((c.row, p.rays));
                }
            }
        }
    }
    out
}

/// Each configuration's ladder from its records: per ray count, the median of every timed render
/// of it and that median's spread, and each replicate's MSE and low-pass MSE.
fn curves(m: &Measured) -> Vec<Curve> {
    let is = |r: &JobResult, row: Row, n: u32| r.rays == n && r.is_row(row);
    m.setup
        .rows
        .iter()
        .map(|&row| {
            let points = m
                .setup
                .rays
                .iter()
                .filter_map(|&n| {
                    let rs: Vec<&JobResult> = m.results.iter().filter(|r| is(r, row, n)).collect();
                    let times: Vec<f64> = rs.iter().flat_map(|r| r.times.iter().copied()).collect();
                    let t = Summary::of(&times)?;
                    Some(Point {
                        rays: n,
                        time_s: t.median,
                        time_spread_s: t.spread(),
                        replicates: rs.iter().map(|r| r.replicate).collect(),
                        mse: rs.iter().map(|r| r.rmse * r.rmse).collect(),
                        lowpass_mse: rs.iter().map(|r| r.lowpass_rmse * r.lowpass_rmse).collect(),
                        whiteness_z: rs.iter().map(|r| r.whiteness_z).collect(),
                        lowfreq_ratio: rs.iter().map(|r| r.lowfreq_ratio).collect(),
                    })
                })
                .collect();
            Curve { row, points }
        })
        .collect()
}

/// Per budget with at least two configurations inside their measured times: every pixel's
/// winner by MSE among the budget's candidates (see `advice::winner`), at `map_replicates`
/// replicates, from the two measured ray counts around the budget.
pub fn winner_maps(m: &Measured, curves: &[Curve], rankings: &[(Ranking, Ranking)]) -> Vec<Map> {
    let reference = &m.reference.coverage;
    let cov: Vec<bool> = (0..reference.len()).map(|i| covered(reference, i)).collect();
    let width = reference.width as usize;
    let mut pooled: HashMap<(Row, u32, u32), Vec<f64>> = HashMap::new();
    let threshold = winner::threshold(m.map_replicates as usize);
    let mut maps = Vec::new();
    for (r, _) in rankings {
        let chosen = candidates(r);
        if chosen.is_empty() {
            continue;
        }
        let mut mse = Vec::new();
        for a in &chosen {
            let c = curves.iter().find(|c| c.row == a.row).expect("ranked rows have curves");
            let (lo, hi) = (c.points[a.lo].rays, c.points[a.lo + 1].rays);
            let mut pool = |rays: u32, rep: u32| -> Vec<f64> {
                let key = (a.row, rays, rep);
                let pooled_of = || match m.errors.get(&key) {
                    Some(err) => winner::pooled_squared_error(err, &cov, width),
                    None => vec![f64::NAN; cov.len()], // never rendered: no winner from it
                };
                pooled.entry(key).or_insert_with(pooled_of).clone()
            };
            let per_replicate: Vec<Vec<f64>> = (0..m.map_replicates)
                .map(|rep| winner::interpolate(&pool(lo, rep), &pool(hi, rep), a.w))
                .collect();
            mse.push(per_replicate);
        }
        let pixels = winner::winners(&mse, &cov, threshold);
        maps.push(Map { budget_s: r.budget_s, rows: chosen.iter().map(|a| a.row).collect(), pixels });
    }
    maps
}

pub fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}
