//! The denoise stage against closed forms: every filter keeps a constant; the Gaussian and the
//! à-trous filter (on a flat plane, where every edge-stopping weight is 1) reduce white noise's
//! variance by Σ K² of their kernel, within a stated number of standard errors; à-trous does not
//! leak across a depth step or a normal crease (synthetic and rendered); the running mean and the
//! warm-started EMA are their closed forms; everything (every pipeline run frame by frame too) is
//! the same for any thread count.

use crate::support::images::{cornell, image, normals, synthetic};
use glam::Vec3;
use hemilab::denoise::{
    Accumulator, AtrousParams, GAUSS_SIGMA, Motion, Pipeline, Temporal, atrous, gaussian,
};
use hemilab::image::Image;
use hemilab::load::load_scene;
use hemilab::render::{GBuffer, gbuffer};
use std::path::Path;

/// Dammertz's five passes, which the edge-stopping tests below were written for (the default is a
/// share of the image: one pass on these small images).
fn five() -> AtrousParams {
    AtrousParams::default().with_iterations(5)
}

fn with_value(sigma: f32) -> AtrousParams {
    AtrousParams { sigma_value: Some(sigma), ..five() }
}

#[test]
fn every_filter_keeps_a_constant_and_leaves_the_background() {
    let (w, h) = (48, 36);
    let g = cornell(w, h);
    let bg = (0..g.coverage.len()).filter(|&i| !g.is_covered(i)).count();
    assert!(bg > 0, "the Cornell box's open front shows background");
    for c in [0.37f32, 1.0, 0.0, 2.5e-3] {
        // Background holds another value, which must neither leak in nor change.
        let img = Image::from_vec(
            w,
            h,
            (0..w * h).map(|i| if g.is_covered(i as usize) { c } else { 9.0 }).collect(),
        );
        let filtered = [
            ("gauss", gaussian(&img, &g.coverage, GAUSS_SIGMA)),
            ("atrous", atrous(&img, &g, &AtrousParams::default())),
            ("atrous:5", atrous(&img, &g, &five())),
            ("atrous+value", atrous(&img, &g, &with_value(0.1))),
            ("pipeline atrous", "atrous".parse::<Pipeline>().unwrap().apply_spatial(&img, &g)),
            ("pipeline raw", Pipeline::RAW.apply_spatial(&img, &g)),
        ]
        .into_iter()
        .map(|(n, o)| (n.to_string(), o))
        .chain(every_pipeline_on(&img, &g));
        for (name, out) in filtered {
            for i in 0..img.len() {
                let want = img.data[i];
                let tol = 2.0 * f32::EPSILON * want.abs();
                assert!(
                    (out.data[i] - want).abs() <= tol,
                    "{name}, c = {c}, pixel {i}: {} vs {want}",
                    out.data[i]
                );
            }
        }
    }
    for mode in [Temporal::Mean, Temporal::Ema(0.1), Temporal::Ema(1.0)] {
        let mut acc = Accumulator::new(mode);
        let frame = image(5, 4, |x, y| 0.1 * (x + 7 * y) as f32 + 0.013);
        assert_eq!(acc.image(), Image::from_vec(0, 0, vec![]));
        for _ in 0..20 {
            acc.push(&frame);
        }
        assert_eq!(acc.image(), frame, "{mode:?}");
        assert_eq!(acc.frames(), 20);
    }
}

/// Every pipeline kind, run by `Pipeline::start` over 6 frames of `img` (static camera): the
/// last output.
fn every_pipeline_on(img: &Image, g: &GBuffer) -> Vec<(String, Image)> {
    let names = [
        "raw",
        "gauss",
        "atrous:5",
        "mean+atrous",
        "ema0.1+gauss",
        "taa0.1",
        "taa0.1+atrous:3",
        "svgf",
        "svgf:5",
    ];
    names
        .iter()
        .map(|name| {
            let mut f = name.parse::<Pipeline>().unwrap().start(img.width, img.height);
            let still = Motion::identity(img.width, img.height);
            let mut out = img.clone();
            for _ in 0..6 {
                out = f.push(img, g, &still);
            }
            (format!("pipeline {name}"), out)
        })
        .collect()
}

/// Σ_l (k⋆k)_l² / (Σ_l k_l²)² of a 1-D kernel: for white noise filtered by k ⊗ k, the relative
/// variance of the mean of N squared outputs is 2 · (this)² / N (Gaussian fields: Var(Y²) = 2σ⁴,
/// Cov(Y_i², Y_j²) = 2σ⁴ρ_ij²).
fn correlation_sum(k: &[f64]) -> f64 {
    let n = k.len() as isize;
    let auto = |lag: isize| -> f64 {
        (0..n).filter(|&i| i + lag >= 0 && i + lag < n).map(|i| k[i as usize] * k[(i + lag) as usize]).sum()
    };
    let zero = auto(0);
    (-(n - 1)..n).map(|l| auto(l).powi(2)).sum::<f64>() / (zero * zero)
}

/// The variance of `filter(white noise of sd 1)` over the pixels at least `margin` from every border,
/// pooled over `seeds` images; with the expected value Σ K² (K = k ⊗ k, normalized) and its sd.
fn variance_ratio(
    w: u32,
    h: u32,
    k: &[f64],
    margin: u32,
    seeds: u64,
    filter: impl Fn(&Image) -> Image,
) -> (f64, f64, f64) {
    let sum: f64 = k.iter().sum();
    let k: Vec<f64> = k.iter().map(|v| v / sum).collect();
    let expected = k.iter().map(|v| v * v).sum::<f64>().powi(2);
    let (mut acc, mut count) = (0.0, 0usize);
    for s in 0..seeds {
        let n = normals((w * h) as usize, s);
        let out = filter(&Image::from_vec(w, h, n.iter().map(|&v| v as f32).collect()));
        for y in margin..h - margin {
            for x in margin..w - margin {
                acc += (out.at(x, y) as f64).powi(2);
                count += 1;
            }
        }
    }
    let rel_sd = (2.0 * correlation_sum(&k).powi(2) / count as f64).sqrt();
    (acc / count as f64, expected, expected * rel_sd)
}

#[test]
fn gaussian_reduces_white_noise_variance_by_the_sum_of_squared_weights() {
    let (w, h) = (160, 120);
    let taps = hemilab::denoise::gaussian::taps(GAUSS_SIGMA);
    let full = image(w, h, |_, _| 1.0);
    let margin = (taps.len() / 2) as u32;
    let (got, want, sd) = variance_ratio(w, h, &taps, margin, 8, |img| gaussian(img, &full, GAUSS_SIGMA));
    eprintln!("gauss σ = {GAUSS_SIGMA}: variance × {got:.5}, Σ G² = {want:.5} ± {sd:.5}");
    // Within 4 standard errors (the estimate is a mean of many nearly Gaussian squares: ~χ²).
    assert!((got - want).abs() < 4.0 * sd, "{got} vs {want} ± {sd}");
}

#[test]
fn atrous_on_a_flat_plane_reduces_white_noise_variance_by_its_kernels_sum_of_squares() {
    // A fronto-parallel plane: equal depths and normals, so every edge-stopping weight is exactly
    // 1 and the five iterations are one linear filter, the B3 kernels dilated by 1, 2, 4, 8, 16
    // convolved.
    let (w, h) = (200, 200);
    let g = synthetic(w, h, |_, _| 3.0, |_, _| Vec3::Z);
    let b3 = [1.0, 4.0, 6.0, 4.0, 1.0];
    let mut k = vec![1.0f64];
    for i in 0..5 {
        let step = 1usize << i;
        let mut next = vec![0.0; k.len() + 4 * step];
        for (a, &ka) in k.iter().enumerate() {
            for (b, &kb) in b3.iter().enumerate() {
                next[a + b * step] += ka * kb;
            }
        }
        k = next;
    }
    let margin = (k.len() / 2) as u32;
    let (got, want, sd) = variance_ratio(w, h, &k, margin, 32, |img| atrous(img, &g, &five()));
    eprintln!("atrous on a plane: variance × {got:.6}, Σ K² = {want:.6} ± {sd:.6}");
    assert!((got - want).abs() < 4.0 * sd, "{got} vs {want} ± {sd}");
    assert!(got < 0.01, "variance down by more than 100×: {got}");
    // Over the whole image, border included, still far down.
    let n = normals((w * h) as usize, 99);
    let noisy = Image::from_vec(w, h, n.iter().map(|&v| v as f32).collect());
    let out = atrous(&noisy, &g, &five());
    let var = out.data.iter().map(|&v| (v as f64).powi(2)).sum::<f64>() / out.len() as f64;
    assert!(var < 0.02, "whole-image variance × {var}");
}

/// The largest |filtered − input| over the pixels `side` selects.
fn leak(img: &Image, out: &Image, side: impl Fn(u32, u32) -> bool) -> f32 {
    (0..img.len())
        .filter(|&i| side(i as u32 % img.width, i as u32 / img.width))
        .map(|i| (out.data[i] - img.data[i]).abs())
        .fold(0.0, f32::max)
}

#[test]
fn atrous_does_not_leak_across_a_depth_step_or_a_normal_crease() {
    let (w, h) = (64, 48);
    let left = |x: u32, _| x < 32;
    // Left 0, right 1, with noise on both sides that the filter does remove.
    let n = normals((w * h) as usize, 5);
    let img = image(w, h, |x, y| (if x < 32 { 0.0 } else { 1.0 }) + 0.05 * n[(y * w + x) as usize] as f32);
    let side_means = |out: &Image| {
        let (mut l, mut r) = (0.0f64, 0.0f64);
        for y in 0..h {
            for x in 0..w {
                if x < 32 { l += out.at(x, y) as f64 } else { r += out.at(x, y) as f64 }
            }
        }
        (l / (32 * h) as f64, r / (32 * h) as f64)
    };
    type Case = (&'static str, GBuffer, f32);
    let cases: [Case; 4] = [
        // A depth step of 1 (half the depth) on a fronto-parallel plane: w_z = e^-1000 = 0.
        ("depth step", synthetic(w, h, |x, _| if x < 32 { 1.0 } else { 2.0 }, |_, _| Vec3::Z), 1e-6),
        // A sloped surface (gradient 0.001 per pixel) stepping by 0.5: the widest taps (32 px) are
        // tolerated σ_z · 0.032 + ε z ≈ 0.034, so w_z ≤ e^-14.
        (
            "sloped step",
            synthetic(w, h, |x, _| 1.0 + 0.001 * x as f32 + if x < 32 { 0.0 } else { 0.5 }, |_, _| Vec3::Z),
            1e-5,
        ),
        // A 90° crease at equal depth: n·n' = 0, w_n = 0.
        ("90° crease", crease(w, h, 45f32.to_radians()), 1e-6),
        // A 30° crease: w_n = cos(30°)^128 ≈ 1e-8 per tap.
        ("30° crease", crease(w, h, 15f32.to_radians()), 1e-5),
    ];
    for (name, g, bound) in cases {
        let out = atrous(&img, &g, &five());
        // The clean step filtered alone shows the leak apart from the noise's removal.
        let clean = image(w, h, |x, _| if x < 32 { 0.0 } else { 1.0 });
        let clean_out = atrous(&clean, &g, &five());
        let (l, r) = (leak(&clean, &clean_out, left), leak(&clean, &clean_out, |x, y| !left(x, y)));
        eprintln!("{name}: leak left {l:.2e}, right {r:.2e}");
        assert!(l < bound && r < bound, "{name}: leak {l:e} / {r:e} (bound {bound:e})");
        let (ml, mr) = side_means(&out);
        assert!(ml.abs() < 0.01 && (mr - 1.0).abs() < 0.01, "{name}: side means {ml} {mr}");
        let residual = leak(&clean, &out, |_, _| true);
        assert!(residual < 0.05, "{name}: the noise (sd 0.05) is filtered down: max residual {residual}");
    }
}

/// Two planes folded along x = 32, normals ±θ from +z (a crease of 2θ), at equal depth.
fn crease(w: u32, h: u32, theta: f32) -> GBuffer {
    let (s, c) = theta.sin_cos();
    synthetic(w, h, |_, _| 1.0, move |x, _| if x < 32 { Vec3::new(-s, 0.0, c) } else { Vec3::new(s, 0.0, c) })
}

/// The rendered floating rectangle: a depth step of 0.8 in front of the floor. An image that is 1
/// on the rectangle and 0 on the floor keeps both after à-trous.
#[test]
fn atrous_keeps_the_rendered_rectangle_apart_from_the_floor() {
    let scene =
        load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/floating-rectangle.toml")).unwrap();
    let (w, h) = (64, 64);
    let g = gbuffer(&scene, w, h);
    let on_rect = |i: usize| g.depth.data[i] < 9.5;
    let img =
        Image::from_vec(w, h, (0..(w * h) as usize).map(|i| if on_rect(i) { 1.0 } else { 0.0 }).collect());
    let out = atrous(&img, &g, &five());
    let worst = (0..img.len()).map(|i| (out.data[i] - img.data[i]).abs()).fold(0.0, f32::max);
    assert!(worst < 1e-6, "leak across the rendered step: {worst:e}");
}

#[test]
fn running_mean_and_ema_match_their_closed_forms() {
    // The warm-started EMA: s_n = s_{n−1} + a_n (x_n − s_{n−1}), a_n = max(α, 1/n), so the weight
    // of frame j in s_n is a_j Π_{i=j+1..n} (1 − a_i) (a_1 = 1); the mean is α = 0.
    let (w, h, frames) = (7u32, 5u32, 30usize);
    let xs: Vec<Vec<f64>> = (0..frames).map(|k| normals((w * h) as usize, 1000 + k as u64)).collect();
    let frame = |k: usize| Image::from_vec(w, h, xs[k].iter().map(|&v| v as f32).collect());
    for mode in [Temporal::Mean, Temporal::Ema(0.1), Temporal::Ema(0.5)] {
        let alpha = match mode {
            Temporal::Ema(a) => a as f64,
            _ => 0.0,
        };
        let a = |n: usize| alpha.max(1.0 / n as f64);
        let mut acc = Accumulator::new(mode);
        for k in 0..frames {
            acc.push(&frame(k));
            let got = acc.image();
            let n = k + 1;
            for (i, &g) in got.data.iter().enumerate() {
                let x = |j: usize| xs[j][i] as f32 as f64;
                let want: f64 = (1..=n)
                    .map(|j| a(j) * ((j + 1)..=n).map(|m| 1.0 - a(m)).product::<f64>() * x(j - 1))
                    .sum();
                assert!((g as f64 - want).abs() < 1e-6, "{mode:?} frame {k} pixel {i}");
            }
        }
    }
}

#[test]
fn filters_are_bit_identical_for_any_thread_count() {
    let (w, h) = (48, 36);
    let g = cornell(w, h);
    let n = normals((w * h) as usize, 11);
    let img = Image::from_vec(w, h, n.iter().map(|&v| 0.5 + 0.1 * v as f32).collect());
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            (
                gaussian(&img, &g.coverage, GAUSS_SIGMA),
                atrous(&img, &g, &five()),
                atrous(&img, &g, &with_value(0.2)),
                every_pipeline_on(&img, &g),
            )
        })
    };
    let one = run(1);
    assert_eq!(one, run(3));
    assert_eq!(one, run(2));
}
