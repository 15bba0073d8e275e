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
//! The filter's floor is not made here: it is the filter's bias measured from the replicates of
//! per-pixel-unbiased input (`jobs::replicates`), not the filter applied to the reference (which a
//! non-linear filter such as SVGF passes through unchanged).

use super::reference::ViewReferences;
use super::tiles::TileSet;
use crate::denoise::Motion;
use crate::image::Image;
use crate::plan::{CameraId, Measurement};
use crate::reference::store::Reference;
use crate::render::{self, FrameGBuffer, GBuffer, ReprojectParams, View, Window};
use crate::scene::Scene;
use crate::scene::camera_path::halton_jitter;
use std::collections::HashMap;
use std::path::PathBuf;

/// The frames of one camera path over one scene.
pub struct CameraFrames<'a> {
    /// Frame f's camera and jitter (from 0).
    pub views: Vec<View>,
    /// Frame f's G-buffer of each part (`Against::parts`: the whole frame, or each tile's window).
    pub gbuffers: Vec<Vec<FrameGBuffer>>,
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
    /// Per scene, its G-buffer of each part.
    gbuffers: HashMap<usize, Vec<GBuffer>>,
    cameras: HashMap<(usize, CameraId), CameraFrames<'a>>,
    /// Per scene, its tiles (`[tiles]`).
    tiles: HashMap<usize, TileSet>,
}

/// What one job is measured against: its reference (the static camera's; a path's frames read
/// theirs from `camera`), the filters' guides, and where a denoiser command works.
pub struct Against<'a> {
    pub reference: &'a Image,
    pub coverage: &'a Image,
    /// The scene's G-buffer at the job's size, one per part (`None` for a single frame).
    pub gbuffer: Option<&'a [GBuffer]>,
    /// The camera path's frames (`None`: the scene's camera, unjittered).
    pub camera: Option<&'a CameraFrames<'a>>,
    /// A directory of the job's own for a denoiser command's files.
    pub scratch: Option<PathBuf>,
    /// The tiles the job is measured on (`None`: the whole image); the references above are then
    /// their mosaics (`jobs::reference::obtain_measured`).
    pub tiles: Option<&'a TileSet>,
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
    /// references; `tiles(scene)` the scene's tiles (`jobs::tiles::of_spec`), asked for the scenes
    /// of jobs measured on tiles.
    pub fn new<'m>(
        needs: impl IntoIterator<Item = Need<'m>>,
        scene: impl Fn(usize) -> &'a Scene,
        views: &'a ViewReferences,
        tiles: impl Fn(usize) -> Option<TileSet>,
    ) -> Self {
        let mut g = Guides::default();
        for n in needs {
            let m = n.measurement;
            let t = n.target;
            if m.tiles.is_some()
                && !g.tiles.contains_key(&t)
                && let Some(set) = tiles(t)
            {
                g.tiles.insert(t, set);
            }
            if m.is_single_frame() {
                continue;
            }
            let windows = parts(g.tiles.get(&t).filter(|_| m.tiles.is_some()), n.width, n.height);
            g.gbuffers.entry(t).or_insert_with(|| {
                windows
                    .iter()
                    .map(|w| render::frame_gbuffer_window(scene(t), &View::SCENE, w).gbuffer)
                    .collect()
            });
            if let Some(run) = m.camera.run() {
                g.cameras
                    .entry((t, m.camera))
                    .or_insert_with(|| camera_frames(scene(t), run, &windows, views.of(t, m.camera)));
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
            tiles: if m.tiles.is_some() { self.tiles.get(&target) } else { None },
        }
    }

    /// The tiles of scene `target`, if its jobs are measured on tiles.
    pub fn tiles(&self, target: usize) -> Option<&TileSet> {
        self.tiles.get(&target)
    }
}

/// The windows of a `width` × `height` frame that are rendered: each tile's, or the whole frame.
fn parts(tiles: Option<&TileSet>, width: u32, height: u32) -> Vec<Window> {
    match tiles {
        Some(t) => t.windows.clone(),
        None => vec![Window::full(width, height)],
    }
}

/// The frames of `run` over `scene`, each of `windows` of the frame.
fn camera_frames<'a>(
    scene: &Scene,
    run: &crate::plan::CameraRun,
    windows: &[Window],
    references: &'a HashMap<u32, Reference>,
) -> CameraFrames<'a> {
    let frames = run.frames.max(1);
    let views: Vec<View> = (0..frames)
        .map(|f| {
            let camera = run.path.camera(&scene.view, f, frames);
            View::new(camera, if run.jitter { halton_jitter(f) } else { glam::Vec2::ZERO })
        })
        .collect();
    let gbuffers: Vec<Vec<FrameGBuffer>> = views
        .iter()
        .map(|v| windows.iter().map(|w| render::frame_gbuffer_window(scene, v, w)).collect())
        .collect();
    let params = ReprojectParams::default();
    let motions = (0..frames as usize)
        .map(|f| {
            (0..windows.len())
                .map(|k| match f {
                    0 => Motion::identity(windows[k].width, windows[k].height),
                    _ => render::reproject(&gbuffers[f - 1][k], &gbuffers[f][k], &params),
                })
                .collect()
        })
        .collect();
    CameraFrames { views, gbuffers, motions, still: run.path.is_static(), references }
}
