//! SVGF (Schied et al. 2017) against closed forms: its variance estimate on white noise of known
//! variance (spatial, over the 7 × 7 window, while the history is short; temporal from the
//! moments after), a constant stays constant, the first à-trous pass is the next frame's colour
//! history, background pixels are left as they are and never read.

use crate::support::images::{cornell, image, noise, plane, with_background};
use hemilab::denoise::{Motion, Svgf, SvgfParams};
use hemilab::image::Image;

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
