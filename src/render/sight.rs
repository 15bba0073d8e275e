//! What the camera sees, one primary ray per pixel centre (how many rays hit the mesh: the image's
//! coverage), and what surrounds its eye. A camera under a floor passes the "sees a triangle" check
//! (it sees the floor's underside) and still shows no view of the scene — its image is the floor's
//! underside, open towards the empty space below, and background wherever the rays go down — so the
//! load says so (`load::facing_warning`) and the scene summary states the coverage (`load::summary`).
//! The backs of triangles do not tell it: the committed scenes' meshes are wound either way round.

use super::{Primary, TILE, View, tile_count, tile_primaries};
use crate::scene::Scene;
use crate::scene::accel::Ray;
use glam::Vec3;
use rayon::prelude::*;

/// Counts over the primary rays of one image, and what surrounds the eye.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sight {
    pub pixels: u64,
    /// Rays that hit a triangle.
    pub hits: u64,
    /// Of the directions from the eye pointing down (away from the camera's `up`), the fraction
    /// that meet nothing; of those pointing up, the fraction that meet the mesh.
    pub below_open: f64,
    pub above_closed: f64,
}

impl Sight {
    /// The fraction of pixels that see the mesh.
    pub fn coverage(&self) -> f64 {
        self.hits as f64 / self.pixels.max(1) as f64
    }

    /// Nothing below the eye and the mesh above it: the eye is under the scene's floor.
    pub fn under_the_floor(&self) -> bool {
        self.below_open > 0.9 && self.above_closed > 0.9
    }
}

/// Directions traced from the eye to see what surrounds it (a Fibonacci sphere: even coverage).
const AROUND: u32 = 512;

/// The primary rays of `scene` at `width` × `height` through its own camera, counted (the same
/// rays as `render`'s, `tile_primaries`), and `AROUND` rays from the eye; deterministic for any
/// thread count.
pub fn sight(scene: &Scene, width: u32, height: u32) -> Sight {
    let hits = primary_hits(scene, &View::SCENE, width, height);
    let (eye, up) = match scene.camera {
        crate::scene::Camera::Perspective { eye, up, .. }
        | crate::scene::Camera::Orthographic { eye, up, .. } => (eye, up.normalize_or_zero()),
    };
    let (mut below, mut below_open, mut above, mut above_closed) = (0u32, 0u32, 0u32, 0u32);
    for i in 0..AROUND {
        // The spherical Fibonacci point set: z evenly spaced, longitudes by the golden angle.
        let z = 1.0 - (2 * i + 1) as f32 / AROUND as f32;
        let phi = i as f32 * std::f32::consts::PI * (3.0 - 5f32.sqrt());
        let r = (1.0 - z * z).max(0.0).sqrt();
        let d = Vec3::new(r * phi.cos(), r * phi.sin(), z);
        let hit = scene.accel.closest(&Ray::new(eye, d, f32::INFINITY)).is_some();
        let h = d.dot(up);
        if h < -0.3 {
            below += 1;
            below_open += (!hit) as u32;
        } else if h > 0.3 {
            above += 1;
            above_closed += hit as u32;
        }
    }
    let frac = |a: u32, b: u32| a as f64 / b.max(1) as f64;
    Sight {
        pixels: width as u64 * height as u64,
        hits,
        below_open: frac(below_open, below),
        above_closed: frac(above_closed, above),
    }
}

/// How many of the primary rays of `view` at `width` × `height` hit the mesh (the same rays as
/// `render`'s): 0 for a camera path's frame that sees nothing.
pub fn primary_hits(scene: &Scene, view: &View, width: u32, height: u32) -> u64 {
    let raster = view.raster(scene, width, height);
    let window = super::Window::full(width, height);
    (0..tile_count(width, height))
        .into_par_iter()
        .with_max_len(1)
        .map_init(
            || Vec::<Primary>::with_capacity((TILE * TILE) as usize),
            |primaries, t| {
                tile_primaries(scene, &raster, &window, t, primaries);
                primaries.iter().filter(|p| p.hit.is_some()).count() as u64
            },
        )
        .sum()
}
