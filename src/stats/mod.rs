//! Leaf statistics module (imports nothing of the crate): ln Gamma and the mean with its standard
//! error here; fits with confidence intervals, paired differences and medians in `stats/fit.rs`. The
//! distributions themselves come from the statrs crate. The tests' chi-square goodness of fit and
//! "within k standard errors" bounds are in `tests/support/stats.rs`; the chi-square tail and the
//! normal quantile they build on (unit tests here use them too) exist only for tests (`cfg(test)`
//! or the `testing` feature, which this package's dev-dependency on itself turns on), except the
//! normal quantile, which advise's error model also uses to turn an interval into a σ.

mod fit;

pub use fit::{
    LinearFit, linear_fit, loglog_fit, median, median_interval, paired_difference, student_t_quantile,
    student_t_two_sided_p,
};

/// ln Gamma(x) for x > 0 (statrs).
pub fn ln_gamma(x: f64) -> f64 {
    statrs::function::gamma::ln_gamma(x)
}

/// P(X >= statistic) for X ~ chi^2(dof).
#[cfg(any(test, feature = "testing"))]
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
}
