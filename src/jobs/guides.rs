//! What a plan's multi-frame measurements are guided by and compared with, made once before any
//! job and outside every timed render (each costs the same whichever sampler is measured, so none
//! can change which sampler wins at equal time):
//!
//! - per scene, its G-buffer at the job's size (the static camera's filters);
//! - per scene × camera path (`plan::CameraId`), every frame's view (the path's camera, its
//!   Halton (2, 3) jitter), its G-buffer, the motion from the frame before (`render::reproject`),
//!   and the references of the frames where error and flicker are measured
//!   (`reference::ViewReferences`, obtained by the run before the executor starts).
//!
//! Under `[tiles]` (`jobs::tiles`) every G-buffer and motion is one per tile window, made by
//! `render::frame_gbuffer_window` and reprojected within the window.
//!
//! **Primary hits.** Each G-buffer keeps its window's primary hits (`render::Primaries`, 20 bytes
//! a pixel: 1.15 MB a frame at 320x180, 75 MB a 64-frame path), and every render of that frame
//! reads them instead of tracing the same rays again (`render::render_window_from`, the same image
//! bit for bit). A record's time still includes its primary rays (`timing::TIME_INCLUDES`): each
//! frame's window's are traced on one thread, alone, timed by that thread's CPU clock (the median
//! of `PRIMARY_TRACES` traces, `Traced::primary`), and that time is added to every render of the
//! frame (`jobs::measure::Frames`): measured once per frame instead of once per render of it, the
//! same for every sampler.
//!
//! The filter's floor is not made here: it is the filter's bias measured from the replicates of
//! per-pixel-unbiased input (`jobs::replicates`), not the filter applied to the reference (which a
//! non-linear filter such as SVGF passes through unchanged).

use super::reference::ViewReferences;
use super::tiles::TileSet;
use crate::denoise::Motion;
use crate::image::Image;
use crate::plan::{CameraId, Measurement};
use crate::reference::store::Reference;
use crate::render::{self, FrameGBuffer, Primaries, ReprojectParams, View, Window};
use crate::scene::Scene;
use crate::scene::camera_path::halton_jitter;
use crate::timing::{Time, clock};
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;

/// A frame's G-buffer of one window (with its primary hits) and what tracing its primary rays took.
pub struct Traced {
    pub frame: FrameGBuffer,
    /// The primary rays' CPU and wall time, traced on one thread alone (module doc).
    pub primary: Time,
}

/// Times a frame's primary rays are traced to time them: the median is kept (the first trace
/// of a frame is the slowest, its BVH nodes not yet in cache).
const PRIMARY_TRACES: usize = 3;

impl Traced {
    /// The frame of `view` over `scene`, its pixels of `window`.
    pub fn new(scene: &Scene, view: &View, window: &Window) -> Self {
        let mut samples = Vec::with_capacity(PRIMARY_TRACES);
        let mut hits = None;
        for _ in 0..PRIMARY_TRACES {
            let (c0, w0) = (clock::thread_cpu_s(), clock::wall_s());
            hits = Some(Primaries::trace_here(scene, view, window));
            samples.push(Time { cpu_s: clock::thread_cpu_s() - c0, wall_s: clock::wall_s() - w0 });
        }
        samples.sort_by(|a, b| a.cpu_s.total_cmp(&b.cpu_s));
        let primary = samples[PRIMARY_TRACES / 2];
        Self { frame: FrameGBuffer::of(scene, hits.expect("traced")), primary }
    }
}

/// The frames of one camera path over one scene.
pub struct CameraFrames<'a> {
    /// Frame f's camera and jitter (from 0).
    pub views: Vec<View>,
    /// Frame f's G-buffer of each part (`Against::parts`: the whole frame, or each tile's window),
    /// its primary hits and their time.
    pub gbuffers: Vec<Vec<Traced>>,
    /// Where frame f's pixels were in frame f − 1, per part (frame 0: `Motion::identity`, no
    /// history yet).
    pub motions: Vec<Vec<Motion>>,
    /// The path does not move (a jittered static camera): one reference serves every frame.
    pub still: bool,
    references: &'a HashMap<u32, Reference>,
}

impl CameraFrames<'_> {
    /// The reference of frame `f` (from 0), if the run obtained it.
    pub fn reference(&self, f: u32) -> Option<&Reference> {
        self.references.get(&if self.still { 0 } else { f })
    }
}

/// Everything the plan's filtered measurements need (module doc).
#[derive(Default)]
pub struct Guides<'a> {
    /// Per scene, its G-buffer of each part, with its primary hits and their time.
    gbuffers: HashMap<usize, Vec<Traced>>,
    cameras: HashMap<(usize, CameraId), CameraFrames<'a>>,
    /// Per scene and camera, its tiles (`[tiles]`): one set of interiors, each camera's apron.
    tiles: HashMap<(usize, CameraId), TileSet>,
}

/// What one job is measured against: its reference (the static camera's; a path's frames read
/// theirs from `camera`), the filters' guides, and where a denoiser command works.
pub struct Against<'a> {
    pub reference: &'a Image,
    pub coverage: &'a Image,
    /// The scene's G-buffer at the job's size, one per part, with its primary hits and their time
    /// (`None` for a single frame).
    pub gbuffer: Option<&'a [Traced]>,
    /// The camera path's frames (`None`: the scene's camera, unjittered).
    pub camera: Option<&'a CameraFrames<'a>>,
    /// A directory of the job's own for a denoiser command's files.
    pub scratch: Option<PathBuf>,
    /// The tiles the job is measured on (`None`: the whole image); the references above are then
    /// their mosaics (`jobs::reference::obtain_measured`).
    pub tiles: Option<&'a TileSet>,
    /// A render for its time alone (the timing protocol's extra renders, `slot.record` false):
    /// the frames are rendered and timed, and nothing that is not timed (the filters, the
    /// denoiser, the images) is done.
    pub timing_only: bool,
}

impl Against<'_> {
    /// What is rendered of a `width` × `height` frame: each tile's window, or the whole frame.
    pub fn parts(&self, width: u32, height: u32) -> Vec<Window> {
        parts(self.tiles, width, height)
    }

    /// The reference and coverage of frame `frame` (from 1).
    pub fn at(&self, frame: u32) -> (&Image, &Image) {
        match self.camera.and_then(|c| c.reference(frame.saturating_sub(1))) {
            Some(r) => (&r.mean, &r.coverage),
            None => (self.reference, self.coverage),
        }
    }
}

/// A plan's multi-frame job as `Guides::new` reads it: its scene (`target`), measurement and size.
pub struct Need<'m> {
    pub target: usize,
    pub measurement: &'m Measurement,
    pub width: u32,
    pub height: u32,
}

impl<'a> Guides<'a> {
    /// For every job of a plan: what its filters need; `views` are the camera paths' frames'
    /// references; `tiles(scene, camera)` the scene's tiles as that camera renders them
    /// (`jobs::tiles::of_camera`), asked for the scenes of jobs measured on tiles. A camera path's
    /// frames are traced from the earliest first frame its jobs render (`Measurement::first_frame`).
    pub fn new<'m>(
        needs: impl IntoIterator<Item = Need<'m>>,
        scene: impl Fn(usize) -> &'a Scene,
        views: &'a ViewReferences,
        tiles: impl Fn(usize, CameraId) -> Option<TileSet>,
    ) -> Self {
        let needs: Vec<Need<'m>> = needs.into_iter().collect();
        let mut from: HashMap<(usize, CameraId), u32> = HashMap::new();
        for n in needs.iter().filter(|n| !n.measurement.is_single_frame()) {
            let m = n.measurement;
            // One frame earlier: a pipeline that shows one frame renders the one before it too.
            let first = m.frames_rendered().first().copied().unwrap_or(0).saturating_sub(1);
            let e = from.entry((n.target, m.camera)).or_insert(first);
            *e = (*e).min(first);
        }
        let mut g = Guides::default();
        for n in needs {
            let m = n.measurement;
            let t = n.target;
            if m.tiles.is_some() {
                for c in [CameraId::STATIC, m.camera] {
                    if !g.tiles.contains_key(&(t, c))
                        && let Some(set) = tiles(t, c)
                    {
                        g.tiles.insert((t, c), set);
                    }
                }
            }
            if m.is_single_frame() {
                continue;
            }
            let tiled = |c: CameraId| g.tiles.get(&(t, c)).filter(|_| m.tiles.is_some());
            let still = parts(tiled(CameraId::STATIC), n.width, n.height);
            g.gbuffers
                .entry(t)
                .or_insert_with(|| still.iter().map(|w| Traced::new(scene(t), &View::SCENE, w)).collect());
            if let Some(run) = m.camera.run() {
                let windows = parts(tiled(m.camera), n.width, n.height);
                let first = from.get(&(t, m.camera)).copied().unwrap_or(0);
                g.cameras
                    .entry((t, m.camera))
                    .or_insert_with(|| camera_frames(scene(t), run, &windows, first, views.of(t, m.camera)));
            }
        }
        g
    }

    /// What a job of reference `target` with measurement `m` is measured against.
    pub fn against(
        &'a self,
        target: usize,
        m: &Measurement,
        reference: &'a Reference,
        scratch: Option<PathBuf>,
    ) -> Against<'a> {
        let single = m.is_single_frame();
        Against {
            reference: &reference.mean,
            coverage: &reference.coverage,
            gbuffer: if single { None } else { self.gbuffers.get(&target).map(Vec::as_slice) },
            camera: self.cameras.get(&(target, m.camera)),
            scratch,
            tiles: if m.tiles.is_some() { self.tiles.get(&(target, m.camera)) } else { None },
            timing_only: false,
        }
    }

    /// The tiles of scene `target` as `camera` renders them, if its jobs are measured on tiles.
    pub fn tiles(&self, target: usize, camera: CameraId) -> Option<&TileSet> {
        self.tiles.get(&(target, camera))
    }
}

/// The windows of a `width` × `height` frame that are rendered: each tile's, or the whole frame.
fn parts(tiles: Option<&TileSet>, width: u32, height: u32) -> Vec<Window> {
    match tiles {
        Some(t) => t.windows.clone(),
        None => vec![Window::full(width, height)],
    }
}

/// The frames of `run` over `scene`, each of `windows` of the frame; frames before `first` (from
/// 0) are rendered by no job: they have their view but no G-buffer, and frame `first` has no
/// history to reproject (`Motion::identity`).
fn camera_frames<'a>(
    scene: &Scene,
    run: &crate::plan::CameraRun,
    windows: &[Window],
    first: u32,
    references: &'a HashMap<u32, Reference>,
) -> CameraFrames<'a> {
    let frames = run.frames.max(1);
    let views: Vec<View> = (0..frames)
        .map(|f| {
            let camera = run.path.camera(&scene.view, f, frames);
            View::new(camera, if run.jitter { halton_jitter(f) } else { glam::Vec2::ZERO })
        })
        .collect();
    let first = first.min(frames - 1) as usize;
    let gbuffers: Vec<Vec<Traced>> =
        views
            .par_iter()
            .enumerate()
            .map(|(f, v)| {
                if f < first {
                    Vec::new()
                } else {
                    windows.iter().map(|w| Traced::new(scene, v, w)).collect()
                }
            })
            .collect();
    let params = ReprojectParams::default();
    let motions = (0..frames as usize)
        .map(|f| {
            if f < first {
                return Vec::new();
            }
            (0..windows.len())
                .map(|k| match f {
                    _ if f == first => Motion::identity(windows[k].width, windows[k].height),
                    _ => render::reproject(&gbuffers[f - 1][k].frame, &gbuffers[f][k].frame, &params),
                })
                .collect()
        })
        .collect();
    CameraFrames { views, gbuffers, motions, still: run.path.is_static(), references }
}
