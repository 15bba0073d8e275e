//! The temporal stability metric against closed forms: 0 for an output that moves exactly as the
//! reference does; √2 σ for outputs of independent noise of variance σ² about the reference.

use crate::support::images::{image, noise};
use hemilab::image::Image;
use hemilab::metrics::{MetricsError, flicker, flicker_sequence};

#[test]
fn an_output_that_is_the_reference_does_not_flicker() {
    let (w, h) = (20u32, 10u32);
    let mask = image(w, h, |x, _| if x < 15 { 1.0 } else { 0.0 });
    let refs: Vec<Image> = (0..6).map(|k| noise(w, h, 0.5, 0.2, 60 + k)).collect();
    assert_eq!(flicker_sequence(&refs, &refs, &mask).unwrap(), 0.0);
    // An output off the reference by a constant error: still no flicker.
    let off: Vec<Image> =
        refs.iter().map(|r| Image::from_vec(w, h, r.data.iter().map(|v| v + 0.25).collect())).collect();
    assert!(flicker_sequence(&off, &refs, &mask).unwrap() < 1e-6);
    assert!(matches!(
        flicker(&refs[0], &refs[1], &refs[0], &refs[1], &image(w, h, |_, _| 0.0)),
        Err(MetricsError::NoCoveredPixels)
    ));
    assert!(matches!(
        flicker(&refs[0], &image(3, 3, |_, _| 0.0), &refs[0], &refs[1], &mask),
        Err(MetricsError::SizeMismatch { .. })
    ));
}

#[test]
fn independent_noise_flickers_by_root_two_sigma() {
    let (w, h, frames, sd) = (64u32, 64u32, 17usize, 0.1f64);
    let mask = image(w, h, |_, _| 1.0);
    let reference = image(w, h, |x, y| 0.3 + 0.01 * ((x + y) % 7) as f32);
    let outs: Vec<Image> = (0..frames)
        .map(|k| {
            let n = noise(w, h, 0.0, sd as f32, 7000 + k as u64);
            Image::from_vec(w, h, reference.data.iter().zip(&n.data).map(|(r, e)| r + e).collect())
        })
        .collect();
    let got = flicker_sequence(&outs, &vec![reference.clone(); frames], &mask).unwrap();
    // The mean of N squares of N(0, 2σ²) differences; consecutive ones share a frame (correlation
    // −1/2, of their squares 1/4), so Var(mean square) = (2σ²)² · 2 (1 + 2·1/4) / N.
    let n = ((frames - 1) * (w * h) as usize) as f64;
    let rel_sd = (2.0 * 1.5 / n).sqrt();
    let want = 2f64.sqrt() * sd;
    eprintln!("flicker {got:.5} against √2 σ = {want:.5} (relative sd of the mean square {rel_sd:.4})");
    assert!(((got * got) / (want * want) - 1.0).abs() < 5.0 * rel_sd, "{got} vs {want}");
}
