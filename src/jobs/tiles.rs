//! A spec's tiles over one scene (`[tiles]`, `plan::tiles`): the probe they are chosen from, the
//! apron that the spec's pipelines and camera paths need around them, and the mosaic their
//! interiors are measured as.
//!
//! Under tiles, every job renders each tile's window (interior + apron, `render::Window`) per frame
//! and pushes each through its own run of the pipeline (`jobs::measure`); the interiors of the
//! shown images are laid side by side, `GAP` uncovered pixels apart, into one **mosaic**, and so
//! are the references of the interiors (`jobs::reference`). Every metric then reads the mosaic
//! exactly as it reads a full frame: error, FLIP and flicker over the interiors' covered pixels, one
//! record per job. The gap keeps the metrics' own kernels (FLIP's, the low-pass error's σ = 1.5 px
//! Gaussian) from reading one tile's pixels into another's: there, test and reference are equal
//! and uncovered, as beyond an image's border.
//!
//! The tile set depends only on the scene, the image size, the spec's `[tiles]`, and the
//! pipelines and camera paths of the spec's groups that measure the scene (`of_spec`), never on
//! which jobs a shard or a resumed run still has to render, so every job of a scene, and its
//! references, see the same tiles.

use crate::denoise::Pipeline;
use crate::image::Image;
use crate::plan::tiles::{self, Probe, TileSpec};
use crate::plan::{CameraId, CameraRun, Geometry};
use crate::render::{self, View, Window};
use crate::scene::Scene;
use crate::scene::camera_path::halton_jitter;
use crate::spec::Spec;

/// Uncovered pixels between two interiors in the mosaic: more than 3σ of the low-pass error's
/// Gaussian (σ = 1.5 px) on each side of the seam.
pub const GAP: u32 = 8;

/// Frames of camera motion the apron holds: an accumulating pipeline's history keeps weight
/// (1 − α)^k on frame k back; at SVGF's α = 0.2 the frames beyond 8 weigh 17 % together, at an
/// EMA's 0.1, 43 % (whose own pixels then come from the apron's edge rather than the full frame's:
/// a history that starts again there, as a disocclusion would).
pub const HISTORY_FRAMES: u32 = 8;

/// The tiles of one scene at one image size.
#[derive(Debug, Clone, PartialEq)]
pub struct TileSet {
    pub spec: TileSpec,
    /// Pixels around each interior that are rendered too (`plan::tiles::apron`).
    pub apron: u32,
    /// The measured rectangles, best first (`plan::tiles::choose`).
    pub interiors: Vec<Window>,
    /// Each interior grown by the apron (clipped to the image): what is rendered.
    pub windows: Vec<Window>,
    /// The share of the whole frame's covered pixels the windows hold (by the probe; a pixel in
    /// two windows counts twice, as it is rendered twice): how the AO rays of a tiled frame compare
    /// with the whole frame's, for estimates (`jobs::calibrate`).
    pub covered_share: f64,
}

impl TileSet {
    /// The tiles of a spec's `[tiles]` chosen from `probe`, with `apron`.
    pub fn new(probe: &Probe, full: [u32; 2], spec: TileSpec, apron: u32) -> Self {
        Self::with_aprons(probe, full, spec, |_| apron)
    }

    /// The same with an apron of each interior's own (`apron(interior)`); `apron` then holds the
    /// widest.
    pub fn with_aprons(
        probe: &Probe,
        full: [u32; 2],
        spec: TileSpec,
        apron: impl Fn(&Window) -> u32,
    ) -> Self {
        let interiors = tiles::choose(probe, full, spec);
        let aprons: Vec<u32> = interiors.iter().map(&apron).collect();
        let windows: Vec<Window> = interiors.iter().zip(&aprons).map(|(w, &a)| w.grown(a)).collect();
        let covered_share = covered_share(probe, full, &windows);
        let apron = aprons.into_iter().max().unwrap_or(0);
        TileSet { spec, apron, interiors, windows, covered_share }
    }

    /// The share of the whole frame's pixels rendered per frame.
    pub fn pixel_share(&self) -> f64 {
        let full = self.windows.first().map_or([1, 1], |w| w.full);
        self.rendered_pixels() as f64 / (full[0] as f64 * full[1] as f64).max(1.0)
    }

    /// Pixels of the mosaic (the measured image a job writes).
    pub fn mosaic_pixels(&self) -> u64 {
        let [w, h] = self.mosaic_size();
        w as u64 * h as u64
    }

    /// The tile set as results and the run's record name it: `4x128+65: x,y+WxH/FWxFH; …`.
    pub fn canonical(&self) -> String {
        let list: Vec<String> = self.interiors.iter().map(Window::canonical).collect();
        format!("{}+{}: {}", self.spec.canonical(), self.apron, list.join("; "))
    }

    /// Pixels rendered per frame (every window).
    pub fn rendered_pixels(&self) -> u64 {
        self.windows.iter().map(Window::pixels).sum()
    }

    /// The mosaic's [width, height]: the interiors side by side, `GAP` apart.
    pub fn mosaic_size(&self) -> [u32; 2] {
        let n = self.interiors.len() as u32;
        let w: u32 = self.interiors.iter().map(|i| i.width).sum::<u32>() + GAP * n.saturating_sub(1);
        let h = self.interiors.iter().map(|i| i.height).max().unwrap_or(0);
        [w, h]
    }

    /// The mosaic of per-interior images (`parts[k]`: interior k's pixels, row-major), `fill`
    /// between and below them.
    pub fn mosaic<T: Copy>(&self, parts: &[Vec<T>], fill: T) -> Vec<T> {
        assert_eq!(parts.len(), self.interiors.len(), "mosaic: one image per tile");
        let [mw, mh] = self.mosaic_size();
        let mut out = vec![fill; mw as usize * mh as usize];
        let mut x0 = 0usize;
        for (part, i) in parts.iter().zip(&self.interiors) {
            assert_eq!(part.len() as u64, i.pixels(), "mosaic: an image of another size than its tile");
            for y in 0..i.height as usize {
                let row = &part[y * i.width as usize..(y + 1) * i.width as usize];
                let at = y * mw as usize + x0;
                out[at..at + row.len()].copy_from_slice(row);
            }
            x0 += (i.width + GAP) as usize;
        }
        out
    }

    /// `mosaic` of images, each of its interior's size.
    pub fn mosaic_image(&self, parts: &[Image], fill: f32) -> Image {
        let [w, h] = self.mosaic_size();
        let data: Vec<Vec<f32>> = parts.iter().map(|p| p.data.clone()).collect();
        Image::from_vec(w, h, self.mosaic(&data, fill))
    }

    /// The interiors of images of the windows (`parts[k]` the size of window k): their mosaic.
    pub fn mosaic_of_windows(&self, parts: &[Image], fill: f32) -> Image {
        let inner: Vec<Image> = parts
            .iter()
            .zip(self.windows.iter().zip(&self.interiors))
            .map(|(p, (w, i))| w.crop_image(p, i))
            .collect();
        self.mosaic_image(&inner, fill)
    }
}

/// Covered probe pixels (each at the image pixel its centre falls on) inside `windows`, summed
/// over the windows, over all covered probe pixels (0 when none is covered).
fn covered_share(probe: &Probe, full: [u32; 2], windows: &[Window]) -> f64 {
    let (pw, ph) = (probe.width as u64, probe.height as u64);
    let mut all = 0u64;
    let mut inside = 0u64;
    for y in 0..ph {
        for x in 0..pw {
            if !probe.covered[(y * pw + x) as usize] {
                continue;
            }
            all += 1;
            let ix = ((2 * x + 1) * full[0] as u64 / (2 * pw)) as u32;
            let iy = ((2 * y + 1) * full[1] as u64 / (2 * ph)) as u32;
            inside += windows.iter().filter(|w| w.contains(ix, iy)).count() as u64;
        }
    }
    if all == 0 { 0.0 } else { inside as f64 / all as f64 }
}

/// The probe of `scene`'s own camera for a `full` image (`plan::tiles::Probe`): its G-buffer at
/// `plan::tiles::probe_size`.
pub fn probe(scene: &Scene, full: [u32; 2]) -> Probe {
    let [w, h] = tiles::probe_size(full);
    let g = render::gbuffer(scene, w, h);
    Probe {
        width: w,
        height: h,
        covered: (0..g.coverage.data.len()).map(|i| g.is_covered(i)).collect(),
        depth: g.depth.data.clone(),
        normal: g.normal.iter().map(|n| n.to_array()).collect(),
    }
}

/// Per probe point of the path's first frame: where it is in a `full` image then, and the most it
/// moves there from one frame of `run` to the next, in pixels (jitter included).
fn motions(scene: &Scene, full: [u32; 2], run: &CameraRun) -> Vec<(glam::Vec2, f32)> {
    let frames = run.frames.max(1);
    if frames < 2 {
        return Vec::new();
    }
    let jitter = |f: u32| if run.jitter { halton_jitter(f) } else { glam::Vec2::ZERO };
    let view = |f: u32| View::new(run.path.camera(&scene.view, f, frames), jitter(f));
    let [pw, ph] = tiles::probe_size(full);
    let first = render::frame_gbuffer(scene, pw, ph, &view(0));
    let points: Vec<glam::Vec3> = (0..first.position.len())
        .filter(|&i| first.gbuffer.is_covered(i))
        .map(|i| first.position[i])
        .collect();
    let raster = |f: u32| view(f).raster(scene, full[0], full[1]);
    let inside = |p: glam::Vec2| p.x >= -0.5 && p.y >= -0.5 && p.x < full[0] as f32 && p.y < full[1] as f32;
    let start = raster(0);
    let mut out: Vec<(glam::Vec2, f32)> =
        points.iter().map(|&p| (start.pixel_of(p).unwrap_or(glam::Vec2::NAN), 0.0)).collect();
    let mut prev = start;
    for f in 1..frames {
        let cur = raster(f);
        for (k, &p) in points.iter().enumerate() {
            if let (Some(a), Some(b)) = (prev.pixel_of(p), cur.pixel_of(p))
                && inside(b)
            {
                out[k].1 = out[k].1.max((a - b).length());
            }
        }
        prev = cur;
    }
    out
}

/// The camera's share of interior `w`'s apron: `HISTORY_FRAMES` (at most the path's frames) times
/// the most a point of the interior, or of the filter's `reach` around it, moves from one frame
/// to the next. The interior's history comes from where its own surfaces were, so the motion of
/// what the frame shows elsewhere (a near chair at the image's edge) need not widen it.
fn motion_of(moves: &[(glam::Vec2, f32)], w: &Window, reach: u32, frames: u32) -> f64 {
    let r = reach as f32;
    let (x0, y0) = (w.x as f32 - r, w.y as f32 - r);
    let (x1, y1) = ((w.x + w.width) as f32 + r, (w.y + w.height) as f32 + r);
    let most = moves
        .iter()
        .filter(|(p, _)| p.x >= x0 && p.x < x1 && p.y >= y0 && p.y < y1)
        .map(|m| m.1 as f64)
        .fold(0.0, f64::max);
    most * HISTORY_FRAMES.min(frames.max(1) - 1) as f64
}

/// A small image of the frame for showing where its tiles are (`report::tiles::tiles_png`): 32-ray
/// AO (sine-cosine, pseudo-random) of the scene's camera at the probe's size, at the spec's AO
/// distance.
pub fn preview(spec: &Spec, scene: &Scene) -> render::RenderOutput {
    let g = Geometry::of(spec.resolution, spec.ao_distance, scene);
    let [w, h] = tiles::probe_size([g.width, g.height]);
    let sampler = crate::sampling::SamplerConfig::new(
        crate::sampling::Sequence::Random,
        crate::sampling::SeedMode::Rotation,
        32,
        1,
    )
    .expect("32 points");
    let job = render::RenderJob {
        distribution: crate::sampling::Distribution::SineCosine,
        sampler,
        width: w,
        height: h,
        ao_distance: g.distance.as_f32(),
    };
    render::render(scene, &job, &|_| {})
}

/// The tiles of `scene` for a `full` image measured through `pipelines` with `cameras`: chosen from
/// its probe, with the apron the widest pipeline and the fastest camera need.
pub fn of(
    scene: &Scene,
    full: [u32; 2],
    spec: TileSpec,
    pipelines: &[Pipeline],
    cameras: &[CameraId],
) -> TileSet {
    let reach = pipelines.iter().map(|p| p.reach(full[0], full[1])).max().unwrap_or(0);
    let runs: Vec<(&CameraRun, Vec<(glam::Vec2, f32)>)> =
        cameras.iter().filter_map(|c| c.run()).map(|r| (r, motions(scene, full, r))).collect();
    TileSet::with_aprons(&probe(scene, full), full, spec, |w| {
        let motion = runs.iter().map(|(r, m)| motion_of(m, w, reach, r.frames)).fold(0.0, f64::max);
        tiles::apron(reach, motion)
    })
}

/// The tiles of scene `si` under `spec`'s `[tiles]` (None without it): the pipelines and cameras
/// of every group that measures the scene (module doc).
pub fn of_spec(spec: &Spec, si: usize, scene: &Scene) -> Option<TileSet> {
    of_spec_seen_by(spec, si, scene, None)
}

/// The tiles of scene `si` as camera `camera` renders them: the same interiors as `of_spec`'s,
/// with the apron that camera's own motion needs (the scene's still camera: the filter's reach
/// alone), so that a still camera's windows are not widened by another camera's motion.
pub fn of_camera(spec: &Spec, si: usize, scene: &Scene, camera: CameraId) -> Option<TileSet> {
    of_spec_seen_by(spec, si, scene, Some(camera))
}

fn of_spec_seen_by(spec: &Spec, si: usize, scene: &Scene, camera: Option<CameraId>) -> Option<TileSet> {
    let t = spec.tiles?;
    let g = Geometry::of(spec.resolution, spec.ao_distance, scene);
    let groups = spec.groups.iter().filter(|g| g.scenes.contains(&si));
    let (mut pipelines, mut cameras) = (Vec::new(), Vec::new());
    for group in groups {
        pipelines.extend(group.pipelines.iter().copied());
        cameras.extend(group.cameras.iter().copied().filter(|c| camera.is_none_or(|only| only == *c)));
    }
    Some(of(scene, [g.width, g.height], t, &pipelines, &cameras))
}
