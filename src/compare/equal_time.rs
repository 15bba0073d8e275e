//! Configurations compared by their error at equal time (pure: records in, rankings out), with the
//! ranking advise uses (`budget::{at_budget, rank}`, `model::gain`), so that `run` and `advise`
//! answer the same question the same way.
//!
//! Why not efficiency, 1 / (MSE · time)? It ranks two configurations as their MSEs at equal time
//! only where MSE ∝ 1/time. The lattice's MSE falls as time^−2.1…−2.5, so a 13 % time penalty costs
//! it 29–36 % MSE at equal time, which efficiency reports as 13 %; and at low ray counts the
//! overhead subtracted from AO time magnifies time ratios. So: each configuration's measured points
//! (median time per image, each replicate's MSE) are joined by straight lines in log time and log
//! MSE, and at a time budget between two of its points it has the MSE that line gives; outside its
//! measured times it is "not measured there", never extrapolated.
//!
//! - **Time**: total render time per image by default (what a renderer pays, and what advise
//!   ranks by); AO time (less the scene's per-image overhead) as a second view (`TimeView`).
//! - **Error model** (1 σ): the replicates' spread of the MSE at the two neighbouring points,
//!   interpolated replicate by replicate and paired across configurations by seed, plus each
//!   time's spread moving the budget along the line (`model::gain`).
//! - **The answer** at a budget is advise's rule: the least MSE among configurations whose error is
//!   not structured (`structure::is_structured`); a structured one ranked above it is rejected, not
//!   the answer.

use crate::compare::budget::{self, AtBudget, Curve, Metric, Place, Point};
use crate::compare::model;
use crate::compare::structure::{self, is_structured};
use crate::compare::{PAPER_DEFAULT, per_pixel_unbiased};
use crate::results::JobResult;
use crate::spec::Row;
use crate::timing::Summary;

/// Which time the budgets are in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeView {
    /// Median render time per image: what a renderer pays (the default).
    Total,
    /// Median render time less the scene's per-image overhead (an image with no AO rays).
    Ao,
}

impl TimeView {
    pub fn name(self) -> &'static str {
        match self {
            TimeView::Total => "total render time",
            TimeView::Ao => "AO time",
        }
    }

    /// The `equal_time.csv` value.
    pub fn key(self) -> &'static str {
        match self {
            TimeView::Total => "total",
            TimeView::Ao => "ao",
        }
    }
}

/// One configuration's ladder on `scene` from the run's records: per ray count of `rays`, the
/// median of every timed render (less the overhead in the AO view; a point whose AO time is not
/// positive is left out) and that median's spread, and each replicate's MSE and structure measure
/// (`structure::of`). `advise` reads its sweep's ladders through here too.
pub fn curve(results: &[JobResult], scene: &str, row: Row, rays: &[u32], view: TimeView) -> Curve {
    let points = rays
        .iter()
        .filter_map(|&n| {
            let rs: Vec<&JobResult> = results.iter().filter(|r| r.is(scene, row, n)).collect();
            let times: Vec<f64> = rs.iter().flat_map(|r| r.times.iter().copied()).collect();
            let t = Summary::of(&times)?;
            let time_s = match view {
                TimeView::Total => t.median,
                TimeView::Ao => t.median - rs[0].overhead_s,
            };
            (time_s > 0.0 && time_s.is_finite()).then(|| Point {
                rays: n,
                time_s,
                time_sigma_ln: model::median_sigma_ln(&times),
                timings: t.n,
                replicates: rs.iter().map(|r| r.replicate).collect(),
                mse: rs.iter().map(|r| r.rmse * r.rmse).collect(),
                lowpass_mse: rs.iter().map(|r| r.lowpass_rmse * r.lowpass_rmse).collect(),
                structure: rs.iter().map(|r| structure::of(r)).collect(),
            })
        })
        .collect();
    Curve { row, points }
}

/// A budget's distance inside a measured range, in log time: `exp ∘ ln` may move a time by an ulp,
/// and a budget an ulp below a configuration's fastest render would read as not measured there.
const INSIDE: f64 = 1e-9;

/// Time budgets, `per_doubling` to each factor 2 of time, log-spaced over the times every curve of
/// two or more points was measured at, so that every configuration is ranked at every budget;
/// rounded to two significant digits where that keeps them inside. When the configurations share
/// no range, over the `baseline`'s own (the others are then not measured at some budgets).
pub fn budgets(curves: &[Curve], baseline: Row, per_doubling: usize) -> Vec<f64> {
    let range = |c: &Curve| {
        let lt = budget::monotone_log_times(&c.points);
        (lt.len() >= 2).then(|| (lt[0], lt[lt.len() - 1]))
    };
    let ranges: Vec<(f64, f64)> = curves.iter().filter_map(range).collect();
    let common = ranges.iter().fold((f64::NEG_INFINITY, f64::INFINITY), |(a, b), r| (a.max(r.0), b.min(r.1)));
    let (lo, hi) = if !ranges.is_empty() && common.0 < common.1 {
        common
    } else {
        match curves.iter().find(|c| c.row == baseline).and_then(range) {
            Some(r) => r,
            None => return Vec::new(),
        }
    };
    if hi - lo < 2.0 * INSIDE {
        return vec![(0.5 * (lo + hi)).exp()];
    }
    let (lo, hi) = (lo + INSIDE, hi - INSIDE);
    let steps = (((hi - lo) / std::f64::consts::LN_2) * per_doubling.max(1) as f64).ceil().max(1.0) as usize;
    let mut out: Vec<f64> = Vec::new();
    for i in 0..=steps {
        let x = lo + (hi - lo) * i as f64 / steps as f64;
        let rounded = budget::round_significant(x.exp(), 2);
        let t = if (lo..=hi).contains(&rounded.ln()) { rounded } else { x.exp() };
        if out.last() != Some(&t) {
            out.push(t);
        }
    }
    out
}

/// `a`'s mean MSE over `b`'s at the same budget, ± its 1 σ error (advise's paired `gain`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ratio {
    pub value: f64,
    pub se: f64,
}

impl Ratio {
    pub fn of(a: &AtBudget, b: &AtBudget) -> Self {
        let g = model::gain(&a.side(Metric::Rmse), &b.side(Metric::Rmse));
        Self { value: g.value, se: g.se }
    }

    /// ln(ratio) in its standard errors (delta method: se(ln r) = se / r); 0 for a ratio of exactly
    /// 1 without error (a configuration against itself).
    pub fn in_se(&self) -> f64 {
        crate::compare::margin::in_se(self.value.ln(), self.se / self.value)
    }
}

/// One configuration at one budget.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub at: AtBudget,
    /// Its error is structured there (`is_structured` on the two neighbouring ray counts' records,
    /// weighted as the interpolation weighs them).
    pub structured: bool,
    pub unbiased: bool,
    /// Its MSE over the baseline's (below 1 = less error); `None` where the baseline is not measured.
    pub vs_baseline: Option<Ratio>,
}

/// Every configuration at one budget.
#[derive(Debug, Clone, PartialEq)]
pub struct AtTime {
    pub budget_s: f64,
    /// Least mean MSE first.
    pub ranked: Vec<Entry>,
    pub outside: Vec<(Row, Place)>,
}

impl AtTime {
    /// The answer (advise's `recommended` rule): the least MSE among configurations whose error is
    /// not structured; `None` when every one measured here is structured.
    pub fn answer(&self) -> Option<&Entry> {
        self.ranked.iter().find(|e| !e.structured)
    }

    /// The next unstructured configuration after the answer.
    pub fn runner_up(&self) -> Option<&Entry> {
        self.ranked.iter().filter(|e| !e.structured).nth(1)
    }

    /// Structured configurations with less MSE than the answer: rejected, not the answer.
    pub fn rejected(&self) -> Vec<&Entry> {
        self.ranked.iter().take_while(|e| e.structured).collect()
    }

    pub fn entry(&self, row: Row) -> Option<&Entry> {
        self.ranked.iter().find(|e| e.at.row == row)
    }
}

/// A sweep on one scene compared at equal time.
#[derive(Debug, Clone, PartialEq)]
pub struct EqualTime {
    pub scene: String,
    pub view: TimeView,
    /// The row every ratio is against: the paper's default when the sweep has it, else its first.
    pub baseline: Row,
    pub curves: Vec<Curve>,
    pub at: Vec<AtTime>,
}

/// `rows` of `scene` over `rays` ranked at `budgets(…, per_doubling)`.
pub fn equal_time(
    results: &[JobResult],
    scene: &str,
    rows: &[Row],
    rays: &[u32],
    view: TimeView,
    per_doubling: usize,
) -> EqualTime {
    let curves: Vec<Curve> = rows.iter().map(|&r| curve(results, scene, r, rays, view)).collect();
    let baseline = if rows.contains(&PAPER_DEFAULT) { PAPER_DEFAULT } else { rows[0] };
    let at = budgets(&curves, baseline, per_doubling)
        .into_iter()
        .map(|b| at_time(results, scene, &curves, baseline, b))
        .collect();
    EqualTime { scene: scene.to_string(), view, baseline, curves, at }
}

/// Every curve at `budget_s` (advise's `rank`), with its structure and its ratio to `baseline`.
pub fn at_time(results: &[JobResult], scene: &str, curves: &[Curve], baseline: Row, budget_s: f64) -> AtTime {
    let ranking = budget::rank(curves, budget_s, Metric::Rmse);
    let base = ranking.ranked.iter().find(|a| a.row == baseline).cloned();
    let ranked = ranking
        .ranked
        .into_iter()
        .map(|at| {
            let curve = curves.iter().find(|c| c.row == at.row).expect("ranked rows have curves");
            let (lo, hi) = (&curve.points[at.lo], &curve.points[at.lo + 1]);
            let mut weighted: Vec<(f64, &JobResult)> = Vec::new();
            for (p, w) in [(lo, 1.0 - at.w), (hi, at.w)] {
                let rs: Vec<&JobResult> = results.iter().filter(|r| r.is(scene, at.row, p.rays)).collect();
                let k = rs.len().max(1) as f64;
                weighted.extend(rs.into_iter().map(|r| (w / k, r)));
            }
            Entry {
                structured: is_structured(&weighted),
                unbiased: per_pixel_unbiased(at.row),
                vs_baseline: base.as_ref().map(|b| Ratio::of(&at, b)),
                at,
            }
        })
        .collect();
    AtTime { budget_s, ranked, outside: ranking.outside }
}
