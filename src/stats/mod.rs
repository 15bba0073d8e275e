//! Leaf statistics module (imports nothing of the crate): the chi-square goodness-of-fit
//! machinery of Mitsuba 3's chi2.py / pbrt-v4's bsdfs_test.cpp, and small helpers for
//! "within k standard errors" checks. The distributions themselves (gamma functions, chi-square,
//! normal quantiles) come from the statrs crate.
//! Fits with confidence intervals, paired differences and
//! medians live in `stats/fit.rs`.

mod fit;

pub use fit::{
    LinearFit, linear_fit, loglog_fit, median, median_interval, paired_difference, student_t_quantile,
    student_t_two_sided_p,
};

use std::fmt;

/// ln Gamma(x) for x > 0 (statrs).
pub fn ln_gamma(x: f64) -> f64 {
    statrs::function::gamma::ln_gamma(x)
}

/// Regularized lower incomplete gamma P(a, x) (statrs); 0 for x <= 0.
pub fn gamma_p(a: f64, x: f64) -> f64 {
    if x <= 0.0 { 0.0 } else { statrs::function::gamma::gamma_lr(a, x) }
}

/// Regularized upper incomplete gamma Q(a, x) = 1 - P(a, x) (statrs, computed directly in the tail
/// so tiny p-values keep their digits); 1 for x <= 0.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 { 1.0 } else { statrs::function::gamma::gamma_ur(a, x) }
}

/// P(X >= statistic) for X ~ chi^2(dof).
pub fn chi2_p_value(statistic: f64, dof: usize) -> f64 {
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    if statistic <= 0.0 {
        return 1.0;
    }
    ChiSquared::new(dof as f64).map_or(f64::NAN, |d| d.sf(statistic))
}

/// The standard normal quantile Φ⁻¹(p) (statrs), for p in (0, 1).
pub fn normal_quantile(p: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, Normal};
    Normal::standard().inverse_cdf(p)
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

/// Sample mean and its standard error (sample standard deviation / sqrt(n)).
pub fn mean_and_standard_error(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    if xs.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let mean = xs.iter().sum::<f64>() / n;
    if xs.len() < 2 {
        return (mean, f64::INFINITY);
    }
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ln_gamma_matches_factorials_and_half() {
        assert!((ln_gamma(1.0)).abs() < 1e-13);
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-12);
    }

    #[test]
    fn chi2_p_values_match_published_critical_values() {
        // Critical values of the chi-square distribution at p = 0.05 and 0.01.
        for (x, dof, p) in
            [(3.841_459, 1, 0.05), (18.307_04, 10, 0.05), (6.634_897, 1, 0.01), (124.342_1, 100, 0.05)]
        {
            let got = chi2_p_value(x, dof);
            assert!((got - p).abs() < 1e-5, "{x} {dof}: {got}");
        }
        // Below a + 1 (the series branch, where the warps' chi2 tests with thousands of dof land):
        // the lower 5 % critical values, and dof 2 in closed form, Q = exp(-x/2).
        for (x, dof) in [(77.929_46, 100), (3.940_299, 10)] {
            let got = chi2_p_value(x, dof);
            assert!((got - 0.95).abs() < 1e-5, "{x} {dof}: {got}");
        }
        assert!((chi2_p_value(0.103, 2) - (-0.0515f64).exp()).abs() < 1e-12);
        // P + Q = 1 on both branches.
        for (a, x) in [(0.5, 0.2), (3.0, 10.0), (2500.0, 2400.0)] {
            assert!((gamma_p(a, x) + gamma_q(a, x) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn pooling_reaches_min_expected_and_keeps_totals() {
        let e = [0.5, 1.0, 2.0, 3.0, 10.0, 0.0, 4.0];
        let o = [1.0, 0.0, 2.0, 4.0, 9.0, 0.0, 5.0];
        let pools = pool_cells(&o, &e, 5.0);
        assert!(pools.iter().all(|p| p.1 >= 5.0));
        assert_eq!(pools.iter().map(|p| p.0).sum::<f64>(), 21.0);
        assert_eq!(pools.iter().map(|p| p.1).sum::<f64>(), 20.5);
    }

    #[test]
    fn chi2_fails_outright_on_sample_in_empty_cell() {
        let r = chi2_test(&[1.0, 10.0, 10.0], &[0.0, 10.0, 11.0], 5.0);
        assert!(matches!(r, Err(Chi2Error::SampleWhereExpectedZero { cell: 0, .. })));
        assert!(matches!(chi2_test(&[1.0], &[5.0, 6.0], 5.0), Err(Chi2Error::LengthMismatch { .. })));
    }

    #[test]
    fn two_sided_z_matches_normal_quantiles() {
        // Published two-sided quantiles of the standard normal.
        for (p, z) in [(0.05, 1.959_964), (0.01, 2.575_829), (0.002_699_796, 3.0), (1e-6, 4.891_638)] {
            assert!((two_sided_z(p) - z).abs() < 1e-5, "p = {p}: {}", two_sided_z(p));
        }
        assert_eq!(two_sided_z(1.0), 0.0);
    }

    #[test]
    fn sidak_threshold_is_alpha_for_one_test() {
        assert!((sidak_threshold(0.01, 1) - 0.01).abs() < 1e-15);
        assert!(sidak_threshold(0.01, 4) < 0.01 / 4.0 + 1e-5);
    }
}
