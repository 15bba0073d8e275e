//! The renderer's primary rays: the square tiles it works in, their pixels' order, and each
//! pixel's primary hit (`tile_primaries`, what `render`, `gbuffer` and `sight` share, so that their
//! hits are the same bits).

use super::Window;
use crate::scene::Scene;
use crate::scene::accel::{Hit, Ray};
use crate::scene::camera::Raster;
use crate::scene::packet::PACKET;
use glam::Vec3;

/// Side of the square tiles the renderer works in.
pub const TILE: u32 = 8;

pub(crate) fn tile_count(width: u32, height: u32) -> u32 {
    width.div_ceil(TILE) * height.div_ceil(TILE)
}

/// The pixels of tile `t` of `window` (tiles in scan order from the window's corner), in scan
/// order, in the full image's coordinates.
pub(crate) fn tile_pixels(t: u32, window: Window) -> impl Iterator<Item = (u32, u32)> {
    let tiles_x = window.width.div_ceil(TILE);
    let (x0, y0) = (window.x + (t % tiles_x) * TILE, window.y + (t / tiles_x) * TILE);
    let (right, bottom) = (window.x + window.width, window.y + window.height);
    (y0..(y0 + TILE).min(bottom)).flat_map(move |y| (x0..(x0 + TILE).min(right)).map(move |x| (x, y)))
}

/// The renderer's pixel order: TILE × TILE tiles in scan order, each in scan order, so that
/// consecutive pixels are neighbours in both directions (and share occluders, see `Occluders`).
pub fn pixel_order(width: u32, height: u32) -> impl Iterator<Item = (u32, u32)> {
    let window = Window::full(width, height);
    (0..tile_count(width, height)).flat_map(move |t| tile_pixels(t, window))
}

/// A pixel's primary ray: its direction and closest hit.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Primary {
    pub(super) x: u32,
    pub(super) y: u32,
    pub(super) dir: Vec3,
    pub(super) hit: Option<Hit>,
}

/// The primary rays of tile `t`'s pixels (in `tile_pixels` order) of `window` of the image `raster`
/// is for into `out` (what `render` and `gbuffer` share; the pixels' ray origins are read from `raster`
/// later). Rays that share their origin (a pinhole camera's: the eye) are traced 32 at a time,
/// 8 × 4 pixels (`Accel::closest_from`), others one by one; the hits are the same bits either way.
#[inline(always)]
pub(crate) fn tile_primaries(
    scene: &Scene,
    raster: &Raster,
    window: &Window,
    t: u32,
    out: &mut Vec<Primary>,
) {
    out.clear();
    debug_assert_eq!(window.full, {
        let (w, h) = raster.size();
        [w, h]
    });
    for (x, y) in tile_pixels(t, *window) {
        out.push(Primary { x, y, dir: raster.ray(x, y).dir, hit: None });
    }
    if raster.shared_origin() {
        let o = raster.ray(0, 0).origin;
        let mut dirs = [Vec3::ZERO; PACKET];
        let mut hits = [None; PACKET];
        for chunk in out.chunks_mut(PACKET) {
            let k = chunk.len();
            for (d, p) in dirs.iter_mut().zip(chunk.iter()) {
                *d = p.dir;
            }
            scene.accel.closest_from(o, &dirs[..k], f32::INFINITY, &mut hits[..k]);
            for (p, h) in chunk.iter_mut().zip(hits) {
                p.hit = h;
            }
        }
    } else {
        for p in out.iter_mut() {
            let r = raster.ray(p.x, p.y);
            p.hit = scene.accel.closest(&Ray::new(r.origin, r.dir, f32::INFINITY));
        }
    }
}
