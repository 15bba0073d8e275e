//! Unit tests of `compare::budget` (kept apart so the module itself stays readable at one sitting).

use super::*;
use crate::compare::PAPER_DEFAULT;
use crate::sampling::{Distribution, SeedMode, Sequence};

const SC: Distribution = Distribution::SineCosine;

fn row(s: Sequence, m: SeedMode) -> Row {
    Row::new(SC, s, m)
}

/// A ladder with time = 1 ms + 0.1 ms per ray and MSE = c / rays, replicate r scaled by `noise[r]`.
fn curve(r: Row, c: f64, noise: &[f64]) -> Curve {
    let points = [1u32, 2, 4, 8, 16]
        .iter()
        .map(|&n| Point {
            rays: n,
            time_s: 1e-3 + 1e-4 * n as f64,
            time_sigma_ln: 0.01 * (1.0 + 0.1 * n as f64),
            timings: 15,
            replicates: (0..noise.len() as u32).collect(),
            mse: noise.iter().map(|k| k * c / n as f64).collect(),
            lowpass_mse: noise.iter().map(|k| k * c / (4.0 * n as f64)).collect(),
            structure: noise.iter().map(|_| n as f64).collect(),
        })
        .collect();
    Curve { row: r, points }
}

#[test]
fn times_are_made_monotone_by_pooling() {
    let mut c = curve(PAPER_DEFAULT, 1.0, &[1.0]);
    let t: Vec<f64> = c.points.iter().map(|p| p.time_s).collect();
    assert_eq!(monotone_log_times(&c.points), t.iter().map(|x| x.ln()).collect::<Vec<_>>());
    // 2 rays measured slower than 4: the two pool to their mean log time.
    c.points[1].time_s = 2e-3;
    c.points[2].time_s = 1.2e-3;
    let lt = monotone_log_times(&c.points);
    assert!(lt.windows(2).all(|w| w[0] <= w[1]), "{lt:?}");
    let pooled = 0.5 * (2e-3f64.ln() + 1.2e-3f64.ln());
    assert!((lt[1] - pooled).abs() < 1e-12 && (lt[2] - pooled).abs() < 1e-12);
    // A budget at the pooled time takes the point with more rays.
    assert_eq!(locate(&c, pooled.exp()), Place::Inside { lo: 2, w: 0.0 });
}

#[test]
fn budgets_are_located_inside_or_reported_outside() {
    let c = curve(PAPER_DEFAULT, 1.0, &[1.0]);
    assert_eq!(locate(&c, 0.5e-3), Place::Below { fastest_s: c.points[0].time_s });
    match locate(&c, 5e-3) {
        Place::Above { slowest_s } => assert!((slowest_s - 2.6e-3).abs() < 1e-12),
        p => panic!("{p:?}"),
    }
    assert_eq!(locate(&c, c.points[0].time_s), Place::Inside { lo: 0, w: 0.0 });
    assert_eq!(locate(&c, c.points[4].time_s), Place::Inside { lo: 3, w: 1.0 });
    let mid = (c.points[1].time_s * c.points[2].time_s).sqrt();
    match locate(&c, mid) {
        Place::Inside { lo, w } => assert!(lo == 1 && (w - 0.5).abs() < 1e-12),
        p => panic!("{p:?}"),
    }
    assert!(matches!(locate(&c, f64::NAN), Place::Below { .. }));
    assert!(at_budget(&c, 1e-4).is_err());
}

#[test]
fn interpolation_is_exact_for_a_power_law_in_time() {
    // MSE = 2e-6 / t exactly (time ∝ rays): the log-log line through any two points is the law.
    let mut c = curve(PAPER_DEFAULT, 1.0, &[1.0, 1.2]);
    for p in &mut c.points {
        p.time_s = 1e-4 * p.rays as f64;
        p.mse = vec![2e-6 / p.time_s, 2.4e-6 / p.time_s];
    }
    let a = at_budget(&c, 0.55e-3).unwrap();
    assert_eq!(a.lo, 2);
    assert!((a.rays - 5.5).abs() < 1e-9, "{}", a.rays);
    assert!((a.mse[0] - 2e-6 / 0.55e-3).abs() < 1e-9 && (a.mse[1] - 2.4e-6 / 0.55e-3).abs() < 1e-9);
    assert!((a.slope + 1.0).abs() < 1e-12);
    let z = 4.0 + 4.0 * (5.5f64 / 4.0).ln() / 2f64.ln();
    assert!((a.structure - z).abs() < 1e-9, "4 and 8 at rays 4 and 8, linear in w: {}", a.structure);
    assert_eq!(a.lo_rays, 4);
    let m = a.mean_mse(Metric::Rmse);
    assert!((m.value - 2.2e-6 / 0.55e-3).abs() < 1e-9);
    // At a budget: the replicates' σ (sd 0.28e-6/t over two: 0.2e-6/t, relative 1/11) and the
    // time's, through the slope −1 (session factor and the interpolated median σ).
    let e = a.time_sigma_ln;
    let rel = (1.0f64 / 11.0).hypot(model::RUN_FACTOR.hypot(e));
    assert!((m.se / m.value - rel).abs() < 1e-9, "{} vs {rel}", m.se / m.value);
    let r = a.rmse(Metric::Rmse);
    assert!((r.value - m.value.sqrt()).abs() < 1e-12 && (r.se - m.se / (2.0 * r.value)).abs() < 1e-12);
}

#[test]
fn ranking_gain_and_paired_margins() {
    // Replicate noise shared by every configuration (same seeds): pairing cancels it.
    let noise = [0.9, 1.0, 1.1, 1.05];
    let base = curve(PAPER_DEFAULT, 1.0, &noise);
    let lattice = curve(row(Sequence::Fibonacci, SeedMode::Shift), 0.25, &noise);
    let mut close = curve(row(Sequence::Fibonacci, SeedMode::BlueNoise), 0.26, &noise);
    close.points[4].time_s = 10.0; // its last point is far dearer: above range only past that
    let mut slow = curve(row(Sequence::Sobol, SeedMode::Shift), 0.2, &noise);
    for p in &mut slow.points {
        p.time_s *= 3.0;
    }
    let curves = vec![base.clone(), lattice.clone(), close, slow];
    let budget = 1.8e-3;
    let r = rank(&curves, budget, Metric::Rmse);
    assert_eq!(r.ranked.len(), 3);
    assert_eq!(r.outside.len(), 1);
    match r.outside[0] {
        (o, Place::Below { fastest_s }) => {
            assert!(o == row(Sequence::Sobol, SeedMode::Shift) && (fastest_s - 3.3e-3).abs() < 1e-12)
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(r.ranked[0].row, lattice.row);
    assert_eq!(r.ranked.last().unwrap().row, PAPER_DEFAULT);
    let values: Vec<f64> = r.ranked.iter().map(|a| a.mean_mse(Metric::Rmse).value).collect();
    assert!(values.windows(2).all(|w| w[0] <= w[1]), "{values:?}");

    let side = |i: usize| r.ranked[i].side(Metric::Rmse);
    let own = model::gain(&side(2), &side(2));
    assert_eq!((own.value, own.se), (1.0, 0.0), "the default against itself");
    let g = model::gain(&side(2), &side(0));
    assert!((g.value - 4.0).abs() < 1e-9, "{g:?}");
    assert!(g.se_replicates < 1e-9, "the same noise in both: the ratio is exact per replicate: {g:?}");
    assert!(g.se_timing > 0.0 && (g.se - g.se_timing).abs() < 1e-12);
    // A 4 % difference in every replicate, but the times' σ (about 2 % each, times the slopes:
    // −1.9, and −0.08 for `close`, whose next point is 10 s away) is in the margin too, and the
    // session factor through the slopes' difference.
    let z = model::behind(&side(0), &side(1));
    let (a0, a1) = (&r.ranked[0], &r.ranked[1]);
    let (k0, k1) = (a0.slope, a1.slope);
    let timing = ((k0 - k1) * model::RUN_FACTOR).hypot(k0 * a0.time_sigma_ln).hypot(k1 * a1.time_sigma_ln);
    let want = 1.04f64.ln() / timing;
    assert!((z - want).abs() < 0.01 * want && z < 1.0, "{z} vs {want}");
    let low = rank(&curves, budget, Metric::Lowpass);
    assert_eq!(low.ranked[0].row, lattice.row);
}
