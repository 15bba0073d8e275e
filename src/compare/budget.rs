//! The equal-time model at one budget (pure: ladders in, rankings out), which `run`'s equal-time
//! comparisons (`equal_time`) and `advise` (`advice`) both rank with.
//!
//! - **Equal time**: a configuration's points (median time per image, error) are joined by straight
//!   lines in log time and log error, so a budget between two measured ray counts gets the error
//!   the configuration would have there (`locate`, `at_budget`). Error falls as a power of time to
//!   a good approximation between neighbouring ray counts a factor 2 apart, so the line is nearly
//!   exact; a budget outside a configuration's measured times is never extrapolated, only reported
//!   as outside (`Place::Below` / `Place::Above`).
//! - **Replicates**: each replicate's MSE is interpolated on its own (the same weight for all), so
//!   a configuration's mean MSE at the budget has a σ from their spread; replicate r has the same
//!   seed in every configuration, so two configurations are compared replicate by replicate. Every
//!   ± and margin is 1 σ of the one error model of `compare::model` (replicates and times).

use crate::compare::PAPER_DEFAULT;
use crate::compare::model::{self, Estimate};
use crate::compare::structure;
use crate::spec::Row;

/// One measured ray count of one configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub rays: u32,
    /// Median time per image (seconds, the timing protocol's), the σ of its ln within the session
    /// (`model::median_sigma_ln`) and how many timed renders it is the median of.
    pub time_s: f64,
    pub time_sigma_ln: f64,
    pub timings: usize,
    /// Replicate ids and, for each, the image's MSE and low-pass MSE (squared low-pass RMSE).
    pub replicates: Vec<u32>,
    pub mse: Vec<f64>,
    pub lowpass_mse: Vec<f64>,
    /// Each replicate's value of the structure measure (`structure::of`).
    pub structure: Vec<f64>,
}

impl Point {
    /// Its median time per image in ms ± 1 σ (the session's factor and the median's scatter).
    pub fn time_ms(&self) -> Estimate {
        let ms = self.time_s * 1e3;
        Estimate { value: ms, se: ms * model::time_sigma_ln(self.time_sigma_ln) }
    }

    /// √(mean MSE) (or low-pass MSE) over its replicates ± 1 σ, at its own ray count
    /// (`model::mean_mse` without the time's part).
    pub fn rmse(&self, m: Metric) -> Estimate {
        let values = match m {
            Metric::Rmse => &self.mse,
            Metric::Lowpass => &self.lowpass_mse,
        };
        // At a ray count neither the row nor the time plays a part (`mean_mse` without the budget).
        let side = model::Side {
            row: PAPER_DEFAULT,
            replicates: &self.replicates,
            values,
            slope: 0.0,
            time_sigma_ln: 0.0,
        };
        model::rmse(model::mean_mse(&side, false))
    }
}

/// A configuration's ladder, points in increasing ray count.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    pub row: Row,
    pub points: Vec<Point>,
}

/// Which error a ranking is by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Metric {
    Rmse,
    /// RMSE of the error after the σ = 1.5 px Gaussian blur: what a blur or denoiser leaves.
    Lowpass,
}

/// Where a budget falls on a configuration's measured times.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Place {
    /// Cheaper than its cheapest measured render, which takes `fastest_s`.
    Below { fastest_s: f64 },
    /// Dearer than its dearest measured render, which takes `slowest_s`.
    Above { slowest_s: f64 },
    /// Between points `lo` and `lo + 1`, at weight `w` in [0, 1] along log time.
    Inside { lo: usize, w: f64 },
}

/// Log times made non-decreasing in ray count (pool-adjacent-violators, equal weights): more rays
/// never cost less, so a median that came out below its cheaper neighbour's is timing noise, and
/// the two are replaced by their mean.
pub fn monotone_log_times(points: &[Point]) -> Vec<f64> {
    let mut blocks: Vec<(f64, usize)> = Vec::new(); // (mean, size)
    for p in points {
        blocks.push((p.time_s.ln(), 1));
        while blocks.len() > 1 && blocks[blocks.len() - 2].0 > blocks[blocks.len() - 1].0 {
            let (b, nb) = blocks.pop().expect("two blocks");
            let (a, na) = blocks.pop().expect("two blocks");
            blocks.push(((a * na as f64 + b * nb as f64) / (na + nb) as f64, na + nb));
        }
    }
    blocks.into_iter().flat_map(|(m, n)| std::iter::repeat_n(m, n)).collect()
}

/// Where `budget_s` falls on `curve`. At a time shared by several points (flattened by
/// `monotone_log_times`) the one with the most rays is taken: same time, more rays.
pub fn locate(curve: &Curve, budget_s: f64) -> Place {
    let lt = monotone_log_times(&curve.points);
    let (Some(&first), Some(&last)) = (lt.first(), lt.last()) else {
        return Place::Below { fastest_s: f64::NAN };
    };
    let lb = budget_s.ln();
    if lt.len() < 2 || lb < first || !lb.is_finite() {
        return Place::Below { fastest_s: first.exp() };
    }
    if lb > last {
        return Place::Above { slowest_s: last.exp() };
    }
    let i = lt.iter().rposition(|&t| t <= lb).expect("lb >= first");
    if i == lt.len() - 1 {
        return Place::Inside { lo: i - 1, w: 1.0 };
    }
    Place::Inside { lo: i, w: (lb - lt[i]) / (lt[i + 1] - lt[i]) }
}

/// Geometric interpolation, exact at the ends (so a zero end needs no logarithm there).
pub fn geo(a: f64, b: f64, w: f64) -> f64 {
    if w <= 0.0 {
        a
    } else if w >= 1.0 {
        b
    } else {
        (a.ln() * (1.0 - w) + b.ln() * w).exp()
    }
}

/// A configuration at a budget, interpolated.
#[derive(Debug, Clone, PartialEq)]
pub struct AtBudget {
    pub row: Row,
    /// Rays per pixel the budget buys (geometric interpolation between the two ray counts).
    pub rays: f64,
    pub replicates: Vec<u32>,
    /// Per replicate: MSE and low-pass MSE at the budget.
    pub mse: Vec<f64>,
    pub lowpass_mse: Vec<f64>,
    /// d ln(mean MSE) / d ln(time) on the segment, and the same for the low-pass MSE.
    pub slope: f64,
    pub lowpass_slope: f64,
    /// σ of ln(time) within the session there (the two points' `time_sigma_ln`, interpolated).
    pub time_sigma_ln: f64,
    /// Mean of the structure measure over the replicates, interpolated linearly between the points.
    pub structure: f64,
    /// The two measured points the budget lies between, and the weight; the ray count of the
    /// first (the sweep measured it within the budget).
    pub lo: usize,
    pub w: f64,
    pub lo_rays: u32,
}

impl AtBudget {
    /// Whether its error is structured (bands, moiré) rather than noise (`structure::structured`).
    pub fn structured(&self) -> bool {
        structure::structured(self.structure)
    }

    /// What a comparison under the error model needs of it.
    pub fn side(&self, m: Metric) -> model::Side<'_> {
        let (values, slope) = match m {
            Metric::Rmse => (&self.mse, self.slope),
            Metric::Lowpass => (&self.lowpass_mse, self.lowpass_slope),
        };
        model::Side {
            row: self.row,
            replicates: &self.replicates,
            values,
            slope,
            time_sigma_ln: self.time_sigma_ln,
        }
    }

    /// Mean MSE (or low-pass MSE) at the budget ± 1 σ (replicates and time, `model::mean_mse`).
    pub fn mean_mse(&self, m: Metric) -> Estimate {
        model::mean_mse(&self.side(m), true)
    }

    /// √(mean MSE) ± 1 σ.
    pub fn rmse(&self, m: Metric) -> Estimate {
        model::rmse(self.mean_mse(m))
    }
}

/// `curve` at `budget_s`, or where the budget lies outside its measured times.
pub fn at_budget(curve: &Curve, budget_s: f64) -> Result<AtBudget, Place> {
    let (lo, w) = match locate(curve, budget_s) {
        Place::Inside { lo, w } => (lo, w),
        outside => return Err(outside),
    };
    let (a, b) = (&curve.points[lo], &curve.points[lo + 1]);
    let mut replicates = Vec::new();
    let (mut mse, mut lowpass_mse) = (Vec::new(), Vec::new());
    for (i, r) in a.replicates.iter().enumerate() {
        if let Some(j) = b.replicates.iter().position(|x| x == r) {
            replicates.push(*r);
            mse.push(geo(a.mse[i], b.mse[j], w));
            lowpass_mse.push(geo(a.lowpass_mse[i], b.lowpass_mse[j], w));
        }
    }
    let lt = monotone_log_times(&curve.points);
    let dt = lt[lo + 1] - lt[lo];
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let slope = |fa: f64, fb: f64| if dt > 0.0 { (fb.ln() - fa.ln()) / dt } else { 0.0 };
    Ok(AtBudget {
        row: curve.row,
        rays: geo(a.rays as f64, b.rays as f64, w),
        replicates,
        mse,
        lowpass_mse,
        slope: slope(mean(&a.mse), mean(&b.mse)),
        lowpass_slope: slope(mean(&a.lowpass_mse), mean(&b.lowpass_mse)),
        time_sigma_ln: (1.0 - w) * a.time_sigma_ln + w * b.time_sigma_ln,
        structure: (1.0 - w) * mean(&a.structure) + w * mean(&b.structure),
        lo,
        w,
        lo_rays: a.rays,
    })
}

/// Every configuration at one budget: those inside their measured times, least error first, and
/// the others with where the budget fell.
#[derive(Debug, Clone, PartialEq)]
pub struct Ranking {
    pub budget_s: f64,
    pub metric: Metric,
    pub ranked: Vec<AtBudget>,
    pub outside: Vec<(Row, Place)>,
}

pub fn rank(curves: &[Curve], budget_s: f64, metric: Metric) -> Ranking {
    let (mut ranked, mut outside) = (Vec::new(), Vec::new());
    for c in curves {
        match at_budget(c, budget_s) {
            Ok(a) => ranked.push(a),
            Err(p) => outside.push((c.row, p)),
        }
    }
    ranked.sort_by(|a, b| a.mean_mse(metric).value.total_cmp(&b.mean_mse(metric).value));
    Ranking { budget_s, metric, ranked, outside }
}

/// `x` rounded to `digits` (≥ 1) significant digits, as the nearest double to that decimal (so
/// 5.1 prints as 5.1, not 5.1000000000000005).
pub fn round_significant(x: f64, digits: usize) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    format!("{:.*e}", digits.max(1) - 1, x).parse().unwrap_or(x)
}

#[cfg(test)]
mod tests;
