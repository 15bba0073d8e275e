//! The tests' statistics: the chi-square goodness-of-fit machinery of Mitsuba 3's chi2.py /
//! pbrt-v4's bsdfs_test.cpp, and "within k standard errors" bounds. The distributions come from
//! statrs, the chi-square tail and normal quantile through `hemilab::stats` (feature `testing`).
//! Their own tests are in `tests/stages/stats.rs`.

use hemilab::stats::{chi2_p_value, normal_quantile};
use std::fmt;

/// Regularized lower incomplete gamma P(a, x) (statrs); 0 for x <= 0.
pub fn gamma_p(a: f64, x: f64) -> f64 {
    if x <= 0.0 { 0.0 } else { statrs::function::gamma::gamma_lr(a, x) }
}

/// Regularized upper incomplete gamma Q(a, x) = 1 - P(a, x) (statrs, computed directly in the tail
/// so tiny p-values keep their digits); 1 for x <= 0.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 { 1.0 } else { statrs::function::gamma::gamma_ur(a, x) }
}

/// Per-test significance level so that k independent tests together reject with prob. alpha.
pub fn sidak_threshold(alpha: f64, k: usize) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / k.max(1) as f64)
}

/// The z with P(|Z| > z) = `p` for a standard normal Z (p in (0, 1]): the "within z standard errors"
/// bound whose two-sided false-alarm rate is `p`, e.g. p = `sidak_threshold(0.01, k)` for a family
/// of k such checks. Taken from the lower tail, −Φ⁻¹(p/2), so that tiny p keep their digits.
pub fn two_sided_z(p: f64) -> f64 {
    if p.is_nan() || p >= 1.0 {
        return 0.0;
    }
    -normal_quantile(0.5 * p)
}

/// Pools cells, sorted by expected count, until each pool expects at least `min_expected`;
/// a short last pool joins the one before. Cells expecting 0 are left out (the caller checks
/// that nothing landed there). Returns (observed, expected) per pool.
pub fn pool_cells(observed: &[f64], expected: &[f64], min_expected: f64) -> Vec<(f64, f64)> {
    let mut order: Vec<usize> = (0..expected.len()).filter(|&i| expected[i] > 0.0).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let mut pools: Vec<(f64, f64)> = Vec::new();
    let (mut o, mut e) = (0.0, 0.0);
    for i in order {
        o += observed[i];
        e += expected[i];
        if e >= min_expected {
            pools.push((o, e));
            (o, e) = (0.0, 0.0);
        }
    }
    if e > 0.0 {
        match pools.last_mut() {
            Some(last) => {
                last.0 += o;
                last.1 += e;
            }
            None => pools.push((o, e)),
        }
    }
    pools
}

/// Outcome of a chi-square goodness-of-fit test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chi2 {
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
    pub pools: usize,
}

/// Why a histogram cannot even be tested (each is an outright failure of the warp under test).
#[derive(Debug, Clone, PartialEq)]
pub enum Chi2Error {
    LengthMismatch { observed: usize, expected: usize },
    NotFinite { cell: usize },
    SampleWhereExpectedZero { cell: usize, observed: f64 },
    ExpectedExceedsTotal { expected: f64, total: f64 },
    TooFewPools(usize),
}

impl fmt::Display for Chi2Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Chi2Error::LengthMismatch { observed, expected } => {
                write!(f, "{observed} observed cells but {expected} expected cells")
            }
            Chi2Error::NotFinite { cell } => write!(f, "cell {cell} has a non-finite count"),
            Chi2Error::SampleWhereExpectedZero { cell, observed } => {
                write!(f, "cell {cell} expects 0 samples but got {observed}")
            }
            Chi2Error::ExpectedExceedsTotal { expected, total } => {
                write!(f, "expected counts sum to {expected}, more than 1.1 x {total} samples")
            }
            Chi2Error::TooFewPools(n) => write!(f, "only {n} pools: nothing to test"),
        }
    }
}

impl std::error::Error for Chi2Error {}

/// Pearson's chi-square test of `observed` against `expected` counts per cell, after pooling
/// to `min_expected` (5 in the usual recipe). dof = pools - 1.
pub fn chi2_test(observed: &[f64], expected: &[f64], min_expected: f64) -> Result<Chi2, Chi2Error> {
    if observed.len() != expected.len() {
        return Err(Chi2Error::LengthMismatch { observed: observed.len(), expected: expected.len() });
    }
    for (cell, (&o, &e)) in observed.iter().zip(expected).enumerate() {
        if !o.is_finite() || !e.is_finite() || e < 0.0 {
            return Err(Chi2Error::NotFinite { cell });
        }
        if e == 0.0 && o > 0.0 {
            return Err(Chi2Error::SampleWhereExpectedZero { cell, observed: o });
        }
    }
    let total: f64 = observed.iter().sum();
    let expected_sum: f64 = expected.iter().sum();
    if expected_sum > 1.1 * total {
        return Err(Chi2Error::ExpectedExceedsTotal { expected: expected_sum, total });
    }
    let pools = pool_cells(observed, expected, min_expected);
    if pools.len() < 2 {
        return Err(Chi2Error::TooFewPools(pools.len()));
    }
    let statistic: f64 = pools.iter().map(|&(o, e)| (o - e) * (o - e) / e).sum();
    let dof = pools.len() - 1;
    Ok(Chi2 { statistic, dof, p_value: chi2_p_value(statistic, dof), pools: pools.len() })
}
