//! The engines' rotation patterns (`sampling::engine`): each is its published formula;
//! its values are uniform over pixels and frames (χ²) and every 4 × 4 (Bayer) or 5 × 5 (magic square)
//! window holds every rotation; a fixed pixel's rotation is uniform over run seeds; and per-pixel
//! unbiasedness is what `compare::per_pixel_unbiased` says: present for pseudo-random numbers (the
//! static set is random over runs), absent for the lattice (a fixed pattern randomizes no pixel's θ).

use super::sampling_blue_noise::{cap, estimate_over_seeds};
use crate::support::stats::{chi2_test, sidak_threshold, two_sided_z};
use glam::Vec2;
use hemilab::compare::per_pixel_unbiased;
use hemilab::sampling::engine::{BAYER4, IGN_FRAME_STEP, Pattern, ign, magic5, to_fixed};
use hemilab::sampling::schedule::r1;
use hemilab::sampling::seed::{PixelSeed, fix_add};
use hemilab::sampling::{Distribution, SamplerConfig, Schedule, SeedMode, Sequence};
use hemilab::spec::Row;

const ENGINES: [SeedMode; 4] = [SeedMode::Ign, SeedMode::Bayer, SeedMode::MagicSquare, SeedMode::R2Dither];

#[test]
fn patterns_are_their_published_formulas() {
    // Jimenez 2014, with Wolfe 2022's per-frame offset (reset every 64 frames).
    for (x, y, t) in [(0u32, 0u32, 0u32), (1, 0, 0), (17, 300, 3), (1919, 1079, 63), (5, 5, 64)] {
        let f = (t % 64) as f64 * IGN_FRAME_STEP;
        let (px, py) = (x as f64 + f, y as f64 + f);
        let inner = (0.06711056 * px + 0.00583715 * py).fract();
        let want = (52.9829189 * inner).fract();
        assert_eq!(Pattern::Ign.value(x, y, t), to_fixed(want), "IGN at ({x}, {y}, {t})");
        assert!((ign(px, py) - want).abs() < 1e-12);
    }
    // Bayer 1973's matrix: the recursive construction from the 2 × 2 [[0, 2], [3, 1]].
    let b2 = [[0u32, 2], [3, 1]];
    for y in 0..4 {
        for x in 0..4 {
            let want = 4 * b2[y % 2][x % 2] + b2[y / 2][x / 2];
            assert_eq!(BAYER4[y * 4 + x], want, "Bayer ({x}, {y})");
        }
    }
    // The magic square: every row, column and (broken) diagonal sums to 60 = 5 · 24 / 2.
    for k in 0..5 {
        assert_eq!((0..5).map(|i| magic5(i, k)).sum::<u32>(), 60, "row {k}");
        assert_eq!((0..5).map(|i| magic5(k, i)).sum::<u32>(), 60, "column {k}");
        assert_eq!((0..5).map(|i| magic5((i + k) % 5, i)).sum::<u32>(), 60, "diagonal {k}");
        assert_eq!((0..5).map(|i| magic5((k + 5 - i) % 5, i)).sum::<u32>(), 60, "anti-diagonal {k}");
    }
    // Roberts 2018's dither: frac(x / g + y / g²).
    let g = 1.324_717_957_244_746_f64;
    for (x, y) in [(0u32, 0u32), (1, 0), (0, 1), (123, 456), (4095, 4095)] {
        let v = (x as f64 / g + y as f64 / (g * g)).fract();
        let got = Pattern::R2Dither.value(x, y, 0) as f64 / (1u64 << 24) as f64;
        assert!((got - v).abs() < 1e-6, "R2 dither ({x}, {y}): {got} vs {v}");
    }
}

/// Pixel (x, y)'s rotation in frame f of run seed `seed` under `r1`: the mode's own step (IGN's
/// pixel offset; R1 for the others), as `SamplerConfig::fill_pixel` combines them.
fn rotation(mode: SeedMode, seed: u64, x: u32, y: u32, f: u32) -> u32 {
    let cfg = SamplerConfig::new(Sequence::Fibonacci, mode, 1, seed).unwrap().with_schedule(Schedule::R1);
    let ps = PixelSeed::new(cfg.seed, 0);
    match mode {
        SeedMode::Ign => ps.offsets_at(mode, x, y, f).0,
        _ => fix_add(ps.offsets_at(mode, x, y, 0).0, r1(f as u64)),
    }
}

#[test]
fn rotations_are_uniform_over_pixels_and_frames() {
    // 240 × 240 pixels (a multiple of both periods) × 64 frames under `r1`. The discrete patterns
    // hold their 16 or 25 rotations equally often, exactly; IGN and R2 dither pass χ² over 64 bins.
    let alpha = sidak_threshold(0.01, 2);
    for mode in ENGINES {
        let bins = match mode {
            SeedMode::Bayer => 16,
            SeedMode::MagicSquare => 25,
            _ => 64,
        };
        let mut counts = vec![0.0; bins];
        for f in 0..64 {
            // The run's offset u moves every bin edge alike: read the bins relative to pixel (0, 0).
            let base = rotation(mode, 7, 0, 0, f);
            for y in 0..240 {
                for x in 0..240 {
                    let v = rotation(mode, 7, x, y, f).wrapping_sub(base) & 0xFF_FFFF;
                    counts[((v as u64 * bins as u64 + (1 << 23)) >> 24) as usize % bins] += 1.0;
                }
            }
        }
        let expected = vec![240.0 * 240.0 * 64.0 / bins as f64; bins];
        let t = chi2_test(&counts, &expected, 5.0).unwrap();
        eprintln!("{mode}: χ² {:.2} dof {} p {:.3}", t.statistic, t.dof, t.p_value);
        if bins < 64 {
            assert_eq!(counts, expected, "{mode}: every rotation equally often");
        } else {
            assert!(t.p_value > alpha, "{mode}: not uniform, p = {}", t.p_value);
        }
    }
}

#[test]
fn every_window_of_bayer_and_the_magic_square_holds_every_rotation() {
    for (mode, n) in [(SeedMode::Bayer, 4u32), (SeedMode::MagicSquare, 5)] {
        for seed in [1u64, 2, 3] {
            for (ox, oy) in [(0, 0), (1, 3), (17, 29)] {
                let ps = PixelSeed::new(seed, 0);
                let mut v: Vec<u32> =
                    (0..n * n).map(|i| ps.offsets_at(mode, ox + i % n, oy + i / n, 0).0).collect();
                v.sort_unstable();
                v.dedup();
                assert_eq!(v.len() as u32, n * n, "{mode} seed {seed} window at ({ox}, {oy})");
                // Equally spaced around the circle: consecutive differences are 1/n (to the grid).
                let step = (1u64 << 24) as f64 / (n * n) as f64;
                for w in v.windows(2) {
                    assert!(((w[1] - w[0]) as f64 - step).abs() <= 1.0, "{mode}: uneven rotations");
                }
            }
        }
    }
}

#[test]
fn each_pixel_rotation_is_uniform_over_run_seeds() {
    let pixels = [(0u32, 0u32), (37, 5), (1000, 77)];
    let alpha = sidak_threshold(0.01, pixels.len() * ENGINES.len());
    for mode in ENGINES {
        for (x, y) in pixels {
            let mut counts = vec![0.0; 64];
            for seed in 0..32768u64 {
                let (ox, oy) = PixelSeed::new(seed, 0).offsets_at(mode, x, y, 0);
                assert_eq!(oy, 0, "{mode}: a rotation moves x alone");
                counts[(ox >> 18) as usize] += 1.0;
            }
            let t = chi2_test(&counts, &[512.0; 64], 5.0).unwrap();
            assert!(t.p_value > alpha, "{mode} ({x}, {y}): p = {}", t.p_value);
        }
    }
}

#[test]
fn frames_step_as_engines_step_them() {
    let at = |mode, schedule, frame| {
        let cfg = SamplerConfig::new(Sequence::Fibonacci, mode, 8, 4)
            .unwrap()
            .with_schedule(schedule)
            .with_frame(frame);
        let mut p = vec![Vec2::ZERO; 8];
        cfg.fill_pixel(10, 20, 0, &mut p);
        p
    };
    let st = at(SeedMode::Static, Schedule::R1, 0);
    let fix = |v: f32| (v as f64 * 16_777_216.0) as u32;
    for mode in ENGINES {
        for f in [1u32, 2, 63, 64, 65] {
            let p = at(mode, Schedule::R1, f);
            let want = rotation(mode, 4, 10, 20, f);
            for (a, b) in p.iter().zip(&st) {
                assert_eq!(fix(a.x).wrapping_sub(fix(b.x)) & 0xFF_FFFF, want, "{mode} frame {f}: x");
                assert_eq!(a.y, b.y, "{mode} frame {f}: y moves");
            }
            assert_ne!(at(mode, Schedule::Independent, f), at(mode, Schedule::Independent, 0), "{mode} {f}");
        }
    }
    // IGN's offset starts again every 64 frames.
    assert_eq!(at(SeedMode::Ign, Schedule::R1, 64), at(SeedMode::Ign, Schedule::R1, 0));
}

#[test]
fn per_pixel_unbiased_for_random_numbers_absent_for_the_lattice() {
    // Over run seeds in one pixel: pseudo-random numbers (a fresh static set per run) rotated by a
    // pattern are unbiased; the lattice rotated by it keeps θ fixed, so a cap around the normal gets
    // the same biased value in every run (the absence the row rule states).
    let caps = [cap(0.0, 1.0), cap(0.6, 0.5)];
    let z = two_sided_z(sidak_threshold(0.01, ENGINES.len() * caps.len()));
    for mode in ENGINES {
        let row = |s| Row::new(Distribution::SineCosine, s, mode);
        assert!(per_pixel_unbiased(row(Sequence::Random)), "{mode}");
        assert!(!per_pixel_unbiased(row(Sequence::Fibonacci)), "{mode}");
        for c in caps {
            let (mean, se) = estimate_over_seeds(Distribution::SineCosine, Sequence::Random, mode, c, 37, 5);
            let bias = mean - c.exact;
            eprintln!("random {mode} cap {:.3}: bias {bias:+.5} se {se:.5}", c.exact);
            assert!(bias.abs() <= z * se, "random {mode}: bias {bias} > {z:.2} se {se}");
        }
        let axial = caps[0];
        let (mean, se) =
            estimate_over_seeds(Distribution::SineCosine, Sequence::Fibonacci, mode, axial, 37, 5);
        let bias = mean - axial.exact;
        eprintln!("fibonacci {mode} axial cap: bias {bias:+.5} se {se:.5}");
        assert!(bias.abs() > 10.0 * se.max(1e-6), "fibonacci {mode}: bias {bias} se {se}");
    }
}
