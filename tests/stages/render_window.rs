//! A window of a bigger image (`render::Window`): `render_window`, `frame_gbuffer_window` and
//! `reproject` of windows give the full frame's pixels, bit for bit, for every seed mode that
//! reads the pixel's coordinates (blue-noise and STBN masks tile by absolute pixel position), for
//! the scene's camera and for a jittered moving one.

use crate::support::parallax;
use hemilab::render::{
    RenderJob, ReprojectParams, View, Window, frame_gbuffer, frame_gbuffer_window, render_view,
    render_window, reproject,
};
use hemilab::sampling::{Distribution, Integrand, SamplerConfig, Schedule, SeedMode, Sequence};
use hemilab::scene::camera_path::{CameraPath, halton_jitter};

/// Not a multiple of the renderer's 8-pixel tiles nor of the 64-pixel masks, so that a window's
/// tiles are not the full frame's.
const FULL: (u32, u32) = (90, 70);

fn windows() -> [Window; 3] {
    [
        Window::new([FULL.0, FULL.1], 37, 21, 30, 25),
        Window::new([FULL.0, FULL.1], 0, 50, 13, 20),
        Window::new([FULL.0, FULL.1], 61, 0, 29, 9),
    ]
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn a_window_is_the_crop_of_the_full_render() {
    let scene = parallax::scene(FULL);
    let path = CameraPath::Orbit { degrees: 12.0 };
    let moving = View::new(path.camera(&scene.view, 3, 8), halton_jitter(3));
    let modes = [
        (Sequence::Random, SeedMode::Rotation),
        (Sequence::Fibonacci, SeedMode::Rotation),
        (Sequence::Fibonacci, SeedMode::BlueNoise),
        (Sequence::Random, SeedMode::BlueNoise),
        (Sequence::Fibonacci, SeedMode::Stbn),
    ];
    for (sequence, seed_mode) in modes {
        for (view, frame, schedule) in [(View::SCENE, 0, Schedule::Independent), (moving, 5, Schedule::R1)] {
            let sampler = SamplerConfig::new(sequence, seed_mode, 2, 11)
                .unwrap()
                .with_frame(frame)
                .with_schedule(schedule);
            let job = RenderJob {
                distribution: Distribution::SineCosine,
                sampler,
                width: FULL.0,
                height: FULL.1,
                ao_distance: 1.5,
            };
            let full = render_view(&scene, &job, Integrand::Ao, &view, &|_| {});
            let all = Window::full(FULL.0, FULL.1);
            for w in windows() {
                let part = render_window(&scene, &job, Integrand::Ao, &view, &w, &|_| {});
                let what = format!("{sequence:?} {seed_mode:?} {view:?} {w:?}");
                assert_eq!(bits(&part.ao.data), bits(&all.crop(&full.ao.data, &w)), "{what}");
                assert_eq!(part.coverage.data, all.crop(&full.coverage.data, &w), "{what}");
                assert!(part.rays > 0 && part.rays < full.rays, "{what}");
            }
            let whole = render_window(&scene, &job, Integrand::Ao, &view, &all, &|_| {});
            assert_eq!(bits(&whole.ao.data), bits(&full.ao.data));
        }
    }
}

#[test]
fn a_windows_gbuffer_and_motion_are_the_full_frames() {
    let scene = parallax::scene(FULL);
    let path = CameraPath::Orbit { degrees: 12.0 };
    let views: Vec<View> =
        (0..3).map(|f| View::new(path.camera(&scene.view, f, 3), halton_jitter(f))).collect();
    let full: Vec<_> = views.iter().map(|v| frame_gbuffer(&scene, FULL.0, FULL.1, v)).collect();
    let all = Window::full(FULL.0, FULL.1);
    let params = ReprojectParams::default();
    let mut compared = 0;
    for w in windows() {
        let part: Vec<_> = views.iter().map(|v| frame_gbuffer_window(&scene, v, &w)).collect();
        for (p, f) in part.iter().zip(&full) {
            assert_eq!(p.window, w);
            assert_eq!(bits(&p.gbuffer.depth.data), bits(&all.crop(&f.gbuffer.depth.data, &w)));
            assert_eq!(p.gbuffer.normal, all.crop(&f.gbuffer.normal, &w));
            assert_eq!(p.gbuffer.primitive, all.crop(&f.gbuffer.primitive, &w));
            assert_eq!(p.position, all.crop(&f.position, &w));
        }
        for k in 1..views.len() {
            let m_full = reproject(&full[k - 1], &full[k], &params);
            let m_part = reproject(&part[k - 1], &part[k], &params);
            for y in w.y..w.y + w.height {
                for x in w.x..w.x + w.width {
                    let i_full = (y * FULL.0 + x) as usize;
                    let taps = m_full.taps(i_full);
                    // Taps into the window are the full frame's, moved into its grid; taps outside
                    // it are off-screen for the window.
                    let inside: Vec<(usize, u32)> = taps
                        .iter()
                        .filter_map(|t| {
                            let (tx, ty) = (t.index % FULL.0, t.index / FULL.0);
                            w.contains(tx, ty).then(|| (w.index(tx, ty), t.weight.to_bits()))
                        })
                        .collect();
                    if inside.len() != taps.len() {
                        continue;
                    }
                    let got: Vec<(usize, u32)> = m_part
                        .taps(w.index(x, y))
                        .iter()
                        .map(|t| (t.index as usize, t.weight.to_bits()))
                        .collect();
                    assert_eq!(got, inside, "frame {k}, pixel ({x}, {y}) of {w:?}");
                    compared += usize::from(!taps.is_empty());
                }
            }
        }
    }
    assert!(compared > 500, "only {compared} pixels with history compared");
}
