//! Scenes whose AO is known exactly: the open floor (no ray is ever blocked, so AO is exactly 1 on
//! every covered pixel) and the closed box (every ray is blocked), for every distribution, sequence,
//! seed mode and ray count, at unit size, scaled by 1e-3 (also moved a few units away) and 1e3, and
//! translated by 1e3 and 1e4.

use glam::DVec3;
use hemilab::render::render;
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::Scene;
use hemilab::scene::procedural::{Placement, closed_box, open_floor};

const RAYS: [u32; 4] = [1, 8, 32, 1024];
const RES: (u32, u32) = (8, 6);

fn placements() -> [(&'static str, Placement); 6] {
    [
        ("unit", Placement::UNIT),
        ("scaled 1e-3", Placement { scale: 1e-3, offset: DVec3::ZERO }),
        ("scaled 1e-3, moved 3 units", Placement { scale: 1e-3, offset: DVec3::new(3.0, -2.0, 1.5) }),
        ("scaled 1e3", Placement { scale: 1e3, offset: DVec3::ZERO }),
        ("translated 1e3", Placement { scale: 1.0, offset: DVec3::new(1e3, 1e3, -1e3) }),
        ("translated 1e4", Placement { scale: 1.0, offset: DVec3::new(1e4, -1e4, 1e4) }),
    ]
}

/// Calls `check` with the output of every distribution × sequence × seed mode × ray count.
fn every_job(scene: &Scene, mut check: impl FnMut(&str, hemilab::render::RenderOutput)) {
    for &distribution in Distribution::ALL {
        for sequence in Sequence::all() {
            for &seed_mode in SeedMode::ALL {
                for rays in RAYS {
                    let sampler = SamplerConfig::new(sequence, seed_mode, rays, 7).unwrap();
                    let job = crate::support::jobs::render_job(
                        distribution,
                        sampler,
                        (RES.0, RES.1),
                        scene.ao_distance,
                    );
                    let what = format!("{} {distribution} {sequence} {seed_mode} {rays} rays", scene.name);
                    check(&what, render(scene, &job, &|_| {}));
                }
            }
        }
    }
}

#[test]
fn open_floor_is_exactly_unoccluded_at_every_scale() {
    for (label, at) in placements() {
        let scene = open_floor(at, RES);
        every_job(&scene, |what, out| {
            let covered = out.coverage.data.iter().filter(|&&c| c == 1.0).count();
            assert!(covered >= 10, "{label} {what}: only {covered} floor pixels in view");
            assert_eq!(out.occluded_rays, 0, "{label} {what}: floor rays were blocked");
            for (a, c) in out.ao.data.iter().zip(&out.coverage.data) {
                if *c == 1.0 {
                    assert_eq!(*a, 1.0, "{label} {what}: AO {a} on the open floor");
                }
            }
        });
    }
}

#[test]
fn closed_box_blocks_every_ray_at_every_scale() {
    for (label, at) in placements() {
        let scene = closed_box(at, RES);
        every_job(&scene, |what, out| {
            assert!(out.coverage.data.iter().all(|&c| c == 1.0), "{label} {what}: box not all covered");
            assert_eq!(out.rays, RES.0 as u64 * RES.1 as u64 * (out.rays / (RES.0 * RES.1) as u64));
            assert_eq!(out.occluded_rays, out.rays, "{label} {what}: rays escaped the closed box");
            if what.contains(" sine-cosine ") {
                // Weight 1 per ray: every blocked ray makes the estimate exactly 1, the image exactly 0.
                assert!(out.ao.data.iter().all(|&a| a == 0.0), "{label} {what}: {:?}", out.ao.data);
            }
        });
    }
}
