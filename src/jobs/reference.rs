//! Rendering a reference the store has not got: its replicates (and an adaptive reference's pilot
//! pass) on every thread, then stored by `reference::store`. `obtain` is the one door: reuse a
//! stored reference whose manifest matches, else build one (unless told not to).

use super::runner::JobRunner;
use crate::error::{Error, Result};
use crate::image::Image;
use crate::io;
use crate::plan::{self, CameraId, Geometry};
use crate::reference::store::{self, Policy, Reference, ReferenceView};
use crate::reference::{self, Adaptive, Manifest};
use crate::scene::Scene;
use crate::spec::{MAX_REFERENCE_RAYS, Spec};
use std::path::Path;
use std::time::Instant;

/// The reference of scene `si`, from `dir` or freshly rendered into it.
///
/// Shards of one spec may start together on a shared filesystem: each takes the reference's lock
/// file (`<stem>.lock`, an OS lock released even if the process is killed) before it looks, so one
/// builds while the others wait and then reuse its result. The image and the manifest are each
/// written atomically, image first, so no reader ever sees a half-written file or a manifest
/// without its image. Where the lock cannot be taken (a read-only reference directory, a filesystem
/// without locks) the run goes on without it: then build the references in a step of their own
/// (`hemilab reference`) and run the shards with `--no-build-reference`.
pub fn obtain(
    spec: &Spec,
    si: usize,
    scene: &Scene,
    dir: &Path,
    policy: Policy,
    runner: &JobRunner,
) -> Result<Reference> {
    let tiles = super::tiles::of_spec(spec, si, scene);
    obtain_measured(spec, si, scene, &ReferenceView::of_scene(scene), tiles.as_ref(), dir, policy, runner)
}

/// The reference a job measures against: `obtain_view`'s, or under `[tiles]` the mosaic
/// (`jobs::tiles::TileSet::mosaic`) of the references of the tiles' interiors, each a reference of
/// its own window (`ReferenceView::of_window`), stored with its window in its manifest and so
/// reused by every run of the same tiles and never taken for a whole frame. The mosaic's manifest
/// is the first tile's without its window, with the mosaic's noise floor.
#[allow(clippy::too_many_arguments)]
pub fn obtain_measured(
    spec: &Spec,
    si: usize,
    scene: &Scene,
    view: &ReferenceView,
    tiles: Option<&super::tiles::TileSet>,
    dir: &Path,
    policy: Policy,
    runner: &JobRunner,
) -> Result<Reference> {
    let Some(tiles) = tiles else { return obtain_view(spec, si, scene, view, dir, policy, runner) };
    let mut parts = Vec::with_capacity(tiles.interiors.len());
    for w in &tiles.interiors {
        parts.push(obtain_view(spec, si, scene, &view.of_window(*w), dir, policy, runner)?);
    }
    let first = parts.first().ok_or_else(|| {
        Error::Refused(format!(
            "scene '{}': no tile of the image sees the scene ([tiles] needs covered pixels)",
            scene.name
        ))
    })?;
    let mosaic = |f: fn(&Reference) -> &Image, fill: f32| {
        let images: Vec<Image> = parts.iter().map(|r| f(r).clone()).collect();
        tiles.mosaic_image(&images, fill)
    };
    let (mean, stderr, coverage) =
        (mosaic(|r| &r.mean, 1.0), mosaic(|r| &r.stderr, 0.0), mosaic(|r| &r.coverage, 0.0));
    let mut manifest = Manifest { window: None, pixels: None, ..first.manifest.clone() };
    manifest.noise_floor = Some(reference::noise_floor(&stderr, &coverage));
    let exr = first.exr.clone();
    Ok(Reference { mean, stderr, coverage, manifest, exr })
}

/// The references of camera paths' frames, by (scene index, camera, frame from 0): for a moving
/// path, the frames where a job measures error (its reported frames) and the frame before each
/// (flicker compares consecutive frames); for a static jittered camera, frame 0 alone (the mean
/// over the jitter cycle serves every frame).
#[derive(Default)]
pub struct ViewReferences {
    by_camera: std::collections::HashMap<(usize, CameraId), std::collections::HashMap<u32, Reference>>,
    empty: std::collections::HashMap<u32, Reference>,
}

impl ViewReferences {
    /// The frames' references of `camera` over scene `si` (empty if it has none).
    pub fn of(&self, si: usize, camera: CameraId) -> &std::collections::HashMap<u32, Reference> {
        self.by_camera.get(&(si, camera)).unwrap_or(&self.empty)
    }

    /// How many references are held.
    pub fn len(&self) -> usize {
        self.by_camera.values().map(|m| m.len()).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The frames (from 0) of camera path `camera` whose references the jobs of `plan` on scene `si`
/// read, ascending.
pub fn view_frames(
    plan: &plan::Plan,
    si_of: impl Fn(&plan::Job) -> usize,
    si: usize,
    camera: CameraId,
) -> Vec<u32> {
    let Some(run) = camera.run() else { return Vec::new() };
    let mut frames: Vec<u32> = Vec::new();
    for j in plan.jobs.iter().filter(|j| j.measurement.camera == camera && si_of(j) == si) {
        if run.path.is_static() {
            frames.push(0);
            continue;
        }
        let f = j.measurement.frame;
        frames.push(f - 1);
        if f >= 2 {
            frames.push(f - 2);
        }
    }
    frames.sort_unstable();
    frames.dedup();
    frames
}

/// One camera path frame's reference a plan reads: scene index, camera, frame (from 0), view.
pub struct NeededView {
    pub scene: usize,
    pub camera: CameraId,
    pub frame: u32,
    pub view: ReferenceView,
}

/// Every camera path frame reference the plan's jobs read (`view_frames` of every moving or
/// jittered camera), by scene, camera and frame: what `obtain_views` obtains and `plan` counts.
pub fn needed_views(
    plan: &plan::Plan,
    scenes: &[std::sync::Arc<Scene>],
    si_of: impl Fn(&plan::Job) -> usize,
) -> Vec<NeededView> {
    let mut cameras: Vec<(usize, CameraId)> = plan
        .jobs
        .iter()
        .filter(|j| j.measurement.camera != CameraId::STATIC)
        .map(|j| (si_of(j), j.measurement.camera))
        .collect();
    cameras.sort_unstable();
    cameras.dedup();
    let mut out = Vec::new();
    for (si, camera) in cameras {
        let run = camera.run().expect("a camera other than the static one is interned");
        let scene = &scenes[si];
        for frame in view_frames(plan, &si_of, si, camera) {
            let view = ReferenceView {
                camera: run.path.camera(&scene.view, frame, run.frames.max(1)),
                jitter_average: run.jitter,
                window: None,
            };
            out.push(NeededView { scene: si, camera, frame, view });
        }
    }
    out
}

/// Every camera path frame reference the plan needs (`ViewReferences`, `needed_views`), each
/// obtained as `obtain_view` does: reused from `dir` when its manifest matches, else built.
pub fn obtain_views(
    spec: &Spec,
    plan: &plan::Plan,
    scenes: &[std::sync::Arc<Scene>],
    si_of: impl Fn(&plan::Job) -> usize,
    dir: &Path,
    policy: Policy,
    runner: &JobRunner,
) -> Result<ViewReferences> {
    let mut out = ViewReferences::default();
    let mut tiles: std::collections::HashMap<usize, Option<super::tiles::TileSet>> = Default::default();
    for n in needed_views(plan, scenes, si_of) {
        let scene = &scenes[n.scene];
        let t = tiles.entry(n.scene).or_insert_with(|| super::tiles::of_spec(spec, n.scene, scene));
        let r = obtain_measured(spec, n.scene, scene, &n.view, t.as_ref(), dir, policy, runner)?;
        out.by_camera.entry((n.scene, n.camera)).or_default().insert(n.frame, r);
    }
    Ok(out)
}

/// `obtain` for another view of the scene (a camera path's frame, a jittered camera's average).
pub fn obtain_view(
    spec: &Spec,
    si: usize,
    scene: &Scene,
    view: &ReferenceView,
    dir: &Path,
    policy: Policy,
    runner: &JobRunner,
) -> Result<Reference> {
    let geometry = Geometry::of(spec.resolution, spec.ao_distance, scene);
    let wanted = store::wanted_view(spec, si, scene, geometry, view);
    let lock_path = dir.join(format!("{}.lock", wanted.file_stem()));
    if policy != Policy::ReuseOnly && !io::exists(dir) {
        // Nothing to reuse: it will be built here, and the lock file needs the directory.
        io::ensure_writable_dir(dir)?;
        io::create_dir_all(dir)?;
    }
    let waiting = |holder: &str| {
        eprintln!("reference for '{}': waiting for {holder} ({})", scene.name, lock_path.display())
    };
    let (_lock, unlocked) = match io::exists(dir).then(|| io::lock(&lock_path, waiting)).transpose()? {
        Some(Ok(lock)) => (Some(lock), None),
        Some(Err(why)) => (None, Some(why)),
        None => (None, None),
    };
    if policy != Policy::Rebuild {
        match store::find(spec, &wanted, dir)? {
            Ok(r) => return Ok(r),
            Err((file, why)) if policy == Policy::ReuseOnly => {
                let flag = if dir == spec.reference_dir {
                    String::new()
                } else {
                    format!(" --reference-dir {}", dir.display())
                };
                return Err(Error::input(
                    &file,
                    format!(
                        "{why}: no usable reference for scene '{}' in {}; build it with `hemilab reference \
                         {}{flag}`, pass --reference-dir DIR if it is stored elsewhere, or drop \
                         --no-build-reference",
                        scene.name,
                        dir.display(),
                        spec.path.display()
                    ),
                ));
            }
            Err((file, why)) => {
                // Fail before the (long) reference render, not after it, if it could not be saved.
                io::ensure_writable_dir(dir)?;
                eprintln!("reference for '{}': {}: {why}; rendering a new one", scene.name, file.display())
            }
        }
    }
    io::ensure_writable_dir(dir)?;
    if let Some(why) = unlocked {
        eprintln!("warning: {why}; another run started now could build this reference at the same time");
    }
    build(spec, si, scene, view, wanted, dir, runner)
}

fn build(
    spec: &Spec,
    si: usize,
    scene: &Scene,
    view: &ReferenceView,
    mut manifest: Manifest,
    dir: &Path,
    runner: &JobRunner,
) -> Result<Reference> {
    if *view != ReferenceView::of_scene(scene) {
        if manifest.adaptive.is_some() {
            return Err(Error::Refused(format!(
                "scene '{}': an adaptive reference (allocation = \"adaptive\") of a camera path's frame or of \
                 a tile is not supported; use allocation = \"even\" in a spec with cameras or [tiles]",
                scene.name
            )));
        }
        return build_view(spec, si, scene, view, manifest, dir, runner);
    }
    let jobs = plan::reference_jobs(spec, si, manifest.rays);
    let start = Instant::now();
    let mut images = Vec::with_capacity(jobs.len());
    let mut coverage = None;
    let counts = match &manifest.adaptive {
        Some(a) => Some(allocation(spec, si, scene, &manifest, a, runner)?),
        None => None,
    };
    for (i, job) in jobs.iter().enumerate() {
        let label = format!("reference {}/{}", i + 1, jobs.len());
        let done = match &counts {
            Some(c) => runner.render_counts(job, scene, c, &label)?,
            None => runner.render_pass(job, scene, &label)?,
        };
        coverage.get_or_insert(done.output.coverage);
        images.push(done.output.ao);
    }
    if let (Some(a), Some(c)) = (manifest.adaptive.as_mut(), &counts) {
        a.total_rays = Some(c.iter().map(|&n| n as u64).sum());
        a.max_rays = c.iter().copied().max();
    }
    let coverage =
        coverage.ok_or_else(|| Error::Refused("a reference needs at least one replicate".into()))?;
    let (mean, stderr) = reference::mean_and_stderr(&images).map_err(Error::Refused)?;
    let r = store::save(manifest, mean, stderr, coverage, dir, &scene.name, start)?;
    if let Some(note) = store::others_note(&r)? {
        eprintln!("{note}");
    }
    Ok(r)
}

/// A reference of another view: each replicate rendered from the view's camera; for a jittered
/// camera, the mean of one render at each offset of the jitter cycle with 1/cycle of the rays
/// (rounded up), each with its own numbers (frame j of the replicate's sampler), and a pixel
/// covered only where every offset's primary ray hits.
fn build_view(
    spec: &Spec,
    si: usize,
    scene: &Scene,
    view: &ReferenceView,
    mut manifest: Manifest,
    dir: &Path,
    runner: &JobRunner,
) -> Result<Reference> {
    use crate::scene::camera_path::{JITTER_CYCLE, halton_jitter};
    let start = Instant::now();
    let offsets: Vec<glam::Vec2> = if view.jitter_average {
        (0..JITTER_CYCLE).map(halton_jitter).collect()
    } else {
        vec![glam::Vec2::ZERO]
    };
    let per = manifest.rays.div_ceil(offsets.len() as u32).max(1);
    let jobs = plan::reference_jobs(spec, si, per);
    let mut images = Vec::with_capacity(jobs.len());
    let mut coverage: Option<Image> = None;
    for (i, job) in jobs.iter().enumerate() {
        let mut sum: Option<Vec<f64>> = None;
        for (j, &jitter) in offsets.iter().enumerate() {
            let label = format!("reference {}/{} ({} of {} views)", i + 1, jobs.len(), j + 1, offsets.len());
            let v = crate::render::View::new(view.camera, jitter);
            let out = runner.render_view_pass(job, scene, &v, view.window, j as u32, &label)?.output;
            let s = sum.get_or_insert_with(|| vec![0.0; out.ao.len()]);
            for (a, &x) in s.iter_mut().zip(&out.ao.data) {
                *a += x as f64;
            }
            coverage = Some(match coverage.take() {
                None => out.coverage,
                Some(c) => Image::from_vec(
                    c.width,
                    c.height,
                    c.data.iter().zip(&out.coverage.data).map(|(&a, &b)| a.min(b)).collect(),
                ),
            });
        }
        let s = sum.expect("at least one view");
        let k = offsets.len() as f64;
        let [w, h] = manifest.image_size();
        images.push(Image::from_vec(w, h, s.iter().map(|&x| (x / k) as f32).collect()));
    }
    let coverage =
        coverage.ok_or_else(|| Error::Refused("a reference needs at least one replicate".into()))?;
    let (mean, stderr) = reference::mean_and_stderr(&images).map_err(Error::Refused)?;
    manifest.rays = manifest.rays.max(per);
    store::save(manifest, mean, stderr, coverage, dir, &scene.name, start)
}

/// Rays per pixel of an adaptive reference: a pilot pass (the reference estimator at the manifest's
/// `rays`, replicates with seeds of their own stream, so the allocation is independent of the final
/// renders) gives each pixel's spread; `reference::allocate` turns it into counts. Under `rays =
/// "auto"` the target floor is `FLOOR_RATIO` of the pilot's single-render RMS error, the error of the
/// reference estimator at the largest ray count the spec measures.
fn allocation(
    spec: &Spec,
    si: usize,
    scene: &Scene,
    manifest: &Manifest,
    a: &Adaptive,
    runner: &JobRunner,
) -> Result<Vec<u32>> {
    let mut pilots = Vec::new();
    let mut coverage = None;
    let mut jobs = plan::reference_jobs(spec, si, manifest.rays);
    for (i, job) in jobs.iter_mut().enumerate() {
        job.seed = plan::reference_seed(spec.reference.seed ^ PILOT_STREAM, job.replicate);
        let done = runner.render_pass(
            job,
            scene,
            &format!("reference pilot {}/{}", i + 1, spec.reference.replicates),
        )?;
        coverage.get_or_insert(done.output.coverage);
        pilots.push(done.output.ao);
    }
    let coverage =
        coverage.ok_or_else(|| Error::Refused("a reference needs at least one replicate".into()))?;
    let (_, se) = reference::mean_and_stderr(&pilots).map_err(Error::Refused)?;
    let k = pilots.len() as f32;
    let sd = Image::from_vec(se.width, se.height, se.data.iter().map(|x| x * k.sqrt()).collect());
    let sd = reference::neighbourhood_max(&sd, &coverage);
    let single_render_error = reference::noise_floor(&sd, &coverage);
    let target = reference::target_floor(single_render_error);
    let allocation = reference::Allocation {
        replicates: manifest.replicates,
        pilot_rays: manifest.rays,
        budget: a.budget,
        target_floor: target,
        min_rays: a.min_rays,
        max_rays: MAX_REFERENCE_RAYS,
    };
    Ok(reference::allocate(&sd, &coverage, &allocation))
}

/// Pilot seeds are their own stream (the reference's seed xor "pilot").
const PILOT_STREAM: u64 = 0x0070_696c_6f74;
