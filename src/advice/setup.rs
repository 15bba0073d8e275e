//! `hemilab advise`'s set-up: the flags become a spec with one convergence sweep (every
//! configuration × the ray ladder × the replicates), at a resolution and with reference settings
//! chosen so that a stored reference of the scene is reused where `run` would reuse it. Every
//! input is checked here, before any work: the flags on their own (`check`), then with what the
//! command loaded for them (`Inputs`: the scene, its stored references). Nothing is read or written
//! here.

use crate::advice;
use crate::compare::{PAPER_DEFAULT, per_pixel_unbiased};
use crate::error::{Error, Result};
use crate::load::{Loaded, check_pixels, check_view};
use crate::plan::Geometry;
use crate::plan::{self, Plan};
use crate::plan::{CameraId, DenoiserId};
use crate::reference::Manifest;
use crate::reference::store as refs;
use crate::sampling::Integrand;
use crate::scene::Scene;
use crate::spec::{self, Group, GroupKind, ReferenceRays, ReferenceSpec, Row, SceneRef, Spec, TimingSpec};
use crate::timing;
use std::path::{Path, PathBuf};

pub use super::request::{DEFAULT_PATH_NAME, Request, default_path, parse_camera_path, parse_denoiser};

/// Default image size, at most: every default configuration's ladder, timed by the protocol, in
/// well under a minute of CPU time, and the kitchen's committed 64×48 reference (docs/advise.md).
pub const DEFAULT_MAX_PIXELS: u64 = 64 * 48;

/// The ray counts advise sweeps when `--rays` is not given: 1 to 64 for the paper's raw image
/// (budgets in ms fall between them), 1, 2 and 4 after a real-time pipeline (the rays per pixel
/// per frame an engine spends, each a budget of its own).
pub fn default_rays(pipeline: crate::denoise::Pipeline) -> Vec<u32> {
    if pipeline == crate::denoise::Pipeline::RAW { vec![1, 2, 4, 8, 16, 32, 64] } else { vec![1, 2, 4] }
}

/// Everything a run of advise needs, checked.
pub struct Setup {
    pub loaded: Loaded,
    pub plan: Plan,
    pub rows: Vec<Row>,
    pub rays: Vec<u32>,
    /// The scene file's stem: the default output directory's name.
    pub stem: String,
    /// How the resolution and reference were chosen, for the report.
    pub choice: String,
    /// Where the reference is found or built.
    pub reference_dir: PathBuf,
    /// What is ranked: the image after this pipeline at this frame (raw, 1: the paper's image).
    pub pipeline: crate::denoise::Pipeline,
    pub frames: u32,
}

impl Setup {
    /// What a budget is the time of: "image", or "frame" after a real-time pipeline.
    pub fn per(&self) -> &'static str {
        if self.pipeline == crate::denoise::Pipeline::RAW { "image" } else { "frame" }
    }

    /// What the page's title says is ranked: "room at 64x48", "room at 320x180 after svgf at
    /// frame 8".
    pub fn title(&self) -> String {
        let [w, h] = self.loaded.spec.resolution.unwrap_or([0, 0]);
        let mut t = format!("{} at {w}x{h}", self.stem);
        if self.pipeline != crate::denoise::Pipeline::RAW {
            t += &format!(" after {} at frame {}", self.pipeline, self.frames);
        }
        if self.denoiser() != DenoiserId::NONE {
            t += &format!(" and the denoiser {}", self.denoiser().name());
        }
        t
    }

    /// What is ranked against what: every configuration under each schedule it is measured
    /// under (`advice::schedules_for`), in sweep order.
    pub fn candidates(&self) -> Vec<(Row, crate::sampling::Schedule)> {
        let mut out = Vec::new();
        for &row in &self.rows {
            for g in self.loaded.spec.groups.iter().filter(|g| g.rows.contains(&row)) {
                out.extend(
                    g.schedules.iter().map(|&s| (row, s)).filter(|c| !out.contains(c)).collect::<Vec<_>>(),
                );
            }
        }
        out
    }

    /// Whether `row` is measured under one schedule only because both would draw the same points
    /// (after an accumulating pipeline; `advice::schedules_for`).
    pub fn schedule_free(&self, row: Row) -> bool {
        self.pipeline.is_temporal() && self.candidates().iter().filter(|c| c.0 == row).count() == 1
    }

    /// The cameras every configuration is seen by, the scene's still one first.
    pub fn cameras(&self) -> Vec<CameraId> {
        self.loaded.spec.groups.first().map_or(vec![CameraId::STATIC], |g| g.cameras.clone())
    }

    /// The user's denoiser (`NONE` without one).
    pub fn denoiser(&self) -> DenoiserId {
        self.loaded.spec.groups.first().and_then(|g| g.denoisers.first().copied()).unwrap_or(DenoiserId::NONE)
    }
}

/// A request's flags checked on their own, before any file is read.
pub struct Checked {
    /// The ray ladder, sorted, without duplicates.
    pub rays: Vec<u32>,
    /// The configurations to sweep (`advice::select`), the paper's default first.
    pub rows: Vec<Row>,
    /// The cameras each configuration is seen by: the scene's still one, then (accumulating
    /// pipelines) the default moving one and `--camera-path`'s.
    pub cameras: Vec<CameraId>,
    /// The user's denoiser (`NONE` without `--denoiser`).
    pub denoiser: DenoiserId,
}

/// Checks the flags that need no file: at least two ray counts, `--only`, an integrand the paper's
/// default has a finite variance for, `--frames` only with a temporal pipeline.
pub fn check(args: &Request) -> Result<Checked> {
    let mut rays = args.rays.clone();
    rays.sort_unstable();
    rays.dedup();
    if rays.len() < 2 {
        return Err(Error::Usage(format!(
            "--rays: {} is a single ray count; give at least two different ones (1..={}) to interpolate \
             between, e.g. 1,2,4,8,16,32,64",
            args.rays.iter().map(u32::to_string).collect::<Vec<_>>().join(","),
            spec::MAX_RAYS
        )));
    }
    let added = added_rows(args)?;
    // What renderers ship is measured where it is built for: after a real-time pipeline, the
    // seed modes an engine chooses from (`advice::realtime_rows`).
    let rows = if args.pipeline != crate::denoise::Pipeline::RAW {
        advice::select_realtime(&args.only, &added)
    } else {
        advice::select_with(&args.only, &added)
    }
    .map_err(|e| Error::Usage(format!("--only: {e}")))?;
    // An accumulating pipeline never recommends a seed whose error repeats every frame: not swept.
    let rows = advice::candidates_for(rows, args.pipeline);
    // Advise measures every gain against the paper's default, sine-cosine, whose weights are
    // unbounded on unweighted visibility (infinite variance: no RMSE of it means anything). So
    // that integrand is refused here rather than ranked; `run` measures it (experiments/integrands.toml).
    if args.integrand.closed_room_variance(PAPER_DEFAULT.distribution).is_infinite() {
        return Err(Error::Usage(format!(
            "--integrand {}: the paper's default (sine-cosine) has infinite variance for it, and advise \
             ranks against that default; allowed here: ao, cos-lobe-N (measure {} with `hemilab run`, \
             as experiments/integrands.toml does)",
            args.integrand, args.integrand
        )));
    }
    if args.frames > 1 && !args.pipeline.is_temporal() {
        return Err(Error::Usage(format!(
            "--frames {}: pipeline '{}' accumulates no frames (each frame is filtered on its own); give a \
             pipeline with a temporal part (mean, emaA, e.g. ema0.1+atrous) or leave --frames out",
            args.frames, args.pipeline
        )));
    }
    let cameras = super::request::cameras(args)?;
    let denoiser = match &args.denoiser {
        None => DenoiserId::NONE,
        Some(text) => {
            let base = args.files_dir.clone().unwrap_or_default();
            DenoiserId::intern(
                parse_denoiser(text, &base).map_err(|e| Error::Usage(format!("--denoiser {text}: {e}")))?,
            )
        }
    };
    if denoiser != DenoiserId::NONE && args.pipeline == crate::denoise::Pipeline::RAW {
        return Err(Error::Usage(
            "--denoiser: it runs on the frames a real-time pipeline ranks; give --pipeline too (e.g. --pipeline \
             ema0.1 for accumulated frames the denoiser then cleans)"
                .into(),
        ));
    }
    Ok(Checked { rays, rows, cameras, denoiser })
}

/// What the set-up needs from files, loaded by the command that owns them (`app::advise`): the
/// scene, where its references are (`reference::store::dir_of_scene`) and the manifests stored
/// there with their images (`reference::store::stored_of_scene`).
pub struct Inputs {
    pub scene: Scene,
    pub reference_dir: PathBuf,
    pub stored: Vec<(Manifest, PathBuf)>,
}

/// Decides the resolution and reference settings from the checked flags and the loaded inputs, and
/// plans the jobs.
pub fn setup(args: &Request, checked: Checked, inputs: Inputs) -> Result<Setup> {
    let Checked { rays, rows, mut cameras, denoiser } = checked;
    let Inputs { scene, reference_dir, stored } = inputs;
    cameras.extend(super::request::scene_cameras(args, &scene, &cameras));
    let name = args.scene.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let stem = name.strip_suffix(".toml").unwrap_or(&name).to_string();
    let given_id = spec::normalize(&args.scene.to_string_lossy());
    let sketch = AdviseSpec {
        path: &args.scene,
        stem: &stem,
        rows: &rows,
        rays: &rays,
        replicates: args.replicates,
        pipeline: args.pipeline,
        frames: args.frames,
        integrand: args.integrand,
        cameras: &cameras,
        denoiser,
    };
    let usable = |m: &Manifest| sketch.reuses(m, &scene);
    let (resolution, how) = match args.resolution {
        Some((w, h)) => {
            check_pixels(w, h).map_err(|e| Error::Usage(format!("--resolution: {e}")))?;
            ([w, h], "--resolution".to_string())
        }
        None => default_resolution(&stored, &scene, &usable),
    };
    // The scene's own size was checked with the file; a thin mesh may be missed by a coarser grid.
    if (resolution[0], resolution[1]) != scene.resolution {
        check_view(&args.scene, &scene, resolution[0], resolution[1])?;
    }
    // After a pipeline the errors are a filtered image's, a tenth of a raw frame's: its reference
    // must have at least `PIPELINE_REFERENCE_RAYS` rays a replicate.
    let enough = |m: &Manifest| {
        args.pipeline == crate::denoise::Pipeline::RAW || m.rays >= super::defaults::PIPELINE_REFERENCE_RAYS
    };
    let mut at_size: Vec<&(Manifest, PathBuf)> =
        stored.iter().filter(|(m, _)| m.resolution == resolution && usable(m) && enough(m)).collect();
    at_size.sort_by(|a, b| {
        a.0.noise_floor.unwrap_or(f64::INFINITY).total_cmp(&b.0.noise_floor.unwrap_or(f64::INFINITY))
    });
    let (spec, which) = match at_size.first() {
        Some((m, file)) => {
            let reference = reference_spec_of(m).expect("usable manifests have one");
            (sketch.spec(&m.scene, resolution, reference), format!("stored reference {}", file.display()))
        }
        None => (
            sketch.spec(&given_id, resolution, super::defaults::reference(args.pipeline)),
            format!("no stored reference of this scene at {}x{}: one is built", resolution[0], resolution[1]),
        ),
    };
    let mut choice = format!("resolution {}x{} ({how}); {which}", resolution[0], resolution[1]);
    if args.pipeline != crate::denoise::Pipeline::RAW {
        choice += &format!(
            "; ranked on the image after {} at frame {} (a budget is the time of one frame: {})",
            args.pipeline,
            args.frames,
            if args.pipeline.is_temporal() {
                "each configuration's time is that of its frames over their number"
            } else {
                "the filter is not timed; it costs every configuration the same"
            }
        );
        if cameras.len() > 1 {
            let names: Vec<String> = cameras
                .iter()
                .map(|c| match c.run() {
                    None => "the scene's still camera".to_string(),
                    Some(r) => {
                        format!("'{}' ({} over the {} frames, jittered)", r.name, r.path.key(), r.frames)
                    }
                })
                .collect();
            choice += &format!(
                "; seen by {}; under both schedules (independent, r1) where the schedule changes the points",
                names.join(" and ")
            );
        }
        if denoiser != DenoiserId::NONE {
            choice += &format!("; each ranked frame then cleaned by the denoiser '{}'", denoiser.name());
        }
    }
    let plan = last_frame_only(plan::plan(&spec), args.frames);
    Ok(Setup {
        loaded: Loaded { spec, scenes: vec![std::sync::Arc::new(scene)] },
        plan,
        rows,
        rays,
        stem,
        choice,
        reference_dir,
        pipeline: args.pipeline,
        frames: args.frames,
    })
}

/// The rows `--texture` and `--points` add: their files read (each error names the flag and the
/// file), then every sensible row naming one of them (`advice::sensible_rows_with`).
fn added_rows(args: &Request) -> Result<Vec<Row>> {
    let base = args.files_dir.clone().unwrap_or_default();
    let (mut sequences, mut modes) = (Vec::new(), Vec::new());
    for f in &args.files {
        if let Some(p) = f.strip_prefix("points:") {
            let s = crate::load::points::points(&base, p)
                .map_err(|e| Error::Usage(format!("--points {p}: {e}")))?;
            sequences.push(s);
        } else {
            let t = f.strip_prefix("texture:").unwrap_or(f);
            let (path, use_) = crate::load::texture_use(t);
            let m = crate::load::texture::texture(&base, path, use_)
                .map_err(|e| Error::Usage(format!("--texture {t}: {e}")))?;
            modes.push(m);
        }
    }
    let rows = advice::sensible_rows_with(&sequences, &modes);
    for &s in &sequences {
        let max = s.imp().max_count().unwrap_or(u32::MAX);
        if let Some(&big) = args.rays.iter().filter(|&&r| r > max).max() {
            return Err(Error::Usage(format!(
                "--rays {big}: --points {s} holds {max} points per pixel; allowed 1..={max}"
            )));
        }
    }
    Ok(rows)
}

/// The parts of advise's spec that do not depend on the reference.
struct AdviseSpec<'a> {
    path: &'a Path,
    stem: &'a str,
    rows: &'a [Row],
    rays: &'a [u32],
    replicates: u32,
    pipeline: crate::denoise::Pipeline,
    frames: u32,
    integrand: Integrand,
    cameras: &'a [CameraId],
    denoiser: DenoiserId,
}

impl AdviseSpec<'_> {
    /// One convergence sweep over every configuration; `id` names the scene in job keys and
    /// reference manifests.
    ///
    /// After a real-time pipeline each configuration is seen by every camera, under both schedules
    /// where the schedule changes its points (`advice::schedules_for`): one group per set of
    /// schedules, the paper's default's first.
    fn spec(&self, id: &str, resolution: [u32; 2], reference: ReferenceSpec) -> Spec {
        let mut groups: Vec<Group> = Vec::new();
        for &row in self.rows {
            let schedules = if self.pipeline == crate::denoise::Pipeline::RAW {
                vec![crate::sampling::Schedule::Independent]
            } else {
                advice::schedules_for(row, self.frames)
            };
            if let Some(g) = groups.iter_mut().find(|g| g.schedules == schedules) {
                g.rows.push(row);
                continue;
            }
            groups.push(Group {
                kind: GroupKind::Convergence,
                name: if groups.is_empty() { "advise".into() } else { format!("advise-{}", schedules.len()) },
                rows: vec![row],
                rays: self.rays.to_vec(),
                replicates: self.replicates,
                scenes: vec![0],
                line: 0,
                frames: self.frames,
                schedules,
                pipelines: vec![self.pipeline],
                cameras: self.cameras.to_vec(),
                denoisers: vec![self.denoiser],
            });
        }
        Spec {
            path: self.path.to_path_buf(),
            name: format!("advise-{}", self.stem),
            scenes: vec![SceneRef {
                path: self.path.to_path_buf(),
                id: id.to_string(),
                name: self.stem.to_string(),
                line: 0,
                integrand: self.integrand,
            }],
            resolution: Some(resolution),
            ao_distance: None,
            flip_ppd: crate::metrics::DEFAULT_PPD,
            // Measured on tiles when the whole frame would cost too much (`plan::tiles::auto`).
            tiles: crate::plan::tiles::auto(resolution),
            // A steady-state frame is measured from the frames its pipeline remembers.
            steady_state: true,
            replicates: self.replicates,
            seed: 1,
            point_figures: false,
            reference,
            // Unused: advise passes its --reference-dir to every reference lookup.
            reference_dir: Path::new("reference").to_path_buf(),
            // After a pipeline a series is rendered for its errors, and its time per frame is
            // only shown: its replicates' renders time it, and none is rendered again for a third
            // sample (a series of 21 frames at 1080p is many seconds of filtering).
            timing: TimingSpec {
                repeats: if self.pipeline == crate::denoise::Pipeline::RAW {
                    timing::DEFAULT_REPEATS
                } else {
                    timing::DEFAULT_REPEATS.min(self.replicates)
                },
                seed: 1,
            },
            groups,
        }
    }

    /// Whether `reference::obtain` would reuse the stored reference `m` for the spec built from it:
    /// the very rule `run` applies, so nothing is reused that `run` would not.
    fn reuses(&self, m: &Manifest, scene: &Scene) -> bool {
        let Some(reference) = reference_spec_of(m) else { return false };
        let spec = self.spec(&m.scene, m.resolution, reference);
        let g = Geometry::of(spec.resolution, None, scene);
        m.matches(&refs::wanted_manifest(&spec, 0, scene, g)).is_ok()
    }
}

/// The `[reference]` settings that reproduce a stored manifest, if its estimator is unbiased per
/// pixel (a reference must be).
fn reference_spec_of(m: &Manifest) -> Option<ReferenceSpec> {
    let estimator =
        Row::new(m.distribution.parse().ok()?, m.sequence.parse().ok()?, m.seed_mode.parse().ok()?);
    if !per_pixel_unbiased(estimator) {
        return None;
    }
    let (rays, adaptive) = match &m.adaptive {
        None => (ReferenceRays::Fixed(m.rays), false),
        Some(a) => (a.budget.map_or(ReferenceRays::Auto, ReferenceRays::Fixed), true),
    };
    Some(ReferenceSpec { rays, replicates: m.replicates, seed: m.seed, estimator, adaptive })
}

/// What `run` builds when nothing is stored: the spec format's defaults, `rays = "auto"`.
/// The largest resolution with a reusable stored reference of at most `DEFAULT_MAX_PIXELS`
/// pixels, else the scene's own scaled down (aspect kept) to at most that many.
fn default_resolution(
    stored: &[(Manifest, PathBuf)],
    scene: &Scene,
    usable: &dyn Fn(&Manifest) -> bool,
) -> ([u32; 2], String) {
    let px = |r: [u32; 2]| r[0] as u64 * r[1] as u64;
    let best = stored
        .iter()
        .filter(|(m, _)| px(m.resolution) <= DEFAULT_MAX_PIXELS && usable(m))
        .map(|(m, _)| m.resolution)
        .max_by_key(|r| (px(*r), r[0]));
    if let Some(r) = best {
        return (r, format!("the largest stored reference of at most {DEFAULT_MAX_PIXELS} pixels"));
    }
    let (w, h) = scene.resolution;
    let s = (DEFAULT_MAX_PIXELS as f64 / (w as f64 * h as f64)).sqrt().min(1.0);
    let r = [((w as f64 * s) as u32).max(1), ((h as f64 * s) as u32).max(1)];
    (r, format!("the scene's {w}x{h} scaled to at most {DEFAULT_MAX_PIXELS} pixels"))
}

/// Base seed of the finalists' replicates; the sweep's is 1 (`AdviseSpec::spec`). Their own, so
/// that what is shipped is measured on replicates that had no say in picking it (and so that their
/// jobs and images never coincide with the sweep's).
pub const VERIFY_SEED: u64 = 2;

/// The finalists' jobs: every (configuration, rays) of `needs` at `replicates` replicates, seeded
/// from [`VERIFY_SEED`] (replicate r still has the same seed in every configuration: paired).
pub fn verify_jobs(spec: &Spec, needs: &[(Row, u32)], replicates: u32) -> Plan {
    let sweep = spec.groups.first();
    let frames = sweep.map_or(1, |g| g.frames);
    let pipelines = sweep.map_or(vec![crate::denoise::Pipeline::RAW], |g| g.pipelines.clone());
    let denoisers = sweep.map_or(vec![DenoiserId::NONE], |g| g.denoisers.clone());
    let groups = needs
        .iter()
        .enumerate()
        .map(|(i, &(row, rays))| Group {
            kind: GroupKind::Table,
            name: format!("finalist{i}"),
            rows: vec![row],
            rays: vec![rays],
            replicates,
            scenes: vec![0],
            line: 0,
            frames,
            schedules: vec![crate::sampling::Schedule::Independent],
            pipelines: pipelines.clone(),
            cameras: vec![CameraId::STATIC],
            denoisers: denoisers.clone(),
        })
        .collect();
    last_frame_only(plan::plan(&Spec { groups, seed: VERIFY_SEED, replicates, ..spec.clone() }), frames)
}

/// Only the jobs measured at frame `frames`: advise ranks the image after the last frame, and the
/// plan's earlier reported frames (1, 2, 4, …) would render most of the frames again.
fn last_frame_only(mut plan: Plan, frames: u32) -> Plan {
    plan.jobs.retain(|j| j.measurement.frame == frames || !j.measurement.pipeline.is_temporal());
    plan
}
