//! A moving camera's frames: `render_view` and `frame_gbuffer` trace each frame's own
//! camera and jitter, and `reproject` finds where each pixel was in the previous frame. Checked
//! against an independent, analytic computation on a scene whose visibility and AO are closed
//! forms (`support::parallax`: a floor under a floating rectangle): the reprojected reference is
//! the next frame's reference, the disoccluded pixels are those the geometry predicts (the floor
//! the rectangle hid from the previous eye, and what enters at the image's edge), and a static
//! camera reprojects to the identity, or to the bilinear taps of the jitter's difference.

use crate::support::parallax::{self, Caster, Sample, Surface};
// The G-buffer's positions are relative to `Scene::origin`, the scene camera's eye.
use glam::{DVec3, Vec2};
use hemilab::denoise::Motion;
use hemilab::render::{
    FrameGBuffer, RenderJob, ReprojectParams, View, frame_gbuffer, gbuffer, render, render_view, reproject,
};
use hemilab::sampling::{Distribution, Integrand, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::camera_path::{CameraPath, Keyframe, halton_jitter};
use hemilab::scene::{Scene, WorldCamera};

const RES: (u32, u32) = (64, 48);

/// One frame of a path: its view, the library's G-buffer and the analytic samples.
struct Frame {
    gb: FrameGBuffer,
    caster: Caster,
    samples: Vec<Sample>,
}

fn frame(scene: &Scene, camera: WorldCamera, jitter: Vec2) -> Frame {
    let gb = frame_gbuffer(scene, RES.0, RES.1, &View::new(camera, jitter));
    let caster = Caster::new(&camera, RES, jitter);
    let samples =
        (0..RES.1).flat_map(|y| (0..RES.0).map(move |x| (x, y))).map(|(x, y)| caster.sample(x, y)).collect();
    Frame { gb, caster, samples }
}

fn frames(scene: &Scene, path: &CameraPath, count: u32, jitter: bool) -> Vec<Frame> {
    path.validate(&scene.view, count).unwrap();
    (0..count)
        .map(|f| {
            let j = if jitter { halton_jitter(f) } else { Vec2::ZERO };
            frame(scene, path.camera(&scene.view, f, count), j)
        })
        .collect()
}

/// What the analytic check of one pair of frames found.
#[derive(Debug, Default)]
struct Found {
    /// Pixels whose taps were compared with the analytic ones.
    checked: usize,
    /// Pixels left out: a sample within `EDGE` of the rectangle's outline, or a tap position
    /// within the snap band of a pixel (where rounding decides which taps have weight).
    ambiguous: usize,
    /// Floor pixels the rectangle hid from the previous eye.
    hidden: usize,
    /// Pixels whose footprint lies wholly outside the previous image.
    off_screen: usize,
    disoccluded: usize,
    /// Largest and mean |reprojected previous reference − current reference| over pixels with all
    /// four taps kept (bilinear interpolation's error), and the largest over pixels with some
    /// rejected (the kept taps' renormalized weights extrapolate up to a pixel).
    max_error: f64,
    mean_error: f64,
    max_error_partial: f64,
}

/// Compares `reproject(prev, cur)` with the analytic taps: per pixel, the bilinear footprint of its
/// sample point in the previous frame, keeping the taps whose previous sample is on the same
/// surface (floor or rectangle) — exactly what the depth and normal tests must keep on this scene
/// (the rectangle's top and the floor share a normal; their depths along a ray differ by 40%).
fn check_pair(prev: &Frame, cur: &Frame, what: &str) -> Found {
    let motion = reproject(&prev.gb, &cur.gb, &ReprojectParams::default());
    let (w, h) = (RES.0 as i64, RES.1 as i64);
    let reference_prev: Vec<f64> = prev.samples.iter().map(parallax::exact_ao).collect();
    let mut found = Found::default();
    let mut error_sum = 0.0;
    let mut with_history = 0usize;
    for (i, s) in cur.samples.iter().enumerate() {
        let taps = motion.taps(i);
        if s.surface == Surface::Background {
            assert!(!cur.gb.gbuffer.is_covered(i) && taps.is_empty(), "{what}: pixel {i} is background");
            continue;
        }
        if s.near_edge {
            found.ambiguous += 1;
            continue;
        }
        assert!(cur.gb.gbuffer.is_covered(i), "{what}: pixel {i}");
        let world = cur.gb.position[i].as_dvec3() + parallax::camera().eye();
        assert!(
            (world - s.point).length() < 2e-4 * (s.point - cur.caster.eye()).length(),
            "{what}: pixel {i}: {world} vs {}",
            s.point
        );
        let (fx, fy) = prev.caster.pixel_of(s.point).expect("in front of every eye");
        let (x0, y0) = (fx.floor(), fy.floor());
        let (ax, ay) = (fx - x0, fy - y0);
        let band = |a: f64| !(2e-3..=1.0 - 2e-3).contains(&a);
        if band(ax) || band(ay) {
            found.ambiguous += 1;
            continue;
        }
        let mut expected = Vec::new();
        let (mut in_bounds, mut ambiguous) = (0, false);
        let mut surfaces = Vec::new();
        for (dx, dy, wt) in [
            (0, 0, (1.0 - ax) * (1.0 - ay)),
            (1, 0, ax * (1.0 - ay)),
            (0, 1, (1.0 - ax) * ay),
            (1, 1, ax * ay),
        ] {
            let (x, y) = (x0 as i64 + dx, y0 as i64 + dy);
            if x < 0 || y < 0 || x >= w || y >= h {
                continue;
            }
            in_bounds += 1;
            let q = (y * w + x) as usize;
            ambiguous |= prev.samples[q].near_edge;
            surfaces.push(prev.samples[q].surface);
            if prev.samples[q].surface == s.surface {
                expected.push((q as u32, wt));
            }
        }
        let (hidden, hidden_edge) =
            if s.surface == Surface::Floor { prev.caster.hidden(s.point) } else { (false, false) };
        if ambiguous || hidden_edge {
            found.ambiguous += 1;
            continue;
        }
        found.checked += 1;
        if let Some(v) = motion.gather(&reference_prev, i) {
            let e = (v - parallax::exact_ao(s)).abs();
            if taps.len() == 4 {
                found.max_error = found.max_error.max(e);
                error_sum += e;
                with_history += 1;
            } else {
                found.max_error_partial = found.max_error_partial.max(e);
            }
        }
        let sum: f64 = expected.iter().map(|&(_, w)| w).sum();
        let got: Vec<(u32, f64)> = taps.iter().map(|t| (t.index, t.weight as f64)).collect();
        assert_eq!(
            got.iter().map(|t| t.0).collect::<Vec<_>>(),
            expected.iter().map(|t| t.0).collect::<Vec<_>>(),
            "{what}: pixel {i} ({:?}) at ({fx:.3}, {fy:.3}) in the previous frame",
            s.surface
        );
        for (&(_, g), &(_, e)) in got.iter().zip(&expected) {
            assert!((g - e / sum).abs() < 1e-3, "{what}: pixel {i}: weight {g} vs {}", e / sum);
        }
        // The geometric prediction: a pixel whose footprint is one surface, wholly in the previous
        // image, is disoccluded exactly when the rectangle hid its point from the previous eye.
        // (The rectangle is convex, so four samples on it enclose only points behind it, and a
        // straight outline between a point and all four of its taps is impossible; only within a
        // couple of pixels of a corner can the corner slip between them.)
        found.hidden += hidden as usize;
        found.off_screen += (in_bounds == 0) as usize;
        found.disoccluded += taps.is_empty() as usize;
        let near_corner = parallax::rectangle()
            .iter()
            .any(|&c| prev.caster.pixel_of(c).is_some_and(|(cx, cy)| (cx - fx).hypot(cy - fy) < 2.0));
        if in_bounds == 4 && surfaces.iter().all(|&f| f == surfaces[0]) && !near_corner {
            assert_eq!(
                taps.is_empty(),
                hidden,
                "{what}: pixel {i}: disoccluded iff hidden from the previous eye"
            );
        }
        if in_bounds == 0 {
            assert!(taps.is_empty(), "{what}: pixel {i} was off-screen");
        }
    }
    found.mean_error = error_sum / with_history.max(1) as f64;
    found
}

#[test]
fn reprojection_of_the_reference_along_a_path_is_the_next_reference_except_where_geometry_disoccludes() {
    let scene = parallax::scene(RES);
    let o = parallax::OFFSET;
    let truck = CameraPath::Keyframes(vec![
        Keyframe {
            frame: 0,
            eye: (o + DVec3::new(0.3, -2.5, 2.0)).to_array(),
            target: (o + DVec3::new(0.1, 0.1, 0.3)).to_array(),
        },
        Keyframe {
            frame: 4,
            eye: (o + DVec3::new(1.5, -2.5, 2.0)).to_array(),
            target: (o + DVec3::new(1.3, 0.1, 0.3)).to_array(),
        },
    ]);
    let paths = [
        ("orbit", CameraPath::Orbit { degrees: 24.0 }),
        ("truck", truck),
        ("dolly", CameraPath::Dolly { distance: 0.6 }),
        ("pan", CameraPath::Pan { degrees: 8.0 }),
    ];
    for (name, path) in paths {
        let fs = frames(&scene, &path, 5, true);
        for t in 1..fs.len() {
            let what = format!("{name}, frame {} -> {t}", t - 1);
            let found = check_pair(&fs[t - 1], &fs[t], &what);
            let pixels = (RES.0 * RES.1) as usize;
            assert!(found.ambiguous * 20 < pixels, "{what}: {found:?}: few pixels are left out");
            assert!(found.max_error < 3e-3 && found.mean_error < 2e-4, "{what}: {found:?}");
            assert!(found.max_error_partial < 0.05, "{what}: {found:?}");
            match name {
                // Pure rotation: no parallax, so nothing is uncovered but what turns into view.
                "pan" => assert!(found.hidden == 0 && found.off_screen > 20, "{what}: {found:?}"),
                "orbit" | "truck" => {
                    assert!(found.hidden >= 10, "{what}: {found:?}: the rectangle uncovers floor")
                }
                _ => {}
            }
            eprintln!("{what}: {found:?}");
        }
    }
}

#[test]
fn static_path_without_jitter_reprojects_to_the_identity() {
    let scene = parallax::scene(RES);
    let fs = frames(&scene, &CameraPath::Static, 2, false);
    assert_eq!(fs[0].gb, fs[1].gb);
    let motion = reproject(&fs[0].gb, &fs[1].gb, &ReprojectParams::default());
    let identity = Motion::identity(RES.0, RES.1);
    let mut covered = 0;
    for i in 0..(RES.0 * RES.1) as usize {
        if fs[1].gb.gbuffer.is_covered(i) {
            covered += 1;
            assert_eq!(motion.taps(i), identity.taps(i), "pixel {i}: weight 1 on itself");
        } else {
            assert!(!motion.has_history(i));
        }
    }
    assert_eq!(covered, RES.0 * RES.1, "the floor fills the view");
    let floor = hemilab::scene::procedural::open_floor(hemilab::scene::procedural::Placement::UNIT, RES);
    let g = frame_gbuffer(&floor, RES.0, RES.1, &View::SCENE);
    let m = reproject(&g, &g, &ReprojectParams::default());
    for i in 0..(RES.0 * RES.1) as usize {
        assert_eq!(
            m.taps(i),
            if g.gbuffer.is_covered(i) { identity.taps(i) } else { &[] },
            "open floor, pixel {i}"
        );
    }
}

#[test]
fn static_path_with_jitter_taps_the_bilinear_neighbours_of_the_jitter_difference_and_rejects_none() {
    let scene = parallax::scene(RES);
    let fs = frames(&scene, &CameraPath::Static, 6, true);
    let (w, h) = (RES.0 as i64, RES.1 as i64);
    for t in 1..fs.len() {
        let (prev, cur) = (&fs[t - 1], &fs[t]);
        let motion = reproject(&prev.gb, &cur.gb, &ReprojectParams::default());
        let d = halton_jitter(t as u32) - halton_jitter(t as u32 - 1);
        let (bx, by) = (d.x.floor(), d.y.floor());
        let (ax, ay) = ((d.x - bx) as f64, (d.y - by) as f64);
        let (mut full, mut straddling) = (0, 0);
        for y in 0..h {
            for x in 0..w {
                let i = (y * w + x) as usize;
                assert!(motion.has_history(i), "frame {t}: pixel {i}: a static camera disoccludes nothing");
                let s = &cur.samples[i];
                let mut expected = Vec::new();
                let mut all_same = !s.near_edge;
                for (dx, dy, wt) in [
                    (0, 0, (1.0 - ax) * (1.0 - ay)),
                    (1, 0, ax * (1.0 - ay)),
                    (0, 1, (1.0 - ax) * ay),
                    (1, 1, ax * ay),
                ] {
                    let (qx, qy) = (x + bx as i64 + dx, y + by as i64 + dy);
                    if qx < 0 || qy < 0 || qx >= w || qy >= h {
                        all_same = false;
                        continue;
                    }
                    let q = (qy * w + qx) as usize;
                    all_same &= prev.samples[q].surface == s.surface && !prev.samples[q].near_edge;
                    expected.push((q as u32, wt));
                }
                if !all_same {
                    straddling += 1;
                    continue;
                }
                full += 1;
                let got: Vec<(u32, f64)> =
                    motion.taps(i).iter().map(|t| (t.index, t.weight as f64)).collect();
                assert_eq!(
                    got.len(),
                    expected.len(),
                    "frame {t}: pixel {i}: no tap rejected: {got:?} vs {expected:?}"
                );
                for (g, e) in got.iter().zip(&expected) {
                    assert!(
                        g.0 == e.0 && (g.1 - e.1).abs() < 1e-3,
                        "frame {t}: pixel {i}: {got:?} vs {expected:?}"
                    );
                }
            }
        }
        assert!(
            full > 9 * straddling,
            "frame {t}: {full} checked, {straddling} straddle the outline or the edge"
        );
    }
}

#[test]
fn reprojection_is_the_same_for_any_thread_count() {
    let scene = parallax::scene(RES);
    let fs = frames(&scene, &CameraPath::Orbit { degrees: 10.0 }, 2, true);
    let all = reproject(&fs[0].gb, &fs[1].gb, &ReprojectParams::default());
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    assert_eq!(pool.install(|| reproject(&fs[0].gb, &fs[1].gb, &ReprojectParams::default())), all);
    let g = pool.install(|| frame_gbuffer(&scene, RES.0, RES.1, &View::new(scene.view, halton_jitter(3))));
    assert_eq!(g, frame_gbuffer(&scene, RES.0, RES.1, &View::new(scene.view, halton_jitter(3))));
}

fn job(scene: &Scene, rays: u32) -> RenderJob {
    crate::support::jobs::render_job(
        Distribution::SineCosine,
        SamplerConfig::new(Sequence::Fibonacci, SeedMode::Shift, rays, 7).unwrap(),
        (RES.0, RES.1),
        scene.ao_distance,
    )
}

#[test]
fn render_view_of_the_scene_camera_without_jitter_is_render_bit_for_bit() {
    let scene = parallax::scene(RES);
    let j = job(&scene, 8);
    let plain = render(&scene, &j, &|_| {});
    for view in [View::SCENE, View::new(scene.view, Vec2::ZERO)] {
        let v = render_view(&scene, &j, Integrand::Ao, &view, &|_| {});
        assert_eq!(
            v.ao.data.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            plain.ao.data.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
        );
        assert_eq!(
            (v.coverage, v.rays, v.occluded_rays),
            (plain.coverage.clone(), plain.rays, plain.occluded_rays)
        );
    }
    assert_eq!(frame_gbuffer(&scene, RES.0, RES.1, &View::SCENE).gbuffer, gbuffer(&scene, RES.0, RES.1));
}

/// Each frame's AO rays start from that frame's own hits: pixels whose (moved, jittered) ray hits
/// the rectangle's top see nothing above it (AO exactly 1), and floor pixels under much of the
/// rectangle are occluded; with the scene's camera the same pixels would mostly be others.
#[test]
fn render_view_traces_the_frames_camera_and_jitter() {
    let scene = parallax::scene(RES);
    let path = CameraPath::Orbit { degrees: 40.0 };
    let camera = path.camera(&scene.view, 1, 2);
    let jitter = Vec2::new(0.37, -0.41);
    let out = render_view(&scene, &job(&scene, 64), Integrand::Ao, &View::new(camera, jitter), &|_| {});
    let caster = Caster::new(&camera, RES, jitter);
    let (mut rect, mut shadowed) = (0, 0);
    for y in 0..RES.1 {
        for x in 0..RES.0 {
            let (s, i) = (caster.sample(x, y), (y * RES.0 + x) as usize);
            if s.near_edge {
                continue;
            }
            match s.surface {
                Surface::Rect => {
                    rect += 1;
                    assert_eq!(out.ao.data[i], 1.0, "pixel ({x}, {y}) is on the rectangle's top");
                }
                Surface::Floor if parallax::exact_ao(&s) < 0.8 => {
                    shadowed += 1;
                    assert!(out.ao.data[i] < 1.0, "pixel ({x}, {y}) is on the floor under the rectangle");
                }
                _ => {}
            }
        }
    }
    assert!(rect > 100 && shadowed > 20, "{rect} rectangle pixels, {shadowed} shadowed floor pixels");
}

/// Falcor's 3 × 3 fallback (`Motion::fallback`) is offered only for covered pixels without taps,
/// and each neighbour it offers is a covered previous pixel; with a static camera there is none.
#[test]
fn the_fallback_neighbours_are_covered_and_only_for_pixels_without_taps() {
    let scene = parallax::scene(RES);
    let fs = frames(&scene, &CameraPath::Orbit { degrees: 24.0 }, 5, true);
    let mut offered = 0;
    for pair in fs.windows(2) {
        let motion = reproject(&pair[0].gb, &pair[1].gb, &ReprojectParams::default());
        for i in 0..(RES.0 * RES.1) as usize {
            let fb = motion.fallback(i);
            if !fb.is_empty() {
                offered += 1;
                assert!(!motion.has_history(i) && pair[1].gb.gbuffer.is_covered(i), "pixel {i}");
                assert!(fb.len() <= 9 && fb.iter().all(|&q| pair[0].gb.gbuffer.is_covered(q as usize)));
            }
        }
    }
    eprintln!("{offered} fallbacks offered over 4 orbit steps");
    let still = frames(&scene, &CameraPath::Static, 2, false);
    let m = reproject(&still[0].gb, &still[1].gb, &ReprojectParams::default());
    assert!((0..(RES.0 * RES.1) as usize).all(|i| m.fallback(i).is_empty()));
}
