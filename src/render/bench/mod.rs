//! The performance figure of record: hemilab's AO query against plain obvhs on identical rays.
//!
//! The ray set is made once (what the renderer would cast: primary hit, offset origin, the pixel's
//! directions) and both paths trace exactly those rays, pixel by pixel, on the current rayon pool.
//! Ray generation is outside both timings; building each path's own ray record (obvhs `Ray` with its
//! inverses, hemilab's packet) is inside its timing. No IO, no printing.

pub mod dump;
pub mod measure;
pub mod points;

use super::{PixelRays, RenderJob, pixel_rays, trace_soa};
use crate::scene::Scene;
use crate::scene::accel::Ray;
use crate::scene::packet::{PACKET, Soa};
use glam::{Vec2, Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::rt_triangle::RtTriangle;
use rayon::prelude::*;

/// Pixels handed to a worker at a time (both paths). Every chunk is its own rayon job
/// (`with_max_len(1)`): rayon otherwise runs a few large ranges sequentially, and pixels differ
/// enough in cost (d = inf) that 2 threads then reached only 1.65x instead of 2x.
const CHUNK_PIXELS: usize = 64;

/// Every covered pixel's AO rays: `n` directions per origin, pixels in the renderer's order.
pub struct RaySet {
    pub n: usize,
    pub origins: Vec<Vec3>,
    /// The surface normal at each origin (hemilab's path uses it; obvhs has no use for it).
    pub normals: Vec<Vec3>,
    /// Every ray's direction (obvhs's path reads these).
    pub dirs: Vec<Vec3>,
    /// The same directions as x, y, z arrays, as the renderer hands them to hemilab's query (the
    /// warps write them so).
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    pub z: Vec<f32>,
}

impl RaySet {
    pub fn len(&self) -> usize {
        self.dirs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.dirs.is_empty()
    }

    /// Masks per pixel in hemilab's answer (`trace_hemilab`): one per 32 rays.
    pub fn masks_per_pixel(&self) -> usize {
        self.n.div_ceil(PACKET)
    }

    /// hemilab's answer (one mask per 32 rays of each pixel) as one flag per ray.
    pub fn unpack(&self, masks: &[u32]) -> Vec<bool> {
        let m = self.masks_per_pixel();
        (0..self.len())
            .map(|i| masks[(i / self.n) * m + (i % self.n) / PACKET] >> (i % self.n % PACKET) & 1 != 0)
            .collect()
    }
}

pub fn ray_set(scene: &Scene, job: &RenderJob) -> RaySet {
    let n = job.sampler.count as usize;
    let mut points = vec![Vec2::ZERO; n];
    let mut px = PixelRays::default();
    let mut set = RaySet {
        n,
        origins: Vec::new(),
        normals: Vec::new(),
        dirs: Vec::new(),
        x: Vec::new(),
        y: Vec::new(),
        z: Vec::new(),
    };
    for (x, y) in super::pixel_order(job.width, job.height) {
        let pixel = y as u64 * job.width as u64 + x as u64;
        if pixel_rays(scene, job, x, y, pixel, &mut points, &mut px) {
            set.origins.push(px.origin);
            set.normals.push(px.normal);
            set.dirs.extend_from_slice(&px.dirs);
            set.x.extend(px.dirs.iter().map(|d| d.x));
            set.y.extend(px.dirs.iter().map(|d| d.y));
            set.z.extend(px.dirs.iter().map(|d| d.z));
        }
    }
    set
}

/// What a user of obvhs would write: a CWBVH with obvhs's medium preset (the one its docs
/// suggest) over the scene's triangles, and its fast triangle layout in BVH order.
pub struct Baseline {
    pub bvh: CwBvh,
    pub tris: Vec<RtTriangle>,
    pub build_s: f64,
}

pub fn obvhs_baseline(scene: &Scene) -> Baseline {
    let soup = scene.accel.source_triangles();
    let mut core = std::time::Duration::ZERO;
    let bvh = build_cwbvh_from_tris(soup, BvhBuildParams::medium_build(), &mut core);
    let tris = bvh.primitive_indices.iter().map(|&i| RtTriangle::from(&soup[i as usize])).collect();
    Baseline { bvh, tris, build_s: core.as_secs_f64() }
}

/// The smallest positive f32: obvhs's triangle test accepts t >= tmin, so this asks it for t > 0,
/// the query hemilab answers. (With tmin = 0 it reports t = -0.0 "hits" on the very triangle an
/// origin lifted by a few ulps leaves: 90 of the kitchen's 2.4 M rays at d = 0.3.)
const OBVHS_TMIN: f32 = f32::from_bits(1);

/// One obvhs occlusion query: its own `Ray`, node test and triangle test; -0.0 canonicalized (bug 1).
#[inline]
fn obvhs_blocked(base: &Baseline, origin: Vec3, dir: Vec3, tmax: f32) -> bool {
    let ray = obvhs::ray::Ray::new(origin.into(), Vec3A::from(dir) + Vec3A::ZERO, OBVHS_TMIN, tmax);
    !base.bvh.ray_traverse_miss(ray, |r, id| base.tris[id].intersect(r))
}

/// The baseline: every ray on its own through plain obvhs `ray_traverse_miss`.
pub fn trace_obvhs(base: &Baseline, set: &RaySet, tmax: f32, out: &mut [bool]) {
    let n = set.n;
    out.par_chunks_mut(n * CHUNK_PIXELS).with_max_len(1).enumerate().for_each(|(c, chunk)| {
        for (i, blocked) in chunk.chunks_mut(n).enumerate() {
            let p = c * CHUNK_PIXELS + i;
            let origin = set.origins[p];
            for (b, d) in blocked.iter_mut().zip(&set.dirs[p * n..(p + 1) * n]) {
                *b = obvhs_blocked(base, origin, *d, tmax);
            }
        }
    });
}

/// hemilab's path: the renderer's own per-pixel query, answering as the renderer reads it: one
/// mask per 32 rays of each pixel (`RaySet::masks_per_pixel`; `unpack` makes flags of them).
pub fn trace_hemilab(scene: &Scene, set: &RaySet, tmax: f32, masks: &mut [u32]) {
    let (n, m) = (set.n, set.masks_per_pixel());
    masks.par_chunks_mut(m * CHUNK_PIXELS).with_max_len(1).enumerate().for_each(|(c, chunk)| {
        for (i, out) in chunk.chunks_mut(m).enumerate() {
            let p = c * CHUNK_PIXELS + i;
            let r = p * n..(p + 1) * n;
            let dirs = Soa { x: &set.x[r.clone()], y: &set.y[r.clone()], z: &set.z[r] };
            trace_soa(scene, set.origins[p], set.normals[p], dirs, tmax, out);
        }
    });
}

/// Where and why the two paths disagree, each disagreeing ray judged by testing every triangle.
#[derive(Debug, Clone, Default, PartialEq, Eq, serde::Serialize)]
pub struct Mismatches {
    /// Rays whose answers differ.
    pub total: u64,
    /// obvhs's node test lost a hit closer than its hard-coded 1e-4 (bug 2): obvhs's own triangle
    /// test over all triangles finds it, its traversal does not.
    pub obvhs_node_test_short: u64,
    /// Same, for a hit at 1e-4 or farther (should be 0).
    pub obvhs_node_test_other: u64,
    /// obvhs's traversal agrees with its own triangle test over all triangles, and that test hits a
    /// triangle whose exact (f64) crossing lies behind the origin: Möller-Trumbore has no error
    /// bound, so from an origin lifted a few ulps off a large triangle it finds that triangle again
    /// at a small positive t. hemilab's test proves the side before it reports a hit.
    pub obvhs_hit_behind_origin: u64,
    /// obvhs's traversal agrees with its own triangle test over all triangles, and the triangle
    /// tests (obvhs's non-watertight Möller-Trumbore vs hemilab's watertight one) decide
    /// differently for another reason.
    pub triangle_test: u64,
    /// hemilab disagrees with its own triangle test over all triangles (must be 0).
    pub hemilab_wrong: u64,
    /// hemilab's answer vs the single-ray traversal `Accel::occluded` over every ray (must be 0).
    pub hemilab_vs_single_ray: u64,
}

/// Judges every ray where `obvhs` and `ours` differ, and checks `ours` against hemilab's single-ray
/// traversal on every ray.
pub fn mismatches(
    scene: &Scene,
    base: &Baseline,
    set: &RaySet,
    tmax: f32,
    obvhs: &[bool],
    ours: &[bool],
) -> Mismatches {
    let n = set.n;
    let acc = &scene.accel;
    (0..set.len())
        .into_par_iter()
        .map(|i| {
            let (origin, dir) = (set.origins[i / n], set.dirs[i]);
            let mut m = Mismatches::default();
            let ray = Ray::new(origin, dir, tmax);
            m.hemilab_vs_single_ray = (acc.occluded(&ray) != ours[i]) as u64;
            if obvhs[i] == ours[i] {
                return m;
            }
            m.total = 1;
            let truth = acc.closest_brute_force(&ray);
            m.hemilab_wrong = (truth.is_some() != ours[i]) as u64;
            let oray = obvhs::ray::Ray::new(origin.into(), Vec3A::from(dir) + Vec3A::ZERO, OBVHS_TMIN, tmax);
            let (obvhs_all, hit) = base
                .tris
                .iter()
                .enumerate()
                .map(|(k, t)| (t.intersect(&oray), k))
                .fold((f32::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
            if (obvhs_all < tmax) == obvhs[i] {
                let t = &acc.source_triangles()[base.bvh.primitive_indices[hit] as usize];
                let behind = obvhs[i] && exact_t([t.v0, t.v1, t.v2], origin, dir) <= 0.0;
                (m.obvhs_hit_behind_origin, m.triangle_test) = if behind { (1, 0) } else { (0, 1) };
            } else if obvhs_all < 1e-4 {
                m.obvhs_node_test_short = 1;
            } else {
                m.obvhs_node_test_other = 1;
            }
            m
        })
        .reduce(Mismatches::default, |a, b| Mismatches {
            total: a.total + b.total,
            obvhs_node_test_short: a.obvhs_node_test_short + b.obvhs_node_test_short,
            obvhs_node_test_other: a.obvhs_node_test_other + b.obvhs_node_test_other,
            obvhs_hit_behind_origin: a.obvhs_hit_behind_origin + b.obvhs_hit_behind_origin,
            triangle_test: a.triangle_test + b.triangle_test,
            hemilab_wrong: a.hemilab_wrong + b.hemilab_wrong,
            hemilab_vs_single_ray: a.hemilab_vs_single_ray + b.hemilab_vs_single_ray,
        })
}

/// Where the ray's line crosses the triangle's plane, in f64 from the f32 inputs (accurate to about
/// 1e-16 relative, so its sign is the truth for any crossing that is not exactly at the origin).
fn exact_t(v: [Vec3A; 3], origin: Vec3, dir: Vec3) -> f64 {
    let [a, b, c] = v.map(|p| Vec3::from(p).as_dvec3());
    let n = (b - a).cross(c - a);
    (a - origin.as_dvec3()).dot(n) / dir.as_dvec3().dot(n)
}
