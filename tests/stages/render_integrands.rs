//! The renderer's integrands against their closed forms.
//!
//! Inside a closed room (the cube of half-size 1 of `render_closed_room`, the centred camera,
//! d infinite) every ray is blocked, so a pixel's value is 1 − the mean of its rays' weights f/p:
//! - the matched pairs (visibility × sine, AO × sine-cosine and concentric-cosine) have every weight
//!   exactly 1, so every covered pixel is exactly 0 at every ray count;
//! - at 1 ray per pixel with fresh pseudo-random numbers per pixel, the pixels are independent draws
//!   of one weight, so their variance is the per-ray variance ∫ f²/p dω − 1 of
//!   `Integrand::closed_room_variance`. Tolerance: 5 standard errors of the sample variance,
//!   √((m4 − s⁴)/N) from the sample's own fourth moment, N = 76,800 pixels (a false failure in one of
//!   the ~16 cells has probability below 1e-5 for near-normal sample variances);
//! - the infinite cell (sine-cosine × visibility, weight 1/(2 cos θ)) is told by its largest weight:
//!   above `Integrand::weight_bound` of every finite cell (≤ 33 here) in 4 renders of 76,800 rays;
//!   P(all of 307,200 weights ≤ 100) = (1 − 2.5e-5)^307200 ≈ 5e-4 (the seeds are fixed, so this
//!   is decided once), and its pixel variance is larger than every finite cell's of that integrand.
//!
//! A closed-form occluded case: a floor point under the floating rectangle, visibility. Its occluded
//! fraction is the solid angle of the rectangle over 2π (Van Oosterom & Strackee 1983, per triangle);
//! pooled over the floor pixels and 32 seeds, per distribution and sequence, the mean signed error is
//! within the Šidák-corrected z of its standard error (the test of `render_closed_form` for AO).

use crate::support::lambert::{Pooled, exact_pixels};
use crate::support::stats::{sidak_threshold, two_sided_z};
use glam::DVec3;
use hemilab::render::{RenderJob, RenderOutput, render, render_integrand};
use hemilab::sampling::{Distribution, Integrand, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::procedural::{RECT_MAX, RECT_MIN, RECT_Z, floating_rectangle};
use hemilab::scene::{Camera, Scene};

const RES: (u32, u32) = (320, 240);

/// The closed cube [-1, 1]³ seen from (0, 0, 0.5) looking down −z, fov 80° (the set-up).
fn room(res: (u32, u32)) -> Scene {
    let v = DVec3::new;
    let tris = crate::support::room::cube_triangles(|v| v);
    let cam = Camera::Perspective {
        eye: v(0.0, 0.0, 0.5),
        target: v(0.0, 0.0, -1.0),
        up: DVec3::Y,
        fov_y_deg: 80.0,
    };
    Scene::from_triangles("closed-room", cam, res, f32::INFINITY, tris).unwrap()
}

fn job(
    d: Distribution,
    sequence: Sequence,
    seed_mode: SeedMode,
    rays: u32,
    seed: u64,
    res: (u32, u32),
) -> RenderJob {
    crate::support::jobs::render_job(
        d,
        SamplerConfig::new(sequence, seed_mode, rays, seed).unwrap(),
        (res.0, res.1),
        f32::INFINITY,
    )
}

/// The covered pixels' values.
fn covered(out: &RenderOutput) -> Vec<f64> {
    out.ao.data.iter().zip(&out.coverage.data).filter(|(_, c)| **c == 1.0).map(|(a, _)| *a as f64).collect()
}

fn lobes() -> [Integrand; 5] {
    [
        Integrand::Visibility,
        Integrand::Ao,
        Integrand::CosLobe(4),
        Integrand::CosLobe(8),
        Integrand::CosLobe(32),
    ]
}

/// `Integrand::Ao` is today's renderer, bit for bit (every existing image and reference is unchanged).
#[test]
fn ao_integrand_is_the_plain_render_bit_for_bit() {
    let scene = floating_rectangle((24, 16));
    for &d in Distribution::ALL {
        let j = job(d, Sequence::Fibonacci, SeedMode::Rotation, 12, 3, (24, 16));
        let (a, b) = (render(&scene, &j, &|_| {}), render_integrand(&scene, &j, Integrand::Ao, &|_| {}));
        let bits = |o: &RenderOutput| o.ao.data.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a), bits(&b), "{d}");
    }
}

/// Visibility × sine and AO × the cosine-weighted warps: every covered pixel exactly 0 (occlusion
/// exactly 1) at 1 and 32 rays (320x240) and 1024 rays (80x60), lattice and pseudo-random.
#[test]
fn matched_pairs_are_exact_in_the_closed_room() {
    let pairs = [
        (Integrand::Visibility, Distribution::Sine),
        (Integrand::Ao, Distribution::SineCosine),
        (Integrand::Ao, Distribution::ConcentricCosine),
    ];
    let big = room(RES);
    let small = room((80, 60));
    let mut failures = Vec::new();
    for (i, d) in pairs {
        assert!(i.unit_weight(d) && i.closed_room_variance(d) == 0.0);
        for (rays, scene, res) in [(1, &big, RES), (32, &big, RES), (1024, &small, (80, 60))] {
            for (s, m) in [(Sequence::Fibonacci, SeedMode::Rotation), (Sequence::Random, SeedMode::Shift)] {
                let out = render_integrand(scene, &job(d, s, m, rays, 3, res), i, &|_| {});
                let px = covered(&out);
                let off = px.iter().filter(|&&v| v != 0.0).count();
                if px.len() != (res.0 * res.1) as usize || off != 0 || out.occluded_rays != out.rays {
                    failures.push(format!("{i} {d} {s} {m} {rays} rays: {off} of {} pixels not 0", px.len()));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Mean, variance, fourth central moment and largest value of `x`.
fn moments(x: &[f64]) -> (f64, f64, f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let m2 = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    let m4 = x.iter().map(|v| (v - mean).powi(4)).sum::<f64>() / n;
    (mean, m2, m4, x.iter().cloned().fold(f64::MIN, f64::max))
}

/// At 1 ray per pixel the variance over pixels of every cell is its closed form; the infinite cell
/// is detected by its largest weight and never given a finite variance.
#[test]
fn one_ray_pixel_variance_matches_the_closed_form_per_cell() {
    let scene = room(RES);
    let mut report = Vec::new();
    let mut failures = Vec::new();
    for i in lobes() {
        for &d in Distribution::ALL {
            let want = i.closed_room_variance(d);
            let seeds: &[u64] = if want.is_infinite() { &[11, 12, 13, 14] } else { &[11] };
            // The weights: 1 − the pixel's value (every ray blocked).
            let mut w = Vec::new();
            for &seed in seeds {
                let out = render_integrand(
                    &scene,
                    &job(d, Sequence::Random, SeedMode::Rotation, 1, seed, RES),
                    i,
                    &|_| {},
                );
                assert_eq!(out.occluded_rays, out.rays, "{i} {d}: a ray escaped");
                w.extend(covered(&out).iter().map(|v| 1.0 - v));
            }
            let (mean, m2, m4, max) = moments(&w);
            let n = w.len() as f64;
            if want.is_infinite() {
                let finite_max = lobes()
                    .iter()
                    .flat_map(|j| Distribution::ALL.iter().map(move |e| j.weight_bound(*e)))
                    .filter(|b| b.is_finite())
                    .fold(0.0, f64::max);
                report.push(format!(
                    "{i} {d}: infinite; largest weight {max:.1} (finite cells ≤ {finite_max:.1})"
                ));
                if max <= 100.0 || max <= finite_max {
                    failures
                        .push(format!("{i} {d}: largest weight {max} does not show the infinite variance"));
                }
                continue;
            }
            let se_mean = (m2 / n).sqrt();
            let se_var = ((m4 - m2 * m2).max(0.0) / n).sqrt();
            report.push(format!("{i} {d}: variance {m2:.4} vs closed form {want:.4} ± {se_var:.4}"));
            if (mean - 1.0).abs() > 5.0 * se_mean + 1e-6 {
                failures.push(format!("{i} {d}: mean weight {mean} ± {se_mean}"));
            }
            if (m2 - want).abs() > 5.0 * se_var + 1e-6 {
                failures.push(format!("{i} {d}: variance {m2} vs {want} ± {se_var}"));
            }
            if max > i.weight_bound(d) * (1.0 + 1e-5) {
                failures.push(format!("{i} {d}: weight {max} above its bound {}", i.weight_bound(d)));
            }
        }
    }
    eprintln!("{}", report.join("\n"));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Solid angle of the triangle (a, b, c) seen from the origin (Van Oosterom & Strackee 1983).
fn triangle_solid_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c)).abs();
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * num.atan2(den)
}

/// A floor point under the floating rectangle: visibility's pixel value 1 − Ω/2π, pooled over floor
/// pixels and seeds, every distribution with pseudo-random and lattice points (`shift`: unbiased).
#[test]
fn visibility_under_the_rectangle_matches_its_solid_angle() {
    const SIDE: u32 = 16;
    const SEEDS: u64 = 32;
    let scene = floating_rectangle((SIDE, SIDE));
    let (lo, hi, z) = (RECT_MIN, RECT_MAX, RECT_Z);
    let origin = scene.origin;
    let exact = |o: DVec3, n: DVec3| {
        let p = o + origin;
        // Floor pixels only (normal +z, below the rectangle's plane, outside its shadow).
        let under = p.x > lo[0] && p.x < hi[0] && p.y > lo[1] && p.y < hi[1];
        if n.z < 0.999 || p.z > 0.5 * z || under {
            return None;
        }
        let q = [
            DVec3::new(lo[0], lo[1], z),
            DVec3::new(hi[0], lo[1], z),
            DVec3::new(hi[0], hi[1], z),
            DVec3::new(lo[0], hi[1], z),
        ]
        .map(|v| v - p);
        let omega = triangle_solid_angle(q[0], q[1], q[2]) + triangle_solid_angle(q[0], q[2], q[3]);
        Some(1.0 - omega / (2.0 * std::f64::consts::PI))
    };
    let pixels = exact_pixels(&scene, SIDE, exact);
    assert!(pixels.len() > 100, "{} floor pixels", pixels.len());
    let z_pooled = two_sided_z(sidak_threshold(0.01, Distribution::ALL.len() * 2));
    let mut failures = Vec::new();
    for &d in Distribution::ALL {
        for sequence in [Sequence::Random, Sequence::Fibonacci] {
            let mut pool = Pooled::new((SIDE * SIDE) as usize);
            for seed in 0..SEEDS {
                let j = job(d, sequence, SeedMode::Shift, 32, 500 + seed, (SIDE, SIDE));
                pool.add(&render_integrand(&scene, &j, Integrand::Visibility, &|_| {}).ao.data);
            }
            let (bias, se) = pool.bias(&pixels);
            eprintln!("visibility {d} {sequence}: mean signed error {bias:+.6}, SE {se:.6}");
            if bias.abs() > z_pooled * se {
                failures.push(format!("{d} {sequence}: {bias:+.6} is {:.1} SE", bias.abs() / se));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn solid_angle_sanity() {
    // An octant's face triangle: the three unit axes bound 1/8 of the sphere, 4π/8.
    let o = triangle_solid_angle(DVec3::X, DVec3::Y, DVec3::Z);
    assert!((o - std::f64::consts::PI / 2.0).abs() < 1e-12, "{o}");
}
