//! Where each pixel of a frame was in the previous frame, for a moving camera: the
//! `denoise::Motion` a temporal filter reads its history through. It lives here, not in `denoise/`,
//! because it needs the frames' cameras and G-buffers, which the renderer owns.
//!
//! Backward reprojection as in SVGF (Schied et al. 2017, §4.1 "temporal filtering") and TAA (Karis
//! 2014): each covered pixel's primary hit (its G-buffer position) is projected into the previous
//! frame's camera with that frame's jitter, giving a fractional position in the previous frame's
//! grid of sample points; its four bilinear neighbours are the candidate taps. A tap is kept only
//! if it is consistent with the current hit (Schied et al.'s geometric tests):
//!
//! * the previous pixel is covered;
//! * its depth is the one the current hit's surface predicts: |z_prev − z_expected| ≤
//!   `depth_tolerance` · z_expected, where z_expected is the distance along the previous pixel's
//!   own primary ray to the plane through the current hit with the current normal. Predicting along
//!   the tap's ray, not at the hit point, makes the test exact on planes at any angle: a grazing
//!   floor's taps a pixel apart differ in depth by far more than any fixed tolerance, yet are the
//!   same surface;
//! * its normal agrees: n · n_prev ≥ `normal_cos` (both face their own camera, so a surface seen
//!   from its other side in the previous frame fails this test).
//!
//! Weights of kept taps are renormalized to sum to 1; a pixel with none is disoccluded (its history
//! starts again). Everything is per pixel and independent, so the result does not depend on the
//! thread count.

use super::FrameGBuffer;
use crate::denoise::Motion;
use crate::scene::camera::Raster;
use glam::Vec3;
use rayon::prelude::*;

/// The consistency tests' thresholds (Schied et al. 2017, §4.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReprojectParams {
    /// Largest |z_prev − z_expected| / z_expected a kept tap may have. Default 0.02: the hit one
    /// pixel over on the same plane predicts its depth to rounding error, while a tap that lands on
    /// another surface (the box behind which the wall was hidden) is typically tens of percent off.
    pub depth_tolerance: f32,
    /// Least n · n_prev a kept tap may have. Default 0.9 (about 26°): neighbouring triangles of a
    /// smooth mesh pass, a crease or the far side of a surface does not.
    pub normal_cos: f32,
}

impl Default for ReprojectParams {
    fn default() -> Self {
        ReprojectParams { depth_tolerance: 0.02, normal_cos: 0.9 }
    }
}

/// A fractional tap position this close to a pixel (in pixels) is taken as that pixel: the
/// projection's rounding error (about 1e-5 px in f32) would otherwise put weights of 1e-5 on
/// neighbours, and a static camera without jitter must give exactly `Motion::identity`'s taps.
/// A 1e-3 px shift is far below anything an image shows.
pub const SNAP_PX: f32 = 1e-3;

/// The motion from `prev` to `cur` (two frames of one scene at one size): per covered pixel of
/// `cur`, its consistent bilinear taps into `prev`, or none (disoccluded: covered now but hidden,
/// off-screen or background in `prev`). Background pixels of `cur` have no taps either.
/// G-buffers of a window of the frames (`FrameGBuffer::window`, the same for both) reproject in
/// the full frame's pixel grid; a tap outside the window counts as off-screen.
pub fn reproject(prev: &FrameGBuffer, cur: &FrameGBuffer, params: &ReprojectParams) -> Motion {
    let (w, h) = (cur.gbuffer.width, cur.gbuffer.height);
    assert!(
        (prev.gbuffer.width, prev.gbuffer.height) == (w, h) && prev.window == cur.window,
        "reproject: frames of different sizes ({}x{} and {w}x{h}) or windows",
        prev.gbuffer.width,
        prev.gbuffer.height
    );
    let [full_w, full_h] = prev.window.full;
    let raster = prev.camera.raster_jittered(full_w, full_h, prev.jitter);
    let taps: Vec<Vec<(u32, f32)>> = (0..w as usize * h as usize)
        .into_par_iter()
        .map(|i| pixel_taps(prev, &raster, cur, i, params))
        .collect();
    let fallback: Vec<(u32, Vec<u32>)> = (0..w as usize * h as usize)
        .into_par_iter()
        .filter(|&i| cur.gbuffer.is_covered(i) && taps[i].is_empty())
        .filter_map(|i| {
            let list = fallback_taps(prev, &raster, cur, i, params);
            (!list.is_empty()).then_some((i as u32, list))
        })
        .collect();
    Motion::from_taps(w, h, taps).with_fallback(fallback)
}

/// Pixel `i`'s consistent previous pixels in the 3 × 3 neighbourhood of the pixel nearest to where
/// it projects (the fallback of Falcor's SVGFPass for a pixel none of whose bilinear taps is
/// consistent; the same tests decide).
fn fallback_taps(
    prev: &FrameGBuffer,
    raster: &Raster,
    cur: &FrameGBuffer,
    i: usize,
    params: &ReprojectParams,
) -> Vec<u32> {
    let (p, n) = (cur.position[i], cur.gbuffer.normal[i]);
    let (w, h) = (prev.gbuffer.width as i64, prev.gbuffer.height as i64);
    let (ox, oy) = (prev.window.x, prev.window.y);
    let Some(at) = raster.pixel_of(p) else { return Vec::new() };
    let (cx, cy) = (at.x.round() as i64 - ox as i64, at.y.round() as i64 - oy as i64);
    let mut kept = Vec::new();
    for dy in -1..=1 {
        for dx in -1..=1 {
            let (x, y) = (cx + dx, cy + dy);
            if x < 0 || y < 0 || x >= w || y >= h {
                continue;
            }
            let q = (y * w + x) as usize;
            if !prev.gbuffer.is_covered(q) {
                continue;
            }
            let ray = raster.ray(x as u32 + ox, y as u32 + oy);
            if consistent(
                p,
                n,
                (ray.origin, ray.dir),
                prev.gbuffer.depth.data[q],
                prev.gbuffer.normal[q],
                params,
            ) {
                kept.push(q as u32);
            }
        }
    }
    kept
}

/// Pixel `i`'s kept taps into `prev` (index, bilinear weight before renormalization).
fn pixel_taps(
    prev: &FrameGBuffer,
    raster: &Raster,
    cur: &FrameGBuffer,
    i: usize,
    params: &ReprojectParams,
) -> Vec<(u32, f32)> {
    if !cur.gbuffer.is_covered(i) {
        return Vec::new();
    }
    let (p, n) = (cur.position[i], cur.gbuffer.normal[i]);
    let (w, h) = (prev.gbuffer.width, prev.gbuffer.height);
    let (ox, oy) = (prev.window.x, prev.window.y);
    let Some(at) = raster.pixel_of(p) else { return Vec::new() };
    let (x0, ax) = split(at.x);
    let (y0, ay) = split(at.y);
    let (x0, y0) = (x0 - ox as i64, y0 - oy as i64);
    let mut kept = Vec::with_capacity(4);
    for (dx, dy, weight) in
        [(0, 0, (1.0 - ax) * (1.0 - ay)), (1, 0, ax * (1.0 - ay)), (0, 1, (1.0 - ax) * ay), (1, 1, ax * ay)]
    {
        let (x, y) = (x0 + dx, y0 + dy);
        if weight <= 0.0 || x < 0 || y < 0 || x >= w as i64 || y >= h as i64 {
            continue;
        }
        let (x, y) = (x as u32, y as u32);
        let q = y as usize * w as usize + x as usize;
        if !prev.gbuffer.is_covered(q) {
            continue;
        }
        let ray = raster.ray(x + ox, y + oy);
        if consistent(p, n, (ray.origin, ray.dir), prev.gbuffer.depth.data[q], prev.gbuffer.normal[q], params)
        {
            kept.push((q as u32, weight));
        }
    }
    kept
}

/// The integer pixel at or below `v` and the fraction past it, snapped to the pixel within
/// `SNAP_PX`.
fn split(v: f32) -> (i64, f32) {
    let base = v.floor();
    let frac = v - base;
    if frac < SNAP_PX {
        (base as i64, 0.0)
    } else if frac > 1.0 - SNAP_PX {
        (base as i64 + 1, 0.0)
    } else {
        (base as i64, frac)
    }
}

/// Whether a previous pixel (primary ray `origin` + t `dir`, hit at depth `z_prev` with normal
/// `n_prev`) saw the surface of the current hit `p` with normal `n` (the tests of the module doc).
fn consistent(
    p: Vec3,
    n: Vec3,
    (origin, dir): (Vec3, Vec3),
    z_prev: f32,
    n_prev: Vec3,
    params: &ReprojectParams,
) -> bool {
    if n.dot(n_prev) < params.normal_cos {
        return false;
    }
    // The tap ray's distance to p's tangent plane; along the ray to p's foot when the ray nearly
    // grazes the plane (the normal test has then already passed, so the plane is a sliver).
    let denom = dir.dot(n);
    let expected = if denom.abs() > 1e-3 { (p - origin).dot(n) / denom } else { (p - origin).dot(dir) };
    expected > 0.0 && (z_prev - expected).abs() <= params.depth_tolerance * expected
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_snaps_rounding_error_to_the_pixel() {
        assert_eq!(split(3.0), (3, 0.0));
        assert_eq!(split(2.99999), (3, 0.0));
        assert_eq!(split(3.00001), (3, 0.0));
        assert_eq!(split(-0.25), (-1, 0.75));
        let (b, f) = split(4.5);
        assert_eq!((b, f), (4, 0.5));
    }

    #[test]
    fn a_plane_seen_at_a_grazing_angle_is_consistent_along_the_tap_ray() {
        let params = ReprojectParams::default();
        // A floor z = 0, hit p; a tap ray from (0, 0, 1) at a grazing angle reaching the floor at
        // t = 50, far from p along the floor: the same plane, so consistent.
        let (p, n) = (Vec3::new(40.0, 0.0, 0.0), Vec3::Z);
        let dir = Vec3::new(1.0, 0.0, -0.02).normalize();
        let origin = Vec3::new(0.0, 0.0, 1.0);
        let t = 1.0 / (0.02 / (1.0f32 + 0.0004).sqrt());
        assert!(consistent(p, n, (origin, dir), t, n, &params));
        assert!(!consistent(p, n, (origin, dir), 0.9 * t, n, &params), "another surface in front");
        assert!(!consistent(p, n, (origin, dir), t, -n, &params), "the other side");
    }
}
