//! The ray-tracing core: obvhs's CWBVH for the tree and its traversal loop, with our own node and
//! triangle tests.
//!
//! Why not obvhs's own `ray_traverse_miss`: its 8-wide node test clamps the entry distance to a
//! hard-coded 1e-4 and ignores `ray.tmin` (obvhs 0.4.0, `cwbvh/simd.rs`), so boxes whose exit lies
//! closer than 1e-4 are culled and short AO hits are lost (scenes scaled by 1e-3 leak light), and
//! it picks the slab order from `dir < 0` but the slab distances from `1/dir`, which disagree for
//! -0.0. Our node test clamps at 0 and pads each child box relative to its distance from the origin
//! (`node`'s `child_planes` and `slabs`, shared with the packets, so single rays and packets cull
//! alike). The triangle test is watertight, so a closed mesh never lets a ray slip between two
//! triangles that share an edge; it is written from the ray origin's point of view (signed volumes
//! of the vertices relative to the origin) so that the rays of one AO pixel, which share their
//! origin, share most of its work (see `packet`). It reports a hit only where the rounding cannot
//! have changed the sign of the distance (see `Seen`): so no ray ever hits a triangle whose plane
//! it truly leaves, whatever the size of the triangle, and an AO origin needs to be lifted only by
//! the error of the hit point itself.

use super::alpha::Mask;
pub use super::effort::{Effort, FAST_BELOW_RAYS_PER_TRIANGLE};
pub use super::node::Ray;
use super::node::{child_planes, slabs};
use glam::{UVec2, Vec3, Vec3A, Vec3Swizzles, Vec4};
use obvhs::cwbvh::{CwBvh, node::CwBvhNode};
use rayon::prelude::*;
use std::cmp::Ordering;

/// One triangle by its three vertices (edges would not be shared bit-exactly between neighbours).
/// One cache line: a packet visiting a leaf touches one line per triangle. The vertices are
/// stored in lexicographic order (a < b < c), so every edge starts at its smaller end (see `Seen`).
/// The fourth lanes carry the rounding bounds `seen_from` needs, computed once here: M (see
/// `T_ERR`) in those of a, b, c, and `Seen::g` in that of n.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(crate) struct Tri {
    pub(super) a: Vec4,
    b: Vec4,
    c: Vec4,
    /// (b - a) × (c - a), for an accurate distance.
    pub(super) n: Vec4,
}

/// The BVH and the triangles in BVH order, so a leaf's primitives are read contiguously.
pub struct Accel {
    pub(crate) bvh: CwBvh,
    pub(crate) tris: Vec<Tri>,
    /// The input triangles in input order (the benchmark builds its plain-obvhs baseline from
    /// them); kept by a full-effort build only (see `build_indexed`).
    source: Option<Vec<obvhs::triangle::Triangle>>,
    /// Unique per build in this process (never 0), so caches can tell scenes apart.
    pub(crate) id: u64,
    /// Each triangle's contacts, found on first use (`near::contacts`).
    pub(crate) contacts: super::near::grid::Table,
    /// The alpha masks per slot, for scenes that have any (`alpha`); `None` keeps every hit.
    pub(crate) alpha: Option<Box<Mask>>,
}

/// A closest hit: distance, triangle (BVH order) and the barycentrics of `b` and `c`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub prim: u32,
    pub bary_b: f32,
    pub bary_c: f32,
}

impl Accel {
    /// `build_indexed` of a triangle soup at full effort (tests and code-made scenes).
    pub fn build(triangles: &[[Vec3; 3]]) -> (Self, f64) {
        let positions: Vec<Vec3> = triangles.iter().flatten().copied().collect();
        let indices: Vec<[u32; 3]> =
            (0..triangles.len() as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
        Self::build_indexed(&positions, indices, Effort::Full)
    }

    /// Builds the CWBVH over the triangles `indices` makes of `positions` and returns it with the
    /// core build time in seconds. Full effort is obvhs's slow preset (spatial pre-splits, more
    /// reinsertion): about 10% faster AO than the medium preset on the kitchen for a build that is
    /// still well under a second. At most 2 triangles per leaf instead of the CWBVH's 3: a packet's
    /// few last rays test fewer triangles they miss (kitchen query, callgrind: d = inf 1150 -> 1136
    /// M instructions, d = 1 654 -> 651 M, d = 0.3 462 -> 459 M; 1 per leaf: 1222 M at d = inf).
    ///
    /// Memory: afterwards the vertices live only in `tris` (BVH order), beside the tree;
    /// the input triangles in input order are kept only by a full build (the benchmark's baseline
    /// needs them, and a full build is for small scenes or long runs). A fast build gives obvhs the
    /// boxes of pairs of triangles alone, and takes `indices` to put them in Z order (`cluster`).
    pub fn build_indexed(positions: &[Vec3], indices: Vec<[u32; 3]>, effort: Effort) -> (Self, f64) {
        let mut core = std::time::Duration::ZERO;
        let (bvh, tris, source) = match effort {
            Effort::Full => {
                let corners = |i: usize| indices[i].map(|k| Vec3A::from(positions[k as usize]));
                let soup: Vec<obvhs::triangle::Triangle> = (0..indices.len())
                    .map(|i| {
                        let [v0, v1, v2] = corners(i);
                        obvhs::triangle::Triangle { v0, v1, v2 }
                    })
                    .collect();
                let bvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(
                    &soup,
                    obvhs::BvhBuildParams { max_prims_per_leaf: 2, ..obvhs::BvhBuildParams::slow_build() },
                    &mut core,
                );
                let tris = bvh.primitive_indices.par_iter().map(|&i| Tri::new(corners(i as usize))).collect();
                (bvh, tris, Some(soup))
            }
            Effort::Fast => {
                let (bvh, tris) = super::cluster::fast(positions, indices, &mut core);
                (bvh, tris, None)
            }
        };
        static BUILDS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
        let id = BUILDS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let contacts = tris.iter().map(|_| Default::default()).collect();
        (Self { bvh, tris, source, id, contacts, alpha: None }, core.as_secs_f64())
    }

    /// Whether a hit on slot `prim` at barycentrics (b, c) counts: always, unless the scene has
    /// alpha masks and the texel there is transparent (`alpha::Mask::keeps`). Every query (single
    /// rays, packets, primary and AO) asks this of the same numbers, so all agree bit for bit.
    #[inline(always)]
    pub(crate) fn keeps(&self, prim: u32, b: f32, c: f32) -> bool {
        match &self.alpha {
            None => true,
            Some(m) => m.keeps(prim, b, c),
        }
    }

    /// Gives the tree its alpha masks (per BVH slot, `alpha::Mask::for_slots`).
    pub fn set_alpha(&mut self, mask: Mask) {
        self.alpha = Some(Box::new(mask));
    }

    /// The build effort the tree was made with (`Effort::for_work`).
    pub fn effort(&self) -> Effort {
        if self.source.is_some() { Effort::Full } else { Effort::Fast }
    }

    /// Whether hits can be rejected by an alpha mask.
    pub fn has_alpha(&self) -> bool {
        self.alpha.is_some()
    }

    /// Unique per build in this process (never 0): lets caches tell scenes apart.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// The vertices of triangle `prim` (BVH order) in the order `Hit`'s barycentrics refer to.
    pub fn triangle(&self, prim: u32) -> [Vec3; 3] {
        let t = &self.tris[prim as usize];
        [t.a.truncate(), t.b.truncate(), t.c.truncate()]
    }

    /// The index in `source_triangles` of the triangle in BVH slot `prim` (spatial splits put one
    /// input triangle in several slots). `render::clearance` tells a wall's slots apart by it.
    pub fn source_index(&self, prim: u32) -> u32 {
        self.bvh.primitive_indices[prim as usize]
    }

    /// The triangles as given to `build` (after dropping unusable ones), in that order. Kept by a
    /// full-effort build only (the benchmark's); a fast build panics here.
    pub fn source_triangles(&self) -> &[obvhs::triangle::Triangle] {
        self.source.as_deref().expect("the input triangles are kept by a full-effort build")
    }

    /// Closest hit with 0 < t < ray.tmax: of the triangles the ray hits, the least (t, prim) (see
    /// `closer`), so the answer does not depend on the order the walk meets them in.
    pub fn closest(&self, ray: &Ray) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        let mut tmax = ray.tmax;
        let mut state = self.bvh.new_traversal(ray.dir);
        let mut node: &CwBvhNode;
        let d = ray.dir.to_array();
        obvhs::traverse!(self.bvh, node, state, node_hits::<false>(node, ray, tmax, state.oct_inv4), {
            let prim = state.primitive_id;
            let s = self.tris[prim as usize].seen_from(ray.org);
            if let Some(h) = closer(&s, d, prim, ray.tmax, best, &self.bvh.primitive_indices)
                && self.keeps(prim, h.bary_b, h.bary_c)
            {
                tmax = h.t;
                best = Some(h);
            }
        });
        best
    }

    /// True if anything lies on the ray with 0 < t < ray.tmax (early exit on the first hit).
    pub fn occluded(&self, ray: &Ray) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::is_x86_feature_detected as has;
            if has!("avx2") && has!("popcnt") && has!("bmi1") {
                // SAFETY: the CPU supports AVX2, POPCNT and BMI1 (checked just above).
                return unsafe { self.occluded_avx2(ray) };
            }
        }
        self.occluded_walk::<false>(ray)
    }

    /// The walk compiled for AVX2 with the 8 children's boxes in one register (`node::wide`): the
    /// same IEEE operations, so the same answers. Kitchen, one thread, against the SSE2 walk: 21 %
    /// less time at d = inf, 25 % at d = 1; whole renders at 1 ray a pixel 19 % less on the
    /// kitchen, 5 % on Sponza (docs/performance.md, "Few rays a pixel").
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,popcnt,bmi1")]
    unsafe fn occluded_avx2(&self, ray: &Ray) -> bool {
        self.occluded_walk::<true>(ray)
    }

    #[inline(always)]
    fn occluded_walk<const WIDE: bool>(&self, ray: &Ray) -> bool {
        let mut state = self.bvh.new_traversal(ray.dir);
        let mut node: &CwBvhNode;
        let mut hit = false;
        'search: {
            obvhs::traverse!(
                self.bvh,
                node,
                state,
                node_hits::<WIDE>(node, ray, ray.tmax, state.oct_inv4),
                {
                    let prim = state.primitive_id;
                    if let Some((_, _, b, c)) = intersect(&self.tris[prim as usize], ray, ray.tmax)
                        && self.keeps(prim, b, c)
                    {
                        hit = true;
                        break 'search;
                    }
                }
            );
        }
        hit
    }
}

impl Accel {
    /// Triangles in the BVH (after dropping unusable ones).
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// The same query as `closest` without the BVH: every triangle is tested. The reference that
    /// proves the traversal culls nothing it should not; far too slow for rendering.
    pub fn closest_brute_force(&self, ray: &Ray) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        for (i, tri) in self.tris.iter().enumerate() {
            let s = tri.seen_from(ray.org);
            if let Some(h) =
                closer(&s, ray.dir.to_array(), i as u32, ray.tmax, best, &self.bvh.primitive_indices)
                && self.keeps(i as u32, h.bary_b, h.bary_c)
            {
                best = Some(h);
            }
        }
        best
    }
}

/// The 8 child boxes of `node` against the ray: the packet path's padded planes relative to the
/// origin (`child_planes`) and its slab test, with the entry clamped at 0 (obvhs clamps at 1e-4).
/// Returns obvhs's hit mask (high byte: inner nodes, low: leaves).
#[inline(always)]
fn node_hits<const WIDE: bool>(node: &CwBvhNode, ray: &Ray, tmax: f32, oct_inv4: u32) -> u32 {
    #[cfg(target_arch = "x86_64")]
    let mut mask = if WIDE {
        use super::node::wide;
        // SAFETY: WIDE is only set by the walks compiled for AVX2, on CPUs that have it.
        unsafe { wide::slabs(&wide::planes(node, ray.org), ray.inv.to_array(), tmax, super::node::WIDEN) }
    } else {
        slabs(&child_planes(node, ray.org), ray.inv.to_array(), tmax)
    };
    #[cfg(not(target_arch = "x86_64"))]
    let mut mask = slabs(&child_planes(node, ray.org), ray.inv.to_array(), tmax);
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(oct_inv4);
    let mut hit_mask = 0u32;
    while mask != 0 {
        let offset = mask.trailing_zeros() * 8;
        mask &= mask - 1;
        let child_bits = ((child_bits8 >> offset) as u32) & 0xff;
        let bit_index = ((bit_index8 >> offset) as u32) & 0xff;
        hit_mask |= child_bits << bit_index;
    }
    hit_mask
}

/// A triangle as seen from a ray origin o: with A, B, C its vertices minus o, the edge normals
/// X = B×C, Y = C×A, Z = A×B (computed as in `Tri::seen_from`), the normal N = (b-a)×(c-a) and
/// T = A·N. A ray o + t·d meets the triangle iff d·X, d·Y, d·Z do not differ in sign, at
/// t = T / d·N. Shared by all rays from o: computed once per (origin, triangle), then 4 dot
/// products per ray.
///
/// The sign of t decides whether the triangle is in front of the origin or behind it, and rounding
/// can flip it where T or d·N is tiny: an AO origin lifted off a large triangle by less than the
/// triangle's rounding (which grows with its size, not with the lift) would see it in front. So a
/// hit needs both signs proven: |T| above a bound on T's rounding error (else `g` is infinite and
/// nothing is hit, decided once per origin), and d·N of T's sign by more than `g`, a bound on the
/// rounding of d·N for any unit d (one comparison per ray, with N turned to T's side). A triangle whose plane
/// passes within its rounding error of the origin, or a ray within about 1e-6 rad of parallel to
/// it, is therefore never hit; any hit that is reported is truly in front (t >= 0).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Seen {
    pub x: [f32; 3],
    pub y: [f32; 3],
    pub z: [f32; 3],
    /// N, negated where T < 0, so that a hit needs d·n > g whatever the side (negation is exact).
    pub n: [f32; 3],
    /// |T|.
    pub t: f32,
    /// d·n must exceed this for a hit; infinite where T's sign is not certain.
    pub g: f32,
}

/// Rounding bounds of `Tri::seen_from`, in units of u = 2^-24 (f32 unit roundoff). With
/// M_i = |e1_j e2_k| + |e1_k e2_j| (the magnitudes that make up N_i = e1_j e2_k - e1_k e2_j):
/// computed N has |N' - N|_i <= 4u M_i (two roundings of the edges, the product, the difference);
/// A' = a - o is off by u|A| and the three-term dot adds 3u, so |T' - T| <= 8u Σ|A_i| M_i, and for
/// |d_i| <= 1, |d·N' - d·N| <= 7u Σ M_i (first order). The constants add half again for the
/// rounding of the bounds themselves and the second-order terms.
pub(crate) const T_ERR: f32 = 12.0 / 16_777_216.0;
const DN_ERR: f32 = 10.5 / 16_777_216.0;

#[inline(always)]
fn cross(p: Vec3A, q: Vec3A) -> [f32; 3] {
    [p.y * q.z - p.z * q.y, p.z * q.x - p.x * q.z, p.x * q.y - p.y * q.x]
}

/// The one order of summation used by the scalar and the packet paths (so both give equal bits).
#[inline(always)]
pub(crate) fn dot(p: [f32; 3], q: [f32; 3]) -> f32 {
    (p[0] * q[0] + p[1] * q[1]) + p[2] * q[2]
}

fn lex_less(p: Vec3A, q: Vec3A) -> bool {
    p.x < q.x || (p.x == q.x && (p.y < q.y || (p.y == q.y && p.z < q.z)))
}

impl Tri {
    /// The triangle with corners `v` (in any order; stored in lexicographic order).
    pub(super) fn new(mut v: [Vec3A; 3]) -> Tri {
        v.sort_unstable_by(|p, q| if lex_less(*p, *q) { Ordering::Less } else { Ordering::Greater });
        let (e1, e2) = (v[1] - v[0], v[2] - v[0]);
        let n = Vec3A::from(cross(e1, e2));
        // The magnitudes N is made of (see `T_ERR`); 0 on the axes where N is exactly 0.
        let m = (e1.yzx() * e2.zxy()).abs() + (e1.zxy() * e2.yzx()).abs();
        Tri {
            a: v[0].extend(m.x),
            b: v[1].extend(m.y),
            c: v[2].extend(m.z),
            n: n.extend(DN_ERR * m.element_sum()),
        }
    }

    /// N = (b - a) × (c - a), as `seen_from` uses it.
    #[inline(always)]
    pub(crate) fn normal(&self) -> [f32; 3] {
        Vec3A::from_vec4(self.n).to_array()
    }

    /// The edge normals from the lexicographically smaller end of each edge, (p-o)×(q-p): accurate
    /// (q-p is short and exact-ish, unlike q-o) and watertight, as every triangle that shares the
    /// edge p–q computes exactly this value (the sign test does not care which way it walks it).
    /// glam's cross is the same per-component formula as `cross` (same products, same order).
    #[inline(always)]
    pub(crate) fn seen_from(&self, o: Vec3A) -> Seen {
        let (a, b, c) = (Vec3A::from_vec4(self.a), Vec3A::from_vec4(self.b), Vec3A::from_vec4(self.c));
        let (pa, pb) = (a - o, b - o);
        let e_ab = pa.cross(b - a);
        let e_ac = pa.cross(c - a);
        let e_bc = pb.cross(c - b);
        let n = Vec3A::from_vec4(self.n);
        let t = dot(pa.to_array(), n.to_array());
        let (m, n) = lanes::w_of_abc_and_signed(self.a, self.b, self.c, n, t);
        let at = t.abs();
        // Opposite a: B×C = (b-o)×(c-b); opposite b: C×A = -(a-o)×(c-a); opposite c: A×B.
        Seen {
            x: e_bc.to_array(),
            y: (-e_ac).to_array(),
            z: e_ab.to_array(),
            n: n.to_array(),
            t: at,
            g: if at > T_ERR * pa.abs().dot(m) { self.n.w } else { f32::INFINITY },
        }
    }
}

/// Lane shuffles of `seen_from` (SSE2 on x86_64, plain code elsewhere).
mod lanes {
    use glam::{Vec3A, Vec4};

    /// (M: the fourth lanes of a, b, c; N negated if t < 0).
    #[inline(always)]
    pub fn w_of_abc_and_signed(a: Vec4, b: Vec4, c: Vec4, n: Vec3A, t: f32) -> (Vec3A, Vec3A) {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::*;
            // SAFETY: SSE2 is part of the x86_64 baseline.
            unsafe {
                let ab = _mm_unpackhi_ps(a.into(), b.into()); // a.z b.z a.w b.w
                let m = _mm_shuffle_ps::<0b11_11_11_10>(ab, c.into()); // a.w b.w c.w c.w
                let sign = _mm_and_ps(_mm_set1_ps(t), _mm_set1_ps(-0.0));
                (Vec3A::from(m), Vec3A::from(_mm_xor_ps(n.into(), sign)))
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let n = if t.is_sign_negative() { -n } else { n };
            (Vec3A::new(a.w, b.w, c.w), n)
        }
    }
}

/// The decision for one ray direction: (t, barycentrics of a, b, c) for 0 <= t < tmax (t = 0 only
/// where a proven positive distance underflows). A ray exactly on an edge (value 0) counts for
/// both triangles that share it.
#[inline(always)]
pub(crate) fn hit_seen(s: &Seen, d: [f32; 3], tmax: f32) -> Option<(f32, f32, f32, f32)> {
    let u = dot(d, s.x);
    let v = dot(d, s.y);
    let w = dot(d, s.z);
    // Mixed signs: no hit. min/max exactly as SSE's minps/maxps (the second operand where either
    // is NaN), so that this and the packet kernels agree even on NaN.
    let (mn, mx) = (|a: f32, b: f32| if a < b { a } else { b }, |a: f32, b: f32| if a > b { a } else { b });
    if mn(mn(u, v), w) < 0.0 && mx(mx(u, v), w) > 0.0 {
        return None;
    }
    let dn = dot(d, s.n);
    // Not `dn <= s.g`: a NaN must fail.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    if !(dn > s.g) {
        return None;
    }
    // t = |T| / d·n < tmax, without the division (d·n > 0 here); the packets do the same.
    let sum = (u + v) + w;
    (s.t < tmax * dn && sum != 0.0).then(|| (s.t / dn, u / sum, v / sum, w / sum))
}

/// A margin above 1 that `closer`'s first test widens the best t by: 2^-20, far more than the
/// rounding of t = |T| / d·n and of the product it is compared with.
pub(crate) const LOOSE: f32 = 1.0 + 1.0 / 1_048_576.0;

/// Triangle `prim`'s hit (seen as `s`, ray direction `d`) if it beats `best`: t = |T| / d·n < ray_tmax
/// and (t, input triangle) less than best's. A total order on the hits of one ray, so the closest
/// hit is the same whatever order a traversal tests the triangles in: the single-ray walk and the
/// primary-ray packets (`packet::closest`) give the same bits. (Accepting a hit where T < tmax·d·n
/// with tmax the best t so far, as before, let two hits within a rounding of each other, e.g. two
/// coplanar overlapping triangles, win by the order they were met in.) Ties go to the smaller
/// input index (`source`, per BVH slot), not BVH slot: the spatial splits put one input triangle in
/// several slots, which hit alike (same vertices) but are not all reached by every walk; of those
/// the first met stays, with the same vertices whichever it is. The cheap test against the best t
/// widened by `LOOSE` comes first; it rejects no hit that wins.
#[inline(always)]
pub(crate) fn closer(
    s: &Seen,
    d: [f32; 3],
    prim: u32,
    ray_tmax: f32,
    best: Option<Hit>,
    source: &[u32],
) -> Option<Hit> {
    let best_t = best.map_or(ray_tmax, |b| b.t);
    let (t, _, v, w) = hit_seen(s, d, best_t * LOOSE)?;
    let wins = match best {
        None => t < ray_tmax,
        Some(b) => t < b.t || (t == b.t && source[prim as usize] < source[b.prim as usize]),
    };
    wins.then_some(Hit { t, prim, bary_b: v, bary_c: w })
}

/// Ray/triangle test for 0 <= t < tmax (see `Seen`).
#[inline(always)]
fn intersect(tri: &Tri, ray: &Ray, tmax: f32) -> Option<(f32, f32, f32, f32)> {
    hit_seen(&tri.seen_from(ray.org), ray.dir.to_array(), tmax)
}

#[cfg(test)]
mod tests;
