//! Leaf statistics module (imports nothing of the crate): ln Gamma, the mean with its standard
//! error, the log ratio of two paired means and Holm's multiplicity adjustment here; fits with
//! confidence intervals, paired differences and medians in `stats/fit.rs`. The
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

/// `n` standard normals (Box–Muller on SplitMix64 from `state`): fixed seeds, so the tests that
/// feed noise to the metrics and filters cannot flake; each caller keeps its own starting state.
#[cfg(any(test, feature = "testing"))]
pub fn normals_from_state(n: usize, mut state: u64) -> Vec<f64> {
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let (u, v) = (next().max(1e-300), next());
            (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
        })
        .collect()
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

/// ln(mean(b) / mean(a)) over paired samples (`a[i]` and `b[i]` share a seed) and its standard error
/// by the delta method ([`paired_log_ratio_variance`]). Pairing takes out the variation the two
/// share, which an unpaired √(se_a² + se_b²) would count twice. The error is NaN with fewer than
/// two pairs (nothing to estimate a spread from).
pub fn paired_log_ratio(a: &[f64], b: &[f64]) -> (f64, f64) {
    let (value, var) = paired_log_ratio_variance(a, b);
    (value, var.sqrt())
}

/// ln(mean(b) / mean(a)) and its variance by the delta method: var ≈ (var(a)/ā² + var(b)/b̄² −
/// 2 cov(a, b)/(ā b̄)) / n; NaN with fewer than two pairs. The variance itself, for a caller that
/// adds other independent parts to it before the square root.
pub fn paired_log_ratio_variance(a: &[f64], b: &[f64]) -> (f64, f64) {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let nf = n as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / nf, b.iter().sum::<f64>() / nf);
    let value = (mb / ma).ln();
    if n < 2 {
        return (value, f64::NAN);
    }
    let cov = |x: &[f64], mx: f64, y: &[f64], my: f64| {
        x.iter().zip(y).map(|(p, q)| (p - mx) * (q - my)).sum::<f64>() / (nf - 1.0)
    };
    let v =
        cov(a, ma, a, ma) / (ma * ma) + cov(b, mb, b, mb) / (mb * mb) - 2.0 * cov(a, ma, b, mb) / (ma * mb);
    (value, v.max(0.0) / nf)
}

/// Holm's step-down adjustment (Holm 1979) of a family of p-values: the i-th smallest (i from 1) is
/// multiplied by m − i + 1, the products made non-decreasing in that order and capped at 1. Every
/// hypothesis whose adjusted p-value is at most α is rejected, and then the chance of rejecting
/// any true one is at most α whatever the dependence between the tests — Bonferroni's guarantee,
/// never with fewer rejections than Bonferroni's m · p. NaN entries (nothing tested) stay NaN and
/// are not counted in m.
pub fn holm_adjusted(p: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..p.len()).filter(|&i| !p[i].is_nan()).collect();
    order.sort_by(|&i, &j| p[i].total_cmp(&p[j]));
    let m = order.len();
    let mut out = vec![f64::NAN; p.len()];
    let mut running = 0.0f64;
    for (k, &i) in order.iter().enumerate() {
        running = running.max(((m - k) as f64 * p[i]).min(1.0));
        out[i] = running;
    }
    out
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
    fn paired_log_ratio_takes_the_shared_variation_out() {
        // b is exactly twice a in every pair: the ratio is known without error however much a varies.
        let a = [1.0, 3.0, 2.0, 6.0];
        let b: Vec<f64> = a.iter().map(|x| 2.0 * x).collect();
        let (v, se) = paired_log_ratio(&a, &b);
        assert!((v - 2f64.ln()).abs() < 1e-12 && se < 1e-9, "{v} {se}");
        assert!(paired_log_ratio(&a[..1], &b[..1]).1.is_nan());
    }
}
