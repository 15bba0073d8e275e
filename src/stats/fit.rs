//! Fits with confidence intervals, paired differences and medians: what the report needs to say
//! how sure a slope, a difference or a time is. Student's t comes from statrs; imports nothing else
//! of the crate but `super`.

use super::{ln_gamma, mean_and_standard_error};
use statrs::distribution::{ContinuousCDF, StudentsT};

/// P(|T| > t) for Student's T with `dof` degrees of freedom: I_{dof/(dof+t²)}(dof/2, 1/2).
pub fn student_t_two_sided_p(t: f64, dof: f64) -> f64 {
    match StudentsT::new(0.0, 1.0, dof) {
        Ok(d) if !t.is_nan() => 2.0 * d.sf(t.abs()),
        _ => f64::NAN,
    }
}

/// The t with P(|T| > t) = `p` for Student's T with `dof` degrees of freedom, e.g. 12.706 for
/// p = 0.05 and 1 dof: the half-width, in standard errors, of a two-sided confidence interval of
/// level 1 − p from a fit with `dof` residual degrees of freedom.
pub fn student_t_quantile(p: f64, dof: f64) -> f64 {
    if p >= 1.0 {
        return 0.0;
    }
    if p.is_nan() || p <= 0.0 {
        return f64::NAN;
    }
    match StudentsT::new(0.0, 1.0, dof) {
        Ok(d) => d.inverse_cdf(1.0 - p / 2.0),
        Err(_) => f64::NAN,
    }
}

/// A weighted least-squares line y = intercept + slope · x, with the standard errors of both
/// coefficients from the residual scatter (so points that do not lie on a line widen the interval).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearFit {
    pub slope: f64,
    pub intercept: f64,
    pub slope_se: f64,
    pub intercept_se: f64,
    /// Points in the fit.
    pub n: usize,
}

impl LinearFit {
    /// Residual degrees of freedom.
    pub fn dof(&self) -> usize {
        self.n.saturating_sub(2)
    }

    /// Two-sided Student-t confidence interval of the slope at `level` (e.g. 0.95); `None` with
    /// fewer than three points (no residual to judge the scatter by).
    pub fn slope_interval(&self, level: f64) -> Option<(f64, f64)> {
        self.interval(self.slope, self.slope_se, level)
    }

    /// The same for the intercept.
    pub fn intercept_interval(&self, level: f64) -> Option<(f64, f64)> {
        self.interval(self.intercept, self.intercept_se, level)
    }

    fn interval(&self, value: f64, se: f64, level: f64) -> Option<(f64, f64)> {
        if self.dof() == 0 || !se.is_finite() {
            return None;
        }
        let t = student_t_quantile(1.0 - level, self.dof() as f64);
        Some((value - t * se, value + t * se))
    }
}

/// Weighted least squares of `ys` on `xs` (weights: `None` = all 1; relative weights, e.g. 1/y² for
/// points whose error is a fixed fraction of y). Points with a non-finite value or a weight ≤ 0
/// are left out. `None` with fewer than two distinct x.
pub fn linear_fit(xs: &[f64], ys: &[f64], weights: Option<&[f64]>) -> Option<LinearFit> {
    let pts: Vec<(f64, f64, f64)> = (0..xs.len().min(ys.len()))
        .map(|i| (xs[i], ys[i], weights.map_or(1.0, |w| w.get(i).copied().unwrap_or(0.0))))
        .filter(|(x, y, w)| x.is_finite() && y.is_finite() && w.is_finite() && *w > 0.0)
        .collect();
    if pts.len() < 2 {
        return None;
    }
    // Weights normalized to mean 1, so the residual variance is in y's units and integer weights
    // act as repeated points only through the fit, not through the point count.
    let norm = pts.len() as f64 / pts.iter().map(|p| p.2).sum::<f64>();
    let pts: Vec<(f64, f64, f64)> = pts.into_iter().map(|(x, y, w)| (x, y, w * norm)).collect();
    let n = pts.len();
    let sw = n as f64;
    let mx = pts.iter().map(|p| p.2 * p.0).sum::<f64>() / sw;
    let my = pts.iter().map(|p| p.2 * p.1).sum::<f64>() / sw;
    let sxx: f64 = pts.iter().map(|p| p.2 * (p.0 - mx).powi(2)).sum();
    if sxx.partial_cmp(&(1e-12 * (1.0 + mx * mx))) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let slope = pts.iter().map(|p| p.2 * (p.0 - mx) * (p.1 - my)).sum::<f64>() / sxx;
    let intercept = my - slope * mx;
    let (slope_se, intercept_se) = if n > 2 {
        let rss: f64 = pts.iter().map(|p| p.2 * (p.1 - intercept - slope * p.0).powi(2)).sum();
        let s2 = rss / (n - 2) as f64;
        ((s2 / sxx).sqrt(), (s2 * (1.0 / sw + mx * mx / sxx)).sqrt())
    } else {
        (f64::NAN, f64::NAN)
    };
    Some(LinearFit { slope, intercept, slope_se, intercept_se, n })
}

/// Least-squares fit of ln y against ln x over the points with x, y > 0 and finite (a power law's
/// exponent is the slope); `None` with fewer than two distinct x.
pub fn loglog_fit(xs: &[f64], ys: &[f64]) -> Option<LinearFit> {
    let (lx, ly): (Vec<f64>, Vec<f64>) = xs
        .iter()
        .zip(ys)
        .filter(|(x, y)| **x > 0.0 && **y > 0.0 && x.is_finite() && y.is_finite())
        .map(|(x, y)| (x.ln(), y.ln()))
        .unzip();
    linear_fit(&lx, &ly, None)
}

/// Mean and standard error of the paired differences b_i − a_i. When measurement i of `a` and of
/// `b` share their random numbers (replicate i uses the same seed in every configuration), the
/// shared noise cancels in each difference, so sd(differences)/√n is the honest, and usually much
/// smaller, standard error of the difference — not √(se_a² + se_b²). Pairs with a non-finite
/// value are left out; `(NaN, NaN)` when no pair is left.
pub fn paired_difference(a: &[f64], b: &[f64]) -> (f64, f64) {
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).filter(|d| d.is_finite()).collect();
    mean_and_standard_error(&d)
}

/// Median of the finite values (mean of the middle two for an even count); NaN when none.
pub fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 { v[m] } else { 0.5 * (v[m - 1] + v[m]) }
}

/// Distribution-free confidence interval of the median: the order statistics x_(k) and
/// x_(n+1−k) with k the largest rank for which the interval still covers the median with
/// probability at least `level` (from the binomial(n, ½) distribution of the count below it); with
/// too few values for `level`, the widest interval, [min, max]. Returns (low, high, coverage);
/// NaNs for no finite value. Assumes nothing about the distribution, so one slow outlier among
/// many timings does not widen it.
pub fn median_interval(values: &[f64], level: f64) -> (f64, f64, f64) {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    // P(B <= j) for B ~ binomial(n, 1/2), accumulated in log space.
    let ln_half_n = -(n as f64) * std::f64::consts::LN_2;
    let ln_choose =
        |j: usize| ln_gamma(n as f64 + 1.0) - ln_gamma(j as f64 + 1.0) - ln_gamma((n - j) as f64 + 1.0);
    let mut below = ln_half_n.exp(); // P(B <= k - 1), k = 1
    let mut k = 1;
    while 2 * (k + 1) <= n + 1 {
        let next = below + (ln_choose(k) + ln_half_n).exp(); // P(B <= k)
        if 1.0 - 2.0 * next < level {
            break;
        }
        below = next;
        k += 1;
    }
    (v[k - 1], v[n - k], 1.0 - 2.0 * below)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn student_t_quantiles_match_tables() {
        // Published two-sided 95 % and 99 % critical values of Student's t.
        for (p, dof, t) in [
            (0.05, 1.0, 12.706_205),
            (0.05, 2.0, 4.302_653),
            (0.05, 9.0, 2.262_157),
            (0.05, 30.0, 2.042_272),
            (0.01, 5.0, 4.032_143),
            (0.05, 1e6, 1.959_966),
        ] {
            let got = student_t_quantile(p, dof);
            assert!((got - t).abs() < 1e-4 * t, "p {p}, dof {dof}: {got}");
            assert!((student_t_two_sided_p(t, dof) - p).abs() < 1e-6);
        }
        assert!(student_t_quantile(0.05, 0.0).is_nan());
        assert_eq!(student_t_quantile(1.0, 3.0), 0.0);
    }

    #[test]
    fn linear_fit_recovers_a_line_and_its_standard_errors() {
        // An exact line: zero standard errors.
        let f = linear_fit(&[1.0, 2.0, 3.0, 4.0], &[3.0, 5.0, 7.0, 9.0], None).unwrap();
        assert!((f.slope - 2.0).abs() < 1e-12 && (f.intercept - 1.0).abs() < 1e-12);
        assert!(f.slope_se < 1e-12 && f.intercept_se < 1e-12);
        // y = 0, 1, 1, 2 on x = 0..3: slope 0.6, intercept 0.1, residuals -0.1, 0.3, -0.3, 0.1,
        // s² = 0.2/2 = 0.1, Sxx = 5: se(slope) = √0.02, se(intercept) = √(0.1 (1/4 + 2.25/5)).
        let f = linear_fit(&[0.0, 1.0, 2.0, 3.0], &[0.0, 1.0, 1.0, 2.0], None).unwrap();
        assert!((f.slope - 0.6).abs() < 1e-12 && (f.intercept - 0.1).abs() < 1e-12);
        assert!((f.slope_se - 0.02f64.sqrt()).abs() < 1e-12);
        assert!((f.intercept_se - (0.1f64 * 0.7).sqrt()).abs() < 1e-12);
        let (lo, hi) = f.slope_interval(0.95).unwrap();
        let t = student_t_quantile(0.05, 2.0);
        assert!((hi - lo - 2.0 * t * 0.02f64.sqrt()).abs() < 1e-9);
        assert!((0.5 * (lo + hi) - 0.6).abs() < 1e-12);
        // Weights move the line like repeated points would.
        let w = linear_fit(&[0.0, 1.0, 2.0], &[0.0, 2.0, 2.0], Some(&[1.0, 2.0, 1.0])).unwrap();
        let r = linear_fit(&[0.0, 1.0, 1.0, 2.0], &[0.0, 2.0, 2.0, 2.0], None).unwrap();
        assert!((w.slope - r.slope).abs() < 1e-12 && (w.intercept - r.intercept).abs() < 1e-12);
        // Two points: a slope, but no interval.
        let two = linear_fit(&[1.0, 2.0], &[1.0, 3.0], None).unwrap();
        assert_eq!(two.slope_interval(0.95), None);
        assert!(linear_fit(&[1.0, 1.0], &[1.0, 2.0], None).is_none());
        let p = loglog_fit(&[1.0, 4.0, 16.0, 0.0], &[1.0, 0.5, 0.25, 3.0]).unwrap();
        assert!((p.slope + 0.5).abs() < 1e-12 && p.n == 3);
        assert!(loglog_fit(&[4.0, 4.0], &[1.0, 2.0]).is_none() && loglog_fit(&[4.0], &[1.0]).is_none());
        assert!((loglog_fit(&[1.0, 10.0], &[1.0, 10.0]).unwrap().slope - 1.0).abs() < 1e-12);
    }

    #[test]
    fn paired_difference_cancels_shared_noise() {
        // Shared replicate noise of ±0.1 and a constant difference of 0.01: the paired standard
        // error is 0 where the unpaired one would be about 0.04.
        let a = [0.5, 0.6, 0.4, 0.55];
        let b: Vec<f64> = a.iter().map(|x| x + 0.01).collect();
        let (d, se) = paired_difference(&a, &b);
        assert!((d - 0.01).abs() < 1e-12 && se < 1e-12);
        // Differences 1, 0, 2: mean 1, sd 1.
        let (d, se) = paired_difference(&[1.0, 2.0, 3.0], &[2.0, 2.0, 5.0]);
        assert!((d - 1.0).abs() < 1e-12 && (se - 1.0 / 3f64.sqrt()).abs() < 1e-12, "{d} {se}");
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        // Order-statistic intervals of the median (tables of the sign test): n = 4 is too few for
        // 95 % (min..max covers 87.5 %); n = 12 gives x(3)..x(10) at 96.1 %; n = 15, x(4)..x(12) at 96.5 %.
        let (lo, hi, c) = median_interval(&[4.0, 1.0, 3.0, 2.0], 0.95);
        assert_eq!((lo, hi), (1.0, 4.0));
        assert!((c - 0.875).abs() < 1e-12);
        let twelve: Vec<f64> = (1..=12).map(f64::from).collect();
        let (lo, hi, c) = median_interval(&twelve, 0.95);
        assert_eq!((lo, hi), (3.0, 10.0));
        assert!((c - (1.0 - 2.0 * 79.0 / 4096.0)).abs() < 1e-12, "{c}");
        let fifteen: Vec<f64> = (1..=15).map(f64::from).collect();
        let (lo, hi, c) = median_interval(&fifteen, 0.95);
        assert_eq!((lo, hi), (4.0, 12.0));
        assert!((c - (1.0 - 2.0 * 576.0 / 32768.0)).abs() < 1e-12, "{c}");
        assert_eq!(median_interval(&[7.0], 0.95).0, 7.0);
        assert!(median_interval(&[], 0.95).0.is_nan());
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0, f64::NAN]), 2.5);
        assert!(median(&[]).is_nan());
    }
}
