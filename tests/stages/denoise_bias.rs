//! The bias/noise split from replicates (`metrics::replicates`) against its closed forms: a linear
//! filter's replicate bias is RMSE(F(ref), ref); a filter that adds a constant c has bias c; on
//! white noise of known variance the noise estimate is unbiased; bias² + noise² is the mean MSE;
//! and the jackknife standard error of bias² on a case worked by hand. Noise is seeded, so every
//! tolerance below is a fixed number of the estimate's own standard errors, never a flake.

use crate::support::images::{cornell, noise, with_background};
use hemilab::denoise::{Motion, Pipeline};
use hemilab::image::Image;
use hemilab::metrics::{self, split};

fn ones(w: u32, h: u32) -> Image {
    Image::from_vec(w, h, vec![1.0; (w * h) as usize])
}

fn add(a: &Image, b: &Image, scale: f32) -> Image {
    Image::from_vec(a.width, a.height, a.data.iter().zip(&b.data).map(|(x, y)| x + scale * y).collect())
}

#[test]
fn the_jackknife_of_three_replicates_is_the_worked_example() {
    // One pixel, reference 0, replicates 1, 2, 4: bias² is the mean of the pairwise products of the
    // errors, (2 + 4 + 8) / 3 = 14/3; leaving one out gives the product of the other two (8, 4, 2),
    // so se² = (2/3) · Σ (θ − 14/3)² = (2/3) · 168/9.
    let px = |v: f32| Image::from_vec(1, 1, vec![v]);
    let (a, b, c) = (px(1.0), px(2.0), px(4.0));
    let s = split(&[&a, &b, &c], &px(0.0), &px(1.0)).unwrap();
    assert!((s.bias2 - 14.0 / 3.0).abs() < 1e-12, "{s:?}");
    assert!((s.noise2 - 7.0 / 3.0).abs() < 1e-12, "{s:?}");
    assert!((s.bias2_se - (2.0 / 3.0 * 168.0 / 9.0f64).sqrt()).abs() < 1e-12, "{s:?}");
    // bias² + noise² is the mean MSE: (1 + 4 + 16) / 3 = 7.
    assert!((s.bias2 + s.noise2 - 7.0).abs() < 1e-12);
}

#[test]
fn a_filter_that_adds_a_constant_has_that_bias() {
    let (w, h) = (64u32, 48u32);
    let reference = noise(w, h, 0.5, 0.1, 1);
    let c = 0.03f32;
    // Noise-free input: exactly c.
    let shifted: Vec<Image> = (0..4).map(|_| add(&reference, &ones(w, h), c)).collect();
    let refs: Vec<&Image> = shifted.iter().collect();
    let s = split(&refs, &reference, &ones(w, h)).unwrap();
    assert!((s.bias_rmse() - c as f64).abs() < 1e-6 && s.noise2 == 0.0, "{s:?}");
    // Noisy input (σ = 0.2, 8 replicates): c within four jackknife standard errors.
    let noisy: Vec<Image> =
        (0..8).map(|r| add(&add(&reference, &ones(w, h), c), &noise(w, h, 0.0, 0.2, 100 + r), 1.0)).collect();
    let refs: Vec<&Image> = noisy.iter().collect();
    let s = split(&refs, &reference, &ones(w, h)).unwrap();
    let want = (c as f64).powi(2);
    assert!(
        (s.bias2 - want).abs() < 4.0 * s.bias2_se,
        "bias² {} ± {} against c² {want}",
        s.bias2,
        s.bias2_se
    );
}

#[test]
fn on_white_noise_of_known_variance_the_noise_estimate_is_unbiased() {
    // σ = 0.2 around the reference, 8 replicates, 64 × 48 pixels: mean s² has sd σ² √(2/7/P).
    let (w, h, sd) = (64u32, 48u32, 0.2f64);
    let reference = noise(w, h, 0.5, 0.1, 2);
    let imgs: Vec<Image> =
        (0..8).map(|r| add(&reference, &noise(w, h, 0.0, sd as f32, 200 + r), 1.0)).collect();
    let refs: Vec<&Image> = imgs.iter().collect();
    let s = split(&refs, &reference, &ones(w, h)).unwrap();
    let tol = 4.0 * sd * sd * (2.0 / 7.0 / (w * h) as f64).sqrt();
    assert!((s.noise2 - sd * sd).abs() < tol, "noise² {} against σ² {}", s.noise2, sd * sd);
    // No bias: bias² within four of its standard errors of 0.
    assert!(s.bias2.abs() < 4.0 * s.bias2_se, "{s:?}");
    // The parts add up to the mean MSE over the replicates.
    let mse: f64 = imgs
        .iter()
        .map(|im| metrics::measure(im, &reference, &ones(w, h)).unwrap().rmse.powi(2))
        .sum::<f64>()
        / 8.0;
    assert!((s.bias2 + s.noise2 - mse).abs() < 1e-9 * mse, "{} + {} against {mse}", s.bias2, s.noise2);
}

#[test]
fn a_linear_filters_replicate_bias_is_the_filter_on_the_reference() {
    // The Gaussian and the EMA + à-trous without a value weight are linear: E[F(x)] = F(ref), so
    // the bias measured from replicates estimates RMSE(F(ref), ref). 16 replicates of 4 frames
    // (σ 0.2) on the Cornell box's G-buffer; within four jackknife standard errors of bias².
    let (w, h) = (48u32, 36u32);
    let g = cornell(w, h);
    let still = Motion::identity(w, h);
    let reference = with_background(&noise(w, h, 0.6, 0.15, 3), &g, 0.0);
    for name in ["gauss", "mean+gauss"] {
        let p: Pipeline = name.parse().unwrap();
        let floor_image = {
            let mut run = p.start(w, h);
            (0..4).map(|_| run.push(&reference, &g, &still)).last().unwrap()
        };
        let floor = metrics::measure(&floor_image, &reference, &g.coverage).unwrap().rmse;
        let outs: Vec<Image> = (0..16u64)
            .map(|r| {
                let mut run = p.start(w, h);
                (0..4u64)
                    .map(|f| {
                        let x = with_background(
                            &add(&reference, &noise(w, h, 0.0, 0.2, 1000 + 10 * r + f), 1.0),
                            &g,
                            0.0,
                        );
                        run.push(&x, &g, &still)
                    })
                    .last()
                    .unwrap()
            })
            .collect();
        let refs: Vec<&Image> = outs.iter().collect();
        let s = split(&refs, &reference, &g.coverage).unwrap();
        assert!(
            (s.bias2 - floor * floor).abs() < 4.0 * s.bias2_se,
            "{name}: bias² {} ± {} against RMSE(F(ref), ref)² {}",
            s.bias2,
            s.bias2_se,
            floor * floor
        );
        assert!(floor > 0.01, "{name}: the filter does blur the reference ({floor})");
    }
}
