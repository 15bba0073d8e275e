//! What one frame is seen through: a camera (the scene's, or a camera path's for that frame) and the
//! frame's sub-pixel jitter. Plain data, so a job's frames are a list of views and `render_view`,
//! `frame_gbuffer` and `reproject` need nothing else to agree on a frame.

use crate::scene::camera::Raster;
use crate::scene::{Camera, Scene, WorldCamera};
use glam::Vec2;

/// A frame's camera and jitter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// The frame's camera in world coordinates (`CameraPath::camera`); None: the scene's own.
    pub camera: Option<WorldCamera>,
    /// Where in its pixel each primary ray passes, from the centre, in pixels (+x right, +y down):
    /// `CameraPath`'s `jitter` (Halton 2, 3), or zero.
    pub jitter: Vec2,
}

impl View {
    /// The scene's camera through pixel centres: what every render before moving cameras used.
    pub const SCENE: View = View { camera: None, jitter: Vec2::ZERO };

    /// A frame of a camera path: its camera and its jitter.
    pub fn new(camera: WorldCamera, jitter: Vec2) -> View {
        View { camera: Some(camera), jitter }
    }

    /// The frame's camera in the renderer's coordinates (relative to `scene.origin`, the scene
    /// camera's eye, subtracted in f64 then rounded once to f32, as `Scene::new` places the
    /// mesh). Panics if the camera cannot make an image (`Camera::problem`): a camera path
    /// refuses such a frame when it is validated, so here it is a bug.
    pub fn camera(&self, scene: &Scene) -> Camera {
        let Some(world) = self.camera else { return scene.camera };
        let camera = world.relative_to(scene.origin);
        if let Some(p) = camera.problem() {
            panic!("render: a frame's camera cannot make an image ({p}): {world:?}");
        }
        camera
    }

    /// The frame's primary rays for a `width` × `height` image.
    pub fn raster(&self, scene: &Scene, width: u32, height: u32) -> Raster {
        assert!(self.jitter.is_finite(), "render: a frame's jitter must be finite, got {}", self.jitter);
        self.camera(scene).raster_jittered(width, height, self.jitter)
    }
}
