//! The G-buffer the edge-aware filter is guided by: from the renderer's own primary rays, so its
//! depth and normal are those of the hits the AO rays start from; and adding it left `render`'s
//! images as they were (fingerprints of main's images, taken before the G-buffer existed).

use hemilab::load::load_scene;
use hemilab::render::{RenderJob, RenderOutput, render};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// FNV-1a (64 bit) over the AO and coverage bits and the ray counts.
fn fingerprint(o: &RenderOutput) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    for v in o.ao.data.iter().chain(&o.coverage.data) {
        eat(&v.to_bits().to_le_bytes());
    }
    eat(&o.rays.to_le_bytes());
    eat(&o.occluded_rays.to_le_bytes());
    h
}

fn job(
    scene: &hemilab::scene::Scene,
    d: Distribution,
    q: Sequence,
    m: SeedMode,
    res: (u32, u32),
) -> RenderJob {
    crate::support::jobs::render_job(
        d,
        SamplerConfig::new(q, m, 16, 3).unwrap(),
        (res.0, res.1),
        scene.ao_distance,
    )
}

/// Images rendered by main's code (commit 321ec7f) before `gbuffer` shared the primary-ray code
/// with `render`: the same bits now.
#[test]
fn render_is_bit_identical_to_mains() {
    let cases = [
        ("scenes/kitchen.toml", (64, 48), Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Rotation),
        ("scenes/cornell-box.toml", (48, 48), Distribution::Uniform, Sequence::Random, SeedMode::Shift),
        (
            "scenes/floating-rectangle.toml",
            (40, 30),
            Distribution::Sine,
            Sequence::Fibonacci,
            SeedMode::Rotation,
        ),
    ];
    let mut got = Vec::new();
    for (file, res, d, q, m) in cases {
        let scene = load_scene(&root().join(file)).unwrap();
        got.push(fingerprint(&render(&scene, &job(&scene, d, q, m, res), &|_| {})));
    }
    eprintln!("{got:#018x?}");
    assert_eq!(got, [0xabc2_a45f_a21b_1b61u64, 0xf53d_59cf_4207_ec33, 0x8f77_36ff_aa8d_3cc2]);
}

/// Depth and normal are the primary hits': on the floating rectangle (orthographic, eye at z = 10
/// looking down −z at the floor z = 0 and the rectangle z = 0.8) every hit's depth is 10 or 9.2 and
/// its normal +z, by closed form; on the Cornell box (a pinhole) each pixel's depth is the closest
/// hit of its camera ray, traced here independently, and its normal the AO rays' frame's
/// (`pixel_rays`). The coverage is `render`'s, bit for bit.
#[test]
fn depth_and_normal_are_the_primary_hits() {
    use glam::Vec3;
    use hemilab::render::{PixelRays, gbuffer, pixel_rays};
    use hemilab::scene::accel::Ray;
    let scene = load_scene(&root().join("scenes/floating-rectangle.toml")).unwrap();
    let (w, h) = (40, 30);
    let g = gbuffer(&scene, w, h);
    let (mut floor, mut rect) = (0, 0);
    for i in 0..(w * h) as usize {
        assert!(g.is_covered(i), "the floor fills the view");
        let z = g.depth.data[i];
        assert!((z - 10.0).abs() < 1e-5 || (z - 9.2).abs() < 1e-5, "pixel {i}: depth {z}");
        if (z - 10.0).abs() < 1e-5 {
            floor += 1
        } else {
            rect += 1
        }
        assert_eq!(g.normal[i], Vec3::Z, "pixel {i}");
    }
    assert!(floor > 0 && rect > 0, "both surfaces seen: {floor} floor, {rect} rectangle pixels");

    let scene = load_scene(&root().join("scenes/cornell-box.toml")).unwrap();
    let (w, h) = (48, 36);
    let g = gbuffer(&scene, w, h);
    let j = job(&scene, Distribution::SineCosine, Sequence::Random, SeedMode::Rotation, (w, h));
    let out = render(&scene, &j, &|_| {});
    assert_eq!(g.coverage, out.coverage);
    let mut points = vec![glam::Vec2::ZERO; 16];
    let mut rays = PixelRays::default();
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let r = scene.camera.ray(x, y, w, h);
            let hit = scene.accel.closest(&Ray::new(r.origin, r.dir, f32::INFINITY));
            assert_eq!(hit.is_some(), g.is_covered(i), "pixel ({x}, {y})");
            let Some(hit) = hit else { continue };
            assert_eq!(g.depth.data[i], hit.t, "pixel ({x}, {y})");
            assert!(pixel_rays(&scene, &j, x, y, i as u64, &mut points, &mut rays));
            assert_eq!(g.normal[i], rays.normal, "pixel ({x}, {y})");
            assert!(g.normal[i].dot(r.dir) < 0.0, "faces the camera");
        }
    }
    // The same for any thread count.
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    assert_eq!(pool.install(|| gbuffer(&scene, w, h)), g);
}
