//! Unit tests of `compare::claims` (kept apart so the module itself stays readable at one sitting).

use super::*;

fn rec(scene: &str, c: Config, rays: u32, replicate: u32, rmse: f64, ratio: f64) -> JobResult {
    JobResult::for_test(scene, c, rays, replicate, rmse, ratio)
}

#[test]
fn critical_values_are_students_t() {
    assert!((critical_se(4) - 5.840_909).abs() < 1e-4);
    assert!((critical_se(8) - 3.499_483).abs() < 1e-4);
}

/// Random slope −0.5, lattice −0.75; cosine 20 % below uniform, sine in between; the static
/// seed's low-frequency ratio `static_ratio` (+ 0.1 per replicate), the others' about 1.
fn synthetic(static_ratio: f64, cosine_vs_sine: f64) -> Vec<JobResult> {
    let mut rs = Vec::new();
    for rep in 0..6u32 {
        let wobble = 1.0 + 0.02 * ((rep * 7 % 5) as f64 - 2.0);
        for n in [1u32, 2, 4, 8, 16, 32, 64] {
            let base = 0.4 * (n as f64).powf(-0.5) * wobble;
            let w2 = 1.0 + 0.01 * ((rep * 3 % 4) as f64 - 1.5);
            rs.push(rec("s", UNIFORM_RANDOM, n, rep, base * 1.25 * w2, 1.01));
            rs.push(rec("s", SINE_RANDOM, n, rep, base * cosine_vs_sine, 0.98));
            rs.push(rec("s", COSINE_RANDOM, n, rep, base, 1.0));
            let fib = 0.4 * (n as f64).powf(-0.75) * wobble * w2;
            rs.push(rec("s", COSINE_FIB_PIXEL, n, rep, fib, 1.0 + 0.03 * (rep as f64 - 2.5)));
            rs.push(rec("s", COSINE_FIB_STATIC, n, rep, fib, static_ratio + 0.1 * rep as f64));
        }
    }
    rs
}

#[test]
fn every_claim_holds_on_a_scene_made_to_satisfy_them() {
    let v = scene_verdicts(&synthetic(4.0, 1.1), "s", &[8, 16, 32], &[1, 2, 4, 8, 16, 32, 64]);
    assert_eq!(v.len(), Claim::all().len());
    // The synthetic scene has none of the equal-time samplers: those cells are not measured.
    let (paper, samplers) = v.split_at(6);
    assert!(samplers.iter().all(|x| x.outcome == Outcome::NotMeasured), "{samplers:?}");
    for x in paper {
        assert_eq!(x.outcome, Outcome::Holds, "{x:?}");
        assert!(x.margin_se > critical_se(6), "{x:?}");
    }
}

#[test]
fn a_reversed_claim_fails_and_a_weak_one_is_not_significant() {
    // Sine better than cosine: the claim fails. The static seed's ratio clearly above the
    // per-pixel seed's but below the threshold (1.2–1.7, mean 1.45): not significant.
    let v = scene_verdicts(&synthetic(1.2, 0.9), "s", &[8, 16, 32], &[1, 2, 4, 8, 16, 32, 64]);
    let get = |c: Claim| v.iter().find(|x| x.claim == c).unwrap();
    assert_eq!(get(Claim::CosineBeatsSine).outcome, Outcome::Fails);
    assert!(get(Claim::CosineBeatsSine).margin_se < 0.0);
    assert_eq!(get(Claim::CosineBeatsUniform).outcome, Outcome::Holds);
    assert_eq!(get(Claim::StaticSeedStructured).outcome, Outcome::NotSignificant);
    assert!(get(Claim::StaticSeedStructured).detail.contains("low-frequency ratio"));
    // Nothing measured on another scene.
    let none = scene_verdicts(&synthetic(4.0, 1.1), "other", &[8], &[1, 2]);
    assert!(none.iter().all(|x| x.outcome == Outcome::NotMeasured), "{none:?}");
}

#[test]
fn holm_keeps_the_strong_cells_family_wise() {
    // Four cells of one margin each at n = 4 (3 degrees of freedom; 5.84 SE per cell):
    // p = 2.2e-6, 0.0021, 0.0074 and, negative, 0.0060.
    let cell = |claim, se: f64| {
        judge("s", claim, vec![("8".into(), Some(Margin { mean: se, se: 1.0, n: 4, base: f64::NAN }))], true)
    };
    let mut v = vec![
        cell(Claim::CosineBeatsUniform, 100.0),
        cell(Claim::CosineBeatsSine, 10.0),
        cell(Claim::FibonacciBeatsRandom, 6.5),
        cell(Claim::FibonacciSteeper, -7.0),
    ];
    let per_cell: Vec<Outcome> = v.iter().map(|x| x.outcome).collect();
    assert_eq!(per_cell, [Outcome::Holds, Outcome::Holds, Outcome::Holds, Outcome::Fails]);
    family_wise(&mut v);
    // Holm: 2.2e-6 × 4, 0.0021 × 3 = 0.0064 ≤ 0.01, then 0.0060 × 2 = 0.012 > 0.01: stop.
    let family: Vec<Outcome> = v.iter().map(|x| x.family).collect();
    assert_eq!(family, [Outcome::Holds, Outcome::Holds, Outcome::NotSignificant, Outcome::NotSignificant]);
    assert!((v[1].holm_p - 3.0 * v[1].p_value).abs() < 1e-12);
    assert!((v[2].holm_p - v[3].holm_p).abs() < 1e-12, "made monotone: {v:?}");
    assert_eq!(holding(&v), (3, 2));
    // A cell that fails at one of three ray counts: its p-value is that margin's times 3.
    let three = |x| Some(Margin { mean: x, se: 1.0, n: 4, base: f64::NAN });
    let f = judge(
        "s",
        Claim::CosineBeatsSine,
        vec![("8".into(), three(9.0)), ("16".into(), three(-7.0)), ("32".into(), three(9.0))],
        true,
    );
    assert_eq!(f.outcome, Outcome::Fails);
    assert!((f.p_value - 3.0 * 0.005_986_255_7).abs() < 1e-6, "{}", f.p_value);
}
