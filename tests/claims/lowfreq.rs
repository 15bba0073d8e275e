//! The low-frequency ratio (`metrics::lowfreq`) on real renders: `experiments/lowfreq.toml` (the seven
//! shipped scenes at 96x72, 8 replicates, fixed seeds) through the real binary against the committed
//! references. Per-pixel seeds must read 1 (white error) on every scene, the static seed above
//! `STRUCTURED_RATIO` (the report's and advise's "structured"), and pseudo-random numbers offset by
//! the blue-noise mask below 1 — the configuration the whiteness z-score, a test of *any*
//! correlation, calls structured.

use crate::support::common;

use hemilab::compare::claims::{self, COSINE_FIB_PIXEL, COSINE_FIB_STATIC, COSINE_RANDOM, Claim, Outcome};
use hemilab::metrics::STRUCTURED_RATIO;
use hemilab::metrics::whiteness::STRUCTURED_Z;
use hemilab::results::JobResult;
use hemilab::sampling::{Distribution, SeedMode, Sequence};
use hemilab::spec::Row;
use std::sync::OnceLock;

const SCENES: [&str; 7] =
    ["kitchen", "cornell-box", "floating-rectangle", "bunny", "atrium", "slats", "terrain"];
const RAYS: [u32; 2] = [8, 32];
const FIB_SHIFT: Row =
    Row { distribution: Distribution::SineCosine, sequence: Sequence::Fibonacci, seed_mode: SeedMode::Shift };
const RANDOM_BLUE: Row = Row {
    distribution: Distribution::SineCosine,
    sequence: Sequence::Random,
    seed_mode: SeedMode::BlueNoise,
};

fn results() -> &'static [JobResult] {
    static RUN: OnceLock<Vec<JobResult>> = OnceLock::new();
    RUN.get_or_init(|| common::run_shipped_spec("lowfreq").0)
}

/// Mean over the 8 replicates of `f`, and the values.
fn mean_of(scene: &str, row: Row, rays: u32, f: fn(&JobResult) -> f64) -> (f64, Vec<f64>) {
    let v: Vec<f64> = results().iter().filter(|r| r.is(scene, row, rays)).map(f).collect();
    assert_eq!(v.len(), 8, "{scene}: {row:?} at {rays} rays: expected 8 replicates");
    (v.iter().sum::<f64>() / v.len() as f64, v)
}

fn ratio(scene: &str, row: Row, rays: u32) -> (f64, Vec<f64>) {
    mean_of(scene, row, rays, |r| r.lowfreq_ratio)
}

#[test]
fn per_pixel_seeds_read_one_on_every_scene() {
    // Measured 0.91–1.09 (8-replicate means, 96x72; one image's sd 0.03–0.28).
    for scene in SCENES {
        for row in [COSINE_RANDOM, COSINE_FIB_PIXEL, FIB_SHIFT] {
            for rays in RAYS {
                let (m, v) = ratio(scene, row, rays);
                eprintln!("{scene}, {}, {rays} rays: R {m:.3}", row.name());
                assert!((m - 1.0).abs() < 0.1, "{scene}, {}, {rays} rays: R {m:.3} ({v:.3?})", row.name());
            }
        }
    }
}

#[test]
fn the_static_seed_is_structured_on_every_scene() {
    // Measured 1.7 (slats, 32 rays) to 19 (floating rectangle, 8 rays).
    for scene in SCENES {
        for rays in RAYS {
            let (m, v) = ratio(scene, COSINE_FIB_STATIC, rays);
            eprintln!("{scene}, static seed, {rays} rays: R {m:.3}");
            assert!(m > STRUCTURED_RATIO, "{scene}, static seed, {rays} rays: R {m:.3} ({v:.3?})");
        }
        // The paper's claim, judged by the same measure: holds, by paired standard errors.
        let verdicts = claims::scene_verdicts(results(), scene, &RAYS, &[]);
        let v = verdicts.iter().find(|v| v.claim == Claim::StaticSeedStructured).expect("the claim");
        assert_eq!(v.outcome, Outcome::Holds, "{scene}: {v:?}");
    }
}

#[test]
fn blue_noise_reads_below_one_although_the_whiteness_test_flags_it() {
    // Measured 0.45–0.57 on the kitchen and the Cornell box, at most 0.79 (slats) elsewhere.
    for scene in SCENES {
        for rays in RAYS {
            let (m, v) = ratio(scene, RANDOM_BLUE, rays);
            let bound = if matches!(scene, "kitchen" | "cornell-box") { 0.9 } else { 1.0 };
            eprintln!("{scene}, random × blue-noise, {rays} rays: R {m:.3}");
            assert!(m < bound, "{scene}, random × blue-noise, {rays} rays: R {m:.3} ({v:.3?})");
        }
    }
    // The old verdict: z above STRUCTURED_Z on the kitchen (7.2 and 7.8), though the error is blue.
    for rays in RAYS {
        let (z, _) = mean_of("kitchen", RANDOM_BLUE, rays, |r| r.whiteness_z);
        assert!(z > STRUCTURED_Z, "kitchen, random × blue-noise, {rays} rays: whiteness z {z:.1}");
    }
}
