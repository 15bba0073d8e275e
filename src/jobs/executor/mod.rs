//! `hemilab run`'s jobs under the timing protocol (`crate::timing`): every configuration's
//! replicates, and re-renders where it has fewer than `repeats`, in seeded interleaved passes
//! across one-thread workers; each scene's no-AO-ray render timed alongside as the overhead; a
//! warm-up before a worker's first timed render on a scene. Each job's image and record are
//! written as soon as it is rendered, so a killed run resumes where it stopped; a signal
//! (`interrupt`) stops the queue between jobs, once the renders in progress are saved.

use crate::error::{Error, Result};
use crate::image::Provenance;
use crate::interrupt;
use crate::load::Loaded;
use crate::metrics;
use crate::outdir;
use crate::plan::{self, Job, Plan};
use crate::reference as refmath;
use crate::reference::store::Reference;
use crate::render::{self, RenderJob, RenderOutput};
use crate::results::{self, JobResult};
use crate::scene::Scene;
use crate::spec::Row;
use crate::timing::{self, Need, Protocol, Slot, Summary, Time};
use state::{Done, State};

mod state;
use indicatif::ProgressBar;
use std::collections::HashMap;
use std::path::Path;
use std::time::Instant;

/// What a session measured besides the records.
pub struct Session {
    /// Per spec scene: the no-AO-ray render's times (`None` if the scene had no job).
    pub overhead: Vec<Option<Summary>>,
    /// Timed renders done in this session, and their total CPU and the session's wall seconds.
    pub renders: usize,
    pub cpu_s: f64,
    pub wall_s: f64,
    /// Jobs whose records an earlier run left (`resumed`), not rendered again.
    pub reused: usize,
}

impl Session {
    /// The session's totals, as `timing.json` records them.
    pub fn record(&self) -> timing::SessionRecord {
        timing::SessionRecord { timed_cpu_s: self.cpu_s, timed_renders: self.renders, wall_s: self.wall_s }
    }

    /// `timing.json`: how the run was timed, what a time includes, each scene's overhead, and the
    /// session's totals (a resumed run's older records keep the times of the session that made them).
    pub fn timing(&self, spec: &crate::spec::Spec, protocol: Protocol) -> timing::RunTiming {
        let overhead = spec
            .scenes
            .iter()
            .zip(&self.overhead)
            .map(|(s, o)| timing::SceneOverhead { scene: s.name.clone(), overhead_s: *o })
            .collect();
        timing::RunTiming::new(protocol, overhead, self.record())
    }
}

/// Rays per pixel of the warm-up render (enough to exercise the AO path, cheap enough to repeat).
const WARMUP_RAYS: u32 = 16;

/// The resume key: the job, and everything outside the job that its numbers depend on (scene
/// content, reference, hemilab version). The reference's measured fields (its render time, noise
/// floor) are left out: a rebuilt identical reference must not invalidate finished jobs. FLIP's
/// viewing condition (`Spec::flip_ppd`) enters only when it is not the default, so the keys of
/// every run made before it was a setting stay what they were.
pub fn run_key(job: &Job, scene: &Scene, reference: &Reference, flip_ppd: f64) -> String {
    // The camera in the form manifests had before it was JSON, so keys do not depend on the form.
    let camera = refmath::CameraRecord::Legacy(reference.manifest.camera.legacy());
    let manifest = refmath::Manifest {
        noise_floor: None,
        time_s: None,
        pixels: None,
        camera,
        ..reference.manifest.clone()
    };
    let mut what = format!(
        "{};{};{};{}",
        job.canonical(),
        scene.content_hash,
        manifest.to_json(),
        env!("CARGO_PKG_VERSION")
    );
    if flip_ppd != crate::metrics::DEFAULT_PPD {
        what.push_str(&format!(";flip_ppd={flip_ppd}"));
    }
    format!("{:016x}", plan::fnv1a64(what.as_bytes()))
}

/// The one resume rule: a job is reused when an earlier run left a record with its key and the
/// image that record names is on disk (a record whose image write was cut short is redone).
pub fn resumed<'a>(previous: &'a HashMap<String, JobResult>, key: &str, out: &Path) -> Option<&'a JobResult> {
    previous.get(key).filter(|r| outdir::has_image(out, &r.image))
}

pub fn render_job(loaded: &Loaded, job: &Job, rays: u32) -> Result<RenderJob> {
    super::runner::render_job(job, loaded.scene_of(job).1, rays)
}

pub use crate::render::overhead_job;

/// After a queue: a signal's stop, with what is saved (`interrupt::message`), once the renders in
/// progress have finished; the stop is a stop even if the queue happened to finish.
fn stop_if_interrupted() -> Result<()> {
    if interrupt::requested() {
        return Err(Error::Interrupted(interrupt::message()));
    }
    Ok(())
}

/// What becomes of a measured job's image (plan index, job, the render): `run` writes it as EXR
/// under `images/`; `advise` keeps its error in memory. Returns the record's `image` column.
pub type Keep<'a> = dyn Fn(usize, &Job, &RenderOutput) -> Result<String> + Sync + 'a;

/// Everything a run of measured jobs reads and where its records go.
pub struct Jobs<'a> {
    pub loaded: &'a Loaded,
    pub plan: &'a Plan,
    /// By spec scene (`Loaded::scene_of`).
    pub references: &'a [Reference],
    /// The camera paths' frames' references (`jobs::reference::obtain_views`; empty without paths).
    pub views: &'a super::reference::ViewReferences,
    /// Earlier records by run key: a job found there (with its image) is not rendered again.
    pub previous: &'a HashMap<String, JobResult>,
    pub out: &'a Path,
    pub protocol: Protocol,
    pub bar: &'a ProgressBar,
    /// The progress bar's label for this phase (every phase has one: a bar that starts again at
    /// 0 % under the same word reads as the same work done twice).
    pub label: &'a str,
    /// Called after each render that made records, as soon as they are made (a killed run keeps them).
    pub write: &'a Write<'a>,
}

/// What a render added: its new records, and every record of the plan so far (by plan position).
pub struct Saved<'a> {
    pub new: &'a [JobResult],
    pub so_far: &'a [Option<JobResult>],
}

/// Where a run's records go as they are made (`Jobs::write`).
pub type Write<'a> = dyn Fn(&Saved) -> Result<()> + Sync + 'a;

/// Renders and measures every job of the plan not already in `previous` (by key, with its image),
/// times everything per the protocol, and returns the records in plan order; each image is written
/// as EXR under `out`.
pub fn run_jobs(j: &Jobs) -> Result<(Vec<JobResult>, Session)> {
    let spec = &j.loaded.spec;
    let tiles: Vec<Option<super::tiles::TileSet>> = match spec.tiles {
        Some(_) => (0..j.loaded.scenes.len())
            .map(|si| super::tiles::of_spec(spec, si, &j.loaded.scenes[si]))
            .collect(),
        None => Vec::new(),
    };
    let keep = |_: usize, job: &Job, output: &RenderOutput| {
        let (si, scene) = j.loaded.scene_of(job);
        let t = tiles.get(si).and_then(Option::as_ref);
        let provenance = provenance_tiled(&spec.name, job, scene, &j.references[si], output, t);
        outdir::write_image(j.out, job, output, &provenance)
    };
    measure_jobs(j, &keep)
}

/// A measured image's provenance, for its EXR header: the configuration, rays, seed, scene and
/// reference it was measured against, and the version (everything its run key covers, readable).
pub fn provenance(
    spec: &str,
    job: &Job,
    scene: &Scene,
    reference: &Reference,
    output: &RenderOutput,
) -> Provenance {
    provenance_tiled(spec, job, scene, reference, output, None)
}

/// `provenance` of a job measured on `tiles` (`[tiles]`): the image is the mosaic of the tiles'
/// interiors, and the tile set (`TileSet::canonical`) is named beside the image's size.
pub fn provenance_tiled(
    spec: &str,
    job: &Job,
    scene: &Scene,
    reference: &Reference,
    output: &RenderOutput,
    tiles: Option<&super::tiles::TileSet>,
) -> Provenance {
    let (w, h) = (output.ao.width, output.ao.height);
    let d = plan::Geometry::of(job.resolution, job.ao_distance, scene).distance.canonical();
    let reference_file =
        reference.exr.file_name().map_or(String::new(), |n| n.to_string_lossy().into_owned());
    let json = serde_json::json!({
        "image": "job",
        "hemilab_version": env!("CARGO_PKG_VERSION"),
        "spec": spec,
        "scene": job.scene_id,
        "scene_name": job.scene_name,
        "scene_hash": scene.content_hash,
        "distribution": job.distribution.name(),
        "sequence": job.sequence.name(),
        "seed_mode": job.seed_mode.name(),
        "rays": job.rays,
        "replicate": job.replicate,
        "seed": job.seed,
        "resolution": [w, h],
        "ao_distance": d,
        "reference": reference_file,
        "reference_noise_floor": reference.noise_floor(),
    });
    let mut json = json;
    let mut on = String::new();
    if let (Some(t), Some(o)) = (tiles, json.as_object_mut()) {
        let g = plan::Geometry::of(job.resolution, job.ao_distance, scene);
        o.insert("tiles".into(), t.canonical().into());
        o.insert("tiles_of".into(), serde_json::json!([g.width, g.height]));
        on = format!(
            "; measured on tiles {} of the {}x{} image (their interiors side by side)",
            t.canonical(),
            g.width,
            g.height
        );
    }
    let summary = format!(
        "hemilab {} job of spec '{spec}': {} / {} / {}, {} rays per pixel, replicate {}, seed {}; scene {} \
         ({w}x{h}, d = {d}, hash {}); measured against reference {reference_file}",
        env!("CARGO_PKG_VERSION"),
        job.distribution.name(),
        job.sequence.name(),
        job.seed_mode.name(),
        job.rays,
        job.replicate,
        job.seed,
        job.scene_id,
        scene.content_hash,
    ) + &on;
    Provenance { summary, json }
}

/// Where, under a run's output directory, a user's denoiser command works on a job's frames
/// (one directory per job, removed after each success).
pub const DENOISE_DIR: &str = ".denoise";

/// Renders given a denoiser directory so far (each its own, `DENOISE_DIR/<job>-<n>`).
static SCRATCH: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// `run_jobs` with the image handed to `keep` instead of written.
pub fn measure_jobs(j: &Jobs, keep: &Keep) -> Result<(Vec<JobResult>, Session)> {
    let Jobs { loaded, plan, references, views, previous, out, protocol, bar, label, write } = *j;
    let start = Instant::now();
    let n = plan.jobs.len();
    let scenes = loaded.scenes.len();
    let keys: Vec<String> = plan
        .jobs
        .iter()
        .map(|j| {
            let (si, s) = loaded.scene_of(j);
            run_key(j, s, &references[si], loaded.spec.flip_ppd)
        })
        .collect();
    let records: Vec<Option<JobResult>> = keys.iter().map(|k| resumed(previous, k, out).cloned()).collect();
    let reused = records.iter().flatten().count();
    // From here a signal lets the renders in progress finish (and be saved) before the run stops.
    let _phase = interrupt::jobs_phase(reused, n);

    // Each series of frames is rendered once, by its leader, for every member's image; it is
    // rendered again (every member's record made anew) unless every member has its record.
    let series = plan::series(plan);
    let mut members_of: HashMap<usize, Vec<usize>> = HashMap::new();
    for s in &series {
        members_of.insert(s.leader, s.members.clone());
    }
    // One unit per configuration: its replicates cost the same.
    let mut unit_of: HashMap<(String, Row, u32), usize> = HashMap::new();
    let mut needs: Vec<Need> = Vec::new();
    for s in &series {
        let u = *unit_of.entry(plan::unit_key(&plan.jobs[s.leader])).or_insert_with(|| {
            needs.push(Need { repeats: protocol.repeats, ..Need::default() });
            needs.len() - 1
        });
        if s.members.iter().all(|&i| records[i].is_some()) {
            needs[u].again.push(s.leader);
            needs[u].have += records[s.leader].as_ref().map_or(0, |r| r.times.len());
        } else {
            needs[u].fresh.push(s.leader);
        }
    }
    // Render jobs (ids < n), then one overhead job per scene (id n + scene), timed when something
    // else is (the overhead must come from the same session as the times it is taken from) or when
    // a record was never split (a run killed after its last job, before the end).
    let mut jobs: Vec<RenderJob> =
        plan.jobs.iter().map(|j| render_job(loaded, j, j.rays)).collect::<Result<_>>()?;
    // Every table and mask a configuration reads is made here, outside every timed render.
    jobs.iter().for_each(|j| j.sampler.prepare());
    let mut warm: Vec<Option<RenderJob>> = vec![None; scenes];
    for j in &plan.jobs {
        let (si, _) = loaded.scene_of(j);
        if warm[si].is_none() {
            warm[si] = Some(render_job(loaded, j, j.rays.min(WARMUP_RAYS))?);
        }
    }
    let mut slots = timing::schedule(&needs, protocol.seed);
    if !slots.is_empty() || records.iter().flatten().any(|r| r.timings == 0) {
        for (si, w) in warm.iter().enumerate() {
            jobs.push(overhead_job(w.as_ref().unwrap_or(&jobs[0])));
            if w.is_some() {
                needs.push(Need {
                    again: vec![n + si],
                    repeats: timing::OVERHEAD_REPEATS,
                    ..Need::default()
                });
            }
        }
        slots = timing::schedule(&needs, protocol.seed);
    }
    let scene_of_id = |id: usize| if id < n { loaded.scene_of(&plan.jobs[id]).0 } else { id - n };
    // Each job's kind of measurement, and what the filtered ones are guided by and compared with.
    let measures: Vec<Box<dyn super::measure::Measure>> =
        plan.jobs.iter().map(|j| super::measure::of(&j.measurement)).collect();
    let guides = super::guides::Guides::new(
        plan.jobs.iter().enumerate().map(|(i, j)| super::guides::Need {
            target: loaded.scene_of(j).0,
            measurement: &j.measurement,
            width: jobs[i].width,
            height: jobs[i].height,
        }),
        |si| &loaded.scenes[si],
        views,
        |si, camera| super::tiles::of_camera(&loaded.spec, si, &loaded.scenes[si], camera),
    );
    let frames_of = |id: usize| measures.get(id).map_or(1, |m| m.frames());
    // Pixels rendered per frame: the tiles' windows under `[tiles]`, else the whole image.
    let camera_of =
        |id: usize| plan.jobs.get(id).map_or(crate::plan::CameraId::STATIC, |j| j.measurement.camera);
    let frame_pixels = |id: usize| match guides
        .tiles(scene_of_id(id), camera_of(id))
        .filter(|_| loaded.spec.tiles.is_some())
    {
        Some(t) => t.rendered_pixels(),
        None => jobs[id].width as u64 * jobs[id].height as u64,
    };
    let pixels = |id: usize| frame_pixels(id) * frames_of(id);
    let cost = |slots: &[Slot]| slots.iter().map(|s| pixels(s.job) * jobs[s.job].sampler.count as u64).sum();
    bar.reset();
    bar.set_length(cost(&slots));
    bar.set_message(label.to_string());

    let work = |worker: &timing::Worker, slot: &Slot| -> Result<Done> {
        // Checked between jobs: a stopped queue hands out no more, and the jobs in flight finish.
        if interrupt::requested() {
            return Err(Error::Interrupted(String::new()));
        }
        let si = scene_of_id(slot.job);
        let scene = &loaded.scenes[si];
        if let Some(w) = &warm[si] {
            worker.warm_up(si, protocol.warmup_s, || {
                render::render(scene, w, &|_| {});
            });
        }
        let rj = &jobs[slot.job];
        let rays = rj.sampler.count as u64;
        // Overhead renders (ids from n) are single AO frames, of the tiles under `[tiles]`.
        let paper = crate::plan::Measurement { tiles: loaded.spec.tiles, ..crate::plan::Measurement::PAPER };
        let single = super::measure::SingleFrame(paper);
        let measure: &dyn super::measure::Measure = measures.get(slot.job).map_or(&single, |m| &**m);
        let members: Vec<usize> = members_of.get(&slot.job).cloned().unwrap_or_else(|| vec![slot.job]);
        let wanted = |i: usize| {
            plan.jobs
                .get(i)
                .map_or((crate::denoise::Pipeline::RAW, 1), |j| (j.measurement.pipeline, j.measurement.frame))
        };
        let mut reported: Vec<(crate::denoise::Pipeline, u32)> = Vec::new();
        for &i in &members {
            if !reported.contains(&wanted(i)) {
                reported.push(wanted(i));
            }
        }
        let m = plan.jobs.get(slot.job).map_or(paper, |j| j.measurement);
        // A directory of this render's own: a job's timing-only renders run beside its recorded
        // one on another worker, and two renders writing one denoiser input collide.
        let scratch = m.denoiser.get().map(|_| {
            let n = SCRATCH.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            out.join(DENOISE_DIR).join(format!("{}-{n}", plan.jobs[slot.job].file_stem()))
        });
        let against = super::guides::Against {
            timing_only: !slot.record,
            ..guides.against(si, &m, &references[si], scratch)
        };
        let (images, time): (Result<Vec<super::measure::FrameImage>>, Time) =
            worker.timed(|| measure.render(scene, rj, &reported, &against, &|px| bar.inc(px * rays)));
        let images = images?;
        let mut parts = Vec::with_capacity(members.len());
        for &i in &members {
            let img = images
                .iter()
                .find(|f| (f.pipeline, f.frame) == wanted(i))
                .expect("every reported frame rendered");
            let t = img.time.unwrap_or(time);
            if !slot.record {
                parts.push((i, t, None));
                continue;
            }
            let job = &plan.jobs[i];
            let refuse = |e: metrics::MetricsError| Error::Refused(format!("job {}: {e}", job.file_stem()));
            let stats = super::measure::errors(img, &against).map_err(refuse)?;
            let image = keep(i, job, &img.output)?;
            let mut record = JobResult::new(job, &stats, img.output.rays, image);
            record.flip = super::measure::flip(img, &against, loaded.spec.flip_ppd);
            record.flicker = Some(img.flicker).filter(|f| f.is_finite());
            record.denoise_s = img.denoise_s;
            record.key = keys[i].clone();
            record.timing_threads = protocol.threads_per_render as u32;
            parts.push((i, t, Some(record)));
        }
        Ok(Done { time, parts })
    };

    let mut state = State::new(records, scenes);
    let workers = timing::workers(protocol.workers).map_err(Error::Refused)?;
    let queued = timing::run_queue(&slots, workers, work, |slot, d| state.done(n, slot, d, write));
    stop_if_interrupted()?;
    queued?;
    // Second round: more samples for the units whose samples add up to little time, when every
    // measurement of the plan takes one (`Measurement::tops_up`).
    let top_up = plan.jobs.iter().all(|j| j.measurement.tops_up());
    if state.renders > 0 && top_up {
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); needs.len()];
        for (i, job) in plan.jobs.iter().enumerate() {
            members[unit_of[&plan::unit_key(job)]].push(i);
        }
        let units: Vec<(Vec<usize>, Vec<f64>)> = needs
            .iter()
            .enumerate()
            .map(|(u, need)| match members.get(u).filter(|m| !m.is_empty()) {
                Some(m) => (m.clone(), m.iter().flat_map(|&i| state.samples(i)).collect()),
                None => (need.again.clone(), state.overhead_samples[need.again[0] - n].clone()),
            })
            .collect();
        let extra = timing::top_up(&units, protocol.min_total_s, protocol.max_repeats);
        let slots = timing::schedule(&extra, protocol.seed ^ 0x5eed_0002);
        // A phase of its own: lengthening the first round's bar would send its percentage back
        // (80 % → 27 %) under the same label.
        bar.reset();
        bar.set_length(cost(&slots));
        bar.set_message(format!("{label}, timing repeats"));
        let workers = timing::workers(protocol.workers).map_err(Error::Refused)?;
        let queued = timing::run_queue(&slots, workers, work, |slot, d| state.done(n, slot, d, write));
        stop_if_interrupted()?;
        queued?;
    }
    let State { records, overhead_samples, renders, cpu_s, .. } = state;
    // Every denoiser run succeeded (a failure stopped the run above, its files kept to try by hand).
    crate::io::remove_dir_all_if_exists(&out.join(DENOISE_DIR))?;

    let overhead: Vec<Option<Summary>> = overhead_samples.iter().map(|s| Summary::of(s)).collect();
    let mut records: Vec<JobResult> =
        records.into_iter().map(|r| r.expect("every job rendered or resumed")).collect();
    let by_name = |name: &str| {
        let si = loaded.spec.scenes.iter().position(|s| s.name == name)?;
        overhead[si].map(|s| s.median)
    };
    // A fully resumed run renders nothing and keeps the overhead its records were split with.
    if renders > 0 {
        results::fill_timing(&mut records, &by_name);
    }
    // Every replicate is measured now: each configuration's bias and noise, from the kept images.
    let against = |i: usize| {
        let job = &plan.jobs[i];
        let si = loaded.scene_of(job).0;
        let a = guides.against(si, &job.measurement, &references[si], None);
        let (r, c) = a.at(job.measurement.frame);
        (r.clone(), c.clone())
    };
    let image = |r: &JobResult| -> Result<Option<crate::image::Image>> {
        if r.image.is_empty() || !outdir::has_image(out, &r.image) {
            return Ok(None);
        }
        outdir::read_image(out, &r.image).map(Some)
    };
    super::replicates::split(&mut records, &plan.jobs, &against, &image)?;
    let wall_s = start.elapsed().as_secs_f64();
    Ok((records, Session { overhead, renders, cpu_s, wall_s, reused }))
}
