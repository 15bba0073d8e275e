//! The noise/bias split of a non-linear filter by joint application (`FrameFilter::push_pair`):
//! for a linear pipeline (Gaussian, à-trous without a value weight, the mean and EMA) the
//! reference's output is the pipeline applied to the reference alone; for a noise-free input
//! (noisy = reference) the noise part is exactly 0 for every pipeline; the noisy output is never
//! changed by carrying the reference; a non-linear pipeline's weights are the noisy frames'.

use crate::support::images::{cornell, noise, with_background};
use hemilab::denoise::{AtrousParams, Motion, Pipeline, atrous, atrous_pair};
use hemilab::image::Image;

const EVERY: [&str; 12] = [
    "raw",
    "gauss",
    "atrous",
    "atrous:4",
    "mean",
    "ema0.1",
    "mean+atrous:3",
    "ema0.2+gauss",
    "taa0.1",
    "taa0.1+atrous:2",
    "svgf",
    "svgf:4",
];

fn frames(w: u32, h: u32, g: &hemilab::render::GBuffer) -> Vec<Image> {
    (0..6).map(|k| with_background(&noise(w, h, 0.5, 0.2, 50 + k), g, 0.0)).collect()
}

#[test]
fn the_joint_application_of_a_linear_pipeline_is_the_pipeline_on_the_reference() {
    let (w, h) = (40u32, 30u32);
    let g = cornell(w, h);
    let still = Motion::identity(w, h);
    let reference = with_background(&noise(w, h, 0.6, 0.05, 7), &g, 0.0);
    for name in ["gauss", "atrous", "atrous:4", "mean", "ema0.1", "mean+atrous:3", "ema0.2+gauss"] {
        let p: Pipeline = name.parse().unwrap();
        let (mut joint, mut alone, mut noisy) = (p.start(w, h), p.start(w, h), p.start(w, h));
        for f in frames(w, h, &g) {
            let (o, r) = joint.push_pair(&f, &reference, &g, &still);
            assert_eq!(r, alone.push(&reference, &g, &still), "{name}");
            assert_eq!(o, noisy.push(&f, &g, &still), "{name}");
        }
    }
}

#[test]
fn a_noise_free_input_has_no_noise_part() {
    let (w, h) = (40u32, 30u32);
    let g = cornell(w, h);
    let still = Motion::identity(w, h);
    for name in EVERY {
        let mut f = name.parse::<Pipeline>().unwrap().start(w, h);
        for x in frames(w, h, &g) {
            let (o, r) = f.push_pair(&x, &x, &g, &still);
            assert_eq!(o, r, "{name}");
        }
        assert_eq!(f.frames(), 6);
    }
    let x = &frames(w, h, &g)[0];
    let valued = AtrousParams { sigma_value: Some(0.1), ..AtrousParams::default().with_iterations(3) };
    let (o, r) = atrous_pair(x, x, &g, &valued);
    assert_eq!(o, r);
    assert_eq!(o, atrous(x, &g, &valued));
}

#[test]
fn carrying_the_reference_does_not_change_the_output_and_nonlinear_weights_are_the_noisy_ones() {
    let (w, h) = (40u32, 30u32);
    let g = cornell(w, h);
    let still = Motion::identity(w, h);
    let reference = with_background(&noise(w, h, 0.6, 0.05, 7), &g, 0.0);
    for name in EVERY {
        let p: Pipeline = name.parse().unwrap();
        let (mut joint, mut noisy, mut alone) = (p.start(w, h), p.start(w, h), p.start(w, h));
        let mut last = None;
        for f in frames(w, h, &g) {
            let (o, r) = joint.push_pair(&f, &reference, &g, &still);
            assert_eq!(o, noisy.push(&f, &g, &still), "{name}");
            last = Some((r, alone.push(&reference, &g, &still)));
        }
        // SVGF and TAA weigh by the values: the reference under the noisy frames' weights is not
        // the filter run on the reference.
        let (r, own) = last.unwrap();
        if name.starts_with("svgf") || name.starts_with("taa") {
            assert_ne!(r, own, "{name}");
        }
    }
    // À-trous with a value weight: the noisy image's weights, applied to the reference.
    let x = &frames(w, h, &g)[0];
    let valued = AtrousParams { sigma_value: Some(0.1), ..AtrousParams::default().with_iterations(3) };
    let (o, r) = atrous_pair(x, &reference, &g, &valued);
    assert_eq!(o, atrous(x, &g, &valued));
    assert_ne!(r, atrous(&reference, &g, &valued));
}

#[test]
#[should_panic(expected = "pushes pairs from its first frame or never")]
fn a_run_does_not_switch_to_pairs() {
    let (w, h) = (8u32, 6u32);
    let g = cornell(w, h);
    let still = Motion::identity(w, h);
    let mut f = "ema0.1".parse::<Pipeline>().unwrap().start(w, h);
    let x = noise(w, h, 0.5, 0.1, 1);
    f.push(&x, &g, &still);
    f.push_pair(&x, &x, &g, &still);
}

#[test]
fn advancing_past_an_unseen_frame_leaves_the_state_a_push_would() {
    // `FrameFilter::advance` skips the spatial work of frames nobody looks at (SVGF's passes after
    // the first, a filter after the accumulation): the frames shown afterwards are bit for bit
    // those of a run that pushed every frame, alone or in pairs.
    let (w, h) = (40u32, 30u32);
    let g = cornell(w, h);
    let still = Motion::identity(w, h);
    let reference = with_background(&noise(w, h, 0.6, 0.05, 7), &g, 0.0);
    let fs = frames(w, h, &g);
    for name in EVERY {
        let p: Pipeline = name.parse().unwrap();
        let (mut every, mut skipping) = (p.start(w, h), p.start(w, h));
        let (mut every_pair, mut skipping_pair) = (p.start(w, h), p.start(w, h));
        for (k, f) in fs.iter().enumerate() {
            let (o, op) = (every.push(f, &g, &still), every_pair.push_pair(f, &reference, &g, &still));
            if k % 2 == 0 {
                skipping.advance(f, None, &g, &still);
                skipping_pair.advance(f, Some(&reference), &g, &still);
            } else {
                assert_eq!(skipping.push(f, &g, &still), o, "{name}, frame {k}");
                assert_eq!(skipping_pair.push_pair(f, &reference, &g, &still), op, "{name}, pair, frame {k}");
            }
        }
        assert_eq!(skipping.frames(), 6, "{name}");
    }
}
