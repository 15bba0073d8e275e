//! The one error model of every comparison at equal time. Every ± advise prints and every margin
//! it states, and every ratio of `run`'s equal-time tables, is one standard deviation (1 σ) of this
//! model, propagated by the delta method; nothing else adds to them.
//!
//! - **Replicates.** Replicate r has the same seed in every configuration (`plan::replicate_seed`),
//!   so a configuration's MSE at a ray count is the mean over its replicates (σ = sd / √n) and two
//!   configurations are compared replicate by replicate (paired: their covariance is taken out).
//! - **Times.** A time is the median of a unit's timed renders, and ln t = ln T + u + e: `u` is the
//!   session's own factor (the machine, the process, the load), shared by every configuration timed
//!   in that session — the interleaved schedule spreads drift over all of them alike — with
//!   σ_u = [`RUN_FACTOR`] (`timing::RUN_TO_RUN`, measured between runs; no run can see it);
//!   `e` is the median's scatter within the session, from its samples ([`median_sigma_ln`]).
//! - **At a budget.** A configuration's MSE there moves with its time: were its time δ (in ln)
//!   longer, fewer rays would fit the budget and its MSE would rise by −k δ, with k = d ln MSE /
//!   d ln t the local slope of its ladder. So the variance of ln(MSE_a / MSE_b) at a budget is the
//!   paired replicate part plus (k_a − k_b)² σ_u² + k_a² σ_ea² + k_b² σ_eb²: the shared factor
//!   cancels between two configurations except through the difference of their slopes.
//!
//! A quantity at a ray count (a measured point; what advise ships, measured at its count) carries
//! the replicates' σ, and its time √(σ_u² + σ_e²); a quantity at a budget (a gain, a margin, an
//! RMSE interpolated at the budget) carries both through the slope.

use crate::compare::margin::{in_se, pairs};
use crate::spec::Row;
use crate::stats::paired_log_ratio_variance;

/// Mean and its standard error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    pub value: f64,
    pub se: f64,
}

/// σ of ln(time) that a session shares with every render it times (see the module notes).
pub const RUN_FACTOR: f64 = crate::timing::RUN_TO_RUN;

/// 1 σ of ln(median) of timing samples: the median's distribution-free interval
/// (`stats::median_interval`, order statistics) at its exact coverage, turned into a normal σ —
/// its half-width in ln time over the normal quantile of that coverage (not a 95 % half-width
/// read as one σ). NaN with fewer than two samples.
pub fn median_sigma_ln(samples: &[f64]) -> f64 {
    let v: Vec<f64> = samples.iter().copied().filter(|x| x.is_finite() && *x > 0.0).collect();
    if v.len() < 2 {
        return f64::NAN;
    }
    let (lo, hi, level) = crate::stats::median_interval(&v, 0.95);
    let z = crate::stats::normal_quantile(0.5 + 0.5 * level);
    if z.is_nan() || z <= 0.0 {
        return f64::NAN;
    }
    0.5 * (hi.ln() - lo.ln()) / z
}

/// σ of ln(time) of one time on its own: the session's factor and the median's scatter.
pub fn time_sigma_ln(own: f64) -> f64 {
    RUN_FACTOR.hypot(own)
}

/// One configuration at one budget, as a comparison needs it.
#[derive(Debug, Clone, Copy)]
pub struct Side<'a> {
    pub row: Row,
    /// Replicate ids and, for each, the MSE (or low-pass MSE) at the budget.
    pub replicates: &'a [u32],
    pub values: &'a [f64],
    /// d ln MSE / d ln time of its ladder there.
    pub slope: f64,
    /// σ of ln(its median time) within the session (`e`).
    pub time_sigma_ln: f64,
}

/// A ratio of mean MSEs with its σ and the σ's two parts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gain {
    pub value: f64,
    pub se: f64,
    /// From the replicates, paired.
    pub se_replicates: f64,
    /// From the times, through the slopes (the session factor cancels but for their difference).
    pub se_timing: f64,
}

impl Gain {
    pub fn estimate(&self) -> Estimate {
        Estimate { value: self.value, se: self.se }
    }
}

/// The two sides' values over the replicates both have, in `a`'s order (`margin::pairs`).
fn shared(a: &Side, b: &Side) -> (Vec<f64>, Vec<f64>) {
    let keyed = |s: &Side| s.replicates.iter().copied().zip(s.values.iter().copied()).collect::<Vec<_>>();
    pairs(&keyed(a), &keyed(b))
}

/// How many times less MSE `better` has than `baseline` at the same budget: mean of `baseline` /
/// mean of `better` over their shared replicates, with its σ under the model. The replicate part:
/// var(ln ratio) ≈ var(ā)/ā² + var(b̄)/b̄² − 2 cov(ā, b̄)/(ā b̄), the means' (co)variances the
/// replicates' / n. 1 ± 0 for a configuration against itself (the same measurement).
pub fn gain(baseline: &Side, better: &Side) -> Gain {
    let (xa, xb) = shared(baseline, better);
    let n = xa.len() as f64;
    let (ma, mb) = (xa.iter().sum::<f64>() / n, xb.iter().sum::<f64>() / n);
    let value = ma / mb;
    // var(ln ratio) of the paired means (`stats::paired_log_ratio_variance`; NaN below two pairs).
    let (_, rel2) = paired_log_ratio_variance(&xa, &xb);
    let timing2 = if baseline.row == better.row {
        0.0
    } else {
        let (ka, kb) = (baseline.slope, better.slope);
        ((ka - kb) * RUN_FACTOR).powi(2)
            + (ka * baseline.time_sigma_ln).powi(2)
            + (kb * better.time_sigma_ln).powi(2)
    };
    let se_replicates = value * rel2.sqrt();
    let se_timing = value * timing2.sqrt();
    Gain { value, se: value * (rel2 + timing2).sqrt(), se_replicates, se_timing }
}

/// How far `other` trails `best` at the same budget, in σ of the model: ln(MSE_other / MSE_best)
/// over its σ (`margin::in_se`: ∞ when that σ is 0; NaN with fewer than two shared replicates).
/// The same model as a gain's, so a distance and a gain never disagree about what is resolved.
pub fn behind(best: &Side, other: &Side) -> f64 {
    if shared(best, other).0.len() < 2 {
        return f64::NAN;
    }
    let g = gain(other, best);
    in_se(g.value.ln(), g.se / g.value)
}

/// A configuration's mean MSE ± σ: over its replicates only for a measured ray count
/// (`at_budget` false); at a budget also its time's, through its slope (both the session factor
/// and the median's scatter: nothing cancels for one configuration alone).
pub fn mean_mse(side: &Side, at_budget: bool) -> Estimate {
    let (value, sd) = crate::metrics::mean_sd(side.values);
    let n = side.values.len() as f64;
    let rel_rep = if n > 1.0 { sd / n.sqrt() / value } else { f64::NAN };
    let rel_time = if at_budget { side.slope * time_sigma_ln(side.time_sigma_ln) } else { 0.0 };
    Estimate { value, se: value * rel_rep.hypot(rel_time) }
}

/// √(mean MSE) ± σ (delta method: σ(MSE) / (2 RMSE)).
pub fn rmse(e: Estimate) -> Estimate {
    let value = e.value.sqrt();
    Estimate { value, se: if value > 0.0 { e.se / (2.0 * value) } else { 0.0 } }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Distribution, SeedMode, Sequence};

    fn side<'a>(row: Row, values: &'a [f64], reps: &'a [u32], slope: f64, e: f64) -> Side<'a> {
        Side { row, replicates: reps, values, slope, time_sigma_ln: e }
    }

    #[test]
    fn the_median_sigma_is_its_interval_at_its_coverage() {
        // 15 samples: the interval is the 4th to 12th order statistic, coverage 96.5 %.
        let s: Vec<f64> = (1..=15).map(|i| (0.01 * i as f64).exp()).collect();
        let (_, _, level) = crate::stats::median_interval(&s, 0.95);
        assert!((level - 0.9648).abs() < 1e-3, "{level}");
        let want = 0.5 * (0.12 - 0.04) / crate::stats::normal_quantile(0.5 + 0.5 * level);
        assert!((median_sigma_ln(&s) - want).abs() < 1e-12);
        // Normal samples of σ = 1 %: the median's σ is about 1.25 % / √n.
        let mut state = 7u64;
        let mut normal = || {
            let mut u = || {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
            };
            (-2.0 * u().ln()).sqrt() * (std::f64::consts::TAU * u()).cos()
        };
        let sig: Vec<f64> = (0..400)
            .map(|_| median_sigma_ln(&(0..15).map(|_| (0.01 * normal()).exp()).collect::<Vec<_>>()))
            .collect();
        let mean = sig.iter().sum::<f64>() / sig.len() as f64;
        let want = 1.2533 * 0.01 / 15f64.sqrt();
        assert!((mean / want - 1.0).abs() < 0.25, "{mean} vs {want}");
        assert!(median_sigma_ln(&[1.0]).is_nan());
    }

    #[test]
    fn gains_and_margins_share_the_model() {
        let a = Row::new(Distribution::SineCosine, Sequence::Random, SeedMode::Rotation);
        let b = Row::new(Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Shift);
        let reps = [0, 1, 2, 3];
        let va = [4.0, 4.4, 3.6, 4.0];
        let vb = [1.0, 1.1, 0.9, 1.0];
        // The same noise in both: the ratio is exact per replicate, only timing is left.
        let g = gain(&side(a, &va, &reps, -1.0, 0.01), &side(b, &vb, &reps, -1.0, 0.02));
        assert!((g.value - 4.0).abs() < 1e-12 && g.se_replicates < 1e-9, "{g:?}");
        // Equal slopes: the session factor cancels; the medians' own scatter is left.
        assert!((g.se_timing / g.value - 0.01f64.hypot(0.02)).abs() < 1e-12, "{g:?}");
        let steep = gain(&side(a, &va, &reps, -2.0, 0.0), &side(b, &vb, &reps, -1.0, 0.0));
        assert!((steep.se_timing / steep.value - RUN_FACTOR).abs() < 1e-12, "{steep:?}");
        let own = gain(&side(a, &va, &reps, -1.0, 0.01), &side(a, &va, &reps, -1.0, 0.01));
        assert_eq!((own.value, own.se), (1.0, 0.0));
        // The distance behind is ln(gain) over its relative σ: the same numbers.
        let m = behind(&side(b, &vb, &reps, -1.0, 0.02), &side(a, &va, &reps, -1.0, 0.01));
        assert!((m - 4f64.ln() / 0.01f64.hypot(0.02)).abs() < 1e-9, "{m}");
        // One configuration's MSE at a budget carries its whole time σ; at a ray count it does not.
        let at = mean_mse(&side(b, &vb, &reps, -1.0, 0.04), true);
        let count = mean_mse(&side(b, &vb, &reps, -1.0, 0.04), false);
        let rep = crate::metrics::mean_sd(&vb).1 / 2.0;
        assert!((count.se - rep).abs() < 1e-12);
        assert!((at.se - rep.hypot(RUN_FACTOR.hypot(0.04))).abs() < 1e-12);
        let r = rmse(count);
        assert!((r.value - 1.0).abs() < 1e-12 && (r.se - rep / 2.0).abs() < 1e-12);
    }
}
