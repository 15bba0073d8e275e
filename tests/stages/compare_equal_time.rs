//! The comparisons `run`'s answer rests on, on synthetic records through the library: equal-time
//! interpolation against an exact power law, never extrapolating; advise's rule that a structured
//! estimator is rejected, not the answer; Holm's adjustment against a hand-worked example; and the
//! pooled cost test of two seeds with the same expected error.

use hemilab::compare::cost::pooled_time_ratio;
use hemilab::compare::equal_time::{self, TimeView, at_time, budgets, curve};
use hemilab::metrics::ErrorStats;
use hemilab::plan::Job;
use hemilab::results::{JobResult, aggregate};
use hemilab::sampling::{Distribution, SeedMode, Sequence};
use hemilab::spec::Row;
use hemilab::stats::holm_adjusted;
use std::path::PathBuf;

const RAYS: [u32; 6] = [1, 2, 4, 8, 16, 32];
const RANDOM: Row =
    Row { distribution: Distribution::SineCosine, sequence: Sequence::Random, seed_mode: SeedMode::Rotation };
const PIXEL: Row = Row {
    distribution: Distribution::SineCosine,
    sequence: Sequence::Fibonacci,
    seed_mode: SeedMode::Rotation,
};
const STATIC: Row = Row {
    distribution: Distribution::SineCosine,
    sequence: Sequence::Fibonacci,
    seed_mode: SeedMode::Static,
};

/// One image's record: its RMSE, whiteness z and timed renders.
fn record(row: Row, rays: u32, replicate: u32, mse: f64, z: f64, times: &[f64]) -> JobResult {
    let job = Job {
        scene: PathBuf::from("s.toml"),
        scene_id: "s".into(),
        scene_name: "s".into(),
        distribution: row.distribution,
        sequence: row.sequence,
        seed_mode: row.seed_mode,
        rays,
        replicate,
        seed: replicate as u64,
        resolution: None,
        ao_distance: None,
        measurement: hemilab::plan::Measurement::PAPER,
    };
    let stats = ErrorStats {
        covered: 100,
        rmse: mse.sqrt(),
        bias: 0.0,
        autocorr_x: 0.0,
        autocorr_y: 0.0,
        lowpass_rmse: 0.5 * mse.sqrt(),
        whiteness_z: z,
        // `z` stands for the error's structure: a static seed's (z 40) is clumped, a per-pixel one's
        // white; the verdict is the low-frequency ratio's.
        lowfreq_ratio: if z > 5.0 { 4.0 } else { 1.0 },
    };
    let mut r = JobResult::new(&job, &stats, rays as u64 * 100, "");
    for &t in times {
        r.add_time(t, t);
    }
    r.overhead_s = 1e-3;
    r
}

/// Time = 1 ms + `per_ray` per ray; MSE = c · time^−slope exactly, replicate r scaled by noise[r]
/// (so every replicate is an exact power law of time too).
fn ladder(row: Row, per_ray: f64, c: f64, slope: f64, z: f64) -> Vec<JobResult> {
    let noise = [0.9, 1.0, 1.1, 1.05];
    let mut out = Vec::new();
    for n in RAYS {
        let t = 1e-3 + per_ray * n as f64;
        for (r, k) in noise.iter().enumerate() {
            out.push(record(row, n, r as u32, k * c * t.powf(-slope), z, &[t, t, t]));
        }
    }
    out
}

#[test]
fn equal_time_interpolation_reproduces_an_exact_power_law() {
    // The lattice: 10 % dearer per ray, MSE falling as time^−2.2; pseudo-random as time^−1.
    let (c_pixel, c_random) = (1e-9, 2e-5);
    let mut rs = ladder(PIXEL, 1.1e-4, c_pixel, 2.2, 0.0);
    rs.extend(ladder(RANDOM, 1e-4, c_random, 1.0, 0.0));
    let curves =
        [curve(&rs, "s", PIXEL, &RAYS, TimeView::Total), curve(&rs, "s", RANDOM, &RAYS, TimeView::Total)];
    let b = budgets(&curves, RANDOM, 2);
    // Inside every curve's measured times: from the lattice's 1-ray time to pseudo-random's 32-ray time.
    let (lo, hi) = (1e-3 + 1.1e-4, 1e-3 + 1e-4 * 32.0);
    assert!(b.len() >= 4 && b[0] >= lo && *b.last().unwrap() <= hi, "{b:?}");
    let mean_noise = (0.9 + 1.0 + 1.1 + 1.05) / 4.0;
    for &t in &b {
        let at = at_time(&rs, "s", &curves, RANDOM, t);
        assert!(at.outside.is_empty(), "{t}: every configuration is measured there");
        let get = |r: Row| at.entry(r).unwrap();
        let mse = |r: Row| get(r).at.mean_mse(hemilab::compare::budget::Metric::Rmse).value;
        let exact_pixel = mean_noise * c_pixel * t.powf(-2.2);
        let exact_random = mean_noise * c_random * t.powf(-1.0);
        assert!((mse(PIXEL) / exact_pixel - 1.0).abs() < 1e-9, "{t}: {} vs {exact_pixel}", mse(PIXEL));
        assert!((mse(RANDOM) / exact_random - 1.0).abs() < 1e-9, "{t}: {} vs {exact_random}", mse(RANDOM));
        // The ratio to the baseline is the power laws' ratio, paired: the replicates' scaling cancels.
        let ratio = get(PIXEL).vs_baseline.unwrap();
        assert!((ratio.value / (exact_pixel / exact_random) - 1.0).abs() < 1e-9);
        // The rays the budget buys lie between the two neighbouring measured ray counts.
        let rays = get(PIXEL).at.rays;
        let below = RAYS.iter().rev().find(|&&n| 1e-3 + 1.1e-4 * n as f64 <= t * (1.0 + 1e-9)).unwrap();
        assert!(
            rays >= *below as f64 * (1.0 - 1e-9) && rays <= 2.0 * *below as f64 * (1.0 + 1e-9),
            "{t}: {rays}"
        );
        assert_eq!(at.answer().unwrap().at.row, PIXEL);
    }
    // Never extrapolated: between pseudo-random's 1-ray time (1.1 ms) and the lattice's (1.11 ms),
    // the lattice is not measured there, not ranked.
    let below = at_time(&rs, "s", &curves, RANDOM, 1.105e-3);
    assert_eq!(below.ranked.iter().map(|e| e.at.row).collect::<Vec<_>>(), [RANDOM]);
    assert_eq!(below.outside.len(), 1);
    assert!(
        matches!(below.outside[0], (PIXEL, hemilab::compare::budget::Place::Below { .. })),
        "{:?}",
        below.outside
    );
}

#[test]
fn a_structured_estimator_with_less_error_is_rejected_not_the_answer() {
    // The static seed: the same cost and expected error as the per-pixel seed but 20 % less MSE in
    // this run, and its error structured (whiteness z 40).
    let mut rs = ladder(PIXEL, 1e-4, 1e-9, 2.0, 0.3);
    rs.extend(ladder(STATIC, 1e-4, 0.8e-9, 2.0, 40.0));
    rs.extend(ladder(RANDOM, 1e-4, 2e-5, 1.0, -0.2));
    let et = equal_time::equal_time(&rs, "s", &[RANDOM, PIXEL, STATIC], &RAYS, TimeView::Total, 1);
    assert_eq!(et.baseline, RANDOM, "the paper's default is the baseline");
    assert!(!et.at.is_empty());
    for at in &et.at {
        assert_eq!(at.ranked[0].at.row, STATIC, "least MSE");
        assert!(at.ranked[0].structured);
        assert_eq!(
            at.answer().unwrap().at.row,
            PIXEL,
            "the answer is the least MSE among unstructured errors"
        );
        assert_eq!(at.rejected().iter().map(|e| e.at.row).collect::<Vec<_>>(), [STATIC]);
        assert_eq!(at.runner_up().unwrap().at.row, RANDOM);
    }
}

#[test]
fn holm_matches_a_hand_worked_example() {
    // m = 4, sorted: 0.005 × 4 = 0.02; 0.01 × 3 = 0.03; 0.03 × 2 = 0.06; 0.04 × 1 = 0.04 → 0.06
    // (made non-decreasing). At α = 0.05 the first two are rejected, and Holm stops at the third.
    let p = [0.01, 0.04, 0.03, 0.005];
    let adjusted = holm_adjusted(&p);
    for (got, want) in adjusted.iter().zip([0.03, 0.06, 0.06, 0.02]) {
        assert!((got - want).abs() < 1e-15, "{adjusted:?}");
    }
    let rejected: Vec<bool> = adjusted.iter().map(|&q| q <= 0.05).collect();
    assert_eq!(rejected, [true, false, false, true]);
    // Holm rejects where Bonferroni (m · p ≤ α) does not: 0.0135 × 4 > 0.05, but 0.0135 × 3 ≤ 0.05.
    let q = holm_adjusted(&[0.001, 0.0135, 0.014, 0.2]);
    assert!((q[1] - 0.0405).abs() < 1e-15 && (q[2] - 0.0405).abs() < 1e-15 && 0.0135 * 4.0 > 0.05, "{q:?}");
    // Untested cells are not counted and stay NaN; the adjustment never exceeds 1.
    let q = holm_adjusted(&[0.3, f64::NAN, 0.6]);
    assert!(q[1].is_nan() && (q[0] - 0.6).abs() < 1e-15 && (q[2] - 0.6).abs() < 1e-15, "{q:?}");
}

#[test]
fn pooling_resolves_a_cost_difference_no_single_ray_count_does() {
    // The static seed 5 % cheaper at every ray count, each time up to ±2 % off by the machine's noise.
    let wobble = [0.02, -0.015, 0.01, -0.02, 0.015, 0.0];
    let mut rs = Vec::new();
    for (i, &n) in RAYS.iter().enumerate() {
        let t = 1e-3 + 1e-4 * n as f64;
        rs.push(record(PIXEL, n, 0, 1.0, 0.0, &[t]));
        rs.push(record(STATIC, n, 0, 1.0, 0.0, &[0.95 * t * (1.0 + wobble[i])]));
    }
    let p = pooled_time_ratio(&aggregate(&rs), "s", PIXEL, STATIC, &RAYS).unwrap();
    assert_eq!(p.n, RAYS.len());
    assert!((p.ratio / 0.95 - 1.0).abs() < 0.01, "{p:?}");
    assert!(p.t < -5.0 && p.p < 1e-3, "{p:?}");
    // A single ray count's ratio is within 2 σ of 1, σ = √2 × the run-to-run scatter of a time.
    let two_sigma = 2.0 * std::f64::consts::SQRT_2 * hemilab::timing::RUN_TO_RUN;
    assert!(p.min.ln().abs() < two_sigma && p.max.ln().abs() < two_sigma, "{p:?}");
}
