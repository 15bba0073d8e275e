//! A real-time frame's render reads the primary hits its G-buffer kept (`render_window_from`)
//! instead of tracing them again: the same image bit for bit, for the whole frame and for windows
//! of it (`[tiles]`: each window's G-buffer keeps that window's hits), for the scene's camera
//! (pinhole and orthographic) and a moving, jittered one, and for a weighted integrand; the hits
//! traced on one thread (`Primaries::trace_here`, what the executor times) are those traced in
//! parallel.

use glam::Vec2;
use hemilab::load::load_scene;
use hemilab::render::{
    Primaries, RenderOutput, View, Window, frame_gbuffer, frame_gbuffer_window, render_view, render_window,
    render_window_from,
};
use hemilab::sampling::{Distribution, Integrand, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::Scene;
use hemilab::scene::camera_path::{CameraPath, halton_jitter};
use std::path::Path;

/// Not a multiple of the renderer's 8-pixel tiles, so that a window's tiles are not the frame's.
const RES: (u32, u32) = (43, 30);

fn scene(file: &str) -> Scene {
    load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join(file)).unwrap()
}

fn bits(o: &RenderOutput) -> (Vec<u32>, Vec<u32>, u64, u64) {
    let b = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    (b(&o.ao.data), b(&o.coverage.data), o.rays, o.occluded_rays)
}

/// The scene's camera, and three frames of an orbit with Halton jitter.
fn views(scene: &Scene) -> Vec<View> {
    let path = CameraPath::Orbit { degrees: 20.0 };
    let mut v = vec![View::SCENE];
    v.extend((0..3).map(|f| View::new(path.camera(&scene.view, f, 3), halton_jitter(f))));
    v
}

/// The whole frame and two windows of it (one at a corner, one inside).
fn windows() -> [Window; 3] {
    let full = [RES.0, RES.1];
    [Window::full(RES.0, RES.1), Window::new(full, 0, 17, 21, 13), Window::new(full, 11, 5, 19, 14)]
}

#[test]
fn a_render_from_kept_primary_hits_is_the_traced_render_bit_for_bit() {
    for (file, d, integrand) in [
        ("scenes/cornell-box.toml", Distribution::SineCosine, Integrand::Ao),
        ("scenes/kitchen.toml", Distribution::Uniform, Integrand::Ao),
        ("scenes/floating-rectangle.toml", Distribution::Sine, Integrand::Ao),
        ("scenes/cornell-box.toml", Distribution::Sine, Integrand::CosLobe(3)),
    ] {
        let scene = scene(file);
        for (k, view) in views(&scene).iter().enumerate() {
            let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 36, 5).unwrap();
            let job =
                crate::support::jobs::render_job(d, sampler.with_frame(k as u32), RES, scene.ao_distance);
            for w in windows() {
                let g = frame_gbuffer_window(&scene, view, &w);
                let traced = render_window(&scene, &job, integrand, view, &w, &|_| {});
                let kept = render_window_from(&scene, &job, integrand, view, &w, Some(&g.primaries), &|_| {});
                let what = format!("{file}, view {k}, window {}", w.canonical());
                assert!(traced.rays > 0, "{what}: the view sees the scene");
                assert_eq!(bits(&kept), bits(&traced), "{what}");
                assert_eq!(Primaries::trace_here(&scene, view, &w), g.primaries, "{what}");
            }
            let full = render_view(&scene, &job, integrand, view, &|_| {});
            let g = frame_gbuffer(&scene, RES.0, RES.1, view);
            let all = Window::full(RES.0, RES.1);
            let kept = render_window_from(&scene, &job, integrand, view, &all, Some(&g.primaries), &|_| {});
            assert_eq!(bits(&kept), bits(&full), "{file}, view {k}: render_view");
        }
    }
}

#[test]
#[should_panic(expected = "primary hits of another view or window")]
fn another_frames_primary_hits_are_refused() {
    let scene = scene("scenes/cornell-box.toml");
    let sampler = SamplerConfig::new(Sequence::Random, SeedMode::Rotation, 4, 1).unwrap();
    let job = crate::support::jobs::render_job(Distribution::SineCosine, sampler, RES, scene.ao_distance);
    let jittered = View::new(scene.view, Vec2::new(0.25, 0.0));
    let g = frame_gbuffer(&scene, RES.0, RES.1, &jittered);
    let all = Window::full(RES.0, RES.1);
    let _ = render_window_from(&scene, &job, Integrand::Ao, &View::SCENE, &all, Some(&g.primaries), &|_| {});
}

#[test]
#[should_panic(expected = "primary hits of another view or window")]
fn another_windows_primary_hits_are_refused() {
    let scene = scene("scenes/cornell-box.toml");
    let sampler = SamplerConfig::new(Sequence::Random, SeedMode::Rotation, 4, 1).unwrap();
    let job = crate::support::jobs::render_job(Distribution::SineCosine, sampler, RES, scene.ao_distance);
    let [_, a, b] = windows();
    let g = frame_gbuffer_window(&scene, &View::SCENE, &a);
    let _ = render_window_from(&scene, &job, Integrand::Ao, &View::SCENE, &b, Some(&g.primaries), &|_| {});
}
