//! An AO image with its own ray count in every pixel, for adaptive references
//! (`reference::allocate`). Built from the renderer's own per-pixel steps (`render::pixel_rays`,
//! `render::trace_pixel`), so a pixel given n rays gets exactly the estimate a plain render at n rays
//! would give it: the same primary hit, origin offset, point set (the n-point set of the sampler:
//! lattice spacing follows n) and weights.

use crate::image::Image;
use crate::render::{self, PixelRays, RenderJob, RenderOutput};
use crate::sampling::Integrand;
use glam::Vec2;
use rayon::prelude::*;

/// Renders `job` with `counts[i]` rays in pixel i (0 = leave it out: background, or not wanted).
/// Pixels run in parallel on the current rayon pool, in the renderer's tile order so neighbours share
/// a thread's occluder cache; the image does not depend on the thread count. `progress(rays)` is called
/// as rows of tiles finish.
pub fn render_counts(
    scene: &crate::scene::Scene,
    job: &RenderJob,
    counts: &[u32],
    progress: &(dyn Fn(u64) + Sync),
) -> RenderOutput {
    render_counts_of(scene, job, Integrand::Ao, counts, progress)
}

/// `render_counts` with the weights of `integrand` (`render::render_integrand`'s).
pub fn render_counts_of(
    scene: &crate::scene::Scene,
    job: &RenderJob,
    integrand: Integrand,
    counts: &[u32],
    progress: &(dyn Fn(u64) + Sync),
) -> RenderOutput {
    let (w, h) = (job.width, job.height);
    let order: Vec<(u32, u32)> = render::pixel_order(w, h).collect();
    // Chunks of 64 pixels (one 8 x 8 tile when the image is a multiple of 8 wide).
    let done: Vec<Vec<(usize, f32, u64, u64)>> = order
        .par_chunks(64)
        .map_init(
            || (Vec::<Vec2>::new(), PixelRays::default(), Vec::<bool>::new()),
            |(points, rays, blocked), chunk| {
                let mut out = Vec::with_capacity(chunk.len());
                let mut cast = 0u64;
                for &(x, y) in chunk {
                    let i = y as usize * w as usize + x as usize;
                    let n = counts.get(i).copied().unwrap_or(0);
                    if n == 0 {
                        continue;
                    }
                    let mut pj = *job;
                    pj.sampler.count = n;
                    points.resize(n as usize, Vec2::ZERO);
                    if !render::pixel_rays_of(scene, &pj, integrand, (x, y, i as u64), points, rays) {
                        continue;
                    }
                    blocked.resize(n as usize, false);
                    render::trace_pixel(
                        scene,
                        rays.origin,
                        rays.normal,
                        &rays.dirs,
                        job.ao_distance,
                        blocked,
                    );
                    let (mut sum, mut occluded) = (0.0f64, 0u64);
                    for (&b, &wt) in blocked.iter().zip(&rays.weights) {
                        if b {
                            sum += wt as f64;
                            occluded += 1;
                        }
                    }
                    out.push((i, (1.0 - sum / n as f64) as f32, n as u64, occluded));
                    cast += n as u64;
                }
                progress(cast);
                out
            },
        )
        .collect();
    let mut ao = vec![1.0f32; (w * h) as usize];
    let mut coverage = vec![0.0f32; (w * h) as usize];
    let (mut total, mut occluded) = (0u64, 0u64);
    for (i, v, n, o) in done.into_iter().flatten() {
        ao[i] = v;
        coverage[i] = 1.0;
        total += n;
        occluded += o;
    }
    RenderOutput {
        ao: Image::from_vec(w, h, ao),
        coverage: Image::from_vec(w, h, coverage),
        rays: total,
        occluded_rays: occluded,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
    use crate::scene::procedural::floating_rectangle;

    #[test]
    fn equal_counts_reproduce_the_plain_render_and_zero_leaves_a_pixel_out() {
        let scene = floating_rectangle((24, 16));
        let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Shift, 12, 3).unwrap();
        let job = RenderJob {
            distribution: Distribution::SineCosine,
            sampler,
            width: 24,
            height: 16,
            ao_distance: scene.ao_distance,
        };
        let plain = render::render(&scene, &job, &|_| {});
        let same = render_counts(&scene, &job, &[12; 24 * 16], &|_| {});
        assert_eq!((&same.ao, &same.coverage, same.rays), (&plain.ao, &plain.coverage, plain.rays));
        // Pixel 5 at 30 rays is what a 30-ray render gives it; pixel 6 is left out.
        let mut counts = vec![12u32; 24 * 16];
        counts[5] = 30;
        counts[6] = 0;
        let mixed = render_counts(&scene, &job, &counts, &|_| {});
        let thirty = render::render(
            &scene,
            &RenderJob { sampler: SamplerConfig { count: 30, ..sampler }, ..job },
            &|_| {},
        );
        assert_eq!(mixed.ao.data[5], thirty.ao.data[5]);
        assert_eq!((mixed.coverage.data[6], mixed.ao.data[7]), (0.0, plain.ao.data[7]));
    }
}
