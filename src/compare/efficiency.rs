//! Comparisons by efficiency, 1 / (MSE · AO time): the most efficient configuration at each ray
//! count with its margin over the runner-up in paired standard errors (a column of `run`'s report,
//! not its ranking, which is by MSE at equal time: `equal_time`), and whether two runs rank the
//! rows' efficiency identically wherever they differ by more than 3 combined spreads (the check
//! behind the README's statement that reruns agree). Pure: aggregates and records in.

use crate::compare::margin::{in_se, pairs};
use crate::results::{Aggregate, JobResult, lookup};
use crate::spec::Row;
use crate::stats::paired_log_ratio;

/// How far apart two efficiencies are, in combined spreads √(s_a² + s_b²).
pub fn spreads_apart(a: &Aggregate, b: &Aggregate) -> f64 {
    let s = (a.efficiency_spread.powi(2) + b.efficiency_spread.powi(2)).sqrt();
    (a.efficiency - b.efficiency).abs() / s
}

/// The most efficient configuration at one ray count, and its margin.
#[derive(Debug, Clone, PartialEq)]
pub struct Best<'a> {
    pub rays: u32,
    pub best: &'a Aggregate,
    pub runner_up: Option<&'a Aggregate>,
    /// ln(best's efficiency / the runner-up's) in its paired standard errors
    /// (`efficiency_log_ratio`); `None` without a runner-up or with fewer than two shared replicates.
    pub margin_se: Option<f64>,
}

impl Best<'_> {
    /// best / runner-up efficiency.
    pub fn ratio(&self) -> Option<f64> {
        self.runner_up.map(|r| self.best.efficiency / r.efficiency)
    }
}

/// Each replicate's MSE of one aggregate's configuration, by replicate.
fn mse_by_replicate(results: &[JobResult], a: &Aggregate) -> Vec<(u32, f64)> {
    let is = |r: &JobResult| {
        r.is_single_frame()
            && r.config()
                == (
                    a.scene.as_str(),
                    a.distribution.as_str(),
                    a.sequence.as_str(),
                    a.seed_mode.as_str(),
                    a.rays,
                )
    };
    results.iter().filter(|r| is(r)).map(|r| (r.replicate, r.rmse * r.rmse)).collect()
}

/// ln(E_a / E_b) of two configurations at the same ray count and its standard error. With
/// E = 1 / (MSE · AO time), ln(E_a/E_b) = ln(MSE_b/MSE_a) + ln(T_b/T_a): the MSE part's error is
/// paired over the replicates the two share (the same seeds: `stats::paired_log_ratio`), which the
/// aggregates' own spreads, each from its replicates alone, would count twice; the time part's is
/// the two times' relative spreads (separate renders), in quadrature. `None` with fewer than two
/// shared replicates or without both AO times.
pub fn efficiency_log_ratio(results: &[JobResult], a: &Aggregate, b: &Aggregate) -> Option<(f64, f64)> {
    let (xa, xb) = pairs(&mse_by_replicate(results, a), &mse_by_replicate(results, b));
    let rel = |g: &Aggregate| g.time.map(|t| t.spread() / g.ao_time_s).filter(|x| x.is_finite());
    let (ta, tb) = (rel(a)?, rel(b)?);
    if xa.len() < 2 || !(a.ao_time_s > 0.0 && b.ao_time_s > 0.0) {
        return None;
    }
    let (ln_mse, se_mse) = paired_log_ratio(&xa, &xb);
    Some((ln_mse + (b.ao_time_s / a.ao_time_s).ln(), se_mse.hypot(ta).hypot(tb)))
}

/// At each of `rays`, the candidate of highest efficiency among `aggs` of `scene` whose row
/// passes `keep`, with its margin over the runner-up in paired standard errors (`results` pair
/// them); ray counts without two defined efficiencies give a `Best` without runner-up, or none at all.
pub fn best_per_ray_count<'a>(
    aggs: &'a [Aggregate],
    results: &[JobResult],
    scene: &str,
    rows: &[Row],
    rays: &[u32],
    keep: impl Fn(Row) -> bool,
) -> Vec<Best<'a>> {
    rays.iter()
        .filter_map(|&n| {
            let mut c: Vec<&Aggregate> = rows
                .iter()
                .filter(|r| keep(**r))
                .filter_map(|&r| lookup(aggs, scene, r, n))
                .filter(|a| a.efficiency.is_finite())
                .collect();
            c.sort_by(|a, b| b.efficiency.total_cmp(&a.efficiency));
            let best = *c.first()?;
            let runner_up = c.get(1).copied();
            let margin_se =
                runner_up.and_then(|r| efficiency_log_ratio(results, best, r)).map(|(v, se)| in_se(v, se));
            Some(Best { rays: n, best, runner_up, margin_se })
        })
        .collect()
}

/// A pair of configurations two runs rank differently although at least one run puts them more
/// than `k` combined spreads apart.
#[derive(Debug, Clone, PartialEq)]
pub struct Disagreement {
    pub scene: String,
    pub rays: u32,
    pub a: String,
    pub b: String,
    /// Efficiencies of a and b in the first and in the second run.
    pub first: (f64, f64),
    pub second: (f64, f64),
    pub spreads: (f64, f64),
}

/// Every pair of `rows` at a common (scene, ray count) that `first` and `second` order
/// differently by efficiency although one of them puts the pair more than `k` combined spreads
/// apart. Also returns how many pairs were that far apart in either run (the pairs checked).
pub fn rank_disagreements(
    first: &[Aggregate],
    second: &[Aggregate],
    rows: &[Row],
    k: f64,
) -> (Vec<Disagreement>, usize) {
    let mut out = Vec::new();
    let mut checked = 0;
    let scenes: Vec<&str> = {
        let mut s: Vec<&str> = first.iter().map(|a| a.scene.as_str()).collect();
        s.dedup();
        s
    };
    let mut rays: Vec<u32> = first.iter().map(|a| a.rays).collect();
    rays.sort_unstable();
    rays.dedup();
    for scene in scenes {
        for &n in &rays {
            for (i, ra) in rows.iter().enumerate() {
                for rb in &rows[i + 1..] {
                    let get = |aggs: &'_ [Aggregate], r: Row| lookup(aggs, scene, r, n).cloned();
                    let (Some(a1), Some(b1), Some(a2), Some(b2)) =
                        (get(first, *ra), get(first, *rb), get(second, *ra), get(second, *rb))
                    else {
                        continue;
                    };
                    let (s1, s2) = (spreads_apart(&a1, &b1), spreads_apart(&a2, &b2));
                    if !(s1 > k || s2 > k) {
                        continue;
                    }
                    checked += 1;
                    if (a1.efficiency > b1.efficiency) != (a2.efficiency > b2.efficiency) {
                        out.push(Disagreement {
                            scene: scene.to_string(),
                            rays: n,
                            a: ra.label(),
                            b: rb.label(),
                            first: (a1.efficiency, b1.efficiency),
                            second: (a2.efficiency, b2.efficiency),
                            spreads: (s1, s2),
                        });
                    }
                }
            }
        }
    }
    (out, checked)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compare::per_pixel_unbiased;
    use crate::sampling::{Distribution, SeedMode, Sequence};

    fn row(d: Distribution, s: Sequence, m: SeedMode) -> Row {
        Row::new(d, s, m)
    }

    fn agg(r: Row, rays: u32, efficiency: f64, spread: f64) -> Aggregate {
        let stat = crate::results::Stat { mean: 0.1, sd: 0.0 };
        Aggregate {
            scene: "k".into(),
            distribution: r.distribution.name().into(),
            sequence: r.sequence.name().into(),
            seed_mode: r.seed_mode.name().into(),
            rays,
            replicates: 4,
            rmse: stat,
            flip: stat,
            bias: stat,
            autocorr_x: stat,
            autocorr_y: stat,
            lowpass_rmse: stat,
            whiteness_z: stat,
            lowfreq_ratio: stat,
            mse: stat,
            time: None,
            overhead_s: 0.009,
            ao_time_s: 0.01,
            ns_per_ray: 50.0,
            rays_cast: 1000.0,
            rays_per_s: 1e7,
            efficiency,
            efficiency_spread: spread,
            bias_rmse: f64::NAN,
            bias_se: f64::NAN,
            noise_rmse: f64::NAN,
        }
    }

    const SC: Distribution = Distribution::SineCosine;

    #[test]
    fn best_per_ray_count_and_margins() {
        let (a, b, c) = (
            row(SC, Sequence::Fibonacci, SeedMode::Shift),
            row(SC, Sequence::Fibonacci, SeedMode::Static),
            row(SC, Sequence::Random, SeedMode::Rotation),
        );
        let aggs =
            vec![agg(a, 8, 100.0, 3.0), agg(b, 8, 120.0, 4.0), agg(c, 8, 40.0, 1.0), agg(a, 16, 90.0, 1.0)];
        let all = best_per_ray_count(&aggs, &[], "k", &[a, b, c], &[8, 16, 32], |_| true);
        assert_eq!(all.len(), 2, "no result at 32 rays: no entry");
        assert_eq!(
            (all[0].best.seed_mode.as_str(), all[0].runner_up.unwrap().seed_mode.as_str()),
            ("static", "shift")
        );
        assert!((all[0].ratio().unwrap() - 1.2).abs() < 1e-12);
        assert_eq!(all[0].margin_se, None, "no records to pair");
        assert_eq!(all[1].runner_up, None);
        let unbiased = best_per_ray_count(&aggs, &[], "k", &[a, b, c], &[8], per_pixel_unbiased);
        assert_eq!(unbiased[0].best.seed_mode, "shift");
        assert_eq!(unbiased[0].runner_up.unwrap().sequence, "random");
    }

    #[test]
    fn the_efficiency_margin_is_paired() {
        let (a, b) =
            (row(SC, Sequence::Fibonacci, SeedMode::Shift), row(SC, Sequence::Random, SeedMode::Rotation));
        // Replicate noise ±20 % shared by both; b's RMSE is 1.1 × a's in every replicate.
        let mut results = Vec::new();
        for (rep, k) in [0.8, 1.0, 1.2, 0.9].into_iter().enumerate() {
            results.push(JobResult::for_test("k", a, 8, rep as u32, 0.1 * k, 0.0));
            results.push(JobResult::for_test("k", b, 8, rep as u32, 0.11 * k, 0.0));
        }
        let summary = |median: f64| crate::timing::Summary {
            median,
            min: median,
            max: median,
            n: 9,
            ci_low: median,
            ci_high: median,
        };
        let (mut ga, mut gb) = (agg(a, 8, 0.0, 0.0), agg(b, 8, 0.0, 0.0));
        (ga.time, ga.ao_time_s, gb.time, gb.ao_time_s) =
            (Some(summary(0.01)), 0.01, Some(summary(0.01)), 0.01);
        let (v, se) = efficiency_log_ratio(&results, &ga, &gb).unwrap();
        assert!((v - 1.21f64.ln()).abs() < 1e-12, "{v}");
        // Only the run-to-run time scatter is left: the MSE ratio is exact.
        let t = crate::timing::RUN_TO_RUN;
        assert!((se - t.hypot(t)).abs() < 1e-9, "{se}");
    }

    #[test]
    fn rank_agreement_ignores_pairs_within_the_spreads() {
        let (a, b, c) = (
            row(SC, Sequence::Fibonacci, SeedMode::Shift),
            row(SC, Sequence::Fibonacci, SeedMode::Rotation),
            row(SC, Sequence::Random, SeedMode::Rotation),
        );
        let first = vec![agg(a, 8, 100.0, 2.0), agg(b, 8, 101.0, 2.0), agg(c, 8, 40.0, 1.0)];
        // a and b swap (1 spread apart: fine); c stays far below both.
        let second = vec![agg(a, 8, 101.0, 2.0), agg(b, 8, 100.0, 2.0), agg(c, 8, 41.0, 1.0)];
        let (bad, checked) = rank_disagreements(&first, &second, &[a, b, c], 3.0);
        assert!(bad.is_empty(), "{bad:?}");
        assert_eq!(checked, 2, "a-c and b-c are far apart");
        // c overtakes a in the second run although the first put them far apart: a disagreement.
        let third = vec![agg(a, 8, 100.0, 2.0), agg(b, 8, 101.0, 2.0), agg(c, 8, 100.5, 1.0)];
        let (bad, _) = rank_disagreements(&first, &third, &[a, b, c], 3.0);
        assert_eq!(bad.len(), 1);
        assert_eq!(
            (bad[0].a.as_str(), bad[0].b.as_str()),
            ("sine-cosine/fibonacci/shift", "sine-cosine/random/rotation")
        );
    }
}
