//! The `stbn` seed mode (Wolfe, Morrical & Ramamoorthi 2022): every slice of its masks is an exact
//! permutation of the ranks and blue in 2-D, every pixel's sequence over the slices is blue in 1-D
//! (against white noise, numbers printed by --nocapture), the masks tile and are generated bit for
//! bit the same; each pixel's offset in every frame is uniform over run seeds, each pixel's
//! estimate unbiased; the schedules act once per cycle of the mask.

use super::sampling_blue_noise::{RINGS, cap, power_spectrum, ring, standardize, white_ranks};
use crate::support::stats::{chi2_test, sidak_threshold, two_sided_z};
use glam::Vec2;
use hemilab::sampling::schedule::r2;
use hemilab::sampling::seed::PixelSeed;
use hemilab::sampling::stbn::{STBN_DEPTH, STBN_SIGMA, STBN_SIZE, StbnMask, StbnShift, stbn_masks};
use hemilab::sampling::{Distribution, SamplerConfig, Schedule, SeedMode, Sequence};
use hemilab::stats::mean_and_standard_error;
use std::f64::consts::TAU;

const M: usize = STBN_SIZE as usize;
const D: usize = STBN_DEPTH as usize;

fn slice(m: &StbnMask, t: usize) -> Vec<f64> {
    m.ranks()[t * M * M..(t + 1) * M * M].iter().map(|&r| r as f64).collect()
}

/// Mean over pixels of each pixel's periodogram along time (|DFT|² / D of its standardized
/// sequence, standardized over the whole volume): white noise has expectation 1 at every k ≠ 0.
fn temporal_power(values: &[f64]) -> Vec<f64> {
    let v = standardize(values);
    let mut power = vec![0.0; D];
    for p in 0..M * M {
        for (k, pk) in power.iter_mut().enumerate() {
            let (mut a, mut b) = (0.0, 0.0);
            for t in 0..D {
                let (s, c) = (TAU * (k * t) as f64 / D as f64).sin_cos();
                a += v[t * M * M + p] * c;
                b -= v[t * M * M + p] * s;
            }
            *pk += (a * a + b * b) / D as f64 / (M * M) as f64;
        }
    }
    power
}

#[test]
fn every_slice_is_a_permutation_of_the_ranks() {
    for m in stbn_masks().iter().chain(&[StbnMask::void_and_cluster(8, 4, STBN_SIGMA, 1)]) {
        let n = (m.size() * m.size()) as usize;
        assert_eq!(m.ranks().len(), n * m.depth() as usize);
        for (t, s) in m.ranks().chunks(n).enumerate() {
            let mut seen = vec![false; n];
            for &r in s {
                assert!(!std::mem::replace(&mut seen[r as usize], true), "slice {t}: rank {r} twice");
            }
        }
    }
    assert_eq!((stbn_masks()[0].size(), stbn_masks()[0].depth()), (STBN_SIZE, STBN_DEPTH));
}

#[test]
fn every_slice_is_blue_in_space() {
    let white = power_spectrum(&white_ranks(7));
    assert!(ring(&white, 0.0, 0.0625) > 0.5 && ring(&white, 0.0625, 0.125) > 0.5, "white-noise control");
    let mut worst = [0.0f64; 2];
    for (c, m) in stbn_masks().iter().enumerate() {
        for t in 0..D {
            let p = power_spectrum(&slice(m, t));
            let rings = RINGS.map(|(a, b)| ring(&p, a, b));
            worst = [worst[0].max(rings[0]), worst[1].max(rings[1])];
            // White noise has mean power 1 in every ring; a slice's two lowest rings (f ≤ 1/8
            // cycles per pixel) hold under 3 % of it (as the 2-D masks must), and its energy sits at high frequencies.
            assert!(rings[0] < 0.03 && rings[1] < 0.03, "mask {c} slice {t}: low rings {rings:?}");
            assert!(rings[5] > 1.0, "mask {c} slice {t}: high ring {}", rings[5]);
        }
    }
    eprintln!("stbn slices: worst low rings {worst:?} (white noise ~1)");
}

#[test]
fn every_pixel_is_blue_in_time() {
    // Control: a white volume (each slice a random permutation) reads ~1 at every k.
    let white: Vec<f64> = (0..D).flat_map(|t| white_ranks(100 + t as u64)).collect();
    let w = temporal_power(&white);
    let low = |p: &[f64]| p[1..=D / 8].iter().sum::<f64>() / (D / 8) as f64;
    eprintln!(
        "white volume: temporal power {:?}",
        w.iter().map(|x| (x * 100.0).round() / 100.0).collect::<Vec<_>>()
    );
    assert!(low(&w) > 0.7, "white control {}", low(&w));
    for (c, m) in stbn_masks().iter().enumerate() {
        let v: Vec<f64> = m.ranks().iter().map(|&r| r as f64).collect();
        let p = temporal_power(&v);
        eprintln!(
            "mask {c}: temporal power {:?}",
            p.iter().map(|x| (x * 100.0).round() / 100.0).collect::<Vec<_>>()
        );
        // The lowest eighth of the temporal frequencies (k = 1..4 of 32) holds under a tenth of
        // white noise's power, and the highest frequency more than white's.
        assert!(low(&p) < 0.1, "mask {c}: low temporal power {}", low(&p));
        assert!(p[D / 2] > 1.0, "mask {c}: high temporal power {}", p[D / 2]);
    }
}

/// FNV-1a over the ranks of both shipped masks.
fn fingerprint(ms: &[StbnMask]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for m in ms {
        for &r in m.ranks() {
            for b in r.to_le_bytes() {
                h = (h ^ b as u64).wrapping_mul(0x0100_0000_01b3);
            }
        }
    }
    h
}

const FINGERPRINT: u64 = 0xdcec_9274_2703_f5c5;

#[test]
fn masks_are_deterministic_and_tile_in_space_and_time() {
    eprintln!("stbn fingerprint {:#018x}", fingerprint(stbn_masks()));
    assert_eq!(fingerprint(stbn_masks()), FINGERPRINT);
    assert_ne!(stbn_masks()[0], stbn_masks()[1], "the two channels must be independent masks");
    let small = || StbnMask::void_and_cluster(16, 8, STBN_SIGMA, 5);
    assert_eq!(small(), small());
    let s = StbnShift::new(42);
    for (x, y, t) in [(0u32, 0u32, 0u32), (13, 40, 7), (63, 1, 31)] {
        assert_eq!(s.offsets(x, y, t), s.offsets(x + STBN_SIZE, y + 3 * STBN_SIZE, t + 2 * STBN_DEPTH));
    }
}

/// Pixel (x, y)'s offsets in frame `frame` for run seed `seed` (what `fill_pixel` adds to the static set).
fn offsets(seed: u64, x: u32, y: u32, frame: u32) -> (f64, f64) {
    let (ox, oy) = PixelSeed::new(seed, 0).offsets_at(SeedMode::Stbn, x, y, frame);
    (ox as f64 / (1u64 << 24) as f64, oy as f64 / (1u64 << 24) as f64)
}

#[test]
fn each_pixel_offset_is_uniform_over_run_seeds_in_every_frame() {
    let cases = [(0u32, 0u32, 0u32), (37, 5, 3), (1000, 77, 31)];
    let alpha = sidak_threshold(0.01, cases.len());
    for (x, y, f) in cases {
        let mut counts = vec![0.0; 256];
        for seed in 0..65536u64 {
            let (ox, oy) = offsets(seed, x, y, f);
            counts[(oy * 16.0) as usize * 16 + (ox * 16.0) as usize] += 1.0;
        }
        let t = chi2_test(&counts, &[256.0; 256], 5.0).unwrap();
        eprintln!("pixel ({x}, {y}) frame {f}: chi2 {:.1} dof {} p {:.3}", t.statistic, t.dof, t.p_value);
        assert!(t.p_value > alpha, "pixel ({x}, {y}) frame {f}: p = {}", t.p_value);
    }
}

#[test]
fn each_pixel_estimate_is_unbiased_over_seeds_in_every_frame() {
    const SEEDS: u64 = 2048;
    const N: u32 = 16;
    let caps = [cap(0.0, 1.0), cap(0.6, 0.5)];
    let frames = [0u32, 5, 40];
    let checks = Sequence::all().len() * caps.len() * frames.len() * 2;
    let z = two_sided_z(sidak_threshold(0.01, checks));
    let d = Distribution::SineCosine;
    let mut pts = vec![Vec2::ZERO; N as usize];
    for seq in Sequence::all() {
        for c in caps {
            for f in frames {
                for schedule in [Schedule::Independent, Schedule::R1] {
                    let (x, y) = (37u32, 5u32);
                    let per_seed: Vec<f64> = (0..SEEDS)
                        .map(|seed| {
                            let cfg = SamplerConfig::new(seq, SeedMode::Stbn, N, seed).unwrap();
                            cfg.with_frame(f).with_schedule(schedule).fill_pixel(x, y, 12345, &mut pts);
                            let hit = |u: &Vec2| {
                                let s = d.sample(*u);
                                if s.dir.dot(c.axis) >= c.cos_half_angle { s.weight as f64 } else { 0.0 }
                            };
                            pts.iter().map(hit).sum::<f64>() / N as f64
                        })
                        .collect();
                    let (mean, se) = mean_and_standard_error(&per_seed);
                    let bias = mean - c.exact;
                    eprintln!("{seq} cap {:.3} frame {f} {schedule}: bias {bias:+.5} se {se:.5}", c.exact);
                    assert!(
                        bias.abs() <= z * se,
                        "{seq} {c:?} frame {f} {schedule}: bias {bias} > {z:.2} se {se}"
                    );
                }
            }
        }
    }
}

/// Within one cycle a frame reads the next slice (same run shift); the cycle after adds R2 under
/// `r1` and draws a new shift under `independent`.
#[test]
fn frames_read_slices_and_schedules_act_per_cycle() {
    let fix = |v: f32| (v as f64 * 16_777_216.0) as u32;
    let base = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Stbn, 4, 9).unwrap();
    let (x, y) = (21u32, 50u32);
    let pts = |cfg: SamplerConfig| {
        let mut p = vec![Vec2::ZERO; 4];
        cfg.fill_pixel(x, y, 7, &mut p);
        p
    };
    let mut st = vec![Vec2::ZERO; 4];
    SamplerConfig::new(Sequence::Fibonacci, SeedMode::Static, 4, 9).unwrap().fill_pixel(x, y, 7, &mut st);
    for schedule in [Schedule::Independent, Schedule::R1] {
        for f in [0u32, 1, 17, 31] {
            let (ox, oy) = PixelSeed::new(9, 0).offsets_at(SeedMode::Stbn, x, y, f);
            for (p, s) in pts(base.with_schedule(schedule).with_frame(f)).iter().zip(&st) {
                assert_eq!((fix(p.x).wrapping_sub(fix(s.x))) % (1 << 24), ox, "frame {f}");
                assert_eq!((fix(p.y).wrapping_sub(fix(s.y))) % (1 << 24), oy, "frame {f}");
            }
        }
    }
    for f in [32u32, 33, 70] {
        let k = (f / STBN_DEPTH) as u64;
        let (ax, ay) = r2(k);
        let (p0, pr) =
            (pts(base.with_frame(f % STBN_DEPTH)), pts(base.with_schedule(Schedule::R1).with_frame(f)));
        for (a, b) in p0.iter().zip(&pr) {
            assert_eq!((fix(b.x).wrapping_sub(fix(a.x))) % (1 << 24), ax, "r1 frame {f}");
            assert_eq!((fix(b.y).wrapping_sub(fix(a.y))) % (1 << 24), ay, "r1 frame {f}");
        }
        assert_ne!(pts(base.with_frame(f)), p0, "independent frame {f}: a new shift");
    }
}
