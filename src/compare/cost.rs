//! What one configuration costs against another over a whole sweep, pooled over its ray counts;
//! and the pairs for which cost is all there is to compare (pure: aggregates in, numbers out).
//!
//! A static seed and a per-pixel seed of the same point set give every pixel a point set of the
//! same distribution (the lattice's index offset is random in both: keyed by the run, or by the
//! pixel), so their expected MSE is identical by construction: an RMSE test at any ray count can
//! only confirm an identity. What can differ is the time, by a few per cent — within one time's
//! spread at one ray count, but resolved when the log time ratios of all ray counts are pooled.

use crate::results::{Aggregate, lookup};
use crate::sampling::{SeedMode, Sequence};
use crate::spec::Row;

/// Pairs (static seed, per-pixel seed) of `rows` whose expected MSE is identical by
/// construction: the same distribution and a sequence whose per-pixel seed is a random index
/// offset of the static set (the Fibonacci lattice) or fresh numbers of the same law
/// (pseudo-random). A stratified or Sobol' set rotated per pixel is not the static set's law.
pub fn same_expected_error(rows: &[Row]) -> Vec<(Row, Row)> {
    rows.iter()
        .filter(|r| {
            r.seed_mode == SeedMode::Static && matches!(r.sequence, Sequence::Fibonacci | Sequence::Random)
        })
        .filter_map(|&s| {
            let pixel = Row { seed_mode: SeedMode::Rotation, ..s };
            rows.iter().any(|r| r.canonical() == pixel.canonical()).then_some((s, pixel))
        })
        .collect()
}

/// b's median render time over a's, pooled over ray counts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pooled {
    /// exp(mean of ln(t_b / t_a)) over the ray counts.
    pub ratio: f64,
    /// Standard error of that mean log ratio: the scatter of the per-ray-count log ratios / √n.
    pub se_log: f64,
    /// Ray counts pooled.
    pub n: usize,
    /// The mean log ratio in its standard errors, and its two-sided p-value (Student's t, n − 1
    /// degrees of freedom).
    pub t: f64,
    pub p: f64,
    /// The least and greatest per-ray-count ratio.
    pub min: f64,
    pub max: f64,
}

/// b's median total render time over a's at every one of `rays` both were timed at, pooled as the
/// mean of the log ratios, with its standard error from their scatter across ray counts (which
/// holds each time's own spread and the machine's drift between them). Pooling assumes one cost
/// ratio for the sweep; where the per-image overhead dilutes it at low ray counts the mean is
/// nearer 1 than the per-ray cost ratio, so the test is conservative. `None` below two ray counts.
pub fn pooled_time_ratio(aggs: &[Aggregate], scene: &str, a: Row, b: Row, rays: &[u32]) -> Option<Pooled> {
    let time = |r: Row, n: u32| lookup(aggs, scene, r, n).and_then(|x| x.time).map(|t| t.median);
    let logs: Vec<f64> = rays
        .iter()
        .filter_map(|&n| Some((time(b, n)? / time(a, n)?).ln()))
        .filter(|x| x.is_finite())
        .collect();
    if logs.len() < 2 {
        return None;
    }
    let (mean, se_log) = crate::stats::mean_and_standard_error(&logs);
    let t = if se_log > 0.0 { mean / se_log } else { mean.signum() * f64::INFINITY };
    let p =
        if t.is_infinite() { 0.0 } else { crate::stats::student_t_two_sided_p(t, (logs.len() - 1) as f64) };
    let (min, max) =
        logs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| (lo.min(x), hi.max(x)));
    Some(Pooled { ratio: mean.exp(), se_log, n: logs.len(), t, p, min: min.exp(), max: max.exp() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Distribution;

    const SC: Distribution = Distribution::SineCosine;

    #[test]
    fn only_index_offset_seeds_are_identities() {
        let stat = Row::new(SC, Sequence::Fibonacci, SeedMode::Static);
        let pixel = Row::new(SC, Sequence::Fibonacci, SeedMode::Rotation);
        let sobol = Row::new(SC, Sequence::Sobol, SeedMode::Static);
        let sobol_pixel = Row::new(SC, Sequence::Sobol, SeedMode::Rotation);
        assert_eq!(same_expected_error(&[pixel, stat, sobol, sobol_pixel]), vec![(stat, pixel)]);
        assert!(same_expected_error(&[stat]).is_empty(), "no per-pixel row to pair");
    }
}
