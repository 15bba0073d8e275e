//! The SIMD kernels of the packet traversal: the packet's ray data, the per-ray box and triangle
//! tests (4 lanes with SSE2, the x86_64 baseline; 8 lanes with AVX2 when the CPU has it), and the
//! child-mask transpose. The 4-wide child planes and slab test are `node`'s, shared with the
//! single-ray walk.

use crate::scene::accel::Seen;
use crate::scene::node::TINY;
use glam::{Vec3, Vec4};

/// Rays per packet.
pub const PACKET: usize = 32;
pub(super) const GROUPS: usize = PACKET / 4;

/// What a node's shared culling needs (see `Horizon`): the normal, s², and d² (padded).
pub(super) struct Cull {
    pub n: [f32; 3],
    pub slope2: f32,
    pub reach2: f32,
}

pub(super) struct Packet {
    /// Directions, 4 rays per `Vec4`, per axis.
    pub d: [[Vec4; GROUPS]; 3],
    /// 1/dir per axis and ray (tiny components clamped as in `safe_inv`), for the slab tests.
    pub inv: [[f32; PACKET]; 3],
}

impl Packet {
    /// Fills `self` from `dirs` (in place: the struct is 768 bytes, not worth a copy per pixel).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // k and g index three parallel arrays
    pub fn fill(&mut self, dirs: &[Vec3]) {
        let mut d = [[0.0f32; PACKET]; 3];
        for (i, v) in dirs.iter().enumerate() {
            let v = *v + Vec3::ZERO; // -0.0 → +0.0, exactly as `Ray::new`
            d[0][i] = v.x;
            d[1][i] = v.y;
            d[2][i] = v.z;
        }
        let tiny = Vec4::splat(TINY);
        let p = self;
        for k in 0..3 {
            for g in 0..GROUPS {
                let x = Vec4::from_slice(&d[k][4 * g..4 * g + 4]);
                p.d[k][g] = x;
                let safe = Vec4::select(x.abs().cmplt(tiny), tiny.copysign(x), x);
                (Vec4::ONE / safe).write_to_slice(&mut p.inv[k][4 * g..4 * g + 4]);
            }
        }
    }
}

impl Packet {
    /// Fills `self` from separate x, y, z arrays (at most 32 each, equal lengths): the same values
    /// as `fill` of the same directions. Lanes past the end get zero directions.
    #[inline(always)]
    pub fn fill_soa(&mut self, x: &[f32], y: &[f32], z: &[f32]) {
        let tiny = Vec4::splat(TINY);
        for (k, src) in [x, y, z].into_iter().enumerate() {
            for g in 0..GROUPS {
                let at = 4 * g;
                let v = if at + 4 <= src.len() {
                    Vec4::from_slice(&src[at..at + 4])
                } else {
                    Vec4::from_array(std::array::from_fn(|l| src.get(at + l).copied().unwrap_or(0.0)))
                };
                let v = v + Vec4::ZERO; // -0.0 → +0.0, exactly as `Ray::new`
                self.d[k][g] = v;
                let safe = Vec4::select(v.abs().cmplt(tiny), tiny.copysign(v), v);
                (Vec4::ONE / safe).write_to_slice(&mut self.inv[k][at..at + 4]);
            }
        }
    }
}

/// The squared distance from the origin to each of children 4h..4h+3 (0 inside), from their
/// `child_planes`.
#[inline(always)]
pub(super) fn box_dist2(pl: &[[Vec4; 2]; 6], h: usize) -> Vec4 {
    let gap = |k: usize| pl[2 * k][h].max(-pl[2 * k + 1][h]).max(Vec4::ZERO);
    let (gx, gy, gz) = (gap(0), gap(1), gap(2));
    gx * gx + gy * gy + gz * gz
}

/// Which lanes of group `g` hit `s` within [0, tmax): the vector form of `accel::hit_seen`.
#[inline(always)]
pub(super) fn hit_group(p: &Packet, g: usize, s: &Seen, tmax: f32) -> u32 {
    let (dx, dy, dz) = (p.d[0][g], p.d[1][g], p.d[2][g]);
    let dotv = |q: [f32; 3]| (dx * Vec4::splat(q[0]) + dy * Vec4::splat(q[1])) + dz * Vec4::splat(q[2]);
    let (u, v, w) = (dotv(s.x), dotv(s.y), dotv(s.z));
    let z = Vec4::ZERO;
    // min/max as SSE does them (the second operand where either is NaN), as `accel::hit_seen`.
    let neg = u.min(v).min(w).cmplt(z);
    let pos = u.max(v).max(w).cmpgt(z);
    let dn = dotv(s.n);
    let near = Vec4::splat(s.t).cmplt(Vec4::splat(tmax) * dn);
    let sum = (u + v) + w;
    let sure = dn.cmpgt(Vec4::splat(s.g));
    let hit = !(neg & pos) & sure & near & sum.cmpne(z);
    hit.bitmask()
}

#[cfg(target_arch = "x86_64")]
pub(super) mod lanes {
    use std::arch::x86_64::*;

    /// Adds ray `i` to the children whose bits are set in `hits` (branch-free transpose).
    #[inline(always)]
    pub fn add_ray(cm: &mut [__m128i; 2], hits: u32, i: usize) {
        // SAFETY: SSE2 is part of the x86_64 baseline.
        unsafe {
            let h = _mm_set1_epi32(hits as i32);
            let r = _mm_set1_epi32((1u32 << i) as i32);
            let b0 = _mm_setr_epi32(1, 2, 4, 8);
            let b1 = _mm_setr_epi32(16, 32, 64, 128);
            cm[0] = _mm_or_si128(cm[0], _mm_and_si128(_mm_cmpeq_epi32(_mm_and_si128(h, b0), b0), r));
            cm[1] = _mm_or_si128(cm[1], _mm_and_si128(_mm_cmpeq_epi32(_mm_and_si128(h, b1), b1), r));
        }
    }

    #[inline(always)]
    pub fn zero() -> [__m128i; 2] {
        // SAFETY: SSE2 is part of the x86_64 baseline.
        unsafe { [_mm_setzero_si128(), _mm_setzero_si128()] }
    }

    #[inline(always)]
    pub fn to_array(cm: [__m128i; 2]) -> [u32; 8] {
        // SAFETY: two 16-byte registers into 32 bytes.
        unsafe { std::mem::transmute(cm) }
    }
}

#[cfg(not(target_arch = "x86_64"))]
pub(super) mod lanes {
    pub fn add_ray(cm: &mut [u32; 8], hits: u32, i: usize) {
        for (c, m) in cm.iter_mut().enumerate() {
            *m |= ((hits >> c) & 1) << i;
        }
    }
    pub fn zero() -> [u32; 8] {
        [0; 8]
    }
    pub fn to_array(cm: [u32; 8]) -> [u32; 8] {
        cm
    }
}

/// Bit c set iff child slot c is not empty (its meta byte is not 0).
#[inline(always)]
pub(super) fn present_children(meta: &[u8; 8]) -> u32 {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        // SAFETY: SSE2 is part of the x86_64 baseline; the load reads exactly the 8 bytes of `meta`.
        unsafe {
            let b = _mm_loadl_epi64(meta.as_ptr() as *const __m128i);
            !(_mm_movemask_epi8(_mm_cmpeq_epi8(b, _mm_setzero_si128())) as u32) & 0xff
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        meta.iter().enumerate().fold(0, |m, (c, &b)| m | ((b != 0) as u32) << c)
    }
}

/// 8-wide versions of the per-ray kernels, for CPUs with AVX2 (runtime-detected). The triangle
/// test is the same sequence of IEEE operations as `hit_group` / `accel::hit_seen` (so the same
/// bits); the box test is the same as the 4-wide one.
#[cfg(target_arch = "x86_64")]
pub(super) mod wide {
    use super::{Cull, Packet, Seen};
    pub use crate::scene::node::wide::planes;
    use glam::Vec3A;
    use obvhs::cwbvh::node::CwBvhNode;
    use std::arch::x86_64::*;

    /// One node against the live rays of the packet, all 8 children in one register: the child
    /// planes (the same values as `child_planes`), the shared culling (unless `few`), and each
    /// live ray's slab test. Returns, per child, the rays that enter it, and the children entered.
    /// `COPY`: one instance per caller (the masked and the unmasked walk, as `hit8`), so that LLVM
    /// compiles the unmasked walk as it does without the masked one (sharing one instance cost
    /// that walk +5 to +14 % instructions on the kitchen's query, callgrind).
    #[inline]
    #[target_feature(enable = "avx2")]
    #[allow(clippy::too_many_arguments)]
    pub fn node<const COPY: bool>(
        node: &CwBvhNode,
        o: Vec3A,
        p: &Packet,
        live: u32,
        few: bool,
        cull: &Cull,
        tmax: f32,
        present: u32,
    ) -> ([u32; 8], u32) {
        let pl = planes(node, o);
        let (mut near, mut inside) = (present, 0u32);
        if !few {
            let z = _mm256_setzero_ps();
            let d2 = dist2(&pl);
            let side = |k: usize, n: f32| {
                let n = _mm256_set1_ps(n);
                _mm256_max_ps(_mm256_mul_ps(pl[2 * k], n), _mm256_mul_ps(pl[2 * k + 1], n))
            };
            let support =
                _mm256_add_ps(_mm256_add_ps(side(0, cull.n[0]), side(1, cull.n[1])), side(2, cull.n[2]));
            let above = _mm256_and_ps(
                _mm256_cmp_ps::<_CMP_GE_OQ>(support, z),
                _mm256_cmp_ps::<_CMP_GE_OQ>(
                    _mm256_mul_ps(support, support),
                    _mm256_mul_ps(_mm256_set1_ps(cull.slope2), d2),
                ),
            );
            let reach = _mm256_cmp_ps::<_CMP_LE_OQ>(d2, _mm256_set1_ps(cull.reach2));
            near = _mm256_movemask_ps(_mm256_and_ps(reach, above)) as u32 & present;
            inside = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_EQ_OQ>(d2, z)) as u32 & near;
        }
        let want = near & !inside;
        let bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
        let lanes_of = |m: u32| _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(m as i32), bits), bits);
        let mut cm = _mm256_setzero_si256();
        if want != 0 {
            let mut rays = live;
            while rays != 0 {
                let i = rays.trailing_zeros() as usize;
                rays &= rays - 1;
                let hits = ray_hits(&pl, p, i, tmax, crate::scene::node::WIDEN) & want;
                cm = _mm256_or_si256(
                    cm,
                    _mm256_and_si256(lanes_of(hits), _mm256_set1_epi32((1u32 << i) as i32)),
                );
            }
        }
        // Children that hold the origin: every live ray enters them.
        cm = _mm256_blendv_epi8(cm, _mm256_set1_epi32(live as i32), lanes_of(inside));
        let empty =
            _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(cm, _mm256_setzero_si256()))) as u32;
        // SAFETY: one 32-byte register into 32 bytes.
        (unsafe { std::mem::transmute::<__m256i, [u32; 8]>(cm) }, !empty & 0xff)
    }

    /// Each child box's squared distance from the origin the planes are relative to (0 inside).
    #[inline]
    #[target_feature(enable = "avx2")]
    pub fn dist2(pl: &[__m256; 6]) -> __m256 {
        let (z, sign) = (_mm256_setzero_ps(), _mm256_set1_ps(-0.0));
        let gap = |k: usize| _mm256_max_ps(_mm256_max_ps(pl[2 * k], _mm256_xor_ps(pl[2 * k + 1], sign)), z);
        let (gx, gy, gz) = (gap(0), gap(1), gap(2));
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(gx, gx), _mm256_mul_ps(gy, gy)), _mm256_mul_ps(gz, gz))
    }

    /// `dist2` as an array.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub fn box_dist2(pl: &[__m256; 6]) -> [f32; 8] {
        // SAFETY: one 32-byte register into 32 bytes.
        unsafe { std::mem::transmute::<__m256, [f32; 8]>(dist2(pl)) }
    }

    /// Children (bits) whose slabs ray `i` crosses within [0, tmax] (`node::wide::slabs`).
    #[inline]
    #[target_feature(enable = "avx2")]
    pub fn ray_hits(pl: &[__m256; 6], p: &Packet, i: usize, tmax: f32, widen: f32) -> u32 {
        crate::scene::node::wide::slabs(pl, [p.inv[0][i], p.inv[1][i], p.inv[2][i]], tmax, widen)
    }

    /// Which of rays 8g..8g+7 hit `s` within (0, tmax) (bits 0..8); `COPY` as in `node`.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub fn hit8<const COPY: bool>(p: &Packet, g: usize, s: &Seen, tmax: f32) -> u32 {
        hit8_below(p, g, s, _mm256_set1_ps(tmax))
    }

    /// `hit8` with each ray's own bound: ray 8g + k's is `bound[8g + k] * widen` (the product
    /// `accel::closer` bounds its hit test with), so the rays it returns are exactly those for which
    /// `closer`'s test finds a hit.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub fn hit8_within(p: &Packet, g: usize, s: &Seen, bound: &[f32; 32], widen: f32) -> u32 {
        // SAFETY: the slice is exactly 8 f32.
        let b = unsafe { _mm256_loadu_ps(bound[8 * g..8 * g + 8].as_ptr()) };
        hit8_below(p, g, s, _mm256_mul_ps(b, _mm256_set1_ps(widen)))
    }

    /// `hit8` against a bound per lane.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn hit8_below(p: &Packet, g: usize, s: &Seen, tmax: __m256) -> u32 {
        // SAFETY: p.d[k] holds 8 Vec4 = 32 contiguous f32; 2g+1 < 8.
        let ld = |k: usize| unsafe { _mm256_loadu_ps(p.d[k].as_ptr().add(2 * g) as *const f32) };
        let (dx, dy, dz) = (ld(0), ld(1), ld(2));
        let dotv = |q: [f32; 3]| {
            let xy = _mm256_add_ps(
                _mm256_mul_ps(dx, _mm256_set1_ps(q[0])),
                _mm256_mul_ps(dy, _mm256_set1_ps(q[1])),
            );
            _mm256_add_ps(xy, _mm256_mul_ps(dz, _mm256_set1_ps(q[2])))
        };
        let (u, v, w) = (dotv(s.x), dotv(s.y), dotv(s.z));
        let z = _mm256_setzero_ps();
        let neg = _mm256_cmp_ps::<_CMP_LT_OQ>(_mm256_min_ps(_mm256_min_ps(u, v), w), z);
        let pos = _mm256_cmp_ps::<_CMP_GT_OQ>(_mm256_max_ps(_mm256_max_ps(u, v), w), z);
        let dn = dotv(s.n);
        let near = _mm256_cmp_ps::<_CMP_LT_OQ>(_mm256_set1_ps(s.t), _mm256_mul_ps(tmax, dn));
        let sum = _mm256_add_ps(_mm256_add_ps(u, v), w);
        let sure = _mm256_cmp_ps::<_CMP_GT_OQ>(dn, _mm256_set1_ps(s.g));
        let ok = _mm256_andnot_ps(_mm256_and_ps(neg, pos), sure);
        let ok = _mm256_and_ps(ok, near);
        let ok = _mm256_and_ps(ok, _mm256_cmp_ps::<_CMP_NEQ_UQ>(sum, z));
        _mm256_movemask_ps(ok) as u32
    }
}

/// Bit 4g set iff group g (rays 4g..4g+3) has a ray in `m`.
#[inline(always)]
pub(super) fn groups_of(m: u32) -> u32 {
    let x = m | (m >> 1);
    (x | (x >> 2)) & 0x1111_1111
}
