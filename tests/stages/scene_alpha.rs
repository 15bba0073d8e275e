//! Alpha masks (`scene::alpha`): a card whose mask keeps exactly one half gives the AO of that half
//! (Lambert's form factor of the opaque rectangle), a fully transparent card gives the open floor,
//! primary and AO rays through masked triangles agree bit for bit between the single-ray walks and
//! the packets (AVX2 and SSE2), and the committed foliage scene is what `scene::foliage` makes.

use crate::support::common::Tmp;
use crate::support::lambert::{exact_pixels, form_factor, pooled_errors};
use glam::{DVec3, Vec2, Vec3};
use hemilab::load::load_scene;
use hemilab::render::{PixelRays, pixel_rays, render};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::accel::{Hit, Ray};
use hemilab::scene::gltf_write::{Doc, Material, Node, Prim};
use hemilab::scene::packet::Occluders;
use hemilab::scene::{Accel, Scene};
use std::path::Path;

/// The card's rectangle at height Z (as `procedural::floating_rectangle`'s), and the floor's half-size.
const LO: [f64; 2] = [-0.4, -0.3];
const HI: [f64; 2] = [0.6, 0.5];
const Z: f64 = 0.8;
const FLOOR: f64 = 4.0;
/// 16 × 16 pixels over ±2: no pixel centre lies on an edge of the card or of its mask.
const SIDE: u32 = 16;

/// A PNG of `w` × `h` texels with the given alpha per texel (first row first).
fn png(w: u32, h: u32, alpha: impl Fn(u32, u32) -> u8) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(w, h, |x, y| image::Rgba([255, 255, 255, alpha(x, y)]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// A floor at z = 0 under the card (texture coordinate u along x, 0 at LO, 1 at HI), masked with
/// `texture` and `factor` (alpha) against cutoff 0.5, seen top-down; loaded through a .glb file.
fn card_scene(name: &str, texture: Vec<u8>, factor: f32) -> Scene {
    let f = FLOOR as f32;
    let floor = Prim {
        positions: vec![[-f, -f, 0.0], [f, -f, 0.0], [f, f, 0.0], [-f, f, 0.0]],
        indices: Some(vec![0, 1, 2, 0, 2, 3]),
        mode: 4,
        ..Prim::default()
    };
    let (lo, hi, z) = (LO.map(|c| c as f32), HI.map(|c| c as f32), Z as f32);
    let card = Prim {
        positions: vec![[lo[0], lo[1], z], [hi[0], lo[1], z], [hi[0], hi[1], z], [lo[0], hi[1], z]],
        indices: Some(vec![0, 1, 2, 0, 2, 3]),
        mode: 4,
        uvs: Some(vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]),
        material: Some(0),
    };
    let doc = Doc {
        meshes: vec![vec![floor, card]],
        nodes: vec![Node { mesh: Some(0), ..Node::default() }],
        roots: vec![0],
        materials: vec![Material {
            base_color_factor: [1.0, 1.0, 1.0, factor],
            texture: Some(0),
            alpha_cutoff: Some(0.5),
        }],
        images: vec![texture],
        ..Doc::default()
    };
    let t = Tmp::new(name);
    std::fs::write(t.path("card.glb"), doc.to_glb()).unwrap();
    let toml = format!(
        "mesh = \"card.glb\"\nresolution = [{SIDE}, {SIDE}]\nao_distance = \"infinite\"\n\
         [camera.orthographic]\neye = [0.0, 0.0, 10.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 1.0, 0.0]\n\
         view_width = 4.0\n"
    );
    std::fs::write(t.path("s.toml"), toml).unwrap();
    load_scene(&t.path("s.toml")).unwrap()
}

#[test]
fn a_half_opaque_card_gives_the_ao_of_its_opaque_half() {
    // 2 × 1 texels: the left one opaque, so the mask keeps x < 0.1 exactly (u = 0.5 is a texel edge).
    let scene = card_scene("alpha-half", png(2, 1, |x, _| if x == 0 { 255 } else { 0 }), 1.0);
    let mid = 0.5 * (LO[0] + HI[0]);
    let half: Vec<DVec3> = [[LO[0], LO[1]], [mid, LO[1]], [mid, HI[1]], [LO[0], HI[1]]]
        .iter()
        .map(|p| DVec3::new(p[0], p[1], Z) - scene.origin)
        .collect();
    let floor_z = -scene.origin.z;
    // Every floor pixel: those under the transparent half too (their primary rays pass through it).
    let floor = exact_pixels(&scene, SIDE, |o, n| {
        (o.z < floor_z + 0.4).then(|| 1.0 - form_factor(DVec3::new(o.x, o.y, floor_z), n, &half))
    });
    let under_clear = floor
        .iter()
        .filter(|(i, _)| {
            let (x, y) = ((i % SIDE as usize) as f64, (i / SIDE as usize) as f64);
            let px = 4.0 / SIDE as f64;
            let (cx, cy) = (-2.0 + (x + 0.5) * px, 2.0 - (y + 0.5) * px);
            cx > mid && cx < HI[0] && cy > LO[1] && cy < HI[1]
        })
        .count();
    assert!(under_clear >= 6, "only {under_clear} floor pixels under the transparent half");
    assert_eq!(floor.len(), (SIDE * SIDE) as usize - 6, "all but the opaque half's 2 × 3 pixels are floor");
    let exact = floor.iter().map(|p| p.1).sum::<f64>() / floor.len() as f64;
    // The whole card (the mask ignored) would be far off: the test tells the half from the whole.
    let whole: Vec<DVec3> = [[LO[0], LO[1]], [HI[0], LO[1]], [HI[0], HI[1]], [LO[0], HI[1]]]
        .iter()
        .map(|p| DVec3::new(p[0], p[1], Z) - scene.origin)
        .collect();
    let solid = exact_pixels(&scene, SIDE, |o, n| {
        (o.z < floor_z + 0.4).then(|| 1.0 - form_factor(DVec3::new(o.x, o.y, floor_z), n, &whole))
    });
    let solid = solid.iter().map(|p| p.1).sum::<f64>() / solid.len() as f64;
    assert!(exact - solid > 0.01, "half {exact} vs whole card {solid}");
    let mut worst = 0.0f64;
    for r in pooled_errors(&scene, SIDE, 32, 24, &floor) {
        assert!(r.se < (exact - solid) / 20.0, "{}: SE {} too wide to tell half from whole", r.what, r.se);
        worst = worst.max(r.z());
        assert!(r.z() <= 4.0, "{}: mean error {:+.6} = {:.1} SE", r.what, r.bias, r.z());
        eprintln!("half-opaque card, {}: mean AO error {:+.6} (SE {:.6})", r.what, r.bias, r.se);
    }
    eprintln!(
        "half-opaque card: {} floor pixels, exact mean AO {exact:.6} (whole card {solid:.6}), worst {worst:.1} SE",
        floor.len()
    );
}

#[test]
fn a_fully_transparent_card_gives_the_open_floor() {
    // Transparent by the texture, and by the factor (alpha 1 × 0.4 < 0.5).
    for (what, texture, factor) in
        [("texture", png(4, 4, |_, _| 0), 1.0), ("factor", png(1, 1, |_, _| 255), 0.4)]
    {
        let scene = card_scene("alpha-clear", texture, factor);
        for distribution in [Distribution::Uniform, Distribution::SineCosine] {
            let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 32, 7).unwrap();
            let job = crate::support::jobs::render_job(distribution, sampler, (SIDE, SIDE), f32::INFINITY);
            let out = render(&scene, &job, &|_| {});
            assert!(out.coverage.data.iter().all(|&c| c == 1.0), "{what}: every pixel sees the floor");
            assert_eq!(out.occluded_rays, 0, "{what} {distribution}: a ray was blocked by a clear card");
            assert!(
                out.ao.data.iter().all(|&a| a == 1.0),
                "{what} {distribution}: AO of the open floor is 1"
            );
        }
    }
}

fn key(acc: &Accel, h: Option<Hit>) -> Option<(u32, u32, u32, u32)> {
    h.map(|h| (h.t.to_bits(), acc.source_index(h.prim), h.bary_b.to_bits(), h.bary_c.to_bits()))
}

#[test]
fn masked_rays_agree_between_single_rays_and_packets() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = load_scene(&root.join("scenes/foliage.toml")).unwrap();
    assert!(scene.accel.has_alpha());
    let acc = &scene.accel;
    let (w, h) = (96u32, 72u32);
    let mut primary_hits = 0;
    // Primary rays in blocks of 8 × 4 pixels (the renderer's packets); every 7th against every triangle.
    for (b, (bx, by)) in (0..h / 4).flat_map(|y| (0..w / 8).map(move |x| (x, y))).enumerate() {
        let mut dirs = Vec::new();
        let mut o = Vec3::ZERO;
        for y in by * 4..by * 4 + 4 {
            for x in bx * 8..bx * 8 + 8 {
                let r = scene.camera.ray(x, y, w, h);
                o = r.origin;
                dirs.push(r.dir);
            }
        }
        let (mut wide, mut sse) = (vec![None; dirs.len()], vec![None; dirs.len()]);
        acc.closest_from(o, &dirs, f32::INFINITY, &mut wide);
        acc.closest_from_sse2(o, &dirs, f32::INFINITY, &mut sse);
        for (i, d) in dirs.iter().enumerate() {
            let ray = Ray::new(o, *d, f32::INFINITY);
            let want = key(acc, acc.closest(&ray));
            assert_eq!(key(acc, wide[i]), want, "block {b} ray {i}: AVX2 packet vs single ray");
            assert_eq!(key(acc, sse[i]), want, "block {b} ray {i}: SSE2 packet vs single ray");
            if b % 7 == 0 {
                assert_eq!(
                    key(acc, acc.closest_brute_force(&ray)),
                    want,
                    "block {b} ray {i}: every triangle"
                );
            }
            primary_hits += want.is_some() as usize;
        }
    }
    assert!(primary_hits > 1000, "{primary_hits} primary hits");
    // AO rays of every 3rd pixel, as the renderer makes them, at d = 1 and unbounded.
    let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 48, 3).unwrap();
    let job = crate::support::jobs::render_job(Distribution::Uniform, sampler, (w, h), 1.0);
    let (mut points, mut px) = (vec![Vec2::ZERO; 48], PixelRays::default());
    let (mut blocked_rays, mut rays) = (0usize, 0usize);
    let mut cache = Occluders::new();
    for i in (0..w * h).step_by(3) {
        let (x, y) = (i % w, i / w);
        if !pixel_rays(&scene, &job, x, y, i as u64, &mut points, &mut px) {
            continue;
        }
        for tmax in [1.0, f32::INFINITY] {
            let (mut wide, mut sse) = (vec![false; px.dirs.len()], vec![false; px.dirs.len()]);
            acc.occluded_from(px.origin, Some(px.normal), &px.dirs, tmax, &mut wide, &mut cache);
            acc.occluded_from_sse2(px.origin, Some(px.normal), &px.dirs, tmax, &mut sse, &mut cache);
            for (k, d) in px.dirs.iter().enumerate() {
                let want = acc.occluded(&Ray::new(px.origin, *d, tmax));
                assert_eq!(wide[k], want, "pixel {i} ray {k} d {tmax}: AVX2 packet vs single ray");
                assert_eq!(sse[k], want, "pixel {i} ray {k} d {tmax}: SSE2 packet vs single ray");
                blocked_rays += want as usize;
                rays += 1;
            }
        }
    }
    assert!(blocked_rays > rays / 20 && blocked_rays < rays, "{blocked_rays} of {rays} AO rays blocked");
}

#[test]
fn the_masks_let_light_through_the_foliage() {
    // The same scene with its masks dropped (every card solid) is darker: the holes are real.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let masked = load_scene(&root.join("scenes/foliage.toml")).unwrap();
    let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 16, 1).unwrap();
    let job = crate::support::jobs::render_job(Distribution::SineCosine, sampler, (64, 48), 1.0);
    let a = render(&masked, &job, &|_| {});
    let tris: Vec<[DVec3; 3]> = (0..masked.accel.source_triangles().len())
        .map(|i| {
            let t = masked.accel.source_triangles()[i];
            [t.v0, t.v1, t.v2].map(|v| Vec3::from(v).as_dvec3() + masked.origin)
        })
        .collect();
    let solid = Scene::from_triangles("solid", masked.view, (64, 48), 1.0, tris).unwrap();
    let b = render(&solid, &job, &|_| {});
    let (ra, rb) = (a.occluded_rays as f64 / a.rays as f64, b.occluded_rays as f64 / b.rays as f64);
    eprintln!("foliage: occluded fraction {ra:.4} with masks, {rb:.4} solid");
    assert!(ra < 0.8 * rb, "masks {ra} vs solid {rb}");
}

#[test]
fn committed_foliage_scene_is_what_the_code_generates() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let (json, bin) = hemilab::scene::foliage::foliage().to_gltf("foliage.bin");
    assert!(std::fs::read(root.join("foliage.gltf")).unwrap() == json.as_bytes(), "foliage.gltf differs");
    assert!(std::fs::read(root.join("foliage.bin")).unwrap() == bin, "foliage.bin differs");
    let png = std::fs::read(root.join(hemilab::scene::foliage::LEAF_PNG)).unwrap();
    assert!(png == hemilab::scene::foliage::leaf_png(), "the leaf PNG differs");
}
