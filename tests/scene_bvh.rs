//! The BVH traversal (obvhs's CWBVH with our node test) against testing every triangle: on the kitchen,
//! from real AO ray origins, in real AO directions, with d = 1, infinite, and 1e-4 (obvhs's hard-coded
//! minimum), the occlusion answer and the closest hit agree ray for ray. (obvhs's own 1e-4 clamp is
//! caught by the scaled closed box in render_exact.rs; here hits that short are rare.)

use glam::Vec2;
use hemilab::app::load_scene;
use hemilab::render::offset_origin;
use hemilab::sampling::{Distribution, Frame, frame};
use hemilab::scene::accel::Ray;
use std::path::Path;

#[test]
fn kitchen_traversal_matches_brute_force() {
    let scene = load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/kitchen.toml")).unwrap();
    let acc = &scene.accel;
    let (w, h) = (40, 30);
    let (mut rays, mut occluded, mut short) = (0, 0, 0);
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut unit = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    for y in 0..h {
        for x in 0..w {
            let pr = scene.camera.ray(x, y, w, h);
            let primary = Ray::new(pr.origin, pr.dir, f32::INFINITY);
            let hit = acc.closest(&primary);
            if (x + y) % 4 == 0 {
                let brute = acc.closest_brute_force(&primary);
                assert_eq!(hit.map(|h| h.t.to_bits()), brute.map(|h| h.t.to_bits()), "primary ({x}, {y})");
            }
            let Some(hit) = hit else { continue };
            let [a, b, c] = acc.triangle(hit.prim);
            let p = a + hit.bary_b * (b - a) + hit.bary_c * (c - a);
            let mut n = (b - a).cross(c - a).normalize();
            if n.dot(pr.dir) > 0.0 {
                n = -n;
            }
            let origin = offset_origin(p, n, acc.scale(hit.prim));
            // One direction anywhere, one near the horizon (where hits in crevices are short).
            for v in [unit(), 0.95 + 0.05 * unit()] {
                let s = Distribution::SineCosine.sample(Vec2::new(unit(), v));
                let dir = frame::canonical(Frame::from_normal(n).to_world(s.dir).normalize());
                let want = acc.closest_brute_force(&Ray::new(origin, dir, f32::INFINITY));
                short += want.is_some_and(|h| h.t < 1e-4) as u32;
                for tmax in [1.0, f32::INFINITY, 1e-4] {
                    let ray = Ray::new(origin, dir, tmax);
                    let want = want.filter(|h| h.t < tmax);
                    assert_eq!(acc.occluded(&ray), want.is_some(), "AO ray at ({x}, {y}), tmax {tmax}");
                    let got = acc.closest(&ray);
                    assert_eq!(got.map(|h| h.t.to_bits()), want.map(|h| h.t.to_bits()), "({x}, {y})");
                    rays += 1;
                    occluded += want.is_some() as u32;
                }
            }
        }
    }
    assert!(rays > 5000 && occluded > 1000, "{rays} rays, {occluded} occluded");
    eprintln!("{rays} rays, {occluded} occluded, {short} closer than 1e-4");
}
