//! How long a plan's run will take *on this machine, now* (`hemilab plan`, `run`'s long-run
//! warning), from a
//! short calibration: a fraction of a second of real renders through the timing protocol's own
//! pieces (one-thread `timing::Worker`s side by side, `timing::Calibration` fitted per estimator),
//! then the protocol's renders (`plan::cost`) and the references that must be built.
//!
//! What the calibration renders, per scene at the spec's resolution (or, for a larger image, at
//! `cost::CALIBRATION_PIXELS` with the same aspect, the per-image costs scaled back up by the pixel ratio:
//! at 8000x8000 a full-size calibration took minutes, and its 2 rays per pixel measured a negative
//! cost per ray): the no-AO-ray overhead render
//! and a 1-ray render of the first estimator, and every estimator the plan uses (and the
//! reference's, if a reference must be built) at a few rays per pixel, 3 times each. Each
//! estimator's cost is the line through its renders' median and the 1-ray renders' median
//! (`Calibration::fit`): a render's time grows linearly with its AO rays (measured on the kitchen
//! from 1 to 1024 rays). Other processes' runnable threads, sampled meanwhile, say how busy the
//! machine is; the estimate assumes it stays so. A real-time job's frame costs its render plus its
//! pipelines' own work (`filter_frames`: each filter timed frame by frame on the calibration frame,
//! still and moving). A recorded job's metrics, FLIP and image file are timed on one calibration
//! render, in wall time (the file's fsync). Not estimated: drawing the report, a few seconds.

use super::filter_cost::{FilterCost, filter_frames, moves};
use super::post_cost::{PostCost, post_cost};
pub use super::to_build::{Build, builds, by_scene};
use crate::error::{Error, Result};
use crate::io;
use crate::jobs::executor::{overhead_job, render_job};
use crate::load::Loaded;
use crate::plan::Geometry;
use crate::plan::{self, Job, Plan, cost};
use crate::reference::Manifest;
use crate::reference::store as refs;
use crate::render::{self, RenderJob, RenderOutput};
use crate::spec::Row;
use crate::timing::{self, Calibration, Time};
use std::sync::Mutex;

/// AO rays per calibration render, about: enough to dwarf the per-image cost, few enough that a
/// dozen estimators take a fraction of a second …
const CALIBRATION_RAYS: u64 = 250_000;
/// … and all estimator renders of all scenes together no more than this.
const CALIBRATION_TOTAL_RAYS: u64 = 4_000_000;
/// Timed samples of the overhead and 1-ray renders per scene, and of each estimator's render (a
/// single one put the paper spec's forecast anywhere from 1 min 00 s to 1 min 25 s on the quiet
/// machine).
const CALIBRATION_SAMPLES: usize = 3;
/// Milliseconds between samples of the machine's runnable threads during the calibration.
const RUNNABLE_EVERY_MS: u64 = 10;
/// Untimed CPU seconds each calibration worker renders on a scene first.
const CALIBRATION_WARMUP_S: f64 = 0.15;

/// What the calibration measured on one scene.
pub struct SceneCal {
    /// Covered pixels (AO rays cast per ray per pixel).
    pub covered: f64,
    /// Median CPU seconds of the no-AO-ray render.
    pub overhead_s: f64,
    /// Per estimator: time = intercept + cost · AO rays.
    pub rows: Vec<(Row, Calibration)>,
    /// Rays per pixel of the estimator renders.
    pub rays: u32,
    /// Per pipeline the plan filters frames with, and whether the camera moves (its history is
    /// then gathered from four taps, not one): CPU seconds of its own work per frame at the
    /// image's size (`filter_frames`), on top of the frame's render.
    pub filters: Vec<(crate::denoise::Pipeline, bool, FilterCost)>,
    /// Under `[tiles]`, the share of the image's pixels and of its covered pixels a frame renders
    /// (its windows, `jobs::tiles::TileSet`): `shares[0]` for the still camera, `shares[1]` for a
    /// moving one (whose windows are wider by its motion); (1, 1) for the whole image. Everything
    /// above is of the whole image.
    pub shares: [(f64, f64); 2],
}

pub struct Calibrated {
    pub scenes: Vec<Option<SceneCal>>,
    /// A recorded job's work after its render and the bytes it writes (`post_cost`).
    pub post: PostCost,
    /// Wall seconds per CPU second a worker will see: `now` where `/proc` has it, else the
    /// geometric mean of `measured` and `averaged`. The calibration's own wall/CPU is a direct
    /// measurement but of a fraction of a second, in which the scheduler favours threads that just
    /// started; the load average (threads wanting a core, with the run's workers added, per online
    /// CPU) is a minute's average of the whole machine, this process's own earlier work and that of
    /// a run which has just ended included. On this project's shared 2-core machine the first alone
    /// came out 1.3–2.3× below what the run then saw, the second 1.2–1.6× above; on the idle machine
    /// a minute after a run the mean said 1.4× where the run then saw 1.0×.
    pub contention: f64,
    pub measured: f64,
    pub averaged: Option<f64>,
    /// (Other processes' runnable threads, sampled during the calibration (`io::Runnable`), plus the
    /// run's workers) per CPU, at least 1: what `contention` is where `/proc` says it.
    pub now: Option<f64>,
    pub cpu_s: f64,
    pub wall_s: f64,
}

impl Calibrated {
    fn scene(&self, loaded: &Loaded, job: &Job) -> &SceneCal {
        self.scenes[loaded.scene_of(job).0].as_ref().expect("every planned scene is calibrated")
    }

    /// Predicted CPU seconds of one render of `job` (on its own row's line), of one frame for a
    /// series, its pipeline's own work included (as one series of the job's frames showing its last
    /// spends it per frame): under `[tiles]` of its camera's windows (`SceneCal::shares`).
    pub fn render_s(&self, loaded: &Loaded, job: &Job) -> f64 {
        let frames = job.measurement.frames_rendered().len();
        self.frame_s(loaded, job) + self.filter_s(loaded, job, frames, 1) / frames.max(1) as f64
    }

    /// `render_s` without the pipeline's work: the frame's render alone.
    pub fn frame_s(&self, loaded: &Loaded, job: &Job) -> f64 {
        let s = self.scene(loaded, job);
        let (pixels, covered) = s.shares[usize::from(moves(job))];
        self.render_share_s(loaded, job, pixels, covered)
    }

    /// CPU seconds of `job`'s pipeline over a series of `frames` frames showing `shown`
    /// (`FilterCost::series_s`), on its camera's windows under `[tiles]`; 0 for raw.
    pub fn filter_s(&self, loaded: &Loaded, job: &Job, frames: usize, shown: usize) -> f64 {
        let s = self.scene(loaded, job);
        let key = (job.measurement.pipeline, moves(job));
        let pixels = s.shares[usize::from(key.1)].0;
        s.filters
            .iter()
            .find(|(p, m, _)| (*p, *m) == key)
            .map_or(0.0, |f| f.2.series_s(frames, shown) * pixels)
    }

    /// `frame_s` of the whole image, whatever `[tiles]` says: a reference's render is scaled by
    /// its own window (`references_s`).
    fn render_whole_s(&self, loaded: &Loaded, job: &Job) -> f64 {
        self.render_share_s(loaded, job, 1.0, 1.0)
    }

    fn render_share_s(&self, loaded: &Loaded, job: &Job, pixels: f64, covered: f64) -> f64 {
        let s = self.scene(loaded, job);
        let row = job.row().canonical();
        let cal = s.rows.iter().find(|(r, _)| *r == row).map(|(_, c)| c).expect("calibrated row");
        let rays = (s.covered * covered * job.rays as f64).round() as u64;
        cal.overhead_s * pixels + cal.ns_per_ray * 1e-9 * rays as f64
    }

    /// The no-AO-ray render of the scene (of the still camera's windows under `[tiles]`).
    pub fn overhead_s(&self, loaded: &Loaded, scene_id: &str) -> f64 {
        let si = loaded.spec.scenes.iter().position(|s| s.id == scene_id).expect("planned scene");
        self.scenes[si].as_ref().map_or(0.0, |s| s.overhead_s * s.shares[0].0)
    }

    /// Bytes per pixel of `job`'s image as written: a filtered one's after a pipeline or a
    /// denoiser, a raw frame's otherwise.
    pub fn bytes_per_pixel(&self, job: &Job) -> f64 {
        let m = &job.measurement;
        let filtered =
            m.pipeline != crate::denoise::Pipeline::RAW || m.denoiser != crate::plan::DenoiserId::NONE;
        if filtered { self.post.filtered_exr_bytes_per_pixel } else { self.post.exr_bytes_per_pixel }
    }

    pub fn model(&self, loaded: &Loaded, workers: usize) -> cost::Model {
        let spec = &loaded.spec;
        cost::Model {
            protocol: timing::Protocol::new(spec.timing.repeats, spec.timing.seed, workers),
            overhead_renders: timing::OVERHEAD_REPEATS,
            // Each job's record is appended to the journal; the results files are rewritten whole
            // every so often.
            post_s: self.post.measure_s + self.post.serialize_per_record_s,
            rewrite_s: self.post.serialize_per_record_s,
            rewrite_every_s: crate::outdir::Saver::EVERY.as_secs_f64(),
            contention: self.contention,
        }
    }
}

/// A calibration render.
#[derive(Clone, Copy)]
struct Probe {
    scene: usize,
    /// `None`: the overhead render; `Some(i)`: estimator `i` of the scene.
    row: Option<usize>,
    rays: u32,
}

/// Renders the probes on `workers` one-thread workers and fits each estimator's line.
pub fn calibrate(
    loaded: &Loaded,
    full: &Plan,
    builds: &[Option<Manifest>],
    workers: usize,
) -> Result<Calibrated> {
    // Per scene: a job of every estimator it uses (the reference's last, if it must be built).
    let mut rows: Vec<Vec<Job>> = vec![Vec::new(); loaded.scenes.len()];
    for job in &full.jobs {
        let (si, _) = loaded.scene_of(job);
        if !rows[si].iter().any(|j| j.row().canonical() == job.row().canonical()) {
            rows[si].push(job.clone());
        }
    }
    for (si, b) in builds.iter().enumerate() {
        if let Some(m) = b {
            let r = plan::reference_jobs(&loaded.spec, si, m.rays).remove(0);
            if !rows[si].iter().any(|j| j.row().canonical() == r.row().canonical()) {
                rows[si].push(r);
            }
        }
    }
    let probes_in_all = rows.iter().map(Vec::len).sum::<usize>() as u64;
    let mut probes = Vec::new();
    let mut renders: Vec<RenderJob> = Vec::new();
    let mut warm: Vec<Option<RenderJob>> = vec![None; loaded.scenes.len()];
    let mut rays_of = vec![1u32; loaded.scenes.len()];
    let mut ratio_of = vec![1.0f64; loaded.scenes.len()];
    for (si, jobs) in rows.iter().enumerate() {
        let Some(first) = jobs.first() else { continue };
        let g = Geometry::of(first.resolution, first.ao_distance, &loaded.scenes[si]);
        let (width, height, ratio) = cost::calibration_size(g.width, g.height);
        ratio_of[si] = ratio;
        let at =
            |job: &Job, rays: u32| render_job(loaded, job, rays).map(|r| RenderJob { width, height, ..r });
        let per_probe = CALIBRATION_RAYS.min(CALIBRATION_TOTAL_RAYS / probes_in_all.max(1));
        let rays = (per_probe / (width as u64 * height as u64).max(1)).clamp(2, 64) as u32;
        rays_of[si] = rays;
        warm[si] = Some(at(first, 16)?);
        // In rounds, each a sample of everything: every line's two ends are measured early and
        // late alike (the 1-ray renders all first, while the machine warmed up, once moved every
        // estimator's per-image cost by 30 %).
        for _ in 0..CALIBRATION_SAMPLES {
            probes.push((Probe { scene: si, row: None, rays: 0 }, renders.len()));
            renders.push(overhead_job(&at(first, 1)?));
            probes.push((Probe { scene: si, row: Some(0), rays: 1 }, renders.len()));
            renders.push(at(first, 1)?);
            for (i, job) in jobs.iter().enumerate() {
                probes.push((Probe { scene: si, row: Some(i), rays }, renders.len()));
                renders.push(at(job, rays)?);
            }
        }
    }

    // Whatever an estimator sets up once per process (the blue-noise masks) is set up here, on a
    // tiny image, so that no calibration render pays for it; a run's first render does, once.
    for (si, jobs) in rows.iter().enumerate() {
        for job in jobs {
            let tiny = RenderJob { width: 4, height: 4, ..render_job(loaded, job, 1)? };
            render::render(&loaded.scenes[si], &tiny, &|_| {});
        }
    }
    let results: Mutex<Vec<(Probe, Time, u64)>> = Mutex::new(Vec::new());
    let sample: Mutex<Option<(usize, RenderOutput)>> = Mutex::new(None);
    // A 1-ray image, the noisiest a run writes, for the bytes per pixel of its images.
    let noisiest: Mutex<Option<RenderOutput>> = Mutex::new(None);
    let work = |w: &timing::Worker, &(p, r): &(Probe, usize)| -> Result<(Probe, Time, RenderOutput)> {
        let scene = &loaded.scenes[p.scene];
        if let Some(wj) = &warm[p.scene] {
            w.warm_up(p.scene, CALIBRATION_WARMUP_S, || {
                render::render(scene, wj, &|_| {});
            });
        }
        let (out, t) = w.timed(|| render::render(scene, &renders[r], &|_| {}));
        Ok((p, t, out))
    };
    let done = |_: &(Probe, usize), (p, t, out): (Probe, Time, RenderOutput)| -> Result<()> {
        results.lock().unwrap_or_else(|e| e.into_inner()).push((p, t, out.rays));
        if p.rays == 1 && p.row.is_some() {
            let mut n = noisiest.lock().unwrap_or_else(|e| e.into_inner());
            if n.is_none() {
                *n = Some(out);
                return Ok(());
            }
        }
        let mut s = sample.lock().unwrap_or_else(|e| e.into_inner());
        if s.is_none() && p.rays > 1 {
            *s = Some((p.scene, out));
        }
        Ok(())
    };
    let pool = timing::workers(workers).map_err(Error::Refused)?;
    // How busy the machine is now: other processes' runnable threads, sampled beside the renders.
    let stop = std::sync::atomic::AtomicBool::new(false);
    let (queued, runnable) = std::thread::scope(|s| {
        let sampler = s.spawn(|| {
            let mut r = io::Runnable::default();
            while !stop.load(std::sync::atomic::Ordering::Relaxed) && r.sample() {
                std::thread::sleep(std::time::Duration::from_millis(RUNNABLE_EVERY_MS));
            }
            r
        });
        let queued = timing::run_queue(&probes, pool, work, done);
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        (queued, sampler.join().unwrap_or_default())
    });
    queued?;
    let results = results.into_inner().unwrap_or_else(|e| e.into_inner());

    let cpu_s: f64 = results.iter().map(|r| r.1.cpu_s).sum();
    let wall_s: f64 = results.iter().map(|r| r.1.wall_s).sum();
    let mut scenes = Vec::new();
    for (si, jobs) in rows.iter().enumerate() {
        if jobs.is_empty() {
            scenes.push(None);
            continue;
        }
        let of = |row: Option<usize>, rays: u32| -> Vec<(u64, f64)> {
            results
                .iter()
                .filter(|(p, ..)| p.scene == si && p.row == row && p.rays == rays)
                .map(|(_, t, cast)| (*cast, t.cpu_s))
                .collect()
        };
        let median = |v: &[(u64, f64)]| crate::stats::median(&v.iter().map(|x| x.1).collect::<Vec<_>>());
        let one = of(Some(0), 1);
        let covered = one.first().map_or(0.0, |x| x.0 as f64);
        let base = (covered.round() as u64, median(&one));
        // Under `[tiles]` a frame renders the tiles' windows as its camera sees them: their share
        // of the pixels (the per-image part, the filter) and of the covered pixels (the AO rays).
        let share_of = |c: crate::plan::CameraId| {
            super::tiles::of_camera(&loaded.spec, si, &loaded.scenes[si], c)
                .map_or((1.0, 1.0), |t| (t.pixel_share(), t.covered_share))
        };
        let still = share_of(crate::plan::CameraId::STATIC);
        let moving = full
            .jobs
            .iter()
            .find(|j| loaded.scene_of(j).0 == si && moves(j))
            .map_or(still, |j| share_of(j.measurement.camera));
        let ratio = ratio_of[si];
        let mut cals = Vec::new();
        for (i, job) in jobs.iter().enumerate() {
            let mine = of(Some(i), rays_of[si]);
            let fit = Calibration::fit(&[base, (mine[0].0, median(&mine))]).ok_or_else(|| {
                Error::Refused(format!("calibration of {} on '{}' failed", job.row().label(), job.scene_name))
            })?;
            // Per image: as many times more as the real image has pixels; per AO ray: the same.
            let fit = Calibration { overhead_s: fit.overhead_s * ratio, overhead_interval: None, ..fit };
            cals.push((job.row().canonical(), fit));
        }
        scenes.push(Some(SceneCal {
            covered: covered * ratio_of[si],
            overhead_s: median(&of(None, 0)) * ratio,
            rows: cals,
            rays: rays_of[si],
            filters: filter_frames(loaded, full, si, &jobs[0])?,
            shares: [still, moving],
        }));
    }

    // Per recorded job: metrics, FLIP and the EXR; per record: the results files.
    let post = post_cost(
        loaded,
        full,
        sample.into_inner().unwrap_or_else(|e| e.into_inner()),
        noisiest.into_inner().unwrap_or_else(|e| e.into_inner()),
        &ratio_of,
    )?;
    let measured = if cpu_s > 0.0 { (wall_s / cpu_s).max(1.0) } else { 1.0 };
    let cpus = timing::cores() as f64;
    let busy = |others: f64| ((others + workers as f64) / cpus).max(1.0);
    let now = runnable.mean().map(busy);
    let averaged = io::load_average().map(|(load, cpus)| ((load + workers as f64) / cpus as f64).max(1.0));
    // Where /proc says who is running now, that; else between the two older measures.
    let contention = now.or(averaged.map(|a| (measured * a).sqrt())).unwrap_or(measured);
    Ok(Calibrated { scenes, post, contention, measured, averaged, now, cpu_s, wall_s })
}

/// The cheapest render of `plan` on this machine now, from its calibration `cal` (a fraction of a
/// second of renders, no reference needed): every estimator's line at the plan's fewest rays, the least of
/// them, with its job. What `advise` checks a budget against before its sweep.
pub fn cheapest(loaded: &Loaded, plan: &Plan, cal: &Calibrated) -> Result<(f64, Job)> {
    let fewest = plan.jobs.iter().map(|j| j.rays).min().unwrap_or(1);
    plan.jobs
        .iter()
        .filter(|j| j.rays == fewest && j.replicate == 0)
        .map(|j| (cal.render_s(loaded, j), j.clone()))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .ok_or_else(|| Error::Refused("nothing to calibrate: the plan has no job".into()))
}

/// Rays per covered pixel of an adaptive reference's renders after its pilot, on average: its
/// budget, or for `rays = "auto"` (settled only by the pilot) the rays an even reference would
/// need, which the adaptive allocation is there to undercut.
pub fn adaptive_rays(loaded: &Loaded, si: usize, m: &Manifest) -> Option<u32> {
    let a = m.adaptive.as_ref()?;
    Some(a.budget.unwrap_or_else(|| refs::auto_rays(&loaded.spec, si)))
}

/// Wall seconds to build `builds` (on `threads` threads): every replicate at the manifest's rays
/// (an adaptive reference's pilot), and an adaptive one's renders; a jittered view's replicate
/// is `views` renders of 1/`views` of the rays each (`jobs::reference`'s `build_view`).
pub fn references_s(loaded: &Loaded, cal: &Calibrated, builds: &[Build], threads: usize) -> f64 {
    let mut cpu = 0.0;
    for b in builds {
        let (si, m) = (b.scene, &b.manifest);
        // A tile's reference renders its window alone.
        let [w, h] = m.image_size();
        let share = (w as f64 * h as f64) / (m.resolution[0] as f64 * m.resolution[1] as f64).max(1.0);
        let passes = [Some(m.rays), adaptive_rays(loaded, si, m)];
        for rays in passes.into_iter().flatten() {
            let per = rays.div_ceil(b.views.max(1)).max(1);
            for job in plan::reference_jobs(&loaded.spec, si, per) {
                cpu += cal.render_whole_s(loaded, &job) * b.views as f64 * share;
            }
        }
    }
    cpu / threads.max(1) as f64 * cal.contention
}

/// `plan`'s estimate of the wall time of running `selected` (of `full`), references included: for
/// `run`'s warning before a long run (a fraction of a second of calibration renders).
pub fn estimate_s(
    loaded: &Loaded,
    full: &Plan,
    selected: &Plan,
    reference_dir: &std::path::Path,
    threads: usize,
) -> Result<f64> {
    let builds = builds(loaded, selected, reference_dir)?;
    let cal = calibrate(loaded, full, &by_scene(loaded, &builds), threads)?;
    let b = cost::jobs(
        selected,
        |j| cal.frame_s(loaded, j),
        |j, frames, shown| cal.filter_s(loaded, j, frames, shown),
        |id| cal.overhead_s(loaded, id),
        &cal.model(loaded, threads),
    );
    Ok(references_s(loaded, &cal, &builds, threads) + b.wall_s)
}
