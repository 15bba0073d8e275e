//! The comparisons the report's answer rests on, computed from the records (pure: no IO).
//!
//! - **Best per unit time**: at each ray count of a sweep, the row with the highest efficiency
//!   (1 / (MSE · AO time), see `results`), overall and among per-pixel-unbiased rows, with its
//!   margin over the runner-up as a ratio and in paired standard errors. The report shows it as
//!   a column; the ranking is by MSE at equal time (`equal_time`).
//! - **Paired differences**: replicate r uses the same seed in every configuration, so two
//!   configurations' RMSEs are compared replicate by replicate (`stats::paired_difference`).
//! - **Rank agreement** of two runs: the check behind "two runs rank the rows' efficiency
//!   identically wherever they differ by more than 3 combined spreads".
//! - **Structure**: whether a configuration's error is structured (`is_structured`), the one test
//!   every part of `run`'s report asks.
//!
//! Comparisons at equal time are in `equal_time`, the claims' verdicts in `claims`, the pooled cost
//! of two configurations in `cost`.

pub mod claims;
pub mod cost;
pub mod equal_time;

use crate::metrics::STRUCTURED_RATIO;
use crate::results::{Aggregate, JobResult};
use crate::sampling::SeedMode;
use crate::sampling::texture::TextureUse;
use crate::spec::Row;
use crate::stats::paired_difference;

/// Whether every pixel's estimate is unbiased: fresh pseudo-random numbers per pixel, or a
/// per-pixel shift (Cranley–Patterson for the lattice, fresh jitter, per-pixel Owen scrambling).
/// A static seed or a rotation keeps part of the point set fixed, so a pixel's error has a mean.
pub fn per_pixel_unbiased(row: Row) -> bool {
    let row = row.canonical();
    match row.seed_mode {
        // A blue-noise mask (2-D or spatiotemporal) shifts every pixel's set by an offset uniform over
        // runs (docs/estimators.md).
        SeedMode::Shift | SeedMode::BlueNoise | SeedMode::Stbn => true,
        // An engine pattern or a rotation texture moves x alone, as `rotation` does: unbiased only
        // where the static set itself is random over runs (docs/estimators.md).
        SeedMode::Rotation | SeedMode::Ign | SeedMode::Bayer | SeedMode::MagicSquare | SeedMode::R2Dither => {
            row.sequence.info().fresh_per_pixel
        }
        // An offset texture is unbiased when its slices are exactly uniform (measured at load); a
        // vector texture's directions are a finite set, never.
        SeedMode::Texture(t) => match t.get().use_() {
            TextureUse::Offset => t.get().uniform(),
            TextureUse::Rotation => row.sequence.info().fresh_per_pixel,
            TextureUse::Vector => false,
        },
        SeedMode::Static => false,
    }
}

/// Whether a configuration's error is structured (bands, moiré: visible, not noise), from its
/// records, each with a weight (the replicates of one ray count at 1/n each; at a budget between
/// two ray counts, advise's interpolation: (1 − w)/n and w/n): the weighted mean low-frequency
/// ratio above [`STRUCTURED_RATIO`] (`metrics::lowfreq`), the test advise's `AtBudget::structured`
/// applies to the same numbers. Every structure decision of `run`'s answer, equal-time tables and claims goes through
/// here, so that the structure measure is switched in one place. False with no weight.
pub fn is_structured(records: &[(f64, &JobResult)]) -> bool {
    let total: f64 = records.iter().map(|(w, _)| w).sum();
    let ratio: f64 = records.iter().map(|(w, r)| w * r.lowfreq_ratio).sum();
    total > 0.0 && ratio / total > STRUCTURED_RATIO
}

/// `records` at equal weights: the structure test of one configuration at one ray count.
pub fn equally<'a>(records: impl IntoIterator<Item = &'a JobResult>) -> Vec<(f64, &'a JobResult)> {
    records.into_iter().map(|r| (1.0, r)).collect()
}

/// The row of an aggregate, if its names parse.
pub fn row_of(a: &Aggregate) -> Option<Row> {
    row_of_names(&a.distribution, &a.sequence, &a.seed_mode)
}

/// The row the results' names `distribution`, `sequence`, `seed_mode` denote, if they parse.
pub fn row_of_names(distribution: &str, sequence: &str, seed_mode: &str) -> Option<Row> {
    Some(Row::new(distribution.parse().ok()?, sequence.parse().ok()?, seed_mode.parse().ok()?))
}

/// Paired RMSE difference of configuration `b` minus `a` (same scene and ray count), over the
/// replicates both have.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Paired {
    /// Mean of rmse_b − rmse_a over replicates.
    pub diff: f64,
    /// sd of the per-replicate differences / √n.
    pub se: f64,
    pub n: usize,
    /// `diff` relative to a's mean RMSE.
    pub relative: f64,
}

impl Paired {
    /// The difference in paired standard errors, a Student's t with n − 1 degrees of freedom (∞ when
    /// every replicate differs by the same).
    pub fn t(&self) -> f64 {
        if self.se > 0.0 { self.diff / self.se } else { self.diff.signum() * f64::INFINITY }
    }
}

fn rmse_by_replicate(results: &[JobResult], scene: &str, row: Row, rays: u32) -> Vec<(u32, f64)> {
    let row = row.canonical();
    let mut v: Vec<(u32, f64)> =
        results.iter().filter(|r| r.is(scene, row, rays)).map(|r| (r.replicate, r.rmse)).collect();
    v.sort_by_key(|x| x.0);
    v
}

/// `b − a` in RMSE, paired by replicate; `None` when they share fewer than two replicates.
pub fn paired_rmse(results: &[JobResult], scene: &str, a: Row, b: Row, rays: u32) -> Option<Paired> {
    let ra = rmse_by_replicate(results, scene, a, rays);
    let rb = rmse_by_replicate(results, scene, b, rays);
    let (mut xa, mut xb) = (Vec::new(), Vec::new());
    for (rep, v) in &ra {
        if let Some((_, w)) = rb.iter().find(|(r, _)| r == rep) {
            xa.push(*v);
            xb.push(*w);
        }
    }
    if xa.len() < 2 {
        return None;
    }
    let (diff, se) = paired_difference(&xa, &xb);
    let mean_a = xa.iter().sum::<f64>() / xa.len() as f64;
    Some(Paired { diff, se, n: xa.len(), relative: diff / mean_a })
}

/// Pairs of rows that differ in exactly one of distribution, sequence and seed mode, in the
/// order the rows are given: the comparisons that isolate one choice.
pub fn one_factor_pairs(rows: &[Row]) -> Vec<(Row, Row)> {
    let mut out = Vec::new();
    for (i, a) in rows.iter().enumerate() {
        for b in &rows[i + 1..] {
            let differ = (a.distribution != b.distribution) as u8
                + (a.sequence != b.sequence) as u8
                + (a.seed_mode != b.seed_mode) as u8;
            if differ == 1 {
                out.push((*a, *b));
            }
        }
    }
    out
}

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
    let (ra, rb) = (mse_by_replicate(results, a), mse_by_replicate(results, b));
    let (xa, xb): (Vec<f64>, Vec<f64>) =
        ra.iter().filter_map(|(r, x)| rb.iter().find(|(q, _)| q == r).map(|(_, y)| (*x, *y))).unzip();
    let rel = |g: &Aggregate| g.time.map(|t| t.spread() / g.ao_time_s).filter(|x| x.is_finite());
    let (ta, tb) = (rel(a)?, rel(b)?);
    if xa.len() < 2 || !(a.ao_time_s > 0.0 && b.ao_time_s > 0.0) {
        return None;
    }
    let (ln_mse, se_mse) = crate::stats::paired_log_ratio(&xa, &xb);
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
                .filter_map(|&r| crate::results::lookup(aggs, scene, r, n))
                .filter(|a| a.efficiency.is_finite())
                .collect();
            c.sort_by(|a, b| b.efficiency.total_cmp(&a.efficiency));
            let best = *c.first()?;
            let runner_up = c.get(1).copied();
            let margin_se = runner_up
                .and_then(|r| efficiency_log_ratio(results, best, r))
                .map(|(v, se)| if se > 0.0 { v / se } else { v.signum() * f64::INFINITY });
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
                    let get =
                        |aggs: &'_ [Aggregate], r: Row| crate::results::lookup(aggs, scene, r, n).cloned();
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
    use crate::sampling::{Distribution, Sequence};

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
        }
    }

    const SC: Distribution = Distribution::SineCosine;

    #[test]
    fn unbiased_rows_are_random_or_shifted() {
        assert!(per_pixel_unbiased(row(SC, Sequence::Random, SeedMode::Rotation)));
        assert!(per_pixel_unbiased(row(SC, Sequence::Random, SeedMode::Shift)));
        assert!(per_pixel_unbiased(row(SC, Sequence::Fibonacci, SeedMode::Shift)));
        assert!(per_pixel_unbiased(row(SC, Sequence::Sobol, SeedMode::Shift)));
        assert!(!per_pixel_unbiased(row(SC, Sequence::Fibonacci, SeedMode::Rotation)));
        assert!(!per_pixel_unbiased(row(SC, Sequence::Random, SeedMode::Static)));
        assert!(!per_pixel_unbiased(row(SC, Sequence::Stratified, SeedMode::Rotation)));
    }

    #[test]
    fn one_factor_pairs_isolate_one_choice() {
        let a = row(SC, Sequence::Fibonacci, SeedMode::Rotation);
        let b = row(SC, Sequence::Fibonacci, SeedMode::Shift);
        let c = row(Distribution::ConcentricCosine, Sequence::Fibonacci, SeedMode::Shift);
        let d = row(Distribution::Uniform, Sequence::Random, SeedMode::Rotation);
        assert_eq!(one_factor_pairs(&[a, b, c, d]), vec![(a, b), (b, c)]);
    }

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

    #[test]
    fn paired_rmse_matches_replicates_by_index() {
        let a = row(SC, Sequence::Fibonacci, SeedMode::Rotation);
        let b = row(SC, Sequence::Fibonacci, SeedMode::Shift);
        let mk = |r: Row, rep: u32, rmse: f64| JobResult::for_test("k", r, 8, rep, rmse, 0.0);
        // Replicate noise ±0.02 shared by both; b is 0.005 above a in every replicate.
        let results = vec![
            mk(a, 0, 0.10),
            mk(a, 1, 0.12),
            mk(a, 2, 0.08),
            mk(b, 2, 0.085),
            mk(b, 0, 0.105),
            mk(b, 1, 0.125),
        ];
        let p = paired_rmse(&results, "k", a, b, 8).unwrap();
        assert_eq!(p.n, 3);
        assert!((p.diff - 0.005).abs() < 1e-12 && p.se < 1e-12, "{p:?}");
        assert!((p.relative - 0.05).abs() < 1e-9);
        assert!(p.t() > 1e6, "the same difference in every replicate: {}", p.t());
        assert!(paired_rmse(&results, "k", a, b, 16).is_none());
    }
}
