//! The AO renderer: one primary ray per pixel centre, then the pixel's N AO rays from the first hit.
//! Rows run in parallel on the current rayon pool; a pixel's result depends only on (scene, job,
//! pixel index), so the image is bit-identical for any thread count. No IO, no printing.

mod offset;

pub use offset::offset_origin;

use crate::image::Image;
use crate::sampling::{Distribution, Frame, SamplerConfig, frame};
use crate::scene::Scene;
use crate::scene::accel::Ray;
use glam::Vec2;
use rayon::prelude::*;

/// Everything that determines one AO image of a scene.
#[derive(Debug, Clone, Copy)]
pub struct RenderJob {
    pub distribution: Distribution,
    pub sampler: SamplerConfig,
    pub width: u32,
    pub height: u32,
    /// AO distance d (`f32::INFINITY` allowed).
    pub ao_distance: f32,
}

pub struct RenderOutput {
    /// 1 - occluded fraction estimate: 1 = fully open. Not clamped: weights above 1 (uniform) can
    /// push a pixel outside [0, 1], and clamping would bias the estimator.
    pub ao: Image,
    /// 1.0 where the primary ray hit the scene, 0.0 for background (excluded from metrics).
    pub coverage: Image,
    /// AO (occlusion) rays cast; primary rays are not counted.
    pub rays: u64,
    /// AO rays that hit something within d.
    pub occluded_rays: u64,
}

/// Renders `job`. `progress(n)` is called as work finishes with the number of pixels just done
/// (one call per row; the calls sum to width × height).
pub fn render(scene: &Scene, job: &RenderJob, progress: &(dyn Fn(u64) + Sync)) -> RenderOutput {
    let (w, h) = (job.width as usize, job.height as usize);
    let n = job.sampler.count as usize;
    if w == 0 || h == 0 {
        let empty = Image::new(job.width, job.height);
        return RenderOutput { ao: empty.clone(), coverage: empty, rays: 0, occluded_rays: 0 };
    }
    let mut ao = vec![1.0f32; w * h];
    let mut coverage = vec![0.0f32; w * h];
    let (rays, occluded) = ao
        .par_chunks_mut(w)
        .zip(coverage.par_chunks_mut(w))
        .enumerate()
        .map_init(
            || vec![Vec2::ZERO; n],
            |points, (y, (ao_row, cov_row))| {
                let mut counts = (0u64, 0u64);
                for x in 0..w {
                    let pixel = (y * w + x) as u64;
                    if let Some((value, occ)) = shade_pixel(scene, job, x as u32, y as u32, pixel, points) {
                        ao_row[x] = value;
                        cov_row[x] = 1.0;
                        counts.0 += n as u64;
                        counts.1 += occ;
                    }
                }
                progress(w as u64);
                counts
            },
        )
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    RenderOutput {
        ao: Image::from_vec(job.width, job.height, ao),
        coverage: Image::from_vec(job.width, job.height, coverage),
        rays,
        occluded_rays: occluded,
    }
}

/// AO value (1 - estimate) and occluded-ray count of one pixel, or None for background.
#[inline]
fn shade_pixel(
    scene: &Scene,
    job: &RenderJob,
    x: u32,
    y: u32,
    pixel: u64,
    points: &mut [Vec2],
) -> Option<(f32, u64)> {
    let primary = scene.camera.ray(x, y, job.width, job.height);
    let hit = scene.accel.closest(&Ray::new(primary.origin, primary.dir, f32::INFINITY))?;
    let [a, b, c] = scene.accel.triangle(hit.prim);
    // From barycentrics and edges: exact on axis-aligned planes, error ~ulps of the vertices elsewhere.
    let p = a + hit.bary_b * (b - a) + hit.bary_c * (c - a);
    let mut n = (b - a).cross(c - a).normalize();
    if n.dot(primary.dir) > 0.0 {
        n = -n;
    }
    let origin = offset_origin(p, n, scene.accel.scale(hit.prim));
    let basis = Frame::from_normal(n);
    job.sampler.fill_pixel(pixel, points);
    let mut sum = 0.0f64;
    let mut occluded = 0u64;
    for &u in points.iter() {
        let s = job.distribution.sample(u);
        let dir = frame::canonical(basis.to_world(s.dir).normalize_or(n));
        if scene.accel.occluded(&Ray::new(origin, dir, job.ao_distance)) {
            sum += s.weight as f64;
            occluded += 1;
        }
    }
    Some(((1.0 - sum / points.len() as f64) as f32, occluded))
}
