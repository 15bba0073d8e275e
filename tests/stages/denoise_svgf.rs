//! SVGF (Schied et al. 2017) against closed forms: its variance estimate on white noise of known
//! variance (spatial, over the 7 × 7 window, while the history is short; temporal from the
//! moments after), a constant stays constant, the first à-trous pass is the next frame's colour
//! history, background pixels are left as they are and never read.

use crate::support::images::{cornell, image, noise, plane, with_background};
use hemilab::denoise::{Motion, Pipeline, Svgf, SvgfOptions, SvgfParams, Temporal};
use hemilab::image::Image;
use hemilab::render::GBuffer;

/// The mean and standard error of `v` (independent values).
fn mean_se(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

#[test]
fn the_variance_estimate_of_white_noise_is_its_closed_form() {
    // iid N(0.5, σ²) frames on a fronto-parallel plane (every depth and normal weight 1).
    let (w, h, sigma) = (140u32, 140u32, 0.1f64);
    let g = plane(w, h);
    let still = Motion::identity(w, h);
    let mut s = Svgf::new(SvgfParams { iterations: Some(1), ..SvgfParams::default() });
    // The moments' weights: a_n = max(0.2, 1/n), the weight of frame j in μ after n frames
    // a_j Π_{i>j} (1 − a_i); E[μ₂ − μ₁²] = σ² (1 − Σ_j w_j²).
    let a = |n: usize| 0.2f64.max(1.0 / n as f64);
    let sum_sq = |n: usize| -> f64 {
        (1..=n).map(|j| (a(j) * ((j + 1)..=n).map(|m| 1.0 - a(m)).product::<f64>()).powi(2)).sum()
    };
    for n in 1..=40usize {
        s.push(&noise(w, h, 0.5, sigma as f32, 3000 + n as u64), &g, &still);
        let var = s.variance();
        let (want, samples): (f64, Vec<f64>) = if n < 4 {
            // Spatial: μ₂ − μ₁² of the moments averaged over the 7 × 7 window (uniform weights on
            // the plane); each pixel's μ₁ is the mean of its n frames (weights 1/n), so
            // E = (σ² + m²) − (m² + σ²/(49 n)) = σ² (1 − 1/(49 n)). Windows 7 px apart do not
            // overlap: independent samples.
            let pts = (3..h - 3)
                .step_by(7)
                .flat_map(|y| (3..w - 3).step_by(7).map(move |x| (y * w + x) as usize))
                .map(|i| var[i])
                .collect();
            (sigma * sigma * (1.0 - 1.0 / (49.0 * n as f64)), pts)
        } else {
            // Temporal: per pixel, independent across pixels.
            (sigma * sigma * (1.0 - sum_sq(n)), var.to_vec())
        };
        let (got, se) = mean_se(&samples);
        eprintln!("frame {n}: variance {got:.6e} against {want:.6e} ± {se:.1e}");
        assert!((got - want).abs() < 5.0 * se, "frame {n}: {got} vs {want} ± {se}");
        if n >= 4 {
            assert!(s.lengths().iter().all(|&l| l as usize == n));
        }
    }
    // Steady state: Σw² → α/(2 − α), the estimate σ² · 2(1 − α)/(2 − α) = 0.889 σ².
    assert!((1.0 - sum_sq(40) - 2.0 * 0.8 / 1.8).abs() < 1e-3);
}

#[test]
fn svgf_keeps_a_constant_and_never_reads_the_background() {
    let (w, h) = (48u32, 36u32);
    let g = cornell(w, h);
    let still = Motion::identity(w, h);
    for c in [0.37f32, 1.0, 0.0] {
        let img = with_background(&image(w, h, |_, _| c), &g, 9.0);
        let mut s = Svgf::new(SvgfParams { iterations: Some(5), ..SvgfParams::default() });
        for _ in 0..6 {
            assert_eq!(s.push(&img, &g, &still), img, "c = {c}");
        }
    }
    // Noisy frames whose background is 9 or NaN: the same output on covered pixels, bit for bit,
    // and the background as it is.
    let run = |bg: f32| {
        let mut s = Svgf::new(SvgfParams { iterations: Some(3), ..SvgfParams::default() });
        (0..5)
            .map(|k| s.push(&with_background(&noise(w, h, 0.5, 0.2, 80 + k), &g, bg), &g, &still))
            .last()
            .unwrap()
    };
    let (a, b) = (run(9.0), run(f32::NAN));
    for i in 0..a.len() {
        if g.is_covered(i) {
            assert_eq!(a.data[i].to_bits(), b.data[i].to_bits(), "pixel {i}");
        } else {
            assert!(a.data[i] == 9.0 && b.data[i].is_nan());
        }
    }
}

#[test]
fn the_first_a_trous_pass_is_the_next_frames_colour_history() {
    let (w, h) = (24u32, 18u32);
    let g = cornell(w, h);
    let still = Motion::identity(w, h);
    let params = |k| SvgfParams { iterations: Some(k), ..SvgfParams::default() };
    let (mut three, mut one) = (Svgf::new(params(3)), Svgf::new(params(1)));
    let mut prev: Option<Image> = None;
    for n in 1..=8u32 {
        let f = noise(w, h, 0.5, 0.2, 120 + n as u64);
        let out3 = three.push(&f, &g, &still);
        let out1 = one.push(&f, &g, &still);
        // The history is the first pass alone: a one-pass SVGF fed the same frames has the same
        // history and its output is it; the third pass's output is not.
        assert_eq!(three.history(), out1, "frame {n}");
        assert_eq!(one.history(), out1);
        assert_ne!(out3, out1);
        // The temporal step reads that history: c = h + α_eff (x − h), α_eff = max(0.2, 1/n).
        if let Some(hist) = &prev {
            let a = 0.2f64.max(1.0 / n as f64);
            let c = three.integrated();
            for i in (0..f.len()).filter(|&i| g.is_covered(i)) {
                let hv = hist.data[i] as f64;
                let want = hv + a * (f.data[i] as f64 - hv);
                assert!((c.data[i] as f64 - want).abs() < 1e-6, "frame {n}, pixel {i}");
            }
        }
        prev = Some(three.history());
    }
}

#[test]
fn a_disoccluded_pixel_restarts_its_svgf_history() {
    let (w, h) = (16u32, 12u32);
    let g = plane(w, h);
    let mut s = Svgf::new(SvgfParams { iterations: Some(2), ..SvgfParams::default() });
    let still = Motion::identity(w, h);
    for k in 0..5 {
        s.push(&noise(w, h, 0.5, 0.2, 300 + k), &g, &still);
    }
    // Pixel 17 has no taps in the next frame: its length is 1 and its colour the frame's own.
    let taps = (0..w * h).map(|i| if i == 17 { vec![] } else { vec![(i, 1.0)] }).collect();
    let f = noise(w, h, 0.5, 0.2, 400);
    s.push(&f, &g, &Motion::from_taps(w, h, taps));
    assert_eq!(s.lengths()[17], 1);
    assert_eq!(s.lengths()[18], 6);
    assert_eq!(s.integrated().data[17], f.data[17]);
}

/// FNV-1a over the bits of every output of `frames` frames of a default two-pass SVGF on the
/// Cornell box, through a motion that shifts half of each pixel's history one pixel over and
/// disoccludes every 13th pixel (with `fallback` neighbours offered for those, which the default
/// must not read).
fn default_run_hash(with_fallback: bool) -> u64 {
    let (w, h) = (48u32, 36u32);
    let g = cornell(w, h);
    let n = w * h;
    let taps = (0..n)
        .map(|i| match i {
            _ if i % 13 == 5 => vec![],
            0 => vec![(0, 1.0)],
            _ => vec![(i - 1, 0.6), (i, 0.4)],
        })
        .collect();
    let mut moving = Motion::from_taps(w, h, taps);
    if with_fallback {
        moving =
            moving.with_fallback((0..n).filter(|i| i % 13 == 5).map(|i| (i, vec![i, (i + 1) % n])).collect());
    }
    let mut s = Svgf::new(SvgfParams { iterations: Some(2), ..SvgfParams::default() });
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    for k in 0..7u64 {
        let m = if k == 0 { Motion::identity(w, h) } else { moving.clone() };
        let out = s.push(&with_background(&noise(w, h, 0.4, 0.2, 900 + k), &g, 0.0), &g, &m);
        for v in &out.data {
            for b in v.to_bits().to_le_bytes() {
                hash = (hash ^ b as u64).wrapping_mul(0x100_0000_01b3);
            }
        }
    }
    hash
}

/// `svgf` and `svgf:K` are what they were before the options existed, bit for bit: the hash was
/// computed by this function on main at 60bde7d (before the options), without the fallback
/// neighbours, which that code's `Motion` did not have.
#[test]
fn the_default_svgf_is_bit_for_bit_what_it_was() {
    const BEFORE: u64 = 0x2b35_1c65_0574_5803;
    assert_eq!(default_run_hash(false), BEFORE);
    assert_eq!(default_run_hash(true), BEFORE, "the default reads no fallback neighbours");
    assert_eq!("svgf:2".parse::<Pipeline>().unwrap().to_string(), "svgf:2");
}

/// Five frames of a still plane, then a frame whose motion gives pixel 17 no tap: its history
/// lengths are then 5 and the colour history is `history`.
fn five_still_frames(s: &mut Svgf, g: &GBuffer) -> Image {
    let (w, h) = (g.width, g.height);
    let still = Motion::identity(w, h);
    for k in 0..5 {
        s.push(&noise(w, h, 0.5, 0.2, 300 + k), g, &still);
    }
    s.history()
}

#[test]
fn the_fallback_keeps_the_history_of_a_disoccluded_pixel_with_valid_neighbours() {
    let (w, h) = (16u32, 12u32);
    let g = plane(w, h);
    let taps = (0..w * h).map(|i| if i == 17 { vec![] } else { vec![(i, 1.0)] }).collect();
    let motion = Motion::from_taps(w, h, taps).with_fallback(vec![(17, vec![1, 16, 18, 33])]);
    let f = noise(w, h, 0.5, 0.2, 400);
    for fallback in [false, true] {
        let mut s = Svgf::new(SvgfParams { iterations: Some(2), fallback, ..SvgfParams::default() });
        let hist = five_still_frames(&mut s, &g);
        s.push(&f, &g, &motion);
        let x = f.data[17] as f64;
        if fallback {
            // The four neighbours with equal weights; n = 5 + 1, α_eff = max(0.2, 1/6) = 0.2.
            let hv = [1usize, 16, 18, 33].iter().map(|&q| hist.data[q] as f64).sum::<f64>() / 4.0;
            assert_eq!(s.lengths()[17], 6);
            assert!((s.integrated().data[17] as f64 - (hv + 0.2 * (x - hv))).abs() < 1e-6);
        } else {
            assert_eq!(s.lengths()[17], 1, "without the option the pixel restarts");
            assert_eq!(s.integrated().data[17], f.data[17]);
        }
    }
    // The pipeline name that turns it on.
    let path = "svgf:fallback".parse::<Pipeline>().unwrap();
    assert_eq!(path.temporal, Some(Temporal::Svgf(SvgfOptions { fallback: true, ..SvgfOptions::default() })));
}

#[test]
fn the_id_test_rejects_a_tap_on_another_primitive() {
    let (w, h) = (16u32, 12u32);
    let before = GBuffer {
        primitive: (0..w * h).map(|i| if i == 31 || i == 17 { 7 } else { 0 }).collect(),
        ..plane(w, h)
    };
    let now = plane(w, h); // every pixel on primitive 0
    // Pixel 30 reads itself and pixel 31 half and half; every other pixel itself.
    let taps =
        (0..w * h).map(|i| if i == 30 { vec![(30, 0.5), (31, 0.5)] } else { vec![(i, 1.0)] }).collect();
    let motion = Motion::from_taps(w, h, taps);
    let f = noise(w, h, 0.5, 0.2, 500);
    for id_test in [false, true] {
        let mut s = Svgf::new(SvgfParams { iterations: Some(2), id_test, ..SvgfParams::default() });
        let hist = five_still_frames(&mut s, &before);
        s.push(&f, &now, &motion);
        let c = s.integrated();
        let (x30, x17) = (f.data[30] as f64, f.data[17] as f64);
        let h30 =
            if id_test { hist.data[30] as f64 } else { 0.5 * (hist.data[30] as f64 + hist.data[31] as f64) };
        assert!((c.data[30] as f64 - (h30 + 0.2 * (x30 - h30))).abs() < 1e-6, "id test {id_test}");
        if id_test {
            // Pixel 17's only tap was on primitive 7: rejected, the pixel restarts.
            assert_eq!(s.lengths()[17], 1);
            assert_eq!(c.data[17], f.data[17]);
        } else {
            let h17 = hist.data[17] as f64;
            assert_eq!(s.lengths()[17], 6);
            assert!((c.data[17] as f64 - (h17 + 0.2 * (x17 - h17))).abs() < 1e-6);
        }
    }
}

/// A noise-free input pushed until its temporal variance is exactly 0: the fixed ε passes it
/// through; the relative one filters it by the closed form of one à-trous pass with
/// w_l = exp(−|c_p − c_q| / (σ_l √(1e-4 · l̄²) + 1e-10)), l̄ the mean level.
#[test]
fn the_relative_epsilon_filters_a_noise_free_input_by_its_closed_form() {
    let (w, h) = (20u32, 20u32);
    let g = plane(w, h);
    let still = Motion::identity(w, h);
    let img = image(w, h, |x, y| 0.3 + 0.02 * ((x * x + 3 * y) % 7) as f32);
    for relative_eps in [false, true] {
        let mut s = Svgf::new(SvgfParams { iterations: Some(1), relative_eps, ..SvgfParams::default() });
        let mut out = img.clone();
        for _ in 0..8 {
            out = s.push(&img, &g, &still);
        }
        assert!(s.variance().iter().all(|&v| v == 0.0), "a converged input has no variance");
        let c: Vec<f64> = s.integrated().data.iter().map(|&v| v as f64).collect();
        if !relative_eps {
            let most = (0..c.len()).map(|i| (out.data[i] as f64 - c[i]).abs()).fold(0.0, f64::max);
            assert!(most < 1e-6, "the fixed epsilon returns its input: {most}");
            continue;
        }
        let level = c.iter().sum::<f64>() / c.len() as f64;
        let scale = 4.0 * (1e-4 * level * level).sqrt() + 1e-10;
        let b3 = [1.0 / 16.0, 4.0 / 16.0, 6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0];
        let mut changed = 0;
        for y in 2..h as i64 - 2 {
            for x in 2..w as i64 - 2 {
                let p = (y * w as i64 + x) as usize;
                let (mut s, mut ws) = (0.0, 0.0);
                for dy in -2..=2i64 {
                    for dx in -2..=2i64 {
                        let q = ((y + dy) * w as i64 + x + dx) as usize;
                        let wt = b3[(dx + 2) as usize]
                            * b3[(dy + 2) as usize]
                            * (-(c[p] - c[q]).abs() / scale).exp();
                        s += wt * c[q];
                        ws += wt;
                    }
                }
                let want = s / ws;
                assert!((out.data[p] as f64 - want).abs() < 1e-5, "pixel {p}: {} vs {want}", out.data[p]);
                changed += usize::from((out.data[p] as f64 - c[p]).abs() > 1e-3);
            }
        }
        assert!(changed > 100, "the relative epsilon filters: {changed} pixels changed");
    }
}

#[test]
fn a_run_started_at_its_memory_shows_the_steady_state_frame_as_a_long_run_does() {
    // What advise's steady-state measurement rests on (`Measurement::at_steady_state`): SVGF's
    // frame 64 from a run of its last `memory_frames` frames has the error of a 64-frame run's.
    let (w, h) = (96u32, 96u32);
    let g = cornell(w, h);
    let still = Motion::identity(w, h);
    let frames: Vec<Image> = (0..64).map(|f| noise(w, h, 0.5, 0.2, 7000 + f)).collect();
    let memory = Temporal::Svgf(SvgfOptions::default()).memory_frames().unwrap() as usize;
    assert_eq!(memory, 21);
    let run = |from: usize| {
        let mut s = Svgf::new(SvgfParams::default());
        let mut last = None;
        for f in &frames[from..] {
            last = Some(s.push(f, &g, &still));
        }
        last.unwrap()
    };
    let (long, steady) = (run(0), run(64 - memory));
    let covered: Vec<usize> = (0..(w * h) as usize).filter(|&i| g.is_covered(i)).collect();
    let rms = |f: &dyn Fn(usize) -> f64| {
        (covered.iter().map(|&i| f(i).powi(2)).sum::<f64>() / covered.len() as f64).sqrt()
    };
    let error = |im: &Image| rms(&|i| im.data[i] as f64 - 0.5);
    let (e_long, e_steady) = (error(&long), error(&steady));
    let apart = rms(&|i| (long.data[i] - steady.data[i]) as f64);
    eprintln!("RMSE 64 frames {e_long:.5}, last {memory} {e_steady:.5}, apart {apart:.5}");
    assert!((e_steady / e_long - 1.0).abs() < 0.02, "{e_steady} vs {e_long}");
    assert!(apart < 0.2 * e_long, "the two images differ by {apart} against an error of {e_long}");
    // A run of 3 frames is not at steady state: its error is well above (the test can tell).
    let short = error(&run(61));
    eprintln!("RMSE of the last 3 frames {short:.5}");
    assert!(short > 1.1 * e_long, "{short} vs {e_long}");
}
