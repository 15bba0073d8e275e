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
//! The filter's floor is not made here: it is the filter's bias measured from the replicates of
//! per-pixel-unbiased input (`jobs::replicates`), not the filter applied to the reference (which a
//! non-linear filter such as SVGF passes through unchanged).

use super::reference::ViewReferences;
use crate::denoise::Motion;
use crate::image::Image;
use crate::plan::{CameraId, Measurement};
use crate::reference::store::Reference;
use crate::render::{self, FrameGBuffer, GBuffer, ReprojectParams, View};
use crate::scene::Scene;
use crate::scene::camera_path::halton_jitter;
use std::collections::HashMap;
use std::path::PathBuf;

/// The frames of one camera path over one scene.
pub struct CameraFrames<'a> {
    /// Frame f's camera and jitter (from 0).
    pub views: Vec<View>,
    /// Frame f's G-buffer.
    pub gbuffers: Vec<FrameGBuffer>,
    /// Where frame f's pixels were in frame f − 1 (frame 0: `Motion::identity`, no history yet).
    pub motions: Vec<Motion>,
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
    gbuffers: HashMap<usize, GBuffer>,
    cameras: HashMap<(usize, CameraId), CameraFrames<'a>>,
}

/// What one job is measured against: its reference (the static camera's; a path's frames read
/// theirs from `camera`), the filters' guides, and where a denoiser command works.
pub struct Against<'a> {
    pub reference: &'a Image,
    pub coverage: &'a Image,
    /// The scene's G-buffer at the job's size (`None` for a single frame).
    pub gbuffer: Option<&'a GBuffer>,
    /// The camera path's frames (`None`: the scene's camera, unjittered).
    pub camera: Option<&'a CameraFrames<'a>>,
    /// A directory of the job's own for a denoiser command's files.
    pub scratch: Option<PathBuf>,
}

impl Against<'_> {
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
    /// references.
    pub fn new<'m>(
        needs: impl IntoIterator<Item = Need<'m>>,
        scene: impl Fn(usize) -> &'a Scene,
        views: &'a ViewReferences,
    ) -> Self {
        let mut g = Guides::default();
        for n in needs {
            let m = n.measurement;
            if m.is_single_frame() {
                continue;
            }
            let t = n.target;
            g.gbuffers.entry(t).or_insert_with(|| render::gbuffer(scene(t), n.width, n.height));
            if let Some(run) = m.camera.run() {
                g.cameras.entry((t, m.camera)).or_insert_with(|| {
                    camera_frames(scene(t), run, n.width, n.height, views.of(t, m.camera))
                });
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
            gbuffer: if single { None } else { self.gbuffers.get(&target) },
            camera: self.cameras.get(&(target, m.camera)),
            scratch,
        }
    }
}

/// The frames of `run` over `scene` at `width` × `height`.
fn camera_frames<'a>(
    scene: &Scene,
    run: &crate::plan::CameraRun,
    width: u32,
    height: u32,
    references: &'a HashMap<u32, Reference>,
) -> CameraFrames<'a> {
    let frames = run.frames.max(1);
    let views: Vec<View> = (0..frames)
        .map(|f| {
            let camera = run.path.camera(&scene.view, f, frames);
            View::new(camera, if run.jitter { halton_jitter(f) } else { glam::Vec2::ZERO })
        })
        .collect();
    let gbuffers: Vec<FrameGBuffer> =
        views.iter().map(|v| render::frame_gbuffer(scene, width, height, v)).collect();
    let params = ReprojectParams::default();
    let motions = (0..frames as usize)
        .map(|f| match f {
            0 => Motion::identity(width, height),
            _ => render::reproject(&gbuffers[f - 1], &gbuffers[f], &params),
        })
        .collect();
    CameraFrames { views, gbuffers, motions, still: run.path.is_static(), references }
}
