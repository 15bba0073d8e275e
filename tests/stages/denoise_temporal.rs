//! The temporal filters against closed forms: the warm-started EMA's weights are exactly 1/n while
//! 1/n ≥ α (it is the running mean, bit for bit) and α after; through a `Motion` a history follows
//! its pixels and restarts where there are no taps; TAA's variance clipping keeps a shifted step's
//! history within the current neighbourhood's mean ± γσ (closed-form values at the edge) and is a
//! no-op where the history agrees with a constant image.

use crate::support::images::{image, noise, plane};
use hemilab::denoise::taa::{clip, neighbourhood};
use hemilab::denoise::{Accumulator, Motion, Taa, Temporal};
use hemilab::image::Image;

/// The exact mean of frames[..n] at pixel i, summed in f64 (f32 inputs are exact in f64).
fn exact_mean(frames: &[Image], n: usize, i: usize) -> f64 {
    frames[..n].iter().map(|f| f.data[i] as f64).sum::<f64>() / n as f64
}

#[test]
fn the_warm_start_weighs_frames_one_over_n_until_that_falls_to_alpha() {
    let (w, h) = (9u32, 7u32);
    let frames: Vec<Image> = (0..40).map(|k| noise(w, h, 0.5, 0.3, 500 + k)).collect();
    // α = 1/8 and 1/4 are exact in binary: 1/n ≥ α exactly for n ≤ 8 (4). For 0.1 (an f32, a hair
    // above 1/10) the switch comes after n = 9.
    for (alpha, last_mean) in [(0.125f32, 8usize), (0.25, 4), (0.1, 9)] {
        let mut ema = Accumulator::new(Temporal::Ema(alpha));
        let mut mean = Accumulator::new(Temporal::Mean);
        for (k, f) in frames.iter().enumerate() {
            let n = k + 1;
            let before = ema.state().to_vec();
            ema.push(f);
            mean.push(f);
            assert!(ema.lengths().iter().all(|&l| l as usize == n));
            if n <= last_mean {
                // The weights are exactly 1/n: the very running mean, bit for bit ...
                assert_eq!(ema.state(), mean.state(), "α {alpha}, frame {n}");
                // ... which is the mean of the frames up to its own rounding.
                for i in 0..f.len() {
                    let (got, want) = (ema.state()[i], exact_mean(&frames, n, i));
                    assert!(
                        (got - want).abs() <= 4.0 * f64::EPSILON * want.abs().max(1.0),
                        "α {alpha}, n {n}"
                    );
                }
            } else {
                // Then α: s_n = s_{n−1} + α (x_n − s_{n−1}), bit for bit.
                let a = alpha as f64;
                for (i, &b) in before.iter().enumerate() {
                    let want = b + a * (f.data[i] as f64 - b);
                    assert_eq!(ema.state()[i], want, "α {alpha}, frame {n}, pixel {i}");
                }
                assert_ne!(ema.state(), mean.state());
            }
        }
    }
}

#[test]
fn a_history_follows_its_pixels_through_the_motion_and_restarts_without_taps() {
    // A camera panning one pixel a frame: pixel x was pixel x − 1; pixel 0 is new each frame.
    let (w, h) = (6u32, 1u32);
    let pan =
        Motion::from_taps(w, h, (0..w).map(|x| if x == 0 { vec![] } else { vec![(x - 1, 1.0)] }).collect());
    let frames: Vec<Image> = (0..4).map(|k| noise(w, h, 0.5, 0.3, 40 + k)).collect();
    let all = image(w, h, |_, _| 1.0);
    let mut acc = Accumulator::new(Temporal::Mean);
    acc.push_through(&frames[0], &all, &Motion::identity(w, h));
    for t in 1..frames.len() {
        acc.push_through(&frames[t], &all, &pan);
        for x in 0..w as usize {
            // The mean along the pixel's trajectory: frames t, t−1, … at x, x−1, … while x − j ≥ 0.
            let n = (x.min(t)) + 1;
            let want = (0..n).map(|j| frames[t - j].data[x - j] as f64).sum::<f64>() / n as f64;
            assert!((acc.state()[x] - want).abs() < 1e-12, "frame {t}, pixel {x}");
            assert_eq!(acc.lengths()[x] as usize, n, "frame {t}, pixel {x}");
        }
    }
    // A pixel that becomes background has no history; when covered again it restarts.
    let half = image(w, h, |x, _| if x == 3 { 0.0 } else { 1.0 });
    acc.push_through(&frames[0], &half, &Motion::identity(w, h));
    assert_eq!(acc.lengths()[3], 0);
    assert_eq!(acc.state()[3], frames[0].data[3] as f64, "background keeps the frame's value");
    acc.push_through(&frames[1], &all, &Motion::identity(w, h));
    assert_eq!(acc.lengths()[3], 1);
    assert_eq!(acc.state()[3], frames[1].data[3] as f64);
}

/// 0 left of column `edge`, 1 from it on.
fn step(w: u32, h: u32, edge: u32) -> Image {
    image(w, h, |x, _| if x < edge { 0.0 } else { 1.0 })
}

#[test]
fn taa_clips_a_shifted_steps_history_to_the_neighbourhood_bounds() {
    let (w, h) = (16u32, 4u32);
    let all = image(w, h, |_, _| 1.0);
    let frame = step(w, h, 8);
    let history = step(w, h, 10);
    let hood = neighbourhood(&frame, &all);
    for (i, &(mean, sd)) in hood.iter().enumerate() {
        let hv = history.data[i] as f64;
        let (c, s) = clip(hv, mean, sd, 1.0);
        assert!(c >= mean - sd - 1e-12 && c <= mean + sd + 1e-12, "pixel {i}: {c} outside {mean} ± {sd}");
        assert!((0.0..=1.0).contains(&s));
        if (hv - mean).abs() <= sd {
            assert_eq!((c, s), (hv, 1.0), "pixel {i}: a history within bounds is untouched");
        }
    }
    // Through a run (α 0.1; frame 2 has n = 2, α_eff = 1/2): at column 8 the neighbourhood is
    // columns 7, 8, 9 = 0, 1, 1: μ = 2/3, σ = √2/3; the history 0 is clipped to μ − σ. At column 9
    // (all 1: σ = 0) it is clipped to 1, where the plain EMA would show 1/2.
    let mut taa = Taa::new(0.1, 1.0);
    let still = Motion::identity(w, h);
    taa.push(&history, &all, &still);
    let out = taa.push(&frame, &all, &still);
    let lo = 2.0 / 3.0 - 2f64.sqrt() / 3.0;
    for y in 0..h {
        assert!((out.at(8, y) as f64 - (lo + 0.5 * (1.0 - lo))).abs() < 1e-6, "row {y}: {}", out.at(8, y));
        assert_eq!(out.at(9, y), 1.0);
        assert_eq!(out.at(3, y), 0.0);
        assert_eq!(out.at(12, y), 1.0);
    }
}

#[test]
fn taa_clipping_is_a_no_op_where_the_history_agrees() {
    let (w, h) = (12u32, 9u32);
    let g = plane(w, h);
    let still = Motion::identity(w, h);
    // A constant image: the history equals the neighbourhood mean, σ = 0, nothing is clipped.
    let c = image(w, h, |_, _| 0.37);
    let mut taa = Taa::new(0.1, 1.0);
    for _ in 0..5 {
        assert_eq!(taa.push(&c, &g.coverage, &still), c);
    }
    assert_eq!(clip(0.37, 0.37, 0.0, 1.0), (0.37, 1.0));
    // With γ so large that nothing is ever clipped, TAA is the warm-started EMA bit for bit (of
    // the same α: the pipeline names hold α as an f32).
    let mut wide = Taa::new(0.1f32 as f64, 1e30);
    let mut ema = Accumulator::new(Temporal::Ema(0.1));
    for k in 0..20 {
        let f = noise(w, h, 0.5, 0.2, 900 + k);
        let out = wide.push(&f, &g.coverage, &still);
        ema.push(&f);
        assert_eq!(out, ema.image(), "frame {k}");
    }
}
