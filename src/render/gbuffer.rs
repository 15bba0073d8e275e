//! The G-buffer: what the primary ray of each pixel hit, for an edge-aware denoiser to be guided by
//! (`denoise::atrous`). Traced by the renderer's own primary-ray code (`tile_primaries`, the same
//! tiles, packets and camera), so its depth and normal are those of the hits the AO rays of
//! `render` start from; `render` itself does not compute or pay for any of it.

use super::{Plane, Primary, TILE, tile_count, tile_primaries};
use crate::image::Image;
use crate::scene::Scene;
use glam::Vec3;
use rayon::prelude::*;

/// Per pixel, row-major like `Image`.
#[derive(Debug, Clone, PartialEq)]
pub struct GBuffer {
    pub width: u32,
    pub height: u32,
    /// Distance from the ray origin to the hit along the (unit) primary ray, in scene units: for an
    /// orthographic camera the view depth, for a pinhole the distance from the eye. 0 on background.
    pub depth: Image,
    /// The unit geometric normal of the hit triangle facing the camera, exactly the normal the AO
    /// rays' hemisphere is built around (`Plane::ao_origin`). Zero on background.
    pub normal: Vec<Vec3>,
    /// 1.0 where the primary ray hit the scene, 0.0 for background: `render`'s coverage, bit for bit.
    pub coverage: Image,
}

impl GBuffer {
    pub fn is_covered(&self, i: usize) -> bool {
        crate::image::covered(&self.coverage, i)
    }
}

/// The G-buffer of `scene` at `width` × `height` (a `RenderJob`'s size): one primary ray per pixel
/// centre, traced in parallel by tiles; deterministic for any thread count.
pub fn gbuffer(scene: &Scene, width: u32, height: u32) -> GBuffer {
    let n = width as usize * height as usize;
    let (mut depth, mut normal, mut coverage) = (vec![0.0f32; n], vec![Vec3::ZERO; n], vec![0.0f32; n]);
    let tiles: Vec<Vec<(u32, f32, Vec3)>> = (0..tile_count(width, height))
        .into_par_iter()
        .with_max_len(1)
        .map_init(
            || Vec::<Primary>::with_capacity((TILE * TILE) as usize),
            |primaries, t| {
                tile_primaries(scene, (width, height), t, primaries);
                primaries
                    .iter()
                    .filter_map(|p| {
                        let hit = p.hit?;
                        let plane = Plane::of(scene.accel.triangle(hit.prim));
                        let (_, nrm) = plane.ao_origin(hit.bary_b, hit.bary_c, p.dir);
                        Some((p.y * width + p.x, hit.t, nrm))
                    })
                    .collect()
            },
        )
        .collect();
    for (i, t, nrm) in tiles.into_iter().flatten() {
        let i = i as usize;
        depth[i] = t;
        normal[i] = nrm;
        coverage[i] = 1.0;
    }
    GBuffer {
        width,
        height,
        depth: Image::from_vec(width, height, depth),
        normal,
        coverage: Image::from_vec(width, height, coverage),
    }
}
