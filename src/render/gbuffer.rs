//! The G-buffer: what the primary ray of each pixel hit, for an edge-aware denoiser to be guided by
//! (`denoise::atrous`). Traced by the renderer's own primary-ray code (`tile_primaries`, the same
//! tiles, packets and camera), so its depth and normal are those of the hits the AO rays of
//! `render` start from. A frame's G-buffer keeps those hits (`Primaries`, per window), and a render
//! of the same frame and window may read them instead of tracing its primary rays again
//! (`render_window_from`).

use super::{Plane, Primary, TILE, View, Window, tile_count, tile_pixels, tile_primaries};
use crate::image::Image;
use crate::scene::accel::Hit;
use crate::scene::camera::Raster;
use crate::scene::{Camera, Scene};
use glam::{Vec2, Vec3};
use rayon::prelude::*;

/// Per pixel, row-major like `Image`.
#[derive(Debug, Clone, PartialEq)]
pub struct GBuffer {
    pub width: u32,
    pub height: u32,
    /// Distance from the ray origin to the hit along the (unit) primary ray, in scene units: for an
    /// orthographic camera the view depth, for a pinhole the distance from the eye. 0 on background.
    pub depth: Image,
    /// The unit geometric normal of the hit triangle facing the camera, exactly the normal the AO
    /// rays' hemisphere is built around (`Plane::ao_origin`). Zero on background.
    pub normal: Vec<Vec3>,
    /// 1.0 where the primary ray hit the scene, 0.0 for background: `render`'s coverage, bit for bit.
    pub coverage: Image,
    /// The hit triangle's index in the scene's acceleration structure (`NO_PRIMITIVE` on
    /// background), for SVGF's primitive-ID test in reprojection (Schied et al. 2017 §4.1 test a
    /// mesh ID; a triangle is the finest such id). Empty: the G-buffer carries no ids (a synthetic
    /// one), and no id test can be made.
    pub primitive: Vec<u32>,
}

/// `GBuffer::primitive` of a background pixel.
pub const NO_PRIMITIVE: u32 = u32::MAX;

impl GBuffer {
    /// A synthetic G-buffer of `width` × `height` pixels from per-pixel depth, normals and coverage
    /// (row-major), without primitive ids: what a filter's test builds.
    pub fn synthetic(
        width: u32,
        height: u32,
        depth: Vec<f32>,
        normal: Vec<Vec3>,
        coverage: Vec<f32>,
    ) -> Self {
        assert!(
            normal.len() == (width * height) as usize,
            "G-buffer: {} normals for {width}x{height} pixels",
            normal.len()
        );
        Self {
            width,
            height,
            depth: Image::from_vec(width, height, depth),
            normal,
            coverage: Image::from_vec(width, height, coverage),
            primitive: Vec::new(),
        }
    }

    pub fn is_covered(&self, i: usize) -> bool {
        crate::image::covered(&self.coverage, i)
    }
}

/// One frame's G-buffer with what reprojecting it needs (`reproject`): the camera and jitter it was
/// traced with and each pixel's hit position.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameGBuffer {
    pub gbuffer: GBuffer,
    /// The frame's camera in the renderer's coordinates (relative to `Scene::origin`, `View::camera`).
    pub camera: Camera,
    /// The frame's sub-pixel jitter (`View::jitter`).
    pub jitter: Vec2,
    /// The rectangle of the frame these pixels are (`frame_gbuffer_window`; the whole frame for
    /// `frame_gbuffer`): the G-buffer is the window's size, its rays those of the full image.
    pub window: Window,
    /// Per pixel, where its primary ray hit: ray origin + depth × unit direction, in the renderer's
    /// coordinates — relative to `Scene::origin` (the scene camera's eye), not to this frame's
    /// camera, so that every frame of a scene shares them and two frames' positions compare
    /// directly; world position = `Scene::origin` + this (in f64). Zero on background.
    pub position: Vec<Vec3>,
    /// The window's primary hits (`render_window_from` reads them instead of tracing them again).
    pub primaries: Primaries,
}

/// The G-buffer of `scene` at `width` × `height` (a `RenderJob`'s size): one primary ray per pixel
/// centre, traced in parallel by tiles; deterministic for any thread count.
pub fn gbuffer(scene: &Scene, width: u32, height: u32) -> GBuffer {
    frame_gbuffer(scene, width, height, &View::SCENE).gbuffer
}

/// The G-buffer of one frame seen through `view` (its camera and jitter), with the hits' positions:
/// the primary rays of `render_view` with the same view, so its depth, normal and coverage are
/// those of the hits that frame's AO rays start from. `View::SCENE` gives `gbuffer`.
pub fn frame_gbuffer(scene: &Scene, width: u32, height: u32, view: &View) -> FrameGBuffer {
    frame_gbuffer_window(scene, view, &Window::full(width, height))
}

/// `frame_gbuffer` of the pixels of `window` alone: a G-buffer of the window's size whose every
/// pixel is the full frame's, bit for bit (the full image's primary rays, `render_window`'s).
pub fn frame_gbuffer_window(scene: &Scene, view: &View, window: &Window) -> FrameGBuffer {
    FrameGBuffer::of(scene, Primaries::trace(scene, view, window))
}

/// One frame's primary hits over a window, as the renderer traces them (`tile_primaries`: the
/// same tiles, packets and camera): what `render_window_from` reads instead of tracing them again.
/// 20 bytes a pixel (1.15 MB at 320x180).
#[derive(Debug, Clone, PartialEq)]
pub struct Primaries {
    /// The frame's camera and jitter.
    pub view: View,
    /// The pixels traced (the whole frame, or a tile's window).
    pub window: Window,
    /// Per pixel of the window (row-major, `Window::index`), its primary ray's closest hit.
    hits: Vec<Option<Hit>>,
}

impl Primaries {
    /// The primary hits of `view` over `window`, tiles in parallel.
    pub fn trace(scene: &Scene, view: &View, window: &Window) -> Self {
        let raster = view.raster(scene, window.full[0], window.full[1]);
        let tiles: Vec<Vec<(usize, Option<Hit>)>> = (0..tile_count(window.width, window.height))
            .into_par_iter()
            .with_max_len(1)
            .map_init(
                || Vec::<Primary>::with_capacity((TILE * TILE) as usize),
                |primaries, t| {
                    tile_primaries(scene, &raster, window, t, primaries);
                    primaries.iter().map(|p| (window.index(p.x, p.y), p.hit)).collect()
                },
            )
            .collect();
        let mut hits = vec![None; window.pixels() as usize];
        for (i, hit) in tiles.into_iter().flatten() {
            hits[i] = hit;
        }
        Self { view: *view, window: *window, hits }
    }

    /// `trace` on the calling thread alone, tile after tile, as one render traces them: so that
    /// the caller can time it (`jobs::guides`).
    pub fn trace_here(scene: &Scene, view: &View, window: &Window) -> Self {
        let raster = view.raster(scene, window.full[0], window.full[1]);
        let mut hits = vec![None; window.pixels() as usize];
        let mut primaries = Vec::<Primary>::with_capacity((TILE * TILE) as usize);
        for t in 0..tile_count(window.width, window.height) {
            tile_primaries(scene, &raster, window, t, &mut primaries);
            for p in &primaries {
                hits[window.index(p.x, p.y)] = p.hit;
            }
        }
        Self { view: *view, window: *window, hits }
    }

    /// What `tile_primaries(scene, raster, window, t, out)` gives, bit for bit, from the kept hits
    /// (`raster` is this frame's, `View::raster` at the full image's size).
    #[inline(always)]
    pub(crate) fn tile(&self, raster: &Raster, t: u32, out: &mut Vec<Primary>) {
        out.clear();
        for (x, y) in tile_pixels(t, self.window) {
            let hit = self.hits[self.window.index(x, y)];
            out.push(Primary { x, y, dir: raster.ray(x, y).dir, hit });
        }
    }

    /// The window's pixel i's hit (row-major).
    pub fn hit(&self, i: usize) -> Option<Hit> {
        self.hits[i]
    }
}

impl FrameGBuffer {
    /// The G-buffer of a frame's primary hits over their window (`frame_gbuffer_window`).
    pub fn of(scene: &Scene, primaries: Primaries) -> FrameGBuffer {
        let (window, view) = (primaries.window, primaries.view);
        let raster = view.raster(scene, window.full[0], window.full[1]);
        let (width, height) = (window.width, window.height);
        let n = width as usize * height as usize;
        let (mut depth, mut normal, mut coverage) = (vec![0.0f32; n], vec![Vec3::ZERO; n], vec![0.0f32; n]);
        let mut position = vec![Vec3::ZERO; n];
        let mut primitive = vec![NO_PRIMITIVE; n];
        let w = width.max(1) as usize;
        depth
            .par_chunks_mut(w)
            .zip(normal.par_chunks_mut(w))
            .zip(coverage.par_chunks_mut(w))
            .zip(position.par_chunks_mut(w))
            .zip(primitive.par_chunks_mut(w))
            .enumerate()
            .for_each(|(y, ((((depth, normal), coverage), position), primitive))| {
                for x in 0..depth.len() {
                    let Some(hit) = primaries.hits[y * w + x] else { continue };
                    let (px, py) = (window.x + x as u32, window.y + y as u32);
                    let dir = raster.ray(px, py).dir;
                    let plane = Plane::of(scene.accel.triangle(hit.prim));
                    let (_, nrm) = plane.ao_origin(hit.bary_b, hit.bary_c, dir);
                    depth[x] = hit.t;
                    normal[x] = nrm;
                    coverage[x] = 1.0;
                    position[x] = raster.origin(px, py) + dir * hit.t;
                    primitive[x] = hit.prim;
                }
            });
        let gbuffer = GBuffer {
            width,
            height,
            depth: Image::from_vec(width, height, depth),
            normal,
            coverage: Image::from_vec(width, height, coverage),
            primitive,
        };
        FrameGBuffer { gbuffer, camera: view.camera(scene), jitter: view.jitter, window, position, primaries }
    }
}
