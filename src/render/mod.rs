//! The AO renderer: one primary ray per pixel centre, then the pixel's N AO rays from the first hit.
//! Tiles run in parallel on the current rayon pool; a pixel's result depends only on (scene, job,
//! pixel index), so the image is bit-identical for any thread count. No IO, no printing.

pub mod adaptive;
pub mod bench;
mod clearance;
mod gbuffer;
mod offset;
mod order;
mod primary;
pub mod reproject;
mod sight;
mod view;
mod window;

pub use gbuffer::{
    FrameGBuffer, GBuffer, NO_PRIMITIVE, Primaries, frame_gbuffer, frame_gbuffer_window, gbuffer,
};
pub use reproject::{ReprojectParams, reproject};
pub use sight::{Sight, primary_hits, sight};
pub use view::View;
pub use window::Window;

pub use offset::{Plane, ao_origin};
pub(crate) use primary::{Primary, tile_count, tile_pixels, tile_primaries};
pub use primary::{TILE, pixel_order};

use crate::image::Image;
use crate::sampling::batch::Directions;
use crate::sampling::integrand::Integrand;
use crate::sampling::{Distribution, Frame, SamplerConfig};
use crate::scene::Scene;
use crate::scene::accel::{Hit, Ray};
use crate::scene::camera::Raster;
use crate::scene::packet::{Occluders, PACKET, Soa};
use glam::{Vec2, Vec3};
use order::RayOrder;
use rayon::prelude::*;
use std::cell::RefCell;

/// Everything that determines one AO image of a scene.
#[derive(Debug, Clone, Copy)]
pub struct RenderJob {
    pub distribution: Distribution,
    pub sampler: SamplerConfig,
    pub width: u32,
    pub height: u32,
    /// AO distance d (`f32::INFINITY` allowed).
    pub ao_distance: f32,
}

pub struct RenderOutput {
    /// 1 - occluded fraction estimate: 1 = fully open. Not clamped: weights above 1 (uniform) can
    /// push a pixel outside [0, 1], and clamping would bias the estimator.
    pub ao: Image,
    /// 1.0 where the primary ray hit the scene, 0.0 for background (excluded from metrics).
    pub coverage: Image,
    /// AO (occlusion) rays cast; primary rays are not counted.
    pub rays: u64,
    /// AO rays that hit something within d.
    pub occluded_rays: u64,
}

/// Per-thread scratch: the tile's primary hits, the pixel's points, directions, weights and answers
/// (no allocation per pixel).
struct Scratch {
    primaries: Vec<Primary>,
    points: Vec<Vec2>,
    rays: PixelRays,
    /// The pixel's answers, one mask per 32 rays, in traced order.
    masks: Vec<u32>,
    /// The order its rays are traced in (bands of elevation, `order`), and the answers and weights back
    /// in the sampler's order where the sum needs them so.
    order: RayOrder,
    sampler_masks: Vec<u32>,
    sampler_weights: Vec<f32>,
}

/// The AO rays of one pixel: they all start at `origin`.
#[derive(Debug, Clone, Default)]
pub struct PixelRays {
    pub origin: Vec3,
    /// The surface normal at the origin (facing the camera): every direction is on its side.
    pub normal: Vec3,
    pub dirs: Vec<Vec3>,
    pub weights: Vec<f32>,
    /// Scratch: the directions as arrays, as the vectorized warp writes them.
    batch: Directions,
    /// The last hit triangle's plane, keyed by (BVH id, triangle): neighbouring pixels mostly hit
    /// the same triangle (kept here, not in a thread-local, so that it is read in place).
    plane: Option<(u64, u32, Plane)>,
    /// Scratch of `clearance` (the triangles around the origin).
    near: clearance::Near,
}

/// A tile's covered pixels as (index, AO value), its AO rays and its occluded rays.
type TileResult = (Vec<(u32, f32)>, u64, u64);

/// Renders `job`. `progress(n)` is called as work finishes with the number of pixels just done
/// (one call per tile; the calls sum to width × height).
pub fn render(scene: &Scene, job: &RenderJob, progress: &(dyn Fn(u64) + Sync)) -> RenderOutput {
    render_integrand(scene, job, Integrand::Ao, progress)
}

/// `render` of another integrand: each ray's weight is `Integrand::weight`, f/p of the
/// job's distribution, so the image is 1 − the estimate of ∫ V f dω. `Integrand::Ao` is `render`,
/// bit for bit (its weights are the warps' own). The integrand is an argument rather than a field
/// of `RenderJob` so that every render of AO, and every `RenderJob` written before it, is unchanged.
pub fn render_integrand(
    scene: &Scene,
    job: &RenderJob,
    integrand: Integrand,
    progress: &(dyn Fn(u64) + Sync),
) -> RenderOutput {
    render_view(scene, job, integrand, &View::SCENE, progress)
}

/// `render_integrand` of one frame of a moving camera: every primary ray comes from
/// `view`'s camera through its pixel's centre plus `view`'s jitter; the AO rays are as ever.
/// `View::SCENE` (the scene's camera, no jitter) is `render_integrand` bit for bit, and so is any
/// view whose camera is the scene's and whose jitter is zero. The view's camera must be usable
/// (`CameraPath::validate` checks every frame's); a camera that is not panics.
pub fn render_view(
    scene: &Scene,
    job: &RenderJob,
    integrand: Integrand,
    view: &View,
    progress: &(dyn Fn(u64) + Sync),
) -> RenderOutput {
    render_window(scene, job, integrand, view, &Window::full(job.width, job.height), progress)
}

/// `render_view` of the pixels of `window` alone (a rectangle of the job's `width` × `height`
/// image): an image of the window's size whose every pixel is the full render's, bit for bit (the
/// full image's primary rays, the sampler at the pixel's absolute coordinates and index; `Window`).
/// `progress` sums to the window's pixels.
pub fn render_window(
    scene: &Scene,
    job: &RenderJob,
    integrand: Integrand,
    view: &View,
    window: &Window,
    progress: &(dyn Fn(u64) + Sync),
) -> RenderOutput {
    render_window_from(scene, job, integrand, view, window, None, progress)
}

/// `render_window` whose primary hits are `primaries` (the frame's G-buffer's for this window,
/// traced with the same `view`, `Primaries`) instead of traced again: the same image, bit for bit
/// (the hits are those `tile_primaries` gives). `None`: traced, `render_window`. Panics if
/// `primaries` were traced for another view or window.
pub fn render_window_from(
    scene: &Scene,
    job: &RenderJob,
    integrand: Integrand,
    view: &View,
    window: &Window,
    primaries: Option<&Primaries>,
    progress: &(dyn Fn(u64) + Sync),
) -> RenderOutput {
    assert_eq!(window.full, [job.width, job.height], "render: a window of another image");
    if let Some(p) = primaries {
        assert!(
            p.view == *view && p.window == *window,
            "render: primary hits of another view or window ({}) than the job's ({})",
            p.window.canonical(),
            window.canonical()
        );
    }
    let (w, h) = (window.width as usize, window.height as usize);
    let n = job.sampler.count as usize;
    if w == 0 || h == 0 {
        let empty = Image::new(window.width, window.height);
        return RenderOutput { ao: empty.clone(), coverage: empty, rays: 0, occluded_rays: 0 };
    }
    let raster = view.raster(scene, job.width, job.height);
    let unit_weight = integrand.unit_weight(job.distribution);
    let tile = Tile { scene, job, integrand, unit_weight, raster, window: *window, primaries, progress };
    // Tiles in parallel, each its own rayon job (pixels differ a lot in cost; large sequential
    // ranges left one of 2 threads idle); each tile's covered pixels come back as (index, AO).
    let tiles: Vec<TileResult> = (0..tile_count(window.width, window.height))
        .into_par_iter()
        .with_max_len(1)
        .map_init(
            || Scratch {
                primaries: Vec::with_capacity((TILE * TILE) as usize),
                points: vec![Vec2::ZERO; n],
                rays: PixelRays::default(),
                masks: vec![0; n.div_ceil(PACKET)],
                order: RayOrder::new(),
                sampler_masks: vec![0; n.div_ceil(PACKET)],
                sampler_weights: vec![0.0; n],
            },
            |s, t| {
                #[cfg(target_arch = "x86_64")]
                if std::arch::is_x86_feature_detected!("avx2") {
                    // SAFETY: the CPU supports AVX2 (checked just above).
                    return unsafe { render_tile_avx2(&tile, t, s) };
                }
                render_tile(&tile, t, s)
            },
        )
        .collect();
    let mut ao = vec![1.0f32; w * h];
    let mut coverage = vec![0.0f32; w * h];
    let (mut rays, mut occluded) = (0u64, 0u64);
    for (done, r, o) in tiles {
        for (i, v) in done {
            ao[i as usize] = v;
            coverage[i as usize] = 1.0;
        }
        rays += r;
        occluded += o;
    }
    RenderOutput {
        ao: Image::from_vec(window.width, window.height, ao),
        coverage: Image::from_vec(window.width, window.height, coverage),
        rays,
        occluded_rays: occluded,
    }
}

/// One tile compiled for AVX2, with the per-pixel steps between the kernels (primary packets, AO
/// origin, bookkeeping) inlined into it: VEX encoding throughout the pixel loop, as in the kernels
/// it calls. No FMA, so the same bits (90 renders byte-compared: README, Performance). `hemilab
/// bench` (kitchen, d = 1, 3 interleaved runs): render_vs_query 0.784-0.794 -> 0.801-0.806.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn render_tile_avx2(tile: &Tile, t: u32, s: &mut Scratch) -> TileResult {
    render_tile(tile, t, s)
}

/// What every tile of a render shares.
#[derive(Clone, Copy)]
struct Tile<'a> {
    scene: &'a Scene,
    job: &'a RenderJob,
    integrand: Integrand,
    /// `Integrand::unit_weight` of the job's warp.
    unit_weight: bool,
    /// The frame's primary rays (`View::raster`).
    raster: Raster,
    /// The pixels rendered (`render_window`).
    window: Window,
    /// Their primary hits, kept from the frame's G-buffer (`None`: traced here).
    primaries: Option<&'a Primaries>,
    progress: &'a (dyn Fn(u64) + Sync),
}

/// Tile `t`'s covered pixels as (index in the window, AO), its AO rays and occluded rays.
#[inline(always)]
fn render_tile(tile: &Tile, t: u32, s: &mut Scratch) -> TileResult {
    let Tile { scene, job, integrand, unit_weight, ref raster, ref window, primaries, progress } = *tile;
    let (w, n) = (job.width as usize, job.sampler.count as usize);
    let mut done = Vec::with_capacity((TILE * TILE) as usize);
    let (mut rays, mut occluded) = (0u64, 0u64);
    match primaries {
        Some(kept) => kept.tile(raster, t, &mut s.primaries),
        None => tile_primaries(scene, raster, window, t, &mut s.primaries),
    }
    for p in &s.primaries {
        let Some(hit) = p.hit else { continue };
        let pixel = p.y as u64 * w as u64 + p.x as u64;
        let from = raster.origin(p.x, p.y);
        let sorted = rays_from_hit(
            scene,
            job,
            integrand,
            (p.x, p.y, pixel),
            (from, p.dir),
            hit,
            &mut s.points,
            &mut s.rays,
            Some(&mut s.order),
        );
        let (r, b) = (&s.rays, &s.rays.batch);
        let dirs = Soa { x: &b.x[..n], y: &b.y[..n], z: &b.z[..n] };
        trace_soa(scene, r.origin, r.normal, dirs, job.ao_distance, &mut s.masks);
        let blocked: u32 = s.masks.iter().map(|m| m.count_ones()).sum();
        occluded += blocked as u64;
        let sum = if unit_weight {
            // Every weight is exactly 1: the in-order sum below is the count, exactly, in any order.
            blocked as f64
        } else {
            // The blocked rays' weights in the sampler's order (the f64 sum's order is part of
            // the result), whatever order they were traced in.
            let (masks, weights) = if sorted {
                s.order.unsort(&s.masks, &mut s.sampler_masks);
                s.order.unsort_values(&b.weight[..n], &mut s.sampler_weights);
                (&s.sampler_masks, &s.sampler_weights)
            } else {
                (&s.masks, &b.weight)
            };
            let mut sum = 0.0f64;
            for (k, &mask) in masks.iter().enumerate() {
                let mut m = mask;
                while m != 0 {
                    sum += weights[k * PACKET + m.trailing_zeros() as usize] as f64;
                    m &= m - 1;
                }
            }
            sum
        };
        done.push((window.index(p.x, p.y) as u32, (1.0 - sum / n as f64) as f32));
        rays += n as u64;
    }
    progress(s.primaries.len() as u64);
    (done, rays, occluded)
}

/// The AO rays of pixel (x, y): primary hit, offset origin, the sampler's directions and weights.
/// False for background. `points` must hold `job.sampler.count` entries.
pub fn pixel_rays(
    scene: &Scene,
    job: &RenderJob,
    x: u32,
    y: u32,
    pixel: u64,
    points: &mut [Vec2],
    out: &mut PixelRays,
) -> bool {
    pixel_rays_of(scene, job, Integrand::Ao, (x, y, pixel), points, out)
}

/// `pixel_rays` with the weights of `integrand` (`render_integrand`'s per-pixel step).
pub fn pixel_rays_of(
    scene: &Scene,
    job: &RenderJob,
    integrand: Integrand,
    (x, y, pixel): (u32, u32, u64),
    points: &mut [Vec2],
    out: &mut PixelRays,
) -> bool {
    let primary = scene.camera.ray(x, y, job.width, job.height);
    let Some(hit) = scene.accel.closest(&Ray::new(primary.origin, primary.dir, f32::INFINITY)) else {
        return false;
    };
    let _ = rays_from_hit(
        scene,
        job,
        integrand,
        (x, y, pixel),
        (primary.origin, primary.dir),
        hit,
        points,
        out,
        None,
    );
    let b = &out.batch;
    out.dirs.clear();
    out.dirs.extend((0..b.len()).map(|i| b.get(i)));
    out.weights.clear();
    out.weights.extend_from_slice(&b.weight[..b.len()]);
    true
}

/// The AO rays of pixel (x, y, index) from its primary ray (origin, direction) and hit: offset
/// origin (off the hit triangle, then off every neighbour it still lies on: `clearance`), the
/// sampler's directions and weights. `points` must hold `job.sampler.count` entries. With `order`,
/// more than one packet of rays comes out in bands of elevation (`order::RayOrder`), which then
/// knows the sampler's order; without, in the sampler's order.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn rays_from_hit(
    scene: &Scene,
    job: &RenderJob,
    integrand: Integrand,
    (x, y, pixel): (u32, u32, u64),
    (from, dir): (Vec3, Vec3),
    hit: Hit,
    points: &mut [Vec2],
    out: &mut PixelRays,
    order: Option<&mut RayOrder>,
) -> bool {
    let key = (scene.accel.id(), hit.prim);
    let plane = match &out.plane {
        Some((id, prim, plane)) if (*id, *prim) == key => plane,
        _ => {
            let plane = Plane::of(scene.accel.triangle(hit.prim));
            &out.plane.insert((key.0, key.1, plane)).2
        }
    };
    let lift = plane.lift(hit.bary_b, hit.bary_c, dir);
    let n = lift.normal;
    out.origin =
        clearance::clear(&scene.accel, hit.prim, (hit.bary_b, hit.bary_c), plane, &lift, from, &mut out.near);
    out.normal = n;
    let basis = Frame::from_normal(n);
    job.sampler.fill_pixel(x, y, pixel, points);
    let sorted = match order {
        Some(order) if points.len() > PACKET => order.sort(points),
        _ => None,
    };
    let moved = sorted.is_some();
    let points = sorted.unwrap_or(points);
    // All points at once (vectorized; bit for bit the one-point path, `batch::world_sample`).
    out.batch.fill(job.distribution, points, &basis);
    if integrand != Integrand::Ao {
        // The weights of another integrand, from the local direction (z = the normal) the warp
        // gives the point: the AO path above is left exactly as it was.
        for (w, &u) in out.batch.weight.iter_mut().zip(points.iter()) {
            *w = integrand.weight(job.distribution, job.distribution.sample(u).dir);
        }
    }
    moved
}

/// hemilab's AO query: which of a pixel's rays (all from `origin`) are blocked within `tmax`.
/// `normal`: the surface normal the directions were drawn around. `blocked`: as long as `dirs`.
/// Each thread keeps the occluders of the last pixel it traced (speed only: the answers do not
/// depend on them), across rayon jobs, so that it is not emptied every tile. They are triangle
/// ids of the BVH they came from; `Occluders` starts afresh when the thread traces another one
/// (one thread may render the kitchen, then the Cornell box's 30 triangles).
/// `trace_pixel` on directions as x, y, z arrays, answering one mask per 32 rays (see
/// `Accel::occluded_soa`): what the renderer and the benchmark's query call.
pub fn trace_soa(scene: &Scene, origin: Vec3, normal: Vec3, dirs: Soa, tmax: f32, masks: &mut [u32]) {
    CACHE.with(|c| scene.accel.occluded_soa(origin, Some(normal), dirs, tmax, masks, &mut c.borrow_mut()));
}

thread_local! {
    /// Each thread's occluders of the last pixel it traced (see `trace_pixel`).
    static CACHE: RefCell<Occluders> = RefCell::new(Occluders::new());
}

pub fn trace_pixel(
    scene: &Scene,
    origin: Vec3,
    normal: Vec3,
    dirs: &[Vec3],
    tmax: f32,
    blocked: &mut [bool],
) {
    CACHE.with(|c| {
        scene.accel.occluded_from(origin, Some(normal), dirs, tmax, blocked, &mut c.borrow_mut());
    });
}
/// The overhead render: `base`'s image with no AO rays, i.e. primary rays, hit points, frames and
/// the image itself: what the timing protocol subtracts, and what shows whether a camera sees
/// anything. (Built directly: `SamplerConfig::new` refuses zero points, which would have no
/// estimate; this render's AO image is never used.)
pub fn overhead_job(base: &RenderJob) -> RenderJob {
    let sampler = crate::sampling::SamplerConfig {
        sequence: crate::sampling::Sequence::Random,
        seed_mode: crate::sampling::SeedMode::Rotation,
        count: 0,
        seed: 0,
        frame: 0,
        schedule: crate::sampling::Schedule::Independent,
    };
    RenderJob { sampler, ..*base }
}

/// A pool of `threads` worker threads (default: one per core).
pub fn pool(threads: Option<u32>) -> crate::error::Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0) as usize)
        .build()
        .map_err(|e| crate::error::Error::Refused(format!("cannot start worker threads: {e}")))
}
