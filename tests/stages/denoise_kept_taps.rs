//! The à-trous taps kept process-wide (`denoise::taps`): filters reading kept tables give the images
//! of filters that compute every tap, bit for bit — SVGF (its default and 5 passes), EMA + à-trous
//! and à-trous alone, over a static camera's frames and a moving, jittered one's (each frame its
//! own G-buffer and motion), a series run again after the first (every table kept by then) — and
//! the cache never holds more bytes than its bound, whatever frames it is asked for.

use hemilab::denoise::taps::{TapCache, with_cache};
use hemilab::denoise::{Motion, Pipeline};
use hemilab::image::Image;
use hemilab::load::load_scene;
use hemilab::render::{FrameGBuffer, ReprojectParams, View, frame_gbuffer, render_view, reproject};
use hemilab::sampling::{Distribution, Integrand, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::Scene;
use hemilab::scene::camera_path::{CameraPath, halton_jitter};
use std::path::Path;
use std::sync::Arc;

const RES: (u32, u32) = (48, 36);
const FRAMES: u32 = 6;
const PIPELINES: [&str; 4] = ["svgf", "svgf:5", "ema0.1+atrous", "atrous"];

/// A series' frames: each one's G-buffer, motion from the frame before and 1-ray AO image.
struct Series {
    gbuffers: Vec<FrameGBuffer>,
    motions: Vec<Motion>,
    images: Vec<Image>,
}

fn series(scene: &Scene, moving: bool) -> Series {
    let path = CameraPath::Orbit { degrees: 12.0 };
    let views: Vec<View> = (0..FRAMES)
        .map(|f| match moving {
            true => View::new(path.camera(&scene.view, f, FRAMES), halton_jitter(f)),
            false => View::SCENE,
        })
        .collect();
    let gbuffers: Vec<FrameGBuffer> = views.iter().map(|v| frame_gbuffer(scene, RES.0, RES.1, v)).collect();
    let motions = (0..FRAMES as usize)
        .map(|f| match f {
            0 => Motion::identity(RES.0, RES.1),
            _ => reproject(&gbuffers[f - 1], &gbuffers[f], &ReprojectParams::default()),
        })
        .collect();
    let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::BlueNoise, 1, 11).unwrap();
    let images = (0..FRAMES)
        .map(|f| {
            let job = crate::support::jobs::render_job(
                Distribution::SineCosine,
                sampler.with_frame(f),
                RES,
                scene.ao_distance,
            );
            render_view(scene, &job, Integrand::Ao, &views[f as usize], &|_| {}).ao
        })
        .collect();
    Series { gbuffers, motions, images }
}

/// Every pipeline's image of every frame (the last frames' bits), under `cache`.
fn filtered(s: &Series, cache: &Arc<TapCache>) -> Vec<Vec<u32>> {
    with_cache(cache, || {
        let mut out = Vec::new();
        for name in PIPELINES {
            let mut run = name.parse::<Pipeline>().unwrap().start(RES.0, RES.1);
            for f in 0..FRAMES as usize {
                let (g, m) = (&s.gbuffers[f].gbuffer, &s.motions[f]);
                // Frame 3 only advances (SVGF: its first pass alone), as an unshown frame does.
                if f == 3 {
                    run.advance(&s.images[f], None, g, m);
                    continue;
                }
                let img = run.push(&s.images[f], g, m);
                out.push(img.data.iter().map(|x| x.to_bits()).collect());
            }
        }
        out
    })
}

#[test]
fn filters_reading_kept_taps_give_the_computed_taps_images_bit_for_bit() {
    let scene = load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml")).unwrap();
    for moving in [false, true] {
        let s = series(&scene, moving);
        let computed = filtered(&s, &Arc::new(TapCache::new(0)));
        let cache = Arc::new(TapCache::new(1 << 30));
        for round in 0..2 {
            assert_eq!(filtered(&s, &cache), computed, "moving {moving}, round {round}");
        }
        assert!(cache.tables() > 0, "tables were kept");
        // One table's worth less than all: some taps kept, the others computed; the same images.
        let small = Arc::new(TapCache::new(cache.bytes() / 2));
        for _ in 0..2 {
            assert_eq!(filtered(&s, &small), computed, "moving {moving}, half the tables");
        }
        assert!(small.bytes() <= cache.bytes() / 2 && small.tables() < cache.tables());
    }
}
