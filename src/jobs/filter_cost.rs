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

/// Frames of a series the calibration times one by one: a pipeline's first frames cost more
/// than its later ones (SVGF estimates a pixel's variance over 7 × 7 neighbours until its history
/// holds `denoise::svgf::SPATIAL_VARIANCE_FRAMES` frames) …
const FIRST_FRAMES: usize = crate::denoise::svgf::SPATIAL_VARIANCE_FRAMES as usize + 1;
/// … then this many later frames, whose median is every later frame's cost.
const LATER_FRAMES: usize = 3;
/// Times the series is filtered, each frame's cost the median of its runs (one run's later frames
/// once came out 1.6x another's on the idle machine).
const FILTER_RUNS: usize = 3;

/// A pipeline's own CPU seconds per frame at the image's size, as a series spends them: its first
/// frames one by one (`first`), each later frame advanced without being shown (`later`: SVGF makes
/// its first à-trous pass only, the colour history), and the shown frame (`shown`: every pass).
/// Measured on Sponza at 1080p's pass count (2026-12-07): SVGF's first five frames cost 1.5–2.0×
/// a later one, and the calibration that timed only frames 2–5 forecast a 21-frame steady-state
/// series' filter at twice its cost.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterCost {
    pub first: Vec<f64>,
    pub later: f64,
    pub shown: f64,
}

impl FilterCost {
    /// CPU seconds over a series of `frames` frames of which `shown` are shown: every frame
    /// advanced (its first ones at their own cost), the shown ones' extra passes on top.
    pub fn series_s(&self, frames: usize, shown: usize) -> f64 {
        let advanced: f64 = (0..frames).map(|k| self.first.get(k).copied().unwrap_or(self.later)).sum();
        advanced + shown as f64 * (self.shown - self.later).max(0.0)
    }
}

/// Per pipeline (other than raw) the plan's jobs on scene `si` use, still or moving, its own CPU
/// seconds per frame at the image's size (`FilterCost`): frames of noise at the calibration size
/// with the scene's G-buffer pushed through the pipeline's filter as a run does (an accumulating
/// one advanced frame by frame, then shown; a spatial filter alone filters each frame anew), on a
/// worker thread as the run times it (a filter's rayon work stays on that thread), with the
/// history gathered from one tap per pixel (a still camera) or four (a moving one), scaled by the
/// pixel ratio. Measured at 64x48 on the kitchen under load (2026-12-07): SVGF 0.9 ms per frame
/// still and 2 ms moving beside a 2-ray frame's 2 ms render, which a forecast of the renders alone
/// left out.
pub(super) fn filter_frames(
    loaded: &Loaded,
    full: &Plan,
    si: usize,
    first: &Job,
) -> Result<Vec<(crate::denoise::Pipeline, bool, FilterCost)>> {
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
    let frames: Vec<image::Image> = (0..(FIRST_FRAMES + LATER_FRAMES + 1) as u64).map(noise).collect();
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
        // The series `FILTER_RUNS` times, each frame's cost the median of its runs.
        let (runs, _) = worker.timed(|| {
            (0..FILTER_RUNS)
                .map(|_| {
                    // The whole image's pass counts, as a run filters it (and each tile's window).
                    let run = p.at_size(g.width, g.height);
                    let mut f = run.start(w, h);
                    let mut timed = |frame: &image::Image, shown: bool| {
                        let c0 = clock::thread_cpu_s();
                        if !p.is_temporal() {
                            // Nothing carries over: each frame is filtered by a run of its own.
                            let _ = run.start(w, h).push(frame, &gbuf, &m);
                        } else if shown {
                            let _ = f.push(frame, &gbuf, &m);
                        } else {
                            f.advance(frame, None, &gbuf, &m);
                        }
                        (clock::thread_cpu_s() - c0) * ratio
                    };
                    let (last, advanced) = frames.split_last().expect("frames to filter");
                    let mut v: Vec<f64> = advanced.iter().map(|frame| timed(frame, false)).collect();
                    v.push(timed(last, true));
                    v
                })
                .collect::<Vec<Vec<f64>>>()
        });
        let median = |k: usize| crate::stats::median(&runs.iter().map(|r| r[k]).collect::<Vec<_>>());
        let mut v: Vec<f64> = (0..runs[0].len()).map(median).collect();
        let shown = v.pop().expect("a shown frame");
        let costs = (v, shown);
        let (v, shown) = costs;
        let cost = if p.is_temporal() {
            FilterCost {
                first: v[..FIRST_FRAMES].to_vec(),
                later: crate::stats::median(&v[FIRST_FRAMES..]),
                shown,
            }
        } else {
            // Every frame alike; the process's first one (code and pages not yet touched, 6x the
            // others on the kitchen) left out.
            let c = crate::stats::median(&v[1..]);
            FilterCost { first: Vec::new(), later: c, shown: c }
        };
        out.push((p, moving, cost));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::FilterCost;

    #[test]
    fn a_series_pays_its_first_frames_at_their_own_cost_and_its_shown_frames_passes() {
        let c = FilterCost { first: vec![3.0, 3.0, 2.0], later: 1.0, shown: 5.0 };
        // 21 frames, the last shown: 3 + 3 + 2 + 18 later ones, and the shown one's 4 more.
        assert_eq!(c.series_s(21, 1), 8.0 + 18.0 + 4.0);
        assert_eq!(c.series_s(2, 2), 6.0 + 8.0);
        // A filter without history: every frame alike.
        let spatial = FilterCost { first: Vec::new(), later: 2.0, shown: 2.0 };
        assert_eq!(spatial.series_s(1, 1), 2.0);
    }
}
