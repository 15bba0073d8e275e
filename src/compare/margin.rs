//! The one paired margin every verdict of the crate rests on: two configurations compared
//! replicate by replicate, d_r = b_r − a_r, with the mean of the differences and its standard error
//! sd(d) / √n.
//!
//! Replicate r of every configuration has the same seed (`plan::replicate_seed`), so the variation
//! the two share (the same random numbers through two warps, the same scene) cancels in each
//! difference: the paired standard error is both the right error bar and a much tighter one than
//! the unpaired √(sd_a²/n + sd_b²/n). The claims (`claims`, at 1 %), the real-time verdicts
//! (`realtime`, at 5 %), the integrand verdicts (`integrands`), the comparisons at equal rays
//! (`paired_rmse`) and the error model's ratios at equal time (`model::gain`, through [`pairs`])
//! all pair here; they differ only in what they call significant and how they word it.

use crate::stats::{mean_and_standard_error, paired_difference, student_t_quantile, student_t_two_sided_p};

/// The values of `a` and `b` (keyed by replicate) that share a replicate, in `a`'s order; pairs
/// with a non-finite value are left out (they would make the mean and its error undefined).
pub fn pairs(a: &[(u32, f64)], b: &[(u32, f64)]) -> (Vec<f64>, Vec<f64>) {
    a.iter()
        .filter_map(|&(r, va)| b.iter().find(|x| x.0 == r).map(|&(_, vb)| (va, vb)))
        .filter(|(va, vb)| va.is_finite() && vb.is_finite())
        .unzip()
}

/// The mean of the paired differences b − a, its standard error, the number of pairs, and the
/// mean of `a` over them (what a relative margin is relative to).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Margin {
    pub mean: f64,
    pub se: f64,
    pub n: usize,
    /// Mean of `a` over the pairs (NaN for a margin that is not a difference of pairs, such as a
    /// slope's distance to a tolerance).
    pub base: f64,
}

/// `b − a` over the replicates both have (`pairs`). With one pair the standard error is ∞, with
/// none everything is NaN: a verdict needs [`Margin::measured`].
pub fn paired(a: &[(u32, f64)], b: &[(u32, f64)]) -> Margin {
    let (va, vb) = pairs(a, b);
    let (mean, se) = paired_difference(&va, &vb);
    let (base, _) = mean_and_standard_error(&va);
    Margin { mean, se, n: va.len(), base }
}

/// `mean / se` in standard errors: ±∞ when the error is 0 and the mean is not, 0 when both are.
pub fn in_se(mean: f64, se: f64) -> f64 {
    if se > 0.0 {
        mean / se
    } else if mean == 0.0 {
        0.0
    } else {
        mean.signum() * f64::INFINITY
    }
}

/// The margin (in standard errors) a paired comparison of `n` pairs needs to be significant at
/// two-sided level `alpha`: Student's t quantile with n − 1 degrees of freedom (∞ when undefined).
pub fn critical_se(alpha: f64, n: usize) -> f64 {
    let t = student_t_quantile(alpha, (n.max(2) - 1) as f64);
    if t.is_nan() { f64::INFINITY } else { t }
}

impl Margin {
    /// The margin when it can carry a verdict: at least two pairs (a spread to estimate the error
    /// from).
    pub fn measured(self) -> Option<Self> {
        (self.n >= 2).then_some(self)
    }

    /// The mean in standard errors ([`in_se`]).
    pub fn in_se(&self) -> f64 {
        in_se(self.mean, self.se)
    }

    /// The mean, and its standard error, relative to `a`'s mean.
    pub fn relative(&self) -> f64 {
        self.mean / self.base
    }

    pub fn relative_se(&self) -> f64 {
        self.se / self.base
    }

    /// +1 when b − a is significantly positive at two-sided level `alpha` (Student's t with n − 1
    /// degrees of freedom), −1 when significantly negative, 0 otherwise (and with fewer than two
    /// pairs or an undefined error).
    pub fn sign(&self, alpha: f64) -> i32 {
        if self.n < 2 || !self.se.is_finite() {
            return 0;
        }
        let (t, crit) = (self.in_se(), critical_se(alpha, self.n));
        if t >= crit {
            1
        } else if t <= -crit {
            -1
        } else {
            0
        }
    }

    /// The two-sided p-value of the mean (Student's t, n − 1 degrees of freedom; 0 at ±∞).
    pub fn p_two_sided(&self) -> f64 {
        let t = self.in_se();
        if t.is_infinite() { 0.0 } else { student_t_two_sided_p(t, (self.n.max(2) - 1) as f64) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_match_replicates_by_number_and_drop_non_finite_ones() {
        let a = [(0, 1.0), (1, 2.0), (2, 3.0), (3, f64::NAN)];
        let b = [(3, 4.0), (2, 3.5), (0, 1.5), (9, 7.0)];
        assert_eq!(pairs(&a, &b), (vec![1.0, 3.0], vec![1.5, 3.5]));
    }

    #[test]
    fn the_margin_uses_the_spread_of_the_differences() {
        // Both vary a lot from replicate to replicate, but b is always a + 0.1 ± 0.01.
        let a = [(0, 1.0), (1, 2.0), (2, 3.0), (3, 4.0)];
        let b = [(0, 1.11), (1, 2.09), (2, 3.1), (3, 4.1)];
        let m = paired(&a, &b);
        assert!((m.mean - 0.1).abs() < 1e-12 && m.n == 4 && (m.base - 2.5).abs() < 1e-12, "{m:?}");
        assert!(m.in_se() > 20.0 && m.sign(0.01) == 1 && m.p_two_sided() < 1e-3, "{m:?}");
        assert!((m.relative() - 0.04).abs() < 1e-12);
        // Differences 0.1, −0.05, 0.1: mean 0.05, se 0.05 → t 1 < t(2 dof, 5 %) = 4.3: no verdict.
        let tie = paired(&[(0, 1.0), (1, 1.0), (2, 1.0)], &[(0, 1.1), (1, 0.95), (2, 1.1)]);
        assert!((tie.relative() - 0.05).abs() < 1e-12 && (tie.relative_se() - 0.05).abs() < 1e-12);
        assert_eq!(tie.sign(0.05), 0);
        // One pair: a value, no error, no verdict.
        let one = paired(&a[..1], &b[..1]);
        assert_eq!((one.n, one.se, one.measured()), (1, f64::INFINITY, None));
        assert_eq!(one.sign(0.05), 0);
        assert_eq!(in_se(0.5, 0.0), f64::INFINITY);
        assert_eq!(in_se(0.0, 0.0), 0.0);
    }

    #[test]
    fn critical_values_are_students_t() {
        assert!((critical_se(0.01, 4) - 5.840_909).abs() < 1e-4);
        assert!((critical_se(0.01, 8) - 3.499_483).abs() < 1e-4);
        assert!((critical_se(0.05, 3) - 4.302_653).abs() < 1e-4);
    }
}
