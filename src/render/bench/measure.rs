//! What `hemilab bench` measures (the figure of record): for each AO distance d and for 1 and all
//! threads, the same AO rays are traced by plain obvhs (`ray_traverse_miss`, one ray at a time) and
//! by hemilab's own path, repeated; rays/s of both and their ratio as min / median / max.
//! `render_vs_query` sets the whole renderer (primary rays, sampling, image) against that AO query
//! on the render's own rays: how much of a render's time is spent outside AO tracing. Every run
//! checks that speed never changes a result: repeated answers are bit-identical, hemilab agrees with
//! its single-ray traversal on every ray, and every ray where obvhs and hemilab disagree is judged
//! against a test of every triangle (the reason is counted, hemilab must be right).

use super::{self as bench, Mismatches, RaySet};
use crate::error::{Error, Result};
use crate::render::{self, RenderJob, pool};
use crate::scene::Scene;
use serde_json::{Value, json};
use std::time::Instant;

/// Pixels each sequence's points are timed over (`points::ns_per_point`): 2 to 40 ms a pass.
const POINT_PIXELS: u32 = 2048;

/// The whole benchmark of `job` on `scene`: whole renders on one and all threads, the render
/// against its own AO query, and obvhs against hemilab at each distance (default: the scene's d,
/// 0.3 d and unbounded), `repeats` timed samples each, and every sequence's cost per point.
/// Returns the JSON `hemilab bench --json`
/// prints. `on_set` is handed the ray set before any timing (`hemilab bench --dump-rays` writes it).
pub fn measure(
    scene: &Scene,
    job: &RenderJob,
    distances: Option<&[f32]>,
    repeats: u32,
    on_set: &mut dyn FnMut(&RaySet) -> Result<()>,
) -> Result<Value> {
    let all = crate::timing::cores();
    let threads: Vec<usize> = if all > 1 { vec![1, all] } else { vec![1] };

    let one = time_renders(scene, job, 1)?;
    let many = time_renders(scene, job, all)?;
    let speedup = many["rays_per_s"].as_f64().unwrap_or(0.0) / one["rays_per_s"].as_f64().unwrap_or(1.0);

    let start = Instant::now();
    let set = bench::ray_set(scene, job);
    let set_s = start.elapsed().as_secs_f64();
    on_set(&set)?;
    let mut rvq = Vec::new();
    for &t in &threads {
        rvq.push(render_vs_query(scene, job, &set, t, repeats)?);
    }
    let base = bench::obvhs_baseline(scene);
    let mut comparisons = Vec::new();
    for &d in &distances.map(<[f32]>::to_vec).unwrap_or_else(|| default_distances(scene.ao_distance)) {
        comparisons.push(compare(scene, &set, &base, d, &threads, repeats)?);
    }
    Ok(json!({
        "scene": scene.name,
        "triangles": scene.triangle_count,
        "bvh_build_s": scene.bvh_build_s,
        "obvhs_baseline_bvh_build_s": base.build_s,
        "resolution": [job.width, job.height],
        "rays_per_pixel": job.sampler.count,
        "distribution": job.distribution.name(),
        "sequence": job.sampler.sequence.name(),
        "seed_mode": job.sampler.seed_mode.name(),
        "cores": all,
        "ao_distance": d_json(scene.ao_distance),
        "single_thread": one,
        "all_threads": many,
        "speedup": speedup,
        "render_vs_query": rvq,
        "ray_set": { "pixels": set.origins.len(), "rays": set.len(), "build_s": set_s },
        "repeats": repeats,
        "comparison": comparisons,
        "points": super::points::ns_per_point(POINT_PIXELS, repeats),
    }))
}

/// Whole renders on `threads` threads for at least ~1 s: AO rays per second of render wall time
/// (primary rays, sampling and shading in the time, not in the count).
fn time_renders(scene: &Scene, job: &RenderJob, threads: usize) -> Result<Value> {
    let pool = pool(Some(threads as u32))?;
    pool.install(|| render::render(scene, job, &|_| {})); // warm caches and threads
    let (mut rays, mut secs) = (0u64, 0.0f64);
    while secs < 1.0 {
        let start = Instant::now();
        let r = pool.install(|| render::render(scene, job, &|_| {}));
        secs += start.elapsed().as_secs_f64();
        rays += r.rays;
        if r.rays == 0 {
            break;
        }
    }
    let rate = rays as f64 / secs.max(1e-9);
    Ok(json!({ "threads": threads, "ao_rays": rays, "seconds": secs, "rays_per_s": rate }))
}

/// `render_vs_query`: the whole render's AO rays/s over hemilab's AO query's rays/s on the same
/// rays (`set`, the render's own rays at the scene's d), on `threads` threads. Each repeat times
/// one sample of each, in alternating order; a sample repeats its work until it has run for at
/// least ~0.2 s of wall time (the same number of times for both), so short renders are not timed
/// by a single clock reading.
fn render_vs_query(
    scene: &Scene,
    job: &RenderJob,
    set: &RaySet,
    threads: usize,
    repeats: u32,
) -> Result<Value> {
    let pool = pool(Some(threads as u32))?;
    let mut out = vec![0u32; set.origins.len() * set.masks_per_pixel()];
    let render_once = || pool.install(|| render::render(scene, job, &|_| {})).rays;
    let mut query_once = || {
        pool.install(|| bench::trace_hemilab(scene, set, job.ao_distance, &mut out));
        set.len() as u64
    };
    // Warm-up, and how many times a sample runs.
    let start = Instant::now();
    render_once();
    query_once();
    let once = start.elapsed().as_secs_f64();
    let times = ((0.4 / once.max(1e-6)).ceil() as u32).clamp(1, 1000);
    let (mut renders, mut queries, mut ratio) = (Vec::new(), Vec::new(), Vec::new());
    for r in 0..repeats {
        let mut time = |render: bool| {
            let start = Instant::now();
            let rays: u64 = (0..times).map(|_| if render { render_once() } else { query_once() }).sum();
            rays as f64 / start.elapsed().as_secs_f64().max(1e-9)
        };
        let (a, b) = if r % 2 == 0 {
            let a = time(true);
            (a, time(false))
        } else {
            let b = time(false);
            (time(true), b)
        };
        renders.push(a);
        queries.push(b);
        ratio.push(a / b);
    }
    Ok(json!({
        "threads": threads,
        "render_rays_per_s": spread(&renders),
        "query_rays_per_s": spread(&queries),
        "ratio": spread(&ratio),
    }))
}

fn spread(v: &[f64]) -> Value {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let median = if s.is_empty() {
        0.0
    } else if s.len() % 2 == 1 {
        s[s.len() / 2]
    } else {
        0.5 * (s[s.len() / 2 - 1] + s[s.len() / 2])
    };
    json!({ "min": s.first().copied().unwrap_or(0.0), "median": median, "max": s.last().copied().unwrap_or(0.0) })
}

fn d_json(d: f32) -> Value {
    // Through the shortest decimal of the f32, so 0.3 prints as 0.3.
    if d.is_finite() { json!(d.to_string().parse::<f64>().unwrap_or(d as f64)) } else { json!("infinite") }
}

/// One distance: answers of both paths, then timed repeats on each thread count.
fn compare(
    scene: &Scene,
    set: &RaySet,
    base: &bench::Baseline,
    d: f32,
    threads: &[usize],
    repeats: u32,
) -> Result<Value> {
    let rays = set.len();
    let masks = set.origins.len() * set.masks_per_pixel();
    let (mut obvhs_ref, mut ours_masks) = (vec![false; rays], vec![0u32; masks]);
    let all = pool(Some(*threads.last().unwrap_or(&1) as u32))?;
    all.install(|| bench::trace_obvhs(base, set, d, &mut obvhs_ref));
    all.install(|| bench::trace_hemilab(scene, set, d, &mut ours_masks));
    let ours_ref = set.unpack(&ours_masks);
    let m: Mismatches = all.install(|| bench::mismatches(scene, base, set, d, &obvhs_ref, &ours_ref));
    if m.hemilab_wrong != 0 || m.hemilab_vs_single_ray != 0 {
        return Err(Error::Refused(format!(
            "bench: d = {d}: hemilab's AO answers are wrong ({m:?}); this is a bug, please report it"
        )));
    }
    let mut rows = Vec::new();
    let (mut out, mut out_masks) = (vec![false; rays], vec![0u32; masks]);
    for &t in threads {
        let pool = pool(Some(t as u32))?;
        // A sample traces the set this many times, the same for both paths: enough for the slower
        // path (obvhs) to run ~0.2 s, so a small scene's sample is not one call of a few ms.
        let start = Instant::now();
        pool.install(|| bench::trace_obvhs(base, set, d, &mut out));
        let times = ((0.2 / start.elapsed().as_secs_f64().max(1e-6)).ceil() as u32).clamp(1, 1000);
        let (mut obvhs_rate, mut ours, mut ratio) = (Vec::new(), Vec::new(), Vec::new());
        for r in 0..repeats {
            let mut run = |hemilab: bool| -> Result<f64> {
                let start = Instant::now();
                for _ in 0..times {
                    if hemilab {
                        pool.install(|| bench::trace_hemilab(scene, set, d, &mut out_masks));
                    } else {
                        pool.install(|| bench::trace_obvhs(base, set, d, &mut out));
                    }
                }
                let secs = start.elapsed().as_secs_f64();
                let same = if hemilab { out_masks == ours_masks } else { out == obvhs_ref };
                if !same {
                    return Err(Error::Refused(format!(
                        "bench: d = {d}, {t} threads: a repeat gave different answers; this is a bug"
                    )));
                }
                Ok(rays as f64 * times as f64 / secs.max(1e-9))
            };
            // Alternate which path runs first so that neither always inherits a warm cache.
            let (b, o) = if r % 2 == 0 {
                let b = run(false)?;
                (b, run(true)?)
            } else {
                let o = run(true)?;
                (run(false)?, o)
            };
            obvhs_rate.push(b);
            ours.push(o);
            ratio.push(o / b);
        }
        rows.push(json!({
            "threads": t,
            "traces_per_sample": times,
            "obvhs_rays_per_s": spread(&obvhs_rate),
            "hemilab_rays_per_s": spread(&ours),
            "ratio": spread(&ratio),
        }));
    }
    let count = |v: &[bool]| v.iter().filter(|&&b| b).count();
    Ok(json!({
        "ao_distance": d_json(d),
        "rays": rays,
        "occluded": { "obvhs": count(&obvhs_ref), "hemilab": count(&ours_ref) },
        "mismatches": m,
        "runs": rows,
    }))
}

/// Where to compare without `--distances`: the scene's own d (what its renders use), a short one
/// (0.3 d, where culling by d matters most) and unbounded.
fn default_distances(d: f32) -> Vec<f32> {
    if d.is_finite() { vec![0.3 * d, d, f32::INFINITY] } else { vec![f32::INFINITY] }
}
