//! A real-time job's pipeline's own CPU time per frame, for the calibration (`calibrate`): the
//! filter pushed over frames of noise at the calibration size, still and moving. Apart from the
//! renders' calibration because it times a filter, not rays.

use crate::error::{Error, Result};
use crate::image;
use crate::load::Loaded;
use crate::plan::{Geometry, Job, Plan, cost};
use crate::render;
use crate::timing::{self, clock};

/// Whether `job`'s camera moves from frame to frame (a path other than the scene's still camera).
pub(super) fn moves(job: &Job) -> bool {
    job.measurement.camera.run().is_some_and(|r| !r.path.is_static())
}

/// Frames each pipeline filters in calibration, after one that starts it.
const FILTER_FRAMES: u32 = 4;

/// Per pipeline (other than raw) the plan's jobs on scene `si` use, still or moving, its own CPU
/// seconds per frame at the image's size: a frame of noise at the calibration size with the
/// scene's G-buffer, pushed through the pipeline's filter `FILTER_FRAMES` times after a first one
/// (as a run advances an accumulating one frame by frame; a spatial filter alone filters its one
/// frame), on a worker thread as the run times it (a filter's rayon work stays on that thread),
/// with the history gathered from one tap per pixel (a still camera) or four (a moving one),
/// scaled by the pixel ratio. Measured at 64x48 on the kitchen under load (2026-12-07): SVGF
/// 0.9 ms per frame still and 2 ms moving beside a 2-ray frame's 2 ms render, which a forecast of
/// the renders alone left out.
pub(super) fn filter_frames(
    loaded: &Loaded,
    full: &Plan,
    si: usize,
    first: &Job,
) -> Result<Vec<(crate::denoise::Pipeline, bool, f64)>> {
    let mut wanted: Vec<(crate::denoise::Pipeline, bool)> = Vec::new();
    for j in full.jobs.iter().filter(|j| loaded.scene_of(j).0 == si) {
        let k = (j.measurement.pipeline, moves(j));
        if k.0 != crate::denoise::Pipeline::RAW && !wanted.contains(&k) {
            wanted.push(k);
        }
    }
    if wanted.is_empty() {
        return Ok(Vec::new());
    }
    let scene = &loaded.scenes[si];
    let g = Geometry::of(first.resolution, first.ao_distance, scene);
    let (w, h, ratio) = cost::calibration_size(g.width, g.height);
    let gbuf = render::gbuffer(scene, w, h);
    let noise = |k: u64| {
        let v = (0..w as u64 * h as u64)
            .map(|i| (crate::sampling::hash::hash(k, i) >> 40) as f32 / (1u64 << 24) as f32)
            .collect();
        image::Image::from_vec(w, h, v)
    };
    let frames: Vec<image::Image> = (0..=FILTER_FRAMES as u64).map(noise).collect();
    let motion = |moving: bool| {
        if !moving {
            return crate::denoise::motion::Motion::identity(w, h);
        }
        // Bilinear reprojection: each pixel's history from itself and its right, lower and
        // diagonal neighbours.
        let taps = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| {
                let (x1, y1) = ((x + 1).min(w - 1), (y + 1).min(h - 1));
                let mut t = vec![(y * w + x, 0.25f32)];
                for (a, b) in [(x1, y), (x, y1), (x1, y1)] {
                    if !t.iter().any(|p| p.0 == b * w + a) {
                        t.push((b * w + a, 0.25));
                    }
                }
                t
            })
            .collect();
        crate::denoise::motion::Motion::from_taps(w, h, taps)
    };
    let worker = timing::Worker::new(0).map_err(Error::Refused)?;
    let mut out = Vec::new();
    for (p, moving) in wanted {
        let m = motion(moving);
        let (cpu, _) = worker.timed(|| {
            // The whole image's pass counts, as a run filters it (and each tile's window).
            let mut f = p.at_size(g.width, g.height).start(w, h);
            let mut step = |frame: &image::Image| {
                if p.is_temporal() {
                    f.advance(frame, None, &gbuf, &m);
                } else {
                    let _ = f.push(frame, &gbuf, &m);
                }
            };
            step(&frames[0]);
            let c0 = clock::thread_cpu_s();
            frames[1..].iter().for_each(&mut step);
            clock::thread_cpu_s() - c0
        });
        out.push((p, moving, cpu / FILTER_FRAMES as f64 * ratio));
    }
    Ok(out)
}
