//! The paper's claims, asserted on real renders: `experiments/claims.toml` (the kitchen at 64x48,
//! fixed seeds, 8 replicates) run through the real binary against the committed reference. Every
//! failure message prints the numbers it compared. Margins are asserted in paired standard errors:
//! replicate r uses the same seed in every configuration, so two configurations are compared
//! replicate by replicate (sd of the per-replicate differences / √n), and a pass is not luck of the
//! seeds.

use crate::support::common;

use hemilab::results::{Aggregate, JobResult, Slope, aggregate, convergence_slopes};
use hemilab::stats::paired_difference;
use std::sync::OnceLock;

const RAYS: [u32; 3] = [8, 16, 32];
/// A claimed difference must be at least this many paired standard errors wide.
const MIN_SE: f64 = 5.0;

struct Run {
    stdout: String,
    stderr: String,
    results: Vec<JobResult>,
    aggs: Vec<Aggregate>,
}

/// Runs the claims spec once per test binary; the tests below share it.
fn run() -> &'static Run {
    static RUN: OnceLock<Run> = OnceLock::new();
    RUN.get_or_init(|| {
        let (results, o) = common::run_shipped_spec("claims");
        let aggs = aggregate(&results);
        Run { stdout: common::stdout(&o), stderr: common::stderr(&o), results, aggs }
    })
}

fn cell<'a>(r: &'a Run, distribution: &str, sequence: &str, seed_mode: &str, rays: u32) -> &'a Aggregate {
    r.aggs
        .iter()
        .find(|a| {
            a.distribution == distribution
                && a.sequence == sequence
                && a.seed_mode == seed_mode
                && a.rays == rays
        })
        .unwrap_or_else(|| panic!("no result for {distribution}/{sequence}/{seed_mode} at {rays} rays"))
}

/// RMSE per replicate of one configuration, by replicate index.
fn per_replicate(r: &Run, a: &Aggregate) -> Vec<(u32, f64)> {
    let mut v: Vec<(u32, f64)> = r
        .results
        .iter()
        .filter(|x| {
            (x.distribution.as_str(), x.sequence.as_str(), x.seed_mode.as_str(), x.rays)
                == (a.distribution.as_str(), a.sequence.as_str(), a.seed_mode.as_str(), a.rays)
        })
        .map(|x| (x.replicate, x.rmse))
        .collect();
    v.sort_by_key(|x| x.0);
    v
}

/// Mean and paired standard error of `worse − better` over the replicates both have (same seeds).
fn paired(r: &Run, better: &Aggregate, worse: &Aggregate) -> (f64, f64, usize) {
    let (b, w) = (per_replicate(r, better), per_replicate(r, worse));
    assert_eq!(
        b.iter().map(|x| x.0).collect::<Vec<_>>(),
        w.iter().map(|x| x.0).collect::<Vec<_>>(),
        "both configurations have the same replicates"
    );
    let bv: Vec<f64> = b.iter().map(|x| x.1).collect();
    let wv: Vec<f64> = w.iter().map(|x| x.1).collect();
    let (d, se) = paired_difference(&bv, &wv);
    (d, se, bv.len())
}

fn show(a: &Aggregate) -> String {
    format!(
        "{}/{}/{} {} rays: RMSE {:.5} ± {:.5} (n = {})",
        a.distribution, a.sequence, a.seed_mode, a.rays, a.rmse.mean, a.rmse.sd, a.replicates
    )
}

/// `better` has lower RMSE than `worse` by at least `MIN_SE` paired standard errors.
fn assert_lower(r: &Run, better: &Aggregate, worse: &Aggregate, claim: &str) {
    let (d, se, n) = paired(r, better, worse);
    assert!(n >= 4, "{claim}: only {n} paired replicates");
    assert!(
        d > MIN_SE * se,
        "{claim}: expected {} below {} by > {MIN_SE} paired SE; difference {d:.5}, SE {se:.5} ({:.1} SE)",
        show(better),
        show(worse),
        d / se
    );
    eprintln!("{claim}: {} < {} by {:.1} paired SE", show(better), show(worse), d / se);
}

#[test]
fn claim1_sine_cosine_beats_uniform_and_sine_with_random_numbers() {
    let r = run();
    for rays in RAYS {
        let sc = cell(r, "sine-cosine", "random", "rotation", rays);
        for other in ["uniform", "sine"] {
            assert_lower(r, sc, cell(r, other, "random", "rotation", rays), "claim 1");
        }
    }
}

#[test]
fn claim2_fibonacci_with_per_pixel_seed_beats_random() {
    let r = run();
    for rays in RAYS {
        for d in ["uniform", "sine", "sine-cosine"] {
            let fib = cell(r, d, "fibonacci", "rotation", rays);
            let rnd = cell(r, d, "random", "rotation", rays);
            eprintln!("{d} at {rays} rays: fibonacci/random RMSE ratio {:.3}", fib.rmse.mean / rnd.rmse.mean);
            if d == "sine-cosine" {
                assert_lower(r, fib, rnd, "claim 2");
            }
        }
    }
}

/// Per-replicate banding metric (mean of the horizontal and vertical lag-1 error autocorrelation).
fn banding(r: &Run, seed_mode: &str, rays: u32) -> Vec<f64> {
    r.results
        .iter()
        .filter(|x| {
            x.distribution == "sine-cosine"
                && x.sequence == "fibonacci"
                && x.seed_mode == seed_mode
                && x.rays == rays
        })
        .map(|x| 0.5 * (x.autocorr_x + x.autocorr_y))
        .collect()
}

#[test]
fn claim3_static_seed_error_is_structured() {
    let r = run();
    for rays in RAYS {
        let stat = banding(r, "static", rays);
        let rot = banding(r, "rotation", rays);
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let (ms, mr) = (mean(&stat), mean(&rot));
        let msg = format!(
            "{rays} rays: banding static {stat:.3?} (mean {ms:.3}), per-pixel {rot:.3?} (mean {mr:.3})"
        );
        assert!(stat.len() >= 4 && rot.len() >= 4, "too few replicates: {msg}");
        assert!(mr.abs() < 0.05, "claim 3: per-pixel seed error should be uncorrelated: {msg}");
        assert!(ms > 0.15, "claim 3: static seed error should be structured: {msg}");
        let lowest_static = stat.iter().cloned().fold(f64::INFINITY, f64::min);
        let highest_rot = rot.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        assert!(lowest_static > highest_rot + 0.1, "claim 3: replicates overlap: {msg}");
        eprintln!("claim 3: {msg}");
    }
}

fn slope<'a>(slopes: &'a [Slope], sequence: &str, seed_mode: &str) -> &'a Slope {
    slopes
        .iter()
        .find(|s| s.distribution == "sine-cosine" && s.sequence == sequence && s.seed_mode == seed_mode)
        .unwrap_or_else(|| panic!("no convergence row sine-cosine/{sequence}/{seed_mode}"))
}

#[test]
fn claim4_convergence_slopes() {
    let r = run();
    let sweep: Vec<u32> = (0..=8).map(|k| 1 << k).collect();
    let slopes = convergence_slopes(&r.aggs, &sweep);
    let points = |s: &Slope| {
        let mut v: Vec<String> = r
            .aggs
            .iter()
            .filter(|a| {
                a.distribution == s.distribution
                    && a.sequence == s.sequence
                    && a.seed_mode == s.seed_mode
                    && sweep.contains(&a.rays)
            })
            .map(|a| format!("{}: {:.4}", a.rays, a.rmse.mean))
            .collect();
        v.dedup();
        v.join(", ")
    };
    let random = slope(&slopes, "random", "rotation");
    let rfit = random.vs_rays.expect("random slope");
    let k = rfit.value;
    assert_eq!(random.points, sweep.len(), "random row lacks ray counts: {}", points(random));
    assert!(
        (k + 0.5).abs() <= 0.08,
        "claim 4: random slope {k:.3} not within -0.5 ± 0.08 ({})",
        points(random)
    );
    let shift = slope(&slopes, "fibonacci", "shift");
    let sfit = shift.vs_rays.expect("shift slope");
    assert_eq!(shift.points, sweep.len(), "shift row lacks ray counts: {}", points(shift));
    // The whole 95 % interval of the lattice's slope is steeper than -0.6, and below the random one's.
    let [_, s_hi] = sfit.ci95.expect("an interval from 9 points");
    let [r_lo, _] = rfit.ci95.expect("an interval from 9 points");
    assert!(
        s_hi < -0.6 && s_hi < r_lo,
        "claim 4: fibonacci shift slope {} not steeper than -0.6 and than random {} ({})",
        sfit.text(),
        rfit.text(),
        points(shift)
    );
    eprintln!("claim 4: slopes random {}, fibonacci shift {}", rfit.text(), sfit.text());
}

#[test]
fn reference_noise_floor_is_a_tenth_of_the_smallest_rmse() {
    let r = run();
    let line = r.stdout.lines().find(|l| l.contains("noise floor")).unwrap_or_default();
    let nums: Vec<f64> =
        line.split(|c: char| c.is_whitespace() || c == ',').filter_map(|w| w.parse::<f64>().ok()).collect();
    assert_eq!(nums.len(), 2, "expected 'noise floor F, smallest RMSE S' in the run's output: {line:?}");
    let (floor, smallest) = (nums[0], nums[1]);
    assert!(
        floor <= smallest / 10.0,
        "noise floor {floor:.2e} above a tenth of the smallest RMSE {smallest:.2e}"
    );
    assert!(!r.stderr.contains("warning: reference noise floor"), "{}", r.stderr);
}
