//! Proof of the sequences and seed modes: structure (strata, elementary intervals), exactness of
//! the fixed-point Fibonacci lattice, the [0,1) range, and what each seed mode changes.

use glam::Vec2;
use hemilab::sampling::fibonacci::{fibonacci_point, fibonacci_x_fixed};
use hemilab::sampling::seed::PixelSeed;
use hemilab::sampling::stratified::grid;
use hemilab::sampling::{SamplerConfig, SamplingError, SeedMode, Sequence};
use std::collections::HashSet;

fn points(seq: Sequence, mode: SeedMode, n: u32, seed: u64, pixel: u64) -> Vec<Vec2> {
    let cfg = SamplerConfig::new(seq, mode, n, seed).unwrap();
    let mut out = vec![Vec2::splat(-1.0); n as usize];
    let (x, y) = xy(pixel);
    cfg.fill_pixel(x, y, pixel, &mut out);
    out
}

/// Pixel coordinates for a pixel index: low and high 32 bits, so huge indices give huge coordinates.
fn xy(pixel: u64) -> (u32, u32) {
    (pixel as u32, (pixel >> 32) as u32)
}

fn in_unit_square(p: Vec2) -> bool {
    (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y)
}

/// Which of `strata` equal strata of [0,1) holds `x` (exact: f64 holds the f32 times n exactly).
fn stratum(x: f32, strata: u32) -> u64 {
    (x as f64 * strata as f64).floor() as u64
}

#[test]
fn zero_count_is_an_error_not_a_panic() {
    for seq in Sequence::all() {
        for &mode in SeedMode::ALL {
            assert_eq!(SamplerConfig::new(seq, mode, 0, 1), Err(SamplingError::ZeroCount));
        }
    }
    assert!(SamplingError::ZeroCount.to_string().contains("count = 0"));
}

#[test]
fn every_point_in_unit_square_for_every_sequence_mode_count_and_pixel() {
    for seq in Sequence::all() {
        for &mode in SeedMode::ALL {
            for n in [1, 2, 3, 5, 7, 8, 9, 16, 17, 32, 100, 1024] {
                for seed in [0, 1, u64::MAX] {
                    for pixel in (0..40).chain([u64::MAX - 1, u64::MAX, 1 << 40]) {
                        for p in points(seq, mode, n, seed, pixel) {
                            assert!(in_unit_square(p), "{seq} {mode} n={n} seed={seed} pixel={pixel}: {p}");
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn fill_pixel_depends_only_on_config_and_pixel() {
    for seq in Sequence::all() {
        for &mode in SeedMode::ALL {
            let forward: Vec<_> = (0..64).map(|p| points(seq, mode, 16, 9, p)).collect();
            let backward: Vec<_> = (0..64).rev().map(|p| points(seq, mode, 16, 9, p)).collect();
            assert!(forward.iter().eq(backward.iter().rev()), "{seq} {mode}");
        }
    }
}

#[test]
fn fill_pixel_with_other_buffer_lengths_writes_a_prefix_of_the_set() {
    for seq in Sequence::all() {
        let cfg = SamplerConfig::new(seq, SeedMode::Shift, 16, 3).unwrap();
        let full = points(seq, SeedMode::Shift, 16, 3, 5);
        let mut short = vec![Vec2::ZERO; 5];
        cfg.fill_pixel(5, 0, 5, &mut short);
        assert_eq!(short[..], full[..5], "{seq}");
        let mut long = vec![Vec2::splat(7.0); 20];
        cfg.fill_pixel(5, 0, 5, &mut long);
        assert_eq!(long[..16], full[..], "{seq}");
        assert!(long[16..].iter().all(|&p| p == Vec2::splat(7.0)), "{seq} wrote past count");
    }
}

#[test]
fn static_mode_gives_the_same_set_in_every_pixel_keyed_by_run_seed() {
    // ZSobol's static mode reads a different Morton block per pixel by design (sampling_samplers.rs).
    for seq in Sequence::all().into_iter().filter(|&s| s != Sequence::ZSobol) {
        let first = points(seq, SeedMode::Static, 16, 42, 0);
        for pixel in [1, 2, 1000, u64::MAX] {
            assert_eq!(points(seq, SeedMode::Static, 16, 42, pixel), first, "{seq}");
        }
        assert_ne!(points(seq, SeedMode::Static, 16, 43, 0), first, "{seq}: run seed ignored");
    }
}

#[test]
fn shift_and_rotation_differ_from_pixel_to_pixel() {
    for seq in Sequence::all() {
        for mode in [SeedMode::Rotation, SeedMode::Shift] {
            let sets: HashSet<Vec<[u32; 2]>> = (0..256)
                .map(|p| points(seq, mode, 8, 1, p).iter().map(|q| [q.x.to_bits(), q.y.to_bits()]).collect())
                .collect();
            assert_eq!(sets.len(), 256, "{seq} {mode}");
        }
    }
}

#[test]
fn random_rotation_and_shift_are_bit_identical() {
    for pixel in 0..1000 {
        let r = points(Sequence::Random, SeedMode::Rotation, 13, 5, pixel);
        let s = points(Sequence::Random, SeedMode::Shift, 13, 5, pixel);
        assert!(
            r.iter().zip(&s).all(|(a, b)| a.x.to_bits() == b.x.to_bits() && a.y.to_bits() == b.y.to_bits())
        );
    }
}

#[test]
fn rotation_is_the_static_set_with_one_x_offset_per_pixel_for_lattices() {
    let fix = |x: f32| (x as f64 * 16_777_216.0) as i64;
    for seq in [
        Sequence::Fibonacci,
        Sequence::Stratified,
        Sequence::Sobol,
        Sequence::Halton,
        Sequence::Pmj02bn,
        Sequence::R2,
    ] {
        for n in [1, 7, 16, 32] {
            let st = points(seq, SeedMode::Static, n, 11, 0);
            for pixel in 0..50 {
                let rot = points(seq, SeedMode::Rotation, n, 11, pixel);
                let offset = (fix(rot[0].x) - fix(st[0].x)).rem_euclid(1 << 24);
                // Fibonacci adds the offset to the indices: constant in 64-bit fixed point, so
                // after truncation to the f32's 24 bits it may vary by one step.
                let slack = if seq == Sequence::Fibonacci { 1 } else { 0 };
                for (r, s) in rot.iter().zip(&st) {
                    assert_eq!(r.y, s.y, "{seq}: rotation moved y");
                    let d = (fix(r.x) - fix(s.x) - offset).rem_euclid(1 << 24);
                    assert!(d <= slack || (1 << 24) - d <= slack, "{seq}: x offset varies by {d}");
                }
            }
        }
    }
}

#[test]
fn fibonacci_one_point_per_y_stratum() {
    for n in [1, 2, 3, 7, 16, 32, 100, 1000, 1 << 20] {
        for mode in [SeedMode::Static, SeedMode::Rotation] {
            for pixel in [0, 99] {
                let pts = points(Sequence::Fibonacci, mode, n, 3, pixel);
                for (i, p) in pts.iter().enumerate() {
                    assert_eq!(stratum(p.y, n), i as u64, "n={n} {mode}: point {i} y={}", p.y);
                }
            }
        }
    }
    // Under shift the y strata are a cyclic shift: still one point per stratum.
    for n in [2, 7, 16, 32] {
        let pts = points(Sequence::Fibonacci, SeedMode::Shift, n, 3, 8);
        let strata: HashSet<u64> = pts.iter().map(|p| stratum(p.y, n)).collect();
        assert_eq!(strata.len(), n as usize);
    }
}

#[test]
fn fibonacci_is_the_papers_lattice_at_offset_zero() {
    let phi_g = (1.0 + 5f64.sqrt()) / 2.0;
    for n in [1u32, 2, 5, 500, 5000] {
        for i in 0..n {
            let p = fibonacci_point(i, n, 0);
            let x = ((i as f64 + 1.0) / phi_g).fract();
            assert!((p.x as f64 - x).abs() < 2f64.powi(-23), "n={n} i={i}: {} vs {x}", p.x);
            assert!((p.y as f64 - (i as f64 + 0.5) / n as f64).abs() < 2f64.powi(-23));
        }
    }
}

/// frac(index / phi_g) * 2^64 from a 128-bit constant (error index * 2^-128, i.e. none here).
/// floor(2^24 * frac(i / phi_g)) for large indices, computed independently with exact integer
/// arithmetic (Python: v = isqrt(5 K^2) - K with K = i * 2^200; (v >> 177) mod 2^24).
const EXACT_X24: &[(u64, u32)] = &[
    (0x10000000000, 0x4a7c15),
    (0x10000000001, 0xe8b38f),
    (0x10000000002, 0x86eb09),
    (0x10000000003, 0x252283),
    (0x10000000007, 0x9e006a),
    (0x10000000064, 0x1827a2),
    (0x100000003e8, 0x532f92),
    (0x1000000ffff, 0x25fe1b),
    (0x100000f422f, 0xc5ebb7),
    (0x100075bcd15, 0x08ede5),
    (0x100075bcd16, 0xa7255f),
    (0x100075bcd17, 0x455cd9),
    (0x100075bcd18, 0xe39453),
    (0x100075bcd1c, 0x5c723a),
    (0x100075bcd79, 0xd69972),
    (0x100075bd0fd, 0x11a162),
    (0x100075ccd14, 0xe46feb),
    (0x100076b0f44, 0x845d87),
    (0x20000000000, 0x94f82b),
    (0x20000000001, 0x332fa5),
    (0x20000000002, 0xd1671f),
    (0x20000000003, 0x6f9e99),
    (0x20000000007, 0xe87c7f),
    (0x20000000064, 0x62a3b8),
    (0x200000003e8, 0x9daba8),
    (0x2000000ffff, 0x707a31),
    (0x200000f422f, 0x1067cd),
    (0x100000000000, 0xa7c15f),
    (0x100000000001, 0x45f8d8),
    (0x100000000002, 0xe43052),
    (0x100000000003, 0x8267cc),
    (0x100000000007, 0xfb45b3),
    (0x100000000064, 0x756ceb),
    (0x1000000003e8, 0xb074db),
    (0x10000000ffff, 0x834364),
    (0x1000000f422f, 0x233100),
    (0x10000000000000, 0xc15f39),
    (0x10000000000001, 0x5f96b3),
    (0x10000000000002, 0xfdce2d),
    (0x10000000000003, 0x9c05a6),
    (0x10000000000007, 0x14e38d),
    (0x10000000000064, 0x8f0ac6),
    (0x100000000003e8, 0xca12b6),
    (0x1000000000ffff, 0x9ce13f),
    (0x100000000f422f, 0x3ccedb),
    (0x4000000000000005, 0x93fc90),
    (0x4000000000000006, 0x32340a),
    (0x4000000000000007, 0xd06b84),
    (0x4000000000000008, 0x6ea2fd),
    (0x400000000000000c, 0xe780e4),
    (0x4000000000000069, 0x61a81d),
    (0x40000000000003ed, 0x9cb00d),
    (0x4000000000010004, 0x6f7e96),
    (0x40000000000f4234, 0x0f6c31),
];

#[test]
fn fibonacci_exact_at_index_2_pow_40() {
    for &(index, want) in EXACT_X24 {
        assert_eq!(fibonacci_x_fixed(index), want, "index {index:#x}");
        let (i, offset) = (3u32, index - 4);
        assert_eq!(fibonacci_point(i, 16, offset).x, want as f32 / (1u32 << 24) as f32, "index {index:#x}");
    }
    // What the fixed point saves us from: an f32 quotient has no fractional bits left.
    let naive = ((1u64 << 40) as f32 / 1.618_034f32).fract();
    assert_eq!(naive, 0.0);
    assert_ne!(fibonacci_x_fixed(1 << 40), 0);
}

#[test]
fn fibonacci_points_in_unit_square_without_duplicates_for_n_1_2_and_2_pow_20() {
    for n in [1u32, 2, 1 << 20] {
        for offset in [0u64, 1, 1 << 40, (1 << 40) + 987_654_321, u64::MAX - 3] {
            let mut seen = HashSet::with_capacity(n as usize);
            for i in 0..n {
                let p = fibonacci_point(i, n, offset);
                assert!(in_unit_square(p), "n={n} offset={offset} i={i}: {p}");
                assert!(seen.insert((p.x.to_bits(), p.y.to_bits())), "n={n} offset={offset}: duplicate {p}");
            }
        }
    }
}

#[test]
fn stratified_one_point_per_stratum() {
    for n in (1..=64).chain([100, 1000, 1021]) {
        let (rows, cols) = grid(n);
        for mode in SeedMode::ALL {
            for pixel in [0, 17] {
                let mut pts = points(Sequence::Stratified, *mode, n, 4, pixel);
                if mode.carries_offsets() {
                    // The static grid shifted by the pixel's mask (or pattern) offsets: shift it back.
                    let (x, y) = xy(pixel);
                    let (ox, oy) = PixelSeed::new(4, pixel).offsets(*mode, x, y);
                    let back =
                        |v: f32, o: u32| ((v as f64 * 16_777_216.0) as u32).wrapping_sub(o) % (1 << 24);
                    let unit = |k: u32| k as f32 / 16_777_216.0;
                    pts.iter_mut().for_each(|p| *p = Vec2::new(unit(back(p.x, ox)), unit(back(p.y, oy))));
                }
                let mut cells = HashSet::new();
                for p in &pts {
                    // Rotation shifts x by one offset mod 1: only the y strata are kept.
                    let c = if *mode == SeedMode::Rotation { 0 } else { stratum(p.x, cols) };
                    cells.insert((stratum(p.y, rows), c));
                }
                let want = if *mode == SeedMode::Rotation { rows } else { n };
                assert_eq!(cells.len(), want as usize, "n={n} ({rows}x{cols}) {mode}");
            }
        }
    }
}

#[test]
fn sobol_is_0_2_sequence_for_powers_of_two() {
    for m in 0..=12u32 {
        let n = 1u32 << m;
        for mode in [SeedMode::Static, SeedMode::Shift] {
            for pixel in [0, 1, 77, 1 << 33] {
                let pts = points(Sequence::Sobol, mode, n, 2, pixel);
                // Every elementary interval of area 2^-m (2^a x 2^(m-a) boxes) holds exactly one point.
                for a in 0..=m {
                    let cells: HashSet<(u64, u64)> =
                        pts.iter().map(|p| (stratum(p.x, 1 << a), stratum(p.y, 1 << (m - a)))).collect();
                    assert_eq!(cells.len(), n as usize, "m={m} a={a} {mode} pixel={pixel}");
                }
            }
        }
    }
}
