//! Point sets from files (`load::points`, `sampling::point_file`): an `.npy` (N × 2,
//! P × N × 2; float64 or float32; C or Fortran order) or UTK's `x y` text is read exactly; the
//! seed modes randomize it as they do R2 (one Cranley–Patterson offset per run under `static`, a
//! fresh one per pixel under `shift`, which is then unbiased per pixel); a point outside [0, 1)² is
//! an error naming its line.

use crate::support::common::Tmp;
use crate::support::stats::{chi2_test, sidak_threshold};
use glam::Vec2;
use hemilab::compare::per_pixel_unbiased;
use hemilab::load::points::points;
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use hemilab::spec::Row;
use std::path::Path;

/// An `.npy` (version 1) of `shape` holding `values` (already in the order `fortran` says).
fn npy(path: &Path, shape: &[usize], values: &[f64], f32s: bool, fortran: bool) {
    let shape_text = match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", shape.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", ")),
    };
    let descr = if f32s { "<f4" } else { "<f8" };
    let order = if fortran { "True" } else { "False" };
    let mut header = format!("{{'descr': '{descr}', 'fortran_order': {order}, 'shape': {shape_text}, }}");
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend((header.len() as u16).to_le_bytes());
    bytes.extend(header.as_bytes());
    for &v in values {
        if f32s {
            bytes.extend((v as f32).to_le_bytes());
        } else {
            bytes.extend(v.to_le_bytes());
        }
    }
    std::fs::write(path, bytes).unwrap();
}

/// The points of pixel (x, y) (index y · 64 + x).
fn pts(seq: Sequence, mode: SeedMode, n: u32, seed: u64, x: u32, y: u32) -> Vec<Vec2> {
    let mut out = vec![Vec2::ZERO; n as usize];
    SamplerConfig::new(seq, mode, n, seed).unwrap().fill_pixel(x, y, (y * 64 + x) as u64, &mut out);
    out
}

/// On the 24-bit grid.
fn fix(v: f32) -> u32 {
    (v as f64 * 16_777_216.0) as u32
}

/// The set shifted back by the first point's offset from `file`'s first point, which must then be
/// the file's points exactly (a Cranley–Patterson shift moves every point alike).
fn assert_shifted(got: &[Vec2], file: &[(f64, f64)]) {
    let f = |v: f64| (v * 16_777_216.0) as u32;
    let (dx, dy) = (fix(got[0].x).wrapping_sub(f(file[0].0)), fix(got[0].y).wrapping_sub(f(file[0].1)));
    for (g, w) in got.iter().zip(file) {
        assert_eq!(fix(g.x).wrapping_sub(dx) & 0xFF_FFFF, f(w.0), "x of {w:?}");
        assert_eq!(fix(g.y).wrapping_sub(dy) & 0xFF_FFFF, f(w.1), "y of {w:?}");
    }
}

fn set(n: usize, k: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            (((i * 7 + k) % n) as f64 / n as f64 + 0.01, ((i * 3 + 2 * k) % n) as f64 / n as f64 + 0.003)
        })
        .collect()
}

#[test]
fn npy_and_text_files_are_read_exactly_and_shifted_once_per_run() {
    let dir = Tmp::new("points");
    let one = set(16, 0);
    let flat: Vec<f64> = one.iter().flat_map(|&(x, y)| [x, y]).collect();
    npy(&dir.path("c.npy"), &[16, 2], &flat, false, false);
    let fortran: Vec<f64> = one.iter().map(|p| p.0).chain(one.iter().map(|p| p.1)).collect();
    npy(&dir.path("f.npy"), &[16, 2], &fortran, false, true);
    let text: String = one.iter().map(|(x, y)| format!("{x} {y}\n")).collect();
    std::fs::write(dir.path("u.txt"), format!("# UTK\n{text}")).unwrap();
    for file in ["c.npy", "f.npy", "u.txt"] {
        let seq = points(&dir.0, file).unwrap_or_else(|e| panic!("{e}"));
        assert!(seq.name().starts_with(&format!("points:{file}#")), "{seq}");
        assert_eq!(seq.imp().max_count(), Some(16));
        let a = pts(seq, SeedMode::Static, 16, 3, 0, 0);
        assert_shifted(&a, &one);
        assert_eq!(a, pts(seq, SeedMode::Static, 16, 3, 40, 9), "{file}: static is one set in every pixel");
        assert_ne!(a, pts(seq, SeedMode::Static, 16, 4, 0, 0), "{file}: the run seed moves the set");
        assert_eq!(
            pts(seq, SeedMode::Static, 5, 3, 0, 0)[..],
            a[..5],
            "{file}: fewer points are its first ones"
        );
        assert_shifted(&pts(seq, SeedMode::Shift, 16, 3, 7, 7), &one);
        assert_ne!(pts(seq, SeedMode::Shift, 16, 3, 7, 7), pts(seq, SeedMode::Shift, 16, 3, 8, 7));
    }
    // float32 keeps what float32 holds.
    npy(&dir.path("s.npy"), &[16, 2], &flat, true, false);
    let s = points(&dir.0, "s.npy").unwrap();
    let f32s: Vec<(f64, f64)> = one.iter().map(|&(x, y)| (x as f32 as f64, y as f32 as f64)).collect();
    assert_shifted(&pts(s, SeedMode::Static, 16, 3, 0, 0), &f32s);
}

#[test]
fn per_pixel_sets_are_read_in_raster_order() {
    let dir = Tmp::new("points-sets");
    let sets: Vec<Vec<(f64, f64)>> = (0..3).map(|k| set(8, k)).collect();
    let flat: Vec<f64> = sets.iter().flatten().flat_map(|&(x, y)| [x, y]).collect();
    npy(&dir.path("p.npy"), &[3, 8, 2], &flat, false, false);
    let text: String = sets
        .iter()
        .map(|s| s.iter().map(|(x, y)| format!("{x}\t{y}\n")).collect::<String>() + "#\n")
        .collect();
    std::fs::write(dir.path("p.txt"), text).unwrap();
    for file in ["p.npy", "p.txt"] {
        let seq = points(&dir.0, file).unwrap();
        for (x, y) in [(0u32, 0u32), (1, 0), (2, 0), (3, 0), (10, 1)] {
            let k = ((y * 64 + x) % 3) as usize;
            assert_shifted(&pts(seq, SeedMode::Static, 8, 9, x, y), &sets[k]);
        }
    }
}

#[test]
fn shift_makes_a_file_set_unbiased_per_pixel() {
    let dir = Tmp::new("points-shift");
    std::fs::write(dir.path("t.txt"), "0.1 0.1\n0.6 0.3\n0.35 0.85\n0.8 0.7\n").unwrap();
    let seq = points(&dir.0, "t.txt").unwrap();
    assert!(per_pixel_unbiased(Row::new(Distribution::SineCosine, seq, SeedMode::Shift)));
    assert!(!per_pixel_unbiased(Row::new(Distribution::SineCosine, seq, SeedMode::Static)));
    // A pixel's first point over run seeds: uniform on 8 × 8 cells.
    let alpha = sidak_threshold(0.01, 2);
    for (x, y) in [(0u32, 0u32), (33, 12)] {
        let mut counts = vec![0.0; 64];
        for seed in 0..16384 {
            let p = pts(seq, SeedMode::Shift, 4, seed, x, y)[0];
            counts[(p.y * 8.0) as usize * 8 + (p.x * 8.0) as usize] += 1.0;
        }
        let t = chi2_test(&counts, &[256.0; 64], 5.0).unwrap();
        assert!(t.p_value > alpha, "({x}, {y}): p = {}", t.p_value);
    }
}

#[test]
fn bad_point_files_are_one_error_naming_the_line() {
    let dir = Tmp::new("points-bad");
    std::fs::write(dir.path("out.txt"), "0.1 0.2\n0.3 0.4\n0.5 1.0\n").unwrap();
    std::fs::write(dir.path("three.txt"), "0.1 0.2 0.3\n").unwrap();
    std::fs::write(dir.path("uneven.txt"), "0.1 0.2\n0.3 0.4\n\n0.5 0.6\n").unwrap();
    npy(&dir.path("shape.npy"), &[8], &[0.5; 8], false, false);
    npy(&dir.path("neg.npy"), &[2, 2], &[0.5, 0.5, -0.25, 0.5], false, false);
    std::fs::write(dir.path("junk.npy"), b"\x93NUMPZ....").unwrap();
    for (file, want) in [
        ("missing.txt", "point file 'missing.txt' not found"),
        ("out.txt", "out.txt: line 3: point (0.5, 1) is outside [0, 1)²"),
        ("three.txt", "three.txt: line 1: '0.1 0.2 0.3' is not a point"),
        ("uneven.txt", "uneven.txt: line 4: set 2 has 1 points, set 1 has 2"),
        ("shape.npy", "has shape [8]; a point set is N × 2 or P × N × 2"),
        ("neg.npy", "point 1 (0-based): (-0.25, 0.5) is outside [0, 1)²"),
        ("junk.npy", "is not an .npy file"),
    ] {
        let e = points(&dir.0, file).expect_err(file);
        assert!(e.contains(want), "{file}: {e}");
        assert_eq!(e.lines().count(), 1, "{file}: {e}");
    }
}
