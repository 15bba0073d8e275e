//! What a ray is to the tree: a ray prepared for traversal (`Ray`: canonical direction, clamped
//! slab inverses) and the test of one CWBVH node's 8 child boxes against it (`child_planes`,
//! `slabs`). Shared by the single-ray walk (`accel`) and the packets (`packet`), so both clamp
//! directions and cull boxes alike; a leaf, it imports nothing of the crate.

use glam::{Vec3, Vec3A, Vec4};
use obvhs::cwbvh::node::CwBvhNode;

/// A ray prepared for traversal: canonical direction and the slab inverses.
pub struct Ray {
    pub(super) org: Vec3A,
    pub(super) dir: Vec3A,
    pub(super) inv: Vec3A,
    pub(super) tmax: f32,
}

/// The slab test widens each box's exit distance by this factor (8 ulps), so the rounding of the
/// products never drops a box the ray touches. One value for every walk, so all cull alike.
pub(in crate::scene) const WIDEN: f32 = 1.0 + 8.0 * f32::EPSILON;

/// Slabs use 1/dir; a zero component would give 0 * inf = NaN, so tiny components are clamped.
pub(crate) const TINY: f32 = 1e-20;

fn safe_inv(x: f32) -> f32 {
    1.0 / if x.abs() < TINY { TINY.copysign(x) } else { x }
}

impl Ray {
    /// `dir`: a unit vector (the triangle test's error bound assumes components of magnitude <= 1).
    pub fn new(org: Vec3, dir: Vec3, tmax: f32) -> Self {
        let dir = Vec3A::from(dir) + Vec3A::ZERO; // -0.0 → +0.0 (obvhs's -0.0 trap, see `accel`)
        let inv = Vec3A::new(safe_inv(dir.x), safe_inv(dir.y), safe_inv(dir.z));
        Self { org: org.into(), dir, inv, tmax }
    }
}

/// The 8 quantized planes of one axis as two `Vec4`s (SSE2 widening; per node, not per ray).
#[inline(always)]
fn q8(v: &[u8; 8]) -> [Vec4; 2] {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        // SAFETY: SSE2 is part of the x86_64 baseline; the load reads exactly the 8 bytes of `v`.
        unsafe {
            let b = _mm_loadl_epi64(v.as_ptr() as *const __m128i);
            let w = _mm_unpacklo_epi8(b, _mm_setzero_si128());
            let lo = _mm_cvtepi32_ps(_mm_unpacklo_epi16(w, _mm_setzero_si128()));
            let hi = _mm_cvtepi32_ps(_mm_unpackhi_epi16(w, _mm_setzero_si128()));
            [Vec4::from(lo), Vec4::from(hi)]
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let q = |h: usize| {
            Vec4::new(v[4 * h] as f32, v[4 * h + 1] as f32, v[4 * h + 2] as f32, v[4 * h + 3] as f32)
        };
        [q(0), q(1)]
    }
}

/// The 8 child boxes of `node` relative to `o` as [axis lo x, hi x, lo y, ...][children 0-3, 4-7],
/// padded outwards by 2^-18 of their extent from `o` (far more than the rounding of the planes
/// and of the triangle test's edge values).
#[inline(always)]
pub(in crate::scene) fn child_planes(node: &CwBvhNode, o: Vec3A) -> [[Vec4; 2]; 6] {
    let e = node.compute_extent();
    let rel = Vec3A::from(node.p) - o;
    let pad = (rel.abs() + e * 255.0) * (1.0 / 262144.0);
    let axis = |lo: &[u8; 8], hi: &[u8; 8], r: f32, e: f32, p: f32| {
        let (ql, qh) = (q8(lo), q8(hi));
        let l = |h: usize| Vec4::splat(r - p) + ql[h] * e;
        let u = |h: usize| Vec4::splat(r + p) + qh[h] * e;
        ([l(0), l(1)], [u(0), u(1)])
    };
    let (lx, hx) = axis(&node.child_min_x, &node.child_max_x, rel.x, e.x, pad.x);
    let (ly, hy) = axis(&node.child_min_y, &node.child_max_y, rel.y, e.y, pad.y);
    let (lz, hz) = axis(&node.child_min_z, &node.child_max_z, rel.z, e.z, pad.z);
    [lx, hx, ly, hy, lz, hz]
}

/// One ray's slab test against the 8 boxes of `child_planes` (relative to its origin), 4 at a
/// time: bit c set if it enters child c within [0, tmax]. The entry is clamped at 0 and the exit
/// widened by 8 ulps, so the rounding of the products never drops a box the ray touches. Shared by
/// the single-ray walk (`accel`) and the packets' SSE2 path, so both cull alike.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // h indexes the halves of six plane arrays
pub(in crate::scene) fn slabs(pl: &[[Vec4; 2]; 6], inv: [f32; 3], tmax: f32) -> u32 {
    let (ix, iy, iz) = (Vec4::splat(inv[0]), Vec4::splat(inv[1]), Vec4::splat(inv[2]));
    let (widen, tmax4) = (Vec4::splat(WIDEN), Vec4::splat(tmax));
    let mut mask = 0u32;
    for h in 0..2 {
        let (x0, x1) = (pl[0][h] * ix, pl[1][h] * ix);
        let (y0, y1) = (pl[2][h] * iy, pl[3][h] * iy);
        let (z0, z1) = (pl[4][h] * iz, pl[5][h] * iz);
        let tn = x0.min(x1).max(y0.min(y1)).max(z0.min(z1)).max(Vec4::ZERO);
        let tf = x0.max(x1).min(y0.max(y1)).min(z0.max(z1)).min(tmax4);
        mask |= tn.cmple(tf * widen).bitmask() << (4 * h);
    }
    mask
}

/// The same node test with AVX2, all 8 children of a plane in one register: the same IEEE
/// operations as `child_planes` and `slabs` (so the same bits), for the single-ray walk's and the
/// packets' AVX2 copies.
#[cfg(target_arch = "x86_64")]
pub(in crate::scene) mod wide {
    use glam::Vec3A;
    use obvhs::cwbvh::node::CwBvhNode;
    use std::arch::x86_64::*;

    /// `super::child_planes` (the same values), all 8 children of each plane in one register.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub fn planes(node: &CwBvhNode, o: Vec3A) -> [__m256; 6] {
        let e = node.compute_extent();
        let rel = Vec3A::from(node.p) - o;
        let pad = (rel.abs() + e * 255.0) * (1.0 / 262144.0);
        // SAFETY: each load reads exactly the 8 bytes of one array.
        let q = |v: &[u8; 8]| unsafe {
            _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64(v.as_ptr() as *const __m128i)))
        };
        let plane = |v: &[u8; 8], base: f32, e: f32| {
            _mm256_add_ps(_mm256_set1_ps(base), _mm256_mul_ps(q(v), _mm256_set1_ps(e)))
        };
        [
            plane(&node.child_min_x, rel.x - pad.x, e.x),
            plane(&node.child_max_x, rel.x + pad.x, e.x),
            plane(&node.child_min_y, rel.y - pad.y, e.y),
            plane(&node.child_max_y, rel.y + pad.y, e.y),
            plane(&node.child_min_z, rel.z - pad.z, e.z),
            plane(&node.child_max_z, rel.z + pad.z, e.z),
        ]
    }

    /// `super::slabs` for one ray against the 8 boxes of `planes`: bit c set if it enters child c
    /// within [0, tmax], the exit widened by `widen`.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub fn slabs(pl: &[__m256; 6], inv: [f32; 3], tmax: f32, widen: f32) -> u32 {
        let (ix, iy, iz) = (_mm256_set1_ps(inv[0]), _mm256_set1_ps(inv[1]), _mm256_set1_ps(inv[2]));
        let (x0, x1) = (_mm256_mul_ps(pl[0], ix), _mm256_mul_ps(pl[1], ix));
        let (y0, y1) = (_mm256_mul_ps(pl[2], iy), _mm256_mul_ps(pl[3], iy));
        let (z0, z1) = (_mm256_mul_ps(pl[4], iz), _mm256_mul_ps(pl[5], iz));
        let tn = _mm256_max_ps(
            _mm256_max_ps(_mm256_max_ps(_mm256_min_ps(x0, x1), _mm256_min_ps(y0, y1)), _mm256_min_ps(z0, z1)),
            _mm256_setzero_ps(),
        );
        let tf = _mm256_min_ps(
            _mm256_min_ps(_mm256_min_ps(_mm256_max_ps(x0, x1), _mm256_max_ps(y0, y1)), _mm256_max_ps(z0, z1)),
            _mm256_set1_ps(tmax),
        );
        _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(tn, _mm256_mul_ps(tf, _mm256_set1_ps(widen)))) as u32
    }
}
