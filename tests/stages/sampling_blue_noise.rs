//! The `blue-noise` seed mode: its masks are permutations of ranks with little low-frequency
//! energy (against white noise, with numbers printed by --nocapture), generated bit-identically;
//! each pixel's offset is uniform over run seeds and each pixel's estimate unbiased over seeds;
//! the point set is the static set shifted by the pixel's offsets.

use crate::support::stats::{chi2_test, sidak_threshold, two_sided_z};
use glam::{Vec2, Vec3};
use hemilab::sampling::blue_noise::{BlueNoiseMask, MASK_SIGMA, MASK_SIZE, MaskShift, masks};
use hemilab::sampling::seed::{PixelSeed, hash};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use hemilab::stats::mean_and_standard_error;
use std::f64::consts::TAU;

const M: usize = MASK_SIZE as usize;

/// Standardized (zero mean, unit variance) copy of a field.
pub(super) fn standardize(v: &[f64]) -> Vec<f64> {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
    v.iter().map(|x| (x - mean) / sd).collect()
}

/// Periodogram |DFT|² / N of a standardized M × M field (row-major), by separable DFTs: white
/// noise has expectation 1 at every non-zero frequency.
pub(super) fn power_spectrum(v: &[f64]) -> Vec<f64> {
    let v = standardize(v);
    let (c, s): (Vec<f64>, Vec<f64>) =
        (0..M).map(|k| (TAU * k as f64 / M as f64).sin_cos()).map(|(s, c)| (c, s)).unzip();
    let dft = |re: &[f64], im: &[f64], k: usize| {
        let (mut a, mut b) = (0.0, 0.0);
        for x in 0..M {
            let (cs, sn) = (c[(k * x) % M], s[(k * x) % M]);
            a += re[x] * cs + im[x] * sn;
            b += im[x] * cs - re[x] * sn;
        }
        (a, b)
    };
    // Rows, then columns.
    let (mut re, mut im) = (vec![0.0; M * M], vec![0.0; M * M]);
    let zero = vec![0.0; M];
    for y in 0..M {
        for k in 0..M {
            let (a, b) = dft(&v[y * M..(y + 1) * M], &zero, k);
            re[y * M + k] = a;
            im[y * M + k] = b;
        }
    }
    let mut power = vec![0.0; M * M];
    for kx in 0..M {
        let col_re: Vec<f64> = (0..M).map(|y| re[y * M + kx]).collect();
        let col_im: Vec<f64> = (0..M).map(|y| im[y * M + kx]).collect();
        for ky in 0..M {
            let (a, b) = dft(&col_re, &col_im, ky);
            power[ky * M + kx] = (a * a + b * b) / (M * M) as f64;
        }
    }
    power
}

/// Radial frequency of DFT bin (kx, ky) in cycles per pixel.
fn radius(kx: usize, ky: usize) -> f64 {
    let (fx, fy) = (kx.min(M - kx) as f64, ky.min(M - ky) as f64);
    (fx * fx + fy * fy).sqrt() / M as f64
}

/// Mean power over the non-zero frequencies with radius in (lo, hi] cycles per pixel.
pub(super) fn ring(power: &[f64], lo: f64, hi: f64) -> f64 {
    let (mut sum, mut n) = (0.0, 0);
    for ky in 0..M {
        for kx in 0..M {
            let r = radius(kx, ky);
            if r > lo && r <= hi {
                sum += power[ky * M + kx];
                n += 1;
            }
        }
    }
    sum / n as f64
}

/// RMS of the standardized field after the metrics' Gaussian low-pass (σ = 1.5 px, toroidal):
/// for white noise about 1/sqrt(4πσ²) = 0.19.
fn lowpass_rms(v: &[f64]) -> f64 {
    let v = standardize(v);
    let sigma = 1.5f64;
    let r = 6i64;
    let k: Vec<f64> = (-r..=r).map(|d| (-(d * d) as f64 / (2.0 * sigma * sigma)).exp()).collect();
    let norm: f64 = k.iter().sum();
    let blur = |src: &[f64], horizontal: bool| -> Vec<f64> {
        let mut out = vec![0.0; M * M];
        for y in 0..M {
            for x in 0..M {
                out[y * M + x] = (-r..=r)
                    .map(|d| {
                        let (sx, sy) = if horizontal {
                            ((x as i64 + d).rem_euclid(M as i64) as usize, y)
                        } else {
                            (x, (y as i64 + d).rem_euclid(M as i64) as usize)
                        };
                        src[sy * M + sx] * k[(d + r) as usize]
                    })
                    .sum::<f64>()
                    / norm;
            }
        }
        out
    };
    let b = blur(&blur(&v, true), false);
    (b.iter().map(|x| x * x).sum::<f64>() / b.len() as f64).sqrt()
}

/// A white-noise mask: a random permutation of the ranks (Fisher–Yates keyed by `seed`).
pub(super) fn white_ranks(seed: u64) -> Vec<f64> {
    let mut r: Vec<usize> = (0..M * M).collect();
    for i in (1..r.len()).rev() {
        r.swap(i, (hash(seed, i as u64) % (i as u64 + 1)) as usize);
    }
    r.into_iter().map(|x| x as f64).collect()
}

fn ranks_f64(m: &BlueNoiseMask) -> Vec<f64> {
    m.ranks().iter().map(|&r| r as f64).collect()
}

/// Pixel (x, y)'s offsets in [0, 1) for run seed `seed` (what `fill_pixel` adds to the static set).
fn offsets(seed: u64, x: u32, y: u32) -> (f64, f64) {
    let (ox, oy) = PixelSeed::new(seed, 0).offsets(SeedMode::BlueNoise, x, y);
    (ox as f64 / (1u64 << 24) as f64, oy as f64 / (1u64 << 24) as f64)
}

/// The rings printed, in cycles per pixel; the first two (f ≤ 1/8) are asserted.
pub(super) const RINGS: [(f64, f64); 6] =
    [(0.0, 0.0625), (0.0625, 0.125), (0.125, 0.1875), (0.1875, 0.25), (0.25, 0.375), (0.375, 0.75)];

#[test]
fn masks_have_little_low_frequency_energy_compared_with_white_noise() {
    let white = power_spectrum(&white_ranks(7));
    let white_lp = lowpass_rms(&white_ranks(7));
    eprintln!(
        "white noise  : rings {:?}, low-pass rms {white_lp:.4}",
        RINGS.map(|(a, b)| (ring(&white, a, b) * 1e3).round() / 1e3)
    );
    for (c, m) in masks().iter().enumerate() {
        let p = power_spectrum(&ranks_f64(m));
        let lp = lowpass_rms(&ranks_f64(m));
        let rings = RINGS.map(|(a, b)| ring(&p, a, b));
        eprintln!(
            "mask {c}       : rings {:?}, low-pass rms {lp:.4}",
            rings.map(|x| (x * 1e4).round() / 1e4)
        );
        // White noise has mean power 1 in every ring (measured ~1 above); the mask's two lowest
        // rings hold under 3 % of it, and the low-pass keeps under a quarter of white's RMS.
        assert!(rings[0] < 0.03 && rings[1] < 0.03, "mask {c}: low rings {rings:?}");
        assert!(ring(&white, 0.0, 0.0625) > 0.5 && ring(&white, 0.0625, 0.125) > 0.5, "white-noise control");
        assert!(lp < 0.25 * white_lp, "mask {c}: low-pass rms {lp} vs white {white_lp}");
        // Blue, not merely smooth: the energy is at high frequencies (total power is 1 on average).
        assert!(rings[5] > 1.0, "mask {c}: high ring {}", rings[5]);
    }
}

#[test]
fn per_run_offsets_are_the_mask_itself_and_stay_blue() {
    // A run's offsets are the toroidally shifted mask plus a constant below one rank step, so their
    // spectrum is the mask's. Printed for comparison: a Cranley–Patterson rotation of the values
    // mod 1 (the usual way to make each pixel uniform, equally unbiased) cuts the range where it
    // wraps, and on the line that binary pattern lets several times more through the low-pass
    // (on the torus, where a shifted point set lives, the rotation changes nothing).
    let white_lp = lowpass_rms(&white_ranks(11));
    for seed in [1u64, 2, 3, 1000, u64::MAX] {
        for c in 0..2 {
            let field: Vec<f64> = (0..M * M)
                .map(|i| {
                    let o = offsets(seed, (i % M) as u32, (i / M) as u32);
                    if c == 0 { o.0 } else { o.1 }
                })
                .collect();
            let rings = RINGS.map(|(a, b)| ring(&power_spectrum(&field), a, b));
            let lp = lowpass_rms(&field);
            let r = (hash(seed, 77) >> 40) as f64 / (1u64 << 24) as f64;
            let rotated: Vec<f64> = field.iter().map(|o| (o + r).fract()).collect();
            let lp_rotated = lowpass_rms(&rotated);
            eprintln!(
                "seed {seed} channel {c}: rings {:?}, low-pass rms {lp:.4} (rotated by {r:.3} mod 1: {lp_rotated:.4}; white {white_lp:.4})",
                rings.map(|x| (x * 1e4).round() / 1e4)
            );
            assert!(rings[0] < 0.03 && rings[1] < 0.03, "seed {seed} channel {c}: {rings:?}");
            assert!(lp < 0.25 * white_lp, "seed {seed} channel {c}: {lp}");
        }
    }
}

#[test]
fn masks_are_blue_on_the_circle_too() {
    // A Cranley–Patterson-shifted set is a periodic function of its offset, so what reaches the
    // image is the offsets on the circle: cos and sin of 2π · rank / N must be blue as well
    // (rank 0 and rank N - 1 are neighbours there).
    let white = white_ranks(5);
    let circle =
        |r: &[f64], f: fn(f64) -> f64| r.iter().map(|&v| f(TAU * v / (M * M) as f64)).collect::<Vec<_>>();
    let white_lp = lowpass_rms(&circle(&white, f64::cos));
    for (c, m) in masks().iter().enumerate() {
        for (name, f) in [("cos", f64::cos as fn(f64) -> f64), ("sin", f64::sin)] {
            let field = circle(&ranks_f64(m), f);
            let rings = RINGS.map(|(a, b)| ring(&power_spectrum(&field), a, b));
            let lp = lowpass_rms(&field);
            eprintln!(
                "mask {c} {name}(2π rank/N): rings {:?}, low-pass rms {lp:.4} (white {white_lp:.4})",
                rings.map(|x| (x * 1e4).round() / 1e4)
            );
            assert!(rings[0] < 0.03 && rings[1] < 0.03, "mask {c} {name}: {rings:?}");
            assert!(lp < 0.15 * white_lp, "mask {c} {name}: {lp} vs white {white_lp}");
        }
    }
}

#[test]
fn masks_are_permutations_of_the_ranks_for_every_size() {
    for m in masks().iter().chain(&[
        BlueNoiseMask::void_and_cluster(2, 1.5, 1),
        BlueNoiseMask::void_and_cluster(7, 1.5, 2),
        BlueNoiseMask::void_and_cluster(16, 1.0, 3),
        BlueNoiseMask::void_and_cluster(32, 2.0, 4),
    ]) {
        let n = (m.size() * m.size()) as usize;
        let mut seen = vec![false; n];
        for &r in m.ranks() {
            assert!(!std::mem::replace(&mut seen[r as usize], true), "size {}: rank {r} twice", m.size());
        }
        assert_eq!(m.ranks().len(), n);
    }
    assert_eq!(masks()[0].size(), MASK_SIZE);
}

/// FNV-1a over the ranks of both shipped masks.
fn fingerprint(ms: &[BlueNoiseMask]) -> u64 {
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

#[test]
fn masks_are_generated_bit_identically() {
    // Regenerated now, equal to the cached copy; and equal to the masks every earlier run made
    // (the fingerprint pins them: integer energies leave no room for platform rounding).
    let again = [
        BlueNoiseMask::void_and_cluster(MASK_SIZE, MASK_SIGMA, 0x626C_7565_2D78),
        BlueNoiseMask::void_and_cluster(MASK_SIZE, MASK_SIGMA, 0x626C_7565_2D79),
    ];
    assert_eq!(&again, masks());
    eprintln!("fingerprint {:#018x}", fingerprint(masks()));
    assert_eq!(fingerprint(masks()), FINGERPRINT);
    assert_ne!(masks()[0], masks()[1], "the two channels must be independent masks");
}

const FINGERPRINT: u64 = 0xe905_31a0_3205_b6b1;

#[test]
fn the_two_masks_are_uncorrelated() {
    let (a, b) = (ranks_f64(&masks()[0]), ranks_f64(&masks()[1]));
    let (a, b) = (standardize(&a), standardize(&b));
    let rho = a.iter().zip(&b).map(|(x, y)| x * y).sum::<f64>() / a.len() as f64;
    eprintln!("rank correlation of the x and y masks: {rho:+.4}");
    // Independent permutations: sd of rho is 1/sqrt(4096) = 0.016.
    assert!(rho.abs() < 4.0 / (M as f64), "{rho}");
}

#[test]
fn same_seed_same_offsets_and_different_seeds_differ() {
    for seed in [0u64, 1, 99] {
        let a: Vec<_> = (0..200).map(|i| offsets(seed, i * 7, i * 3)).collect();
        let b: Vec<_> = (0..200).map(|i| offsets(seed, i * 7, i * 3)).collect();
        assert_eq!(a, b);
        assert_eq!(MaskShift::new(seed), MaskShift::new(seed));
        let c: Vec<_> = (0..200).map(|i| offsets(seed + 1, i * 7, i * 3)).collect();
        assert_ne!(a, c);
    }
}

#[test]
fn one_tile_holds_every_rank_once_with_one_common_jitter() {
    // A pixel's offset is rank · 2^12 + the run's jitter (< 2^12) in 24-bit fixed point, so in a
    // tile all offsets agree mod 2^12 and are distinct; the tile repeats.
    for seed in [3u64, 4, 5] {
        let ps = PixelSeed::new(seed, 0);
        for c in 0..2 {
            let at = |x: u32, y: u32| {
                let o = ps.offsets(SeedMode::BlueNoise, x, y);
                if c == 0 { o.0 } else { o.1 }
            };
            let tile: Vec<u32> = (0..M * M).map(|i| at((i % M) as u32 + 5, (i / M) as u32 + 9)).collect();
            let mut sorted = tile.clone();
            sorted.sort_unstable();
            sorted.dedup();
            assert_eq!(sorted.len(), M * M, "seed {seed} channel {c}: repeated offsets in a tile");
            assert!(tile.iter().all(|&o| o % 4096 == tile[0] % 4096), "not one common jitter");
            for (x, y) in [(0, 0), (13, 40), (63, 1)] {
                assert_eq!(at(x, y), at(x + MASK_SIZE, y + 2 * MASK_SIZE), "tile does not repeat");
            }
        }
    }
}

#[test]
fn each_pixel_offset_is_uniform_over_run_seeds() {
    // 16 x 16 cells of [0,1)^2, 65536 seeds: chi-square per pixel, Šidák over the pixels.
    let pixels = [(0u32, 0u32), (37, 5), (63, 63), (1000, 77)];
    let alpha = sidak_threshold(0.01, pixels.len());
    for (x, y) in pixels {
        let mut counts = vec![0.0; 256];
        for seed in 0..65536u64 {
            let (ox, oy) = offsets(seed, x, y);
            counts[(oy * 16.0) as usize * 16 + (ox * 16.0) as usize] += 1.0;
        }
        let t = chi2_test(&counts, &[256.0; 256], 5.0).unwrap();
        eprintln!("pixel ({x}, {y}): chi2 {:.1} dof {} p {:.3}", t.statistic, t.dof, t.p_value);
        assert!(t.p_value > alpha, "pixel ({x}, {y}): offsets not uniform, p = {}", t.p_value);
    }
}

#[test]
fn blue_noise_is_the_static_set_shifted_per_pixel() {
    let fix = |x: f32| (x as f64 * 16_777_216.0) as i64;
    // ZSobol's static set is a different block in every pixel (its design), so it is left out.
    for seq in Sequence::all().into_iter().filter(|&s| s != Sequence::ZSobol) {
        for n in [1, 7, 16] {
            let cfg = |m| SamplerConfig::new(seq, m, n, 21).unwrap();
            let mut st = vec![Vec2::ZERO; n as usize];
            cfg(SeedMode::Static).fill_pixel(0, 0, 0, &mut st);
            for (x, y) in [(0u32, 0u32), (1, 0), (5, 70), (200, 3)] {
                let mut bn = vec![Vec2::ZERO; n as usize];
                cfg(SeedMode::BlueNoise).fill_pixel(x, y, (y * 320 + x) as u64, &mut bn);
                let (ox, oy) = PixelSeed::new(21, 0).offsets(SeedMode::BlueNoise, x, y);
                for (b, s) in bn.iter().zip(&st) {
                    assert_eq!((fix(b.x) - fix(s.x)).rem_euclid(1 << 24), ox as i64, "{seq} n={n} ({x},{y})");
                    assert_eq!((fix(b.y) - fix(s.y)).rem_euclid(1 << 24), oy as i64, "{seq} n={n} ({x},{y})");
                }
            }
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Cap {
    pub(super) axis: Vec3,
    pub(super) cos_half_angle: f32,
    pub(super) exact: f64,
}

/// The cosine-weighted fraction of a cap of half-angle `half_angle` tilted by `tilt` from the
/// normal (as in sampling_estimators.rs): cos(tilt) sin²(half_angle).
pub(super) fn cap(tilt: f64, half_angle: f64) -> Cap {
    let axis = Vec3::new(tilt.sin() as f32, 0.0, tilt.cos() as f32);
    Cap { axis, cos_half_angle: half_angle.cos() as f32, exact: tilt.cos() * half_angle.sin().powi(2) }
}

const SEEDS: u64 = 2048;
const N: u32 = 16;
const PIXELS: [(u32, u32); 3] = [(0, 0), (37, 5), (1000, 77)];

/// Mean and standard error over SEEDS run seeds of pixel (x, y)'s N-point estimate: seeds are
/// independent, so the standard error is exact for "this pixel, over runs" (pixels of one run are
/// not independent under a mask, so averaging over pixels would not test this).
pub(super) fn estimate_over_seeds(
    d: Distribution,
    seq: Sequence,
    mode: SeedMode,
    c: Cap,
    x: u32,
    y: u32,
) -> (f64, f64) {
    let mut pts = vec![Vec2::ZERO; N as usize];
    let per_seed: Vec<f64> = (0..SEEDS)
        .map(|seed| {
            SamplerConfig::new(seq, mode, N, seed).unwrap().fill_pixel(x, y, (y * 4096 + x) as u64, &mut pts);
            let sum: f64 = pts
                .iter()
                .map(|&u| d.sample(u))
                .filter(|s| s.dir.dot(c.axis) >= c.cos_half_angle)
                .map(|s| s.weight as f64)
                .sum();
            sum / N as f64
        })
        .collect();
    mean_and_standard_error(&per_seed)
}

#[test]
fn each_pixel_estimate_is_unbiased_over_seeds() {
    let caps = [cap(0.0, 1.0), cap(0.6, 0.5)];
    // Šidák over every check of this test (family-wise false alarm 1 %).
    let checks = Sequence::all().len() * Distribution::ALL.len() * caps.len() * PIXELS.len();
    let z = two_sided_z(sidak_threshold(0.01, checks));
    for seq in Sequence::all() {
        for &d in Distribution::ALL {
            for c in caps {
                for (x, y) in PIXELS {
                    let (mean, se) = estimate_over_seeds(d, seq, SeedMode::BlueNoise, c, x, y);
                    let bias = mean - c.exact;
                    eprintln!("{seq} {d} cap {:.3} pixel ({x},{y}): bias {bias:+.5} se {se:.5}", c.exact);
                    assert!(bias.abs() <= z * se, "{seq} {d} {c:?} ({x},{y}): bias {bias} > {z:.2} se {se}");
                }
            }
        }
    }
}

#[test]
fn the_over_seeds_check_sees_the_bias_of_rotation() {
    // Control: the same check flags the paper's per-pixel seed (theta stays the midpoint rule).
    let c = cap(0.0, 1.0);
    let (mean, se) =
        estimate_over_seeds(Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Rotation, c, 37, 5);
    let bias = mean - c.exact;
    assert!(bias.abs() > 10.0 * se.max(1e-6), "rotation bias {bias} se {se}");
}
