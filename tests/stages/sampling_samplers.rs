//! Proof of the four samplers beside the paper's lattice: `halton`, `pmj02bn`, `zsobol`
//! and `r2` — χ² through every warp, each one's defining property checked exactly, determinism.

use crate::sampling_warps::{PHI_BINS, THETA_BINS, cell_of, expected_counts, space};
use crate::support::stats::{chi2_test, sidak_threshold};
use glam::Vec2;
use hemilab::sampling::halton::{POW3, base3_to_fixed, radical_inverse_3};
use hemilab::sampling::pmj02::pmj02bn_fixed;
use hemilab::sampling::sobol::{owen_scramble, sobol_x, sobol_y};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};

const NEW: [Sequence; 4] = [Sequence::Halton, Sequence::Pmj02bn, Sequence::ZSobol, Sequence::R2];

fn points(seq: Sequence, mode: SeedMode, n: u32, seed: u64, x: u32, y: u32) -> Vec<Vec2> {
    let cfg = SamplerConfig::new(seq, mode, n, seed).unwrap();
    let mut out = vec![Vec2::splat(-1.0); n as usize];
    cfg.fill_pixel(x, y, (y as u64) * 4096 + x as u64, &mut out);
    out
}

fn fixed(v: f32) -> u32 {
    (v as f64 * 16_777_216.0) as u32
}

/// Whether the points (24-bit fixed) hold exactly one point in every elementary interval of
/// area 1/n (n = 2^m): 2^a × 2^(m−a) for every a.
fn is_net(pts: &[(u32, u32)]) -> bool {
    let n = pts.len();
    let m = n.trailing_zeros();
    (0..=m).all(|a| {
        let mut seen = vec![false; n];
        pts.iter().all(|&(x, y)| {
            let cell = (((x >> (24 - a)) as usize) << (m - a)) | (y >> (24 - (m - a))) as usize;
            !std::mem::replace(&mut seen[cell], true)
        })
    })
}

#[test]
fn chi2_every_new_sequence_through_every_warp() {
    let alpha = sidak_threshold(0.01, NEW.len() * Distribution::ALL.len());
    for seq in NEW {
        for &d in Distribution::ALL {
            let (n, pixels) = (64u32, 16_384u32);
            let mut observed = vec![0.0; PHI_BINS * THETA_BINS];
            for p in 0..pixels {
                for u in points(seq, SeedMode::Shift, n, 3, p % 128, p / 128) {
                    observed[cell_of(d.sample(u).dir, space(d))] += 1.0;
                }
            }
            let expected = expected_counts(|w| d.pdf(w), space(d), (n * pixels) as usize);
            let t = chi2_test(&observed, &expected, 5.0).unwrap();
            eprintln!("{seq} {d}: chi2 {:.1} dof {} p {:.4}", t.statistic, t.dof, t.p_value);
            assert!(t.p_value >= alpha, "{seq} {d}: not the warp's pdf, p = {}", t.p_value);
        }
    }
}

#[test]
fn pmj02bn_every_power_of_two_prefix_is_a_0m2_net() {
    let base: Vec<(u32, u32)> = (0..4096).map(pmj02bn_fixed).collect();
    for m in 0..=12 {
        assert!(is_net(&base[..1 << m]), "prefix 2^{m} of the base sequence");
    }
    // Randomized per pixel (XOR shift), every mode without a mod-1 offset keeps it exactly.
    for mode in [SeedMode::Static, SeedMode::Shift] {
        for (x, y) in [(0, 0), (1, 0), (17, 93), (4000, 3000)] {
            let pts: Vec<(u32, u32)> = points(Sequence::Pmj02bn, mode, 1024, 9, x, y)
                .iter()
                .map(|p| (fixed(p.x), fixed(p.y)))
                .collect();
            for m in 0..=10 {
                assert!(is_net(&pts[..1 << m]), "{mode} ({x},{y}) prefix 2^{m}");
            }
        }
    }
}

/// (normalized minimum, normalized mean) nearest-neighbour toroidal distance of 24-bit points,
/// times sqrt(n): the spacing a blue-noise set has and a clumpy one lacks.
fn spacing(pts: &[(u32, u32)]) -> (f64, f64) {
    let d = |a: u32, b: u32| {
        let t = a.abs_diff(b) as f64 / 16_777_216.0;
        t.min(1.0 - t)
    };
    let nearest: Vec<f64> = (0..pts.len())
        .map(|i| {
            let others = pts.iter().enumerate().filter(|&(j, _)| j != i);
            others.map(|(_, q)| d(pts[i].0, q.0).hypot(d(pts[i].1, q.1))).fold(f64::MAX, f64::min)
        })
        .collect();
    let scale = (pts.len() as f64).sqrt();
    let min = nearest.iter().copied().fold(f64::MAX, f64::min);
    (min * scale, nearest.iter().sum::<f64>() / pts.len() as f64 * scale)
}

#[test]
fn pmj02bn_prefixes_are_spaced_wider_than_owen_scrambled_sobol() {
    // The blue-noise selection (Christensen et al. 2018, §6): summed over the prefixes of
    // 4..=1024 points, both the minimum and the mean nearest-neighbour distance of the base
    // sequence exceed those of Owen-scrambled Sobol' (the same (0,2) stratification, no selection)
    // averaged over 16 scrambles.
    let base: Vec<(u32, u32)> = (0..1024).map(pmj02bn_fixed).collect();
    let (mut pmj, mut sobol) = ((0.0, 0.0), (0.0, 0.0));
    for m in 2..=10 {
        let s = spacing(&base[..1 << m]);
        pmj = (pmj.0 + s.0, pmj.1 + s.1);
        for seed in 0..16u32 {
            let (sx, sy) = (seed.wrapping_mul(0x9E37_79B9) ^ 0x1234, seed.wrapping_mul(0x85EB_CA6B) ^ 0x5678);
            let pts: Vec<(u32, u32)> = (0..1u32 << m)
                .map(|i| (owen_scramble(sobol_x(i), sx) >> 8, owen_scramble(sobol_y(i), sy) >> 8))
                .collect();
            let s = spacing(&pts);
            sobol = (sobol.0 + s.0 / 16.0, sobol.1 + s.1 / 16.0);
        }
    }
    eprintln!("summed min / mean nn distance: pmj02bn {pmj:.3?}, Owen-Sobol' {sobol:.3?}");
    assert!(pmj.0 > sobol.0 && pmj.1 > sobol.1, "pmj02bn {pmj:?} not wider than Owen-Sobol' {sobol:?}");
}

#[test]
fn pmj02bn_is_generated_the_same_way_every_time() {
    // The table is made in code: regenerating it gives the same points, and the process-wide
    // table is that sequence.
    let again = hemilab::sampling::pmj02::generate(256);
    assert_eq!(again[..], hemilab::sampling::pmj02::table()[..256]);
}

#[test]
fn radical_inverses_are_exact_at_large_indices() {
    // Base 3 against an independent u128 rational evaluation, floor(2^24 · Σ d_k 3^-(k+1)).
    for i in (0..2000u32).chain((u32::MAX - 2000)..=u32::MAX).chain([3u32.pow(20), 3u32.pow(20) - 1]) {
        let (mut j, mut num, mut den) = (i as u128, 0u128, 1u128);
        while j > 0 {
            num = num * 3 + j % 3;
            den *= 3;
            j /= 3;
        }
        let exact = ((num << 24) / den) as u32;
        assert_eq!(base3_to_fixed(radical_inverse_3(i)), exact, "base 3 at {i}");
        assert!(radical_inverse_3(i) < POW3);
    }
    // Base 2 (Halton x = Sobol' x) and Sobol' y against their definitions at large indices.
    for i in [u32::MAX, u32::MAX - 1, 1 << 31, (1 << 31) + 12345, 0xDEAD_BEEF] {
        let vdc: u64 = (0..32).filter(|b| i >> b & 1 == 1).map(|b| 1u64 << (31 - b)).sum();
        assert_eq!(sobol_x(i) as u64, vdc, "base 2 at {i}");
        // Sobol' dimension 1 is the Pascal matrix mod 2: bit r of the result = XOR over c >= r of C(c, r) i_c.
        let mut y = 0u32;
        for r in 0..32 {
            let bit = (r..32).filter(|&c| i >> c & 1 == 1 && (c & r) == r).count() & 1;
            y |= (bit as u32) << (31 - r);
        }
        assert_eq!(sobol_y(i), y, "Sobol' y at {i}");
    }
}

#[test]
fn zsobol_per_pixel_sets_are_sobol_nets() {
    for mode in [SeedMode::Static, SeedMode::Shift] {
        for l in 0..=9 {
            for (x, y) in [(0, 0), (1, 0), (0, 1), (7, 5), (319, 239), (65535, 65535)] {
                let pts: Vec<(u32, u32)> = points(Sequence::ZSobol, mode, 1 << l, 5, x, y)
                    .iter()
                    .map(|p| (fixed(p.x), fixed(p.y)))
                    .collect();
                assert!(is_net(&pts), "{mode} 2^{l} at ({x},{y})");
            }
        }
    }
    // Neighbouring pixels get different blocks of the one sequence.
    let a = points(Sequence::ZSobol, SeedMode::Static, 16, 5, 0, 0);
    let b = points(Sequence::ZSobol, SeedMode::Static, 16, 5, 1, 0);
    assert_ne!(a, b);
}

#[test]
fn halton_and_r2_unscrambled_structure() {
    // R2 points are frac(s + i a) for one s per set: consecutive differences are constant mod 1.
    let p = points(Sequence::R2, SeedMode::Static, 64, 1, 3, 4);
    let step = |a: f32, b: f32| (fixed(b) as i64 - fixed(a) as i64).rem_euclid(1 << 24);
    for w in p.windows(3) {
        let (d0, d1) = (step(w[0].x, w[1].x), step(w[1].x, w[2].x));
        assert!((d0 - d1).abs() <= 1 || ((d0 - d1).abs() - (1 << 24)).abs() <= 1, "{d0} {d1}");
    }
    // Owen-scrambled Halton: the first 2^a · 3^b points hold one point per 1/2^a × 1/3^b cell.
    let h = points(Sequence::Halton, SeedMode::Shift, 36, 2, 9, 9);
    let mut seen = [false; 36];
    for q in &h {
        let cell = (q.x * 4.0) as usize * 9 + (q.y * 9.0) as usize;
        assert!(!std::mem::replace(&mut seen[cell], true), "two points in cell {cell}");
    }
}

#[test]
fn new_sequences_are_deterministic_and_prefix_stable() {
    for seq in NEW {
        for &mode in SeedMode::ALL {
            let a = points(seq, mode, 100, 7, 11, 13);
            assert_eq!(a, points(seq, mode, 100, 7, 11, 13), "{seq} {mode}");
            // A shorter output buffer gets the first points of the same set.
            let cfg = SamplerConfig::new(seq, mode, 100, 7).unwrap();
            let mut short = vec![Vec2::ZERO; 10];
            cfg.fill_pixel(11, 13, 13 * 4096 + 11, &mut short);
            assert_eq!(short[..], a[..10], "{seq} {mode}");
            assert_ne!(a, points(seq, mode, 100, 8, 11, 13), "{seq} {mode}: the seed changes nothing");
        }
    }
}
