//! The paper's claims on every shipped scene: `experiments/scene-claims.toml` (eight scenes at 96x72,
//! 8 replicates, fixed seeds) run through the real binary against the committed references. Each
//! claim is asserted only where theory backs it, by at least `MIN_SE` standard errors of the *paired*
//! difference (replicate r shares its seed across configurations: `compare::claims`). And on the
//! slat scene, where the lag-1 autocorrelation misses the static seed's diagonal moiré (a diagonal pattern the row and column lags do not see),
//! the whiteness z-score must separate the static seed from the per-pixel seed by many replicate
//! spreads at 8, 16 and 32 rays.

use crate::support::common;

use hemilab::compare::claims::{
    self as claims, COSINE_FIB_PIXEL, COSINE_FIB_STATIC, COSINE_RANDOM, Claim, Config, Outcome, SINE_RANDOM,
    SLOPE_TOLERANCE, UNIFORM_RANDOM,
};
use hemilab::compare::equal_time::{Ratio, TimeView, equal_time};
use hemilab::compare::margin::{Margin, paired};
use hemilab::metrics::whiteness::STRUCTURED_Z;
use hemilab::results::JobResult;
use hemilab::sampling::{Distribution, SeedMode, Sequence};
use std::sync::OnceLock;

const RAYS: [u32; 3] = [8, 16, 32];
const SWEEP: [u32; 8] = [1, 2, 4, 8, 16, 32, 64, 128];
/// A claimed difference must be at least this many standard errors of the paired difference wide.
const MIN_SE: f64 = 5.0;

/// Every scene of the spec, and whether its occluders sit well above the horizon of the surfaces
/// seen. Cosine-weighted sampling has the least variance of the three distributions only then: for
/// occlusion confined to a band near the horizon (cos θ < c, azimuth-uniform), the occluded fraction
/// is p = c², and one ray's variance is p − p² with sine-cosine but 4c³/3 − p² with sine (weight
/// 2 cos θ, cos θ uniform), which is *smaller* for c < 3/4. Uniform-in-angles (weight π sin θ cos θ)
/// has 2π ∫₀^c u² √(1 − u²) du − p², which tends to π/2 × sine's as c → 0: larger than sine's, though
/// still below sine-cosine's for small c. Open terrain is lit from the
/// whole sky and occluded by slopes and boulders near the horizon, so theory does not back Table 2's
/// ordering there.
const SCENES: [(&str, bool); 8] = [
    ("kitchen", true),
    ("cornell-box", true),
    ("floating-rectangle", true),
    ("bunny", true),
    ("atrium", true),
    ("slats", true),
    ("terrain", false),
    ("foliage", true),
];

fn results() -> &'static [JobResult] {
    static RUN: OnceLock<Vec<JobResult>> = OnceLock::new();
    RUN.get_or_init(|| {
        let (records, o) = common::run_shipped_spec("scene-claims");
        assert!(!common::stderr(&o).contains("warning: reference noise floor"));
        records
    })
}

/// (replicate, value) of one configuration.
fn values(scene: &str, c: Config, rays: u32, f: fn(&JobResult) -> f64) -> Vec<(u32, f64)> {
    let v: Vec<(u32, f64)> =
        results().iter().filter(|r| r.is(scene, c, rays)).map(|r| (r.replicate, f(r))).collect();
    assert_eq!(v.len(), 8, "{scene}: {c:?} at {rays} rays: expected 8 replicates");
    v
}

fn assert_margin(m: Option<Margin>, what: &str) -> f64 {
    let m = m.unwrap_or_else(|| panic!("{what}: fewer than two paired replicates"));
    let se = m.in_se();
    assert!(
        se >= MIN_SE,
        "{what}: paired difference {:.5} ± {:.5} is only {se:.1} SE (need {MIN_SE})",
        m.mean,
        m.se
    );
    eprintln!("{what}: {se:+.1} SE");
    se
}

/// RMSE of `better` below that of `worse` by ≥ MIN_SE paired SE at every ray count.
fn assert_lower(scene: &str, better: Config, worse: Config, claim: &str) {
    for rays in RAYS {
        let (b, w) = (values(scene, better, rays, |r| r.rmse), values(scene, worse, rays, |r| r.rmse));
        assert_margin(paired(&b, &w).measured(), &format!("{scene}, {claim}, {rays} rays"));
    }
}

#[test]
fn table2_sine_cosine_beats_uniform_and_sine_where_occluders_are_above_the_horizon() {
    for (scene, above) in SCENES {
        if above {
            assert_lower(scene, COSINE_RANDOM, UNIFORM_RANDOM, "sine-cosine < uniform");
            assert_lower(scene, COSINE_RANDOM, SINE_RANDOM, "sine-cosine < sine");
        } else {
            // Not backed by theory here (see SCENES): the margins are reported, not asserted.
            for rays in RAYS {
                let c = values(scene, COSINE_RANDOM, rays, |r| r.rmse);
                let s = values(scene, SINE_RANDOM, rays, |r| r.rmse);
                let m = paired(&c, &s).measured().expect("pairs");
                eprintln!("{scene}, sine-cosine < sine, {rays} rays (not asserted): {:+.1} SE", m.in_se());
            }
        }
    }
}

#[test]
fn table3_fibonacci_with_a_per_pixel_seed_beats_pseudo_random_on_every_scene() {
    for (scene, _) in SCENES {
        assert_lower(scene, COSINE_FIB_PIXEL, COSINE_RANDOM, "Fibonacci per-pixel < pseudo-random");
    }
}

#[test]
fn table3_the_static_seeds_error_is_structured_on_every_scene() {
    // One point set shared by every pixel makes the error a function of the local geometry, which
    // neighbouring pixels share: structured wherever the geometry is, i.e. on every scene.
    for (scene, _) in SCENES {
        for rays in RAYS {
            let stat = values(scene, COSINE_FIB_STATIC, rays, |r| r.whiteness_z);
            let pixel = values(scene, COSINE_FIB_PIXEL, rays, |r| r.whiteness_z);
            let what = format!("{scene}, static seed structured, {rays} rays");
            assert_margin(paired(&pixel, &stat).measured(), &what);
            let mean = stat.iter().map(|v| v.1).sum::<f64>() / stat.len() as f64;
            assert!(mean > STRUCTURED_Z, "{what}: mean whiteness z {mean:.1} of the static seed");
            // The per-pixel seed's error is white: z stays within the N(0, 1) range in every replicate.
            assert!(pixel.iter().all(|v| v.1.abs() < 4.0), "{what}: per-pixel seed z {pixel:.1?}");
        }
    }
}

#[test]
fn convergence_slopes_on_every_scene() {
    for (scene, _) in SCENES {
        let random = claims::replicate_slopes(results(), scene, COSINE_RANDOM, &SWEEP);
        let fib = claims::replicate_slopes(results(), scene, COSINE_FIB_PIXEL, &SWEEP);
        assert_eq!((random.len(), fib.len()), (8, 8), "{scene}: a replicate lacks ray counts");
        // Independent rays: MSE ∝ 1/rays exactly, so the slope is −0.5 (within the tolerance the
        // reference's noise floor allows), by ≥ MIN_SE SE of the mean slope.
        let zero: Vec<(u32, f64)> = random.iter().map(|&(r, _)| (r, 0.0)).collect();
        let m = paired(&zero, &random).measured().expect("slopes");
        let inside = Margin { mean: SLOPE_TOLERANCE - (m.mean + 0.5).abs(), ..m };
        assert_margin(
            Some(inside),
            &format!("{scene}, pseudo-random slope {:.3} within −0.5 ± {SLOPE_TOLERANCE}", m.mean),
        );
        // The lattice (low discrepancy; about −0.75 for integrands with edges, Brauchart et al. 2014)
        // converges faster than independent rays.
        assert_margin(paired(&fib, &random).measured(), &format!("{scene}, Fibonacci slope steeper"));
    }
}

/// Mean and sample sd.
fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    (m, (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt())
}

#[test]
fn whiteness_separates_the_static_seed_on_the_slats_where_lag1_autocorrelation_does_not() {
    for rays in RAYS {
        let z = |c: Config| {
            values("slats", c, rays, |r| r.whiteness_z).into_iter().map(|v| v.1).collect::<Vec<_>>()
        };
        let rho = |c: Config| {
            values("slats", c, rays, |r| 0.5 * (r.autocorr_x + r.autocorr_y))
                .into_iter()
                .map(|v| v.1)
                .collect::<Vec<_>>()
        };
        let (zs, zp) = (z(COSINE_FIB_STATIC), z(COSINE_FIB_PIXEL));
        let (rs, rp) = (rho(COSINE_FIB_STATIC), rho(COSINE_FIB_PIXEL));
        // Separation in replicate spreads: difference of means over the larger of the two sds.
        let separation = |a: &[f64], b: &[f64]| {
            let ((ma, sa), (mb, sb)) = (mean_sd(a), mean_sd(b));
            (ma - mb) / sa.max(sb)
        };
        let (new, old) = (separation(&zs, &zp), separation(&rs, &rp));
        let msg = format!(
            "slats, {rays} rays: whiteness z static {zs:.1?} vs per-pixel {zp:.1?} ({new:.1} spreads); \
             lag-1 ρ static {rs:.3?} vs per-pixel {rp:.3?} ({old:.1} spreads)"
        );
        let lowest_static = zs.iter().cloned().fold(f64::INFINITY, f64::min);
        let highest_pixel = zp.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        assert!(lowest_static > STRUCTURED_Z, "every static replicate is flagged: {msg}");
        assert!(highest_pixel < 4.0, "no per-pixel replicate is flagged: {msg}");
        let (_, sd_pixel) = mean_sd(&zp);
        assert!(lowest_static - highest_pixel > 10.0 * sd_pixel, "the replicates are far apart: {msg}");
        assert!(new >= 4.0, "separated by many replicate spreads: {msg}");
        assert!(new > 2.0 * old, "the whiteness z separates better than lag-1 ρ: {msg}");
        eprintln!("{msg}");
    }
}

/// The samplers a renderer would ship instead, as they ship (sine-cosine, `shift`).
fn sampler(s: Sequence) -> Config {
    Config::new(Distribution::SineCosine, s, SeedMode::Shift)
}

#[test]
fn equal_time_all_four_shipped_samplers_trail_the_lattice_at_the_largest_budget() {
    // Against the lattice with a per-pixel seed at equal total render time, at the largest common
    // budget, all four have more MSE (R2 and pmj02bn measured ×1.3–3.3 on the eight scenes, Halton
    // and ZSobol ×1.6–3.7 once they render at their fair speed), by a number of SE that is printed;
    // Before the precomputed-permutation rewrite Halton's and ZSobol's
    // per-digit hashing made each render several times slower and they lost by at least MIN_SE
    // everywhere; at ×1.2–1.3 the lattice's time (their points' cost: every sequence's rays are
    // traced in the same order) they are timed like R2 and pmj02bn, and like them (a CI run measured Halton below the
    // lattice on foliage at the smallest budget, MSE ×0.88, −3.9 SE) only the largest budget is
    // asserted. At the smallest budget (one or two rays) all four can tie or beat the
    // lattice, whose one or two points per pixel keep their elevations under a per-pixel rotation:
    // a CI run measured R2 below it on the floating rectangle there (MSE ×0.62, −5.5 SE), so that
    // end is printed, not asserted — equal-time verdicts move with the machine's timings.
    for (scene, _) in SCENES {
        let verdicts = claims::scene_verdicts(results(), scene, &RAYS, &SWEEP);
        for seq in [Sequence::Halton, Sequence::R2, Sequence::ZSobol, Sequence::Pmj02bn] {
            let v = verdicts
                .iter()
                .find(|v| v.claim == Claim::FibonacciBeatsAtEqualTime(seq))
                .expect("the equal-time claim");
            eprintln!("{scene}, {}: {} ({})", v.claim.label(), v.outcome.label(), v.detail);
            assert_ne!(v.outcome, Outcome::NotMeasured, "{scene}, {seq}");
            let et =
                equal_time(results(), scene, &[COSINE_FIB_PIXEL, sampler(seq)], &SWEEP, TimeView::Total, 1);
            let last = et.at.last().expect("a common budget");
            let r =
                Ratio::of(&last.entry(sampler(seq)).unwrap().at, &last.entry(COSINE_FIB_PIXEL).unwrap().at);
            let what = format!(
                "{scene}, {seq} at {:.1} ms: MSE × {:.2} ± {:.2}",
                last.budget_s * 1e3,
                r.value,
                r.se
            );
            assert!(r.value > 1.0, "{what}: the lattice has more MSE at the largest budget");
            eprintln!("{what} ({:+.1} SE)", r.in_se());
        }
    }
}
