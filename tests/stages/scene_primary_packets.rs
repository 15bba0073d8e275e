//! Primary rays traced 32 at a time (`Accel::closest_from`, as the renderer does per tile) give the
//! single-ray walk's closest hit bit for bit (distance, triangle, barycentrics), on every pixel of
//! every shipped scene and on meshes built to tie (duplicate and overlapping coplanar triangles,
//! rays through shared edges and vertices), on the AVX2 and the SSE2 kernels; and both agree with
//! testing every triangle. And a whole render equals the per-pixel path (`pixel_rays`).

use glam::{Vec2, Vec3};
use hemilab::load::load_scene;
use hemilab::render::{PixelRays, pixel_rays, render, trace_pixel};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::Accel;
use hemilab::scene::accel::{Hit, Ray};
use std::path::Path;

/// A hit as the renderer uses it: distance, input triangle (one triangle may fill several BVH
/// slots, which hit alike), barycentrics.
fn key(acc: &Accel, h: Option<Hit>) -> Option<(u32, u32, u32, u32)> {
    h.map(|h| (h.t.to_bits(), acc.source_index(h.prim), h.bary_b.to_bits(), h.bary_c.to_bits()))
}

/// Checks one packet of rays from `o` against single rays (and, if `brute`, every triangle).
fn check(acc: &Accel, o: Vec3, dirs: &[Vec3], tmax: f32, brute: bool, what: &str) -> usize {
    let (mut wide, mut sse) = (vec![None; dirs.len()], vec![None; dirs.len()]);
    acc.closest_from(o, dirs, tmax, &mut wide);
    acc.closest_from_sse2(o, dirs, tmax, &mut sse);
    let mut hits = 0;
    for (i, d) in dirs.iter().enumerate() {
        let ray = Ray::new(o, *d, tmax);
        let want = key(acc, acc.closest(&ray));
        assert_eq!(key(acc, wide[i]), want, "{what}: ray {i} ({d}), AVX2 packet vs single ray");
        assert_eq!(key(acc, sse[i]), want, "{what}: ray {i} ({d}), SSE2 packet vs single ray");
        if brute {
            assert_eq!(
                key(acc, acc.closest_brute_force(&ray)),
                want,
                "{what}: ray {i} ({d}), every triangle"
            );
        }
        hits += want.is_some() as usize;
    }
    hits
}

#[test]
fn every_scene_pixel_packet_equals_single_rays() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for name in
        ["kitchen", "cornell-box", "atrium", "bunny", "slats", "terrain", "floating-rectangle", "foliage"]
    {
        let scene = load_scene(&root.join(format!("scenes/{name}.toml"))).unwrap();
        let (w, h) = scene.resolution;
        let mut hits = 0;
        // Blocks of 8 × 4 pixels, as the renderer's tiles are split; every 5th block also against
        // every triangle.
        for (b, (bx, by)) in
            (0..h.div_ceil(4)).flat_map(|y| (0..w.div_ceil(8)).map(move |x| (x, y))).enumerate()
        {
            let mut origin = None;
            let mut dirs = Vec::new();
            for y in by * 4..(by * 4 + 4).min(h) {
                for x in bx * 8..(bx * 8 + 8).min(w) {
                    let r = scene.camera.ray(x, y, w, h);
                    let o = *origin.get_or_insert(r.origin);
                    if o != r.origin {
                        continue; // an orthographic camera: one origin per pixel, one ray per packet
                    }
                    dirs.push(r.dir);
                }
            }
            let Some(o) = origin else { continue };
            hits += check(&scene.accel, o, &dirs, f32::INFINITY, b % 5 == 0 && name != "bunny", name);
        }
        assert!(hits > 0, "{name}: no primary ray hit anything");
    }
}

/// Triangles that tie: the same triangle twice, a quad split along both diagonals (overlapping,
/// coplanar), a fan whose edges and shared vertex rays pass through exactly, and a second layer
/// a float's ulp behind the first.
#[test]
fn ties_are_broken_alike_in_any_order() {
    let v = Vec3::new;
    let mut tris = Vec::new();
    let (a, b, c, d) = (v(-1.0, -1.0, 2.0), v(1.0, -1.0, 2.0), v(1.0, 1.0, 2.0), v(-1.0, 1.0, 2.0));
    tris.extend([[a, b, c], [a, c, d], [a, b, d], [b, c, d], [a, b, c]]);
    let z = f32::from_bits(2.0f32.to_bits() + 1);
    tris.extend([[v(-1.0, -1.0, z), v(1.0, -1.0, z), v(0.0, 1.0, z)]]);
    for k in 0..8 {
        let (p, q) = (k as f32 * std::f32::consts::FRAC_PI_4, (k + 1) as f32 * std::f32::consts::FRAC_PI_4);
        tris.push([
            v(0.0, 0.0, 3.0),
            v(p.cos() * 2.0, p.sin() * 2.0, 3.0),
            v(q.cos() * 2.0, q.sin() * 2.0, 3.0),
        ]);
    }
    let (acc, _) = Accel::build(&tris);
    let mut dirs = Vec::new();
    // Through vertices, along edges and diagonals, and a grid of rays across the quad.
    for t in [v(0.0, 0.0, 2.0), v(1.0, 1.0, 2.0), v(-1.0, 1.0, 2.0), v(0.0, -1.0, 2.0), v(0.5, 0.5, 2.0)] {
        dirs.push(t.normalize());
    }
    for i in 0..27 {
        let (x, y) = ((i % 9) as f32 * 0.25 - 1.0, (i / 9) as f32 * 0.5 - 0.5);
        dirs.push(v(x, y, 2.0).normalize());
    }
    let mut hits = 0;
    for chunk in dirs.chunks(32) {
        for tmax in [f32::INFINITY, 2.5, 2.0] {
            hits += check(&acc, Vec3::ZERO, chunk, tmax, true, "ties");
        }
    }
    assert!(hits > 40, "{hits} hits");
}

/// The renderer's tiles (packets of primary rays) against the per-pixel path, on the scene with the
/// most coplanar overlaps (the atrium): the same AO image, bit for bit.
#[test]
fn render_equals_the_per_pixel_path() {
    let scene = load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/atrium.toml")).unwrap();
    let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 8, 3).unwrap();
    let (width, height) = (61, 45);
    let job = crate::support::jobs::render_job(Distribution::SineCosine, sampler, (width, height), 1.0);
    let out = render(&scene, &job, &|_| {});
    let (mut points, mut px, mut blocked) = (vec![Vec2::ZERO; 8], PixelRays::default(), vec![false; 8]);
    for y in 0..height {
        for x in 0..width {
            let i = (y * width + x) as usize;
            if !pixel_rays(&scene, &job, x, y, i as u64, &mut points, &mut px) {
                assert_eq!(out.coverage.data[i], 0.0, "({x}, {y})");
                continue;
            }
            trace_pixel(&scene, px.origin, px.normal, &px.dirs, job.ao_distance, &mut blocked);
            let sum: f64 = blocked.iter().zip(&px.weights).filter(|(b, _)| **b).map(|(_, w)| *w as f64).sum();
            let want = (1.0 - sum / 8.0) as f32;
            assert_eq!(out.ao.data[i].to_bits(), want.to_bits(), "({x}, {y})");
        }
    }
}
