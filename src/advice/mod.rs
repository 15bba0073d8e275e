//! `hemilab advise`'s arithmetic (pure: no IO, no rendering): which configuration gives the least
//! error **at equal time**, from each configuration's measured ladder of ray counts.
//!
//! - **Equal time**: a configuration's points (median time per image, error) are joined by straight
//!   lines in log time and log error, so a budget between two measured ray counts gets the error
//!   the configuration would have there (`locate`, `at_budget`). Error falls as a power of time to
//!   a good approximation between neighbouring ray counts a factor 2 apart, so the line is nearly
//!   exact; a budget outside a configuration's measured times is never extrapolated, only reported
//!   as outside (`Place::Below` / `Place::Above`).
//! - **Replicates**: each replicate's MSE is interpolated on its own (the same weight for all), so
//!   the configuration's mean MSE at the budget has a standard error from their spread; replicate r
//!   has the same seed in every configuration, so two configurations are compared replicate by
//!   replicate (`gain`, `paired_z`).
//! - **Which configurations**: every distribution × sequence × seed mode that is a distinct,
//!   sensible estimator (`sensible_rows`), or the subset `--only` patterns select (`select`).
//!
//! The per-pixel winner map is in `advice/winner.rs`.

pub mod analysis;
pub mod setup;
pub mod winner;

use crate::metrics::STRUCTURED_RATIO;
use crate::sampling::{Distribution, SeedMode, Sequence};
use crate::spec::Row;

/// The paper's default estimator, the baseline of every gain: sine-cosine with pseudo-random
/// numbers, fresh in every pixel (its "random seed per pixel").
pub const PAPER_DEFAULT: Row =
    Row { distribution: Distribution::SineCosine, sequence: Sequence::Random, seed_mode: SeedMode::Rotation };

/// Why a row is left out of the default set, or `None` if it is a distinct, sensible estimator.
/// (`random` × `shift` is `random` × `rotation` by `Row::canonical` and never reaches here.)
pub fn not_sensible(row: Row) -> Option<&'static str> {
    match (row.distribution, row.sequence, row.seed_mode) {
        (_, Sequence::Random, SeedMode::Static) => {
            Some("one set of pseudo-random numbers in every pixel: the static seed without the lattice")
        }
        (Distribution::ConcentricCosine, s, SeedMode::Rotation) if s != Sequence::Random => {
            Some("through the concentric map an x offset is not a rotation about the normal")
        }
        _ => None,
    }
}

/// Every distribution × sequence × seed mode that `advise` runs by default: canonical (duplicates
/// such as `random` × `shift` = `random` × `rotation` merged) and sensible (`not_sensible`), in the
/// order of `Distribution::ALL`, `Sequence::ALL`, `SeedMode::ALL`.
pub fn sensible_rows() -> Vec<Row> {
    let mut rows = Vec::new();
    for &d in Distribution::ALL {
        for &s in Sequence::ALL {
            for &m in SeedMode::ALL {
                let r = Row::new(d, s, m).canonical();
                if not_sensible(r).is_none() && !rows.contains(&r) {
                    rows.push(r);
                }
            }
        }
    }
    rows
}

/// One `--only` item, `distribution/sequence/seed_mode`, each part a name or `*` (any).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pattern {
    pub distribution: Option<Distribution>,
    pub sequence: Option<Sequence>,
    pub seed_mode: Option<SeedMode>,
}

impl Pattern {
    /// `sine-cosine/fibonacci/*`, `*/*/blue-noise`, …; the message names the item and what is allowed.
    pub fn parse(s: &str) -> Result<Self, String> {
        let parts: Vec<&str> = s.trim().split('/').map(str::trim).collect();
        let [d, q, m] = parts[..] else {
            return Err(format!(
                "'{s}' must be distribution/sequence/seed_mode, each a name or *, e.g. sine-cosine/fibonacci/*"
            ));
        };
        fn part<T: std::str::FromStr<Err = String>>(p: &str) -> Result<Option<T>, String> {
            if p == "*" { Ok(None) } else { p.parse().map(Some) }
        }
        let at = |e: String| format!("'{s}': {e}");
        Ok(Self {
            distribution: part(d).map_err(at)?,
            sequence: part(q).map_err(at)?,
            seed_mode: part(m).map_err(at)?,
        })
    }

    fn exact(&self) -> Option<Row> {
        Some(Row::new(self.distribution?, self.sequence?, self.seed_mode?).canonical())
    }

    fn matches(&self, r: Row) -> bool {
        self.distribution.is_none_or(|d| d == r.distribution)
            && self.sequence.is_none_or(|s| s == r.sequence)
            && self.seed_mode.is_none_or(|m| m == r.seed_mode)
    }
}

/// The configurations to run: all sensible rows (no patterns), else those the patterns match — a
/// fully named pattern is taken as asked even if not in the default set — and always the paper's
/// default (every gain is against it), first. A pattern that matches nothing is an error.
pub fn select(patterns: &[Pattern]) -> Result<Vec<Row>, String> {
    let all = sensible_rows();
    let mut rows = vec![PAPER_DEFAULT];
    if patterns.is_empty() {
        rows.extend(all.into_iter().filter(|r| *r != PAPER_DEFAULT));
        return Ok(rows);
    }
    for p in patterns {
        let hits: Vec<Row> = match p.exact() {
            Some(r) => vec![r],
            None => all.iter().copied().filter(|r| p.matches(*r)).collect(),
        };
        if hits.is_empty() {
            let show = |o: Option<&str>| o.unwrap_or("*").to_string();
            return Err(format!(
                "'{}/{}/{}' matches no configuration of the default set (which leaves out random × static \
                 and concentric-cosine × rotation of a lattice, scramble or jitter; name one in full to run it)",
                show(p.distribution.map(|d| d.name())),
                show(p.sequence.map(|s| s.name())),
                show(p.seed_mode.map(|m| m.name()))
            ));
        }
        for r in hits {
            if !rows.contains(&r) {
                rows.push(r);
            }
        }
    }
    Ok(rows)
}

/// One measured ray count of one configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub rays: u32,
    /// Median time per image (seconds, the timing protocol's) and its spread (`Summary::spread`).
    pub time_s: f64,
    pub time_spread_s: f64,
    /// Replicate ids and, for each, the image's MSE and low-pass MSE (squared low-pass RMSE).
    pub replicates: Vec<u32>,
    pub mse: Vec<f64>,
    pub lowpass_mse: Vec<f64>,
    /// Each replicate's whiteness z-score (`metrics::whiteness`), reported: a test of any
    /// correlation, which blue noise fails too.
    pub whiteness_z: Vec<f64>,
    /// Each replicate's low-frequency ratio (`metrics::lowfreq`): what "structured" is judged by.
    pub lowfreq_ratio: Vec<f64>,
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
fn geo(a: f64, b: f64, w: f64) -> f64 {
    if w <= 0.0 {
        a
    } else if w >= 1.0 {
        b
    } else {
        (a.ln() * (1.0 - w) + b.ln() * w).exp()
    }
}

/// Mean and its standard error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    pub value: f64,
    pub se: f64,
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
    /// The time's relative spread there (spread / median, interpolated).
    pub time_rel_spread: f64,
    /// Mean whiteness z-score over the replicates, interpolated linearly between the two points.
    pub whiteness_z: f64,
    /// Mean low-frequency ratio over the replicates, interpolated the same way.
    pub lowfreq_ratio: f64,
    /// The two measured points the budget lies between, and the weight.
    pub lo: usize,
    pub w: f64,
}

impl AtBudget {
    /// Whether its error is structured — clumped in blotches or bands that a blur keeps — rather
    /// than noise: mean low-frequency ratio above [`STRUCTURED_RATIO`]. Not the whiteness z, which
    /// flags any correlation, blue noise's negative one included, and grows with the pixel count.
    pub fn structured(&self) -> bool {
        self.lowfreq_ratio > STRUCTURED_RATIO
    }

    fn values(&self, m: Metric) -> &[f64] {
        match m {
            Metric::Rmse => &self.mse,
            Metric::Lowpass => &self.lowpass_mse,
        }
    }

    /// Mean MSE (or low-pass MSE) over replicates ± its standard error (sd / √n).
    pub fn mean_mse(&self, m: Metric) -> Estimate {
        let (value, sd) = crate::metrics::mean_sd(self.values(m));
        let n = self.values(m).len() as f64;
        Estimate { value, se: if n > 1.0 { sd / n.sqrt() } else { f64::NAN } }
    }

    /// √(mean MSE) ± its standard error (delta method: se(MSE) / (2 RMSE)).
    pub fn rmse(&self, m: Metric) -> Estimate {
        let e = self.mean_mse(m);
        let value = e.value.sqrt();
        Estimate { value, se: e.se / (2.0 * value) }
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
        time_rel_spread: (1.0 - w) * a.time_spread_s / a.time_s + w * b.time_spread_s / b.time_s,
        whiteness_z: (1.0 - w) * mean(&a.whiteness_z) + w * mean(&b.whiteness_z),
        lowfreq_ratio: (1.0 - w) * mean(&a.lowfreq_ratio) + w * mean(&b.lowfreq_ratio),
        lo,
        w,
    })
}

/// A ratio of mean MSEs with its standard error and that error's two parts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gain {
    pub value: f64,
    pub se: f64,
    /// From the replicates, paired (their covariance taken out).
    pub se_replicates: f64,
    /// From the spread of the two configurations' times: a time off by δ moves the budget's MSE by
    /// the local slope × δ.
    pub se_timing: f64,
}

/// How many times less (low-pass) MSE `better` has than `baseline` at the same budget: mean MSE of
/// `baseline` / mean MSE of `better`. Its standard error by the delta method over the shared
/// replicates, paired: var(ln ratio) ≈ var(ā)/ā² + var(b̄)/b̄² − 2 cov(ā, b̄)/(ā b̄), with the means'
/// (co)variances the replicates' / n; plus the timing part. 1 ± 0 for a configuration against itself.
pub fn gain(baseline: &AtBudget, better: &AtBudget, m: Metric) -> Gain {
    let (xa, xb) = shared(baseline, better, m);
    let n = xa.len() as f64;
    let (ma, mb) = (xa.iter().sum::<f64>() / n, xb.iter().sum::<f64>() / n);
    let value = ma / mb;
    let rel2 = if n > 1.0 {
        let cov = |x: &[f64], mx: f64, y: &[f64], my: f64| {
            x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum::<f64>() / (n - 1.0)
        };
        let v = cov(&xa, ma, &xa, ma) / (ma * ma) + cov(&xb, mb, &xb, mb) / (mb * mb)
            - 2.0 * cov(&xa, ma, &xb, mb) / (ma * mb);
        v.max(0.0) / n
    } else {
        f64::NAN
    };
    let se_timing = if baseline.row == better.row {
        0.0
    } else {
        let k = |a: &AtBudget| match m {
            Metric::Rmse => a.slope,
            Metric::Lowpass => a.lowpass_slope,
        };
        value * (k(baseline) * baseline.time_rel_spread).hypot(k(better) * better.time_rel_spread)
    };
    let se_replicates = value * rel2.sqrt();
    Gain { value, se: se_replicates.hypot(se_timing), se_replicates, se_timing }
}

/// The two configurations' values over the replicates both have, in the same order.
fn shared(a: &AtBudget, b: &AtBudget, m: Metric) -> (Vec<f64>, Vec<f64>) {
    let (mut xa, mut xb) = (Vec::new(), Vec::new());
    for (i, r) in a.replicates.iter().enumerate() {
        if let Some(j) = b.replicates.iter().position(|x| x == r) {
            xa.push(a.values(m)[i]);
            xb.push(b.values(m)[j]);
        }
    }
    (xa, xb)
}

/// `other`'s mean MSE minus `best`'s, in paired standard errors over the shared replicates (∞ when
/// every replicate differs by the same; NaN with fewer than two shared).
pub fn paired_z(best: &AtBudget, other: &AtBudget, m: Metric) -> f64 {
    let (xa, xb) = shared(best, other, m);
    if xa.len() < 2 {
        return f64::NAN;
    }
    let (diff, se) = crate::stats::paired_difference(&xa, &xb);
    if se > 0.0 { diff / se } else { diff.signum() * f64::INFINITY }
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

/// What to ship at a budget: the best-ranked configuration whose error is not structured
/// (low-frequency ratio at most [`STRUCTURED_RATIO`]), because a sampler with visible blotches or
/// bands is not an answer a renderer can ship however low its RMSE; the best overall when every one
/// is structured. Blue noise (ratio below 1: the error pushed to high frequencies, which a blur or
/// the eye removes) is shippable.
pub fn recommended(r: &Ranking) -> Option<&AtBudget> {
    r.ranked.iter().find(|a| !a.structured()).or_else(|| r.ranked.first())
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

/// Default budgets when none are given: three times spread over the paper default's measured
/// range — a quarter, half and three quarters of the way in log time from its cheapest to its
/// dearest render — rounded to two significant digits (and kept inside the range). On a narrow
/// range (a tiny image) two of them can round to the same number: then more digits are kept, so
/// there are always three distinct budgets when the range is not a single time.
pub fn default_budgets(paper_default: &Curve) -> Vec<f64> {
    let lt = monotone_log_times(&paper_default.points);
    let (Some(&a), Some(&b)) = (lt.first(), lt.last()) else { return Vec::new() };
    let spread = |digits: usize| {
        let mut out: Vec<f64> = Vec::new();
        for q in [0.25, 0.5, 0.75] {
            let t = round_significant((a + q * (b - a)).exp(), digits).clamp(a.exp(), b.exp());
            if !out.contains(&t) {
                out.push(t);
            }
        }
        out
    };
    (2..=6).map(spread).find(|b| b.len() == 3).unwrap_or_else(|| spread(2))
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
