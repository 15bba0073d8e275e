//! The ray-tracing core: obvhs's CWBVH for the tree and its traversal loop, with our own node and
//! triangle tests.
//!
//! Why not obvhs's own `ray_traverse_miss`: its 8-wide node test clamps the entry distance to a
//! hard-coded 1e-4 and ignores `ray.tmin` (obvhs 0.4.0, `cwbvh/simd.rs`), so boxes whose exit lies
//! closer than 1e-4 are culled and short AO hits are lost (scenes scaled by 1e-3 leak light), and it
//! picks the slab order from `dir < 0` but the slab distances from `1/dir`, which disagree for -0.0.
//! Our node test clamps at 0, takes the order from the sign of the inverse it uses, and is otherwise
//! the same arithmetic. The triangle test is watertight, so a closed mesh never lets a ray slip
//! between two triangles that share an edge; it is written from the ray origin's point of view
//! (signed volumes of the vertices relative to the origin) so that the rays of one AO pixel, which
//! share their origin, share most of its work (see `packet`).

use glam::{UVec2, Vec3, Vec3A, Vec4};
use obvhs::cwbvh::{CwBvh, node::CwBvhNode};
use std::cmp::Ordering;

/// One triangle by its three vertices (edges would not be shared bit-exactly between neighbours).
/// One cache line: a packet visiting a leaf touches one line per triangle. The vertices are
/// stored in lexicographic order (a < b < c), so every edge starts at its smaller end (see `Seen`).
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(crate) struct Tri {
    a: Vec3A,
    b: Vec3A,
    c: Vec3A,
    /// (b - a) × (c - a), for an accurate distance.
    n: Vec3A,
}

/// The BVH and the triangles in BVH order, so a leaf's primitives are read contiguously.
pub struct Accel {
    pub(crate) bvh: CwBvh,
    pub(crate) tris: Vec<Tri>,
    /// The input triangles in input order (the benchmark builds its plain-obvhs baseline from them).
    source: Vec<obvhs::triangle::Triangle>,
    /// Per triangle (BVH order): a power of two >= its largest absolute coordinate, for the
    /// scale-aware origin offset.
    scale: Vec<f32>,
}

/// A closest hit: distance, triangle (BVH order) and the barycentrics of `b` and `c`.
#[derive(Debug, Clone, Copy)]
pub struct Hit {
    pub t: f32,
    pub prim: u32,
    pub bary_b: f32,
    pub bary_c: f32,
}

/// A ray prepared for traversal: canonical direction and the slab inverses.
pub struct Ray {
    org: Vec3A,
    dir: Vec3A,
    inv: Vec3A,
    neg: [bool; 3],
    tmax: f32,
}

/// Slabs use 1/dir; a zero component would give 0 * inf = NaN, so tiny components are clamped.
pub(crate) const TINY: f32 = 1e-20;

fn safe_inv(x: f32) -> f32 {
    1.0 / if x.abs() < TINY { TINY.copysign(x) } else { x }
}

impl Ray {
    /// `dir` need not be unit length; distances are in units of |dir|.
    pub fn new(org: Vec3, dir: Vec3, tmax: f32) -> Self {
        let dir = Vec3A::from(dir) + Vec3A::ZERO; // -0.0 → +0.0 (obvhs bug 1)
        let inv = Vec3A::new(safe_inv(dir.x), safe_inv(dir.y), safe_inv(dir.z));
        Self { org: org.into(), dir, inv, neg: [inv.x < 0.0, inv.y < 0.0, inv.z < 0.0], tmax }
    }
}

impl Accel {
    /// Builds the CWBVH and returns it with the core build time in seconds. obvhs's slow preset
    /// (spatial pre-splits, more reinsertion): about 10% faster AO than the medium preset on the
    /// kitchen for a build that is still well under a second.
    pub fn build(triangles: &[[Vec3; 3]]) -> (Self, f64) {
        let soup: Vec<obvhs::triangle::Triangle> = triangles
            .iter()
            .map(|t| obvhs::triangle::Triangle { v0: t[0].into(), v1: t[1].into(), v2: t[2].into() })
            .collect();
        let mut core = std::time::Duration::ZERO;
        let bvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(
            &soup,
            obvhs::BvhBuildParams::slow_build(),
            &mut core,
        );
        let mut tris = Vec::with_capacity(bvh.primitive_indices.len());
        let mut scale = Vec::with_capacity(bvh.primitive_indices.len());
        for &i in &bvh.primitive_indices {
            let t = &soup[i as usize];
            let mut v = [t.v0, t.v1, t.v2];
            v.sort_unstable_by(|p, q| if lex_less(*p, *q) { Ordering::Less } else { Ordering::Greater });
            let n = Vec3A::from(cross(v[1] - v[0], v[2] - v[0]));
            tris.push(Tri { a: v[0], b: v[1], c: v[2], n });
            let m = t.v0.abs().max(t.v1.abs()).max(t.v2.abs()).max_element();
            scale.push(pow2_at_least(m));
        }
        (Self { bvh, tris, scale, source: soup }, core.as_secs_f64())
    }

    pub fn triangle(&self, prim: u32) -> [Vec3; 3] {
        let t = &self.tris[prim as usize];
        [t.a.into(), t.b.into(), t.c.into()]
    }

    pub fn scale(&self, prim: u32) -> f32 {
        self.scale[prim as usize]
    }

    /// The triangles as given to `build` (after dropping unusable ones), in that order.
    pub fn source_triangles(&self) -> &[obvhs::triangle::Triangle] {
        &self.source
    }

    /// Closest hit with 0 < t < ray.tmax.
    pub fn closest(&self, ray: &Ray) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        let mut tmax = ray.tmax;
        let mut state = self.bvh.new_traversal(ray.dir);
        let mut node: &CwBvhNode;
        obvhs::traverse!(self.bvh, node, state, node_hits(node, ray, tmax, state.oct_inv4), {
            if let Some((t, _, v, w)) = intersect(&self.tris[state.primitive_id as usize], ray, tmax) {
                tmax = t;
                best = Some(Hit { t, prim: state.primitive_id, bary_b: v, bary_c: w });
            }
        });
        best
    }

    /// True if anything lies on the ray with 0 < t < ray.tmax (early exit on the first hit).
    pub fn occluded(&self, ray: &Ray) -> bool {
        let mut state = self.bvh.new_traversal(ray.dir);
        let mut node: &CwBvhNode;
        let mut hit = false;
        'search: {
            obvhs::traverse!(self.bvh, node, state, node_hits(node, ray, ray.tmax, state.oct_inv4), {
                if intersect(&self.tris[state.primitive_id as usize], ray, ray.tmax).is_some() {
                    hit = true;
                    break 'search;
                }
            });
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
        let mut tmax = ray.tmax;
        for (i, tri) in self.tris.iter().enumerate() {
            if let Some((t, _, v, w)) = intersect(tri, ray, tmax) {
                tmax = t;
                best = Some(Hit { t, prim: i as u32, bary_b: v, bary_c: w });
            }
        }
        best
    }
}

fn pow2_at_least(m: f32) -> f32 {
    if m.is_nan() || m <= f32::MIN_POSITIVE {
        return f32::MIN_POSITIVE;
    }
    let p = f32::from_bits(m.to_bits() & 0xFF80_0000); // largest power of two <= m
    if p == m { p } else { p * 2.0 }
}

/// The 8 child boxes of `node` against the ray, 4 at a time (obvhs's `intersect_ray_simd` with the
/// entry clamped at 0 instead of 1e-4). Returns obvhs's hit mask (high byte: inner nodes, low: leaves).
#[inline(always)]
fn node_hits(node: &CwBvhNode, ray: &Ray, tmax: f32, oct_inv4: u32) -> u32 {
    let adj_inv = node.compute_extent() * ray.inv;
    let adj_org = (Vec3A::from(node.p) - ray.org) * ray.inv;
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(oct_inv4);
    let q = |v: &[u8; 8], i: usize| {
        Vec4::new(v[4 * i] as f32, v[4 * i + 1] as f32, v[4 * i + 2] as f32, v[4 * i + 3] as f32)
    };
    // Ize 2013 ("Robust BVH ray traversal"): widen the exit a little against rounding.
    let tmax4 = Vec4::splat(tmax);
    let widen = 1.0 + 2.0 * 3.0 * f32::EPSILON;
    let mut hit_mask = 0u32;
    for i in 0..2 {
        let slab = |lo: &[u8; 8], hi: &[u8; 8], neg: bool, s: f32, o: f32| {
            let (near, far) = if neg { (q(hi, i), q(lo, i)) } else { (q(lo, i), q(hi, i)) };
            (near * s + Vec4::splat(o), far * s + Vec4::splat(o))
        };
        let (nx, fx) = slab(&node.child_min_x, &node.child_max_x, ray.neg[0], adj_inv.x, adj_org.x);
        let (ny, fy) = slab(&node.child_min_y, &node.child_max_y, ray.neg[1], adj_inv.y, adj_org.y);
        let (nz, fz) = slab(&node.child_min_z, &node.child_max_z, ray.neg[2], adj_inv.z, adj_org.z);
        let tmin = nx.max(ny).max(nz).max(Vec4::ZERO);
        let tmax = (fx.min(fy).min(fz) * widen).min(tmax4);
        let mask = tmin.cmple(tmax).bitmask();
        for j in 0..4 {
            if mask & (1 << j) != 0 {
                let offset = (i * 4 + j) * 8;
                let child_bits = ((child_bits8 >> offset) as u32) & 0xff;
                let bit_index = ((bit_index8 >> offset) as u32) & 0xff;
                hit_mask |= child_bits << bit_index;
            }
        }
    }
    hit_mask
}

/// A triangle as seen from a ray origin o: with A, B, C its vertices minus o, the edge normals
/// X = B×C, Y = C×A, Z = A×B (computed as in `Tri::seen_from`), the normal N = (b-a)×(c-a) and
/// T = A·N. A ray o + t·d meets the
/// triangle iff d·X, d·Y, d·Z do not differ in sign, at t = T / d·N. Shared by all rays from o:
/// computed once per (origin, triangle), then 4 dot products per ray.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Seen {
    pub x: [f32; 3],
    pub y: [f32; 3],
    pub z: [f32; 3],
    pub n: [f32; 3],
    pub t: f32,
}

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
    /// The edge normals from the lexicographically smaller end of each edge, (p-o)×(q-p): accurate
    /// (q-p is short and exact-ish, unlike q-o) and watertight, as every triangle that shares the
    /// edge p–q computes exactly this value (the sign test does not care which way it walks it).
    /// glam's cross is the same per-component formula as `cross` (same products, same order).
    #[inline(always)]
    pub(crate) fn seen_from(&self, o: Vec3A) -> Seen {
        let (pa, pb) = (self.a - o, self.b - o);
        let e_ab = pa.cross(self.b - self.a);
        let e_ac = pa.cross(self.c - self.a);
        let e_bc = pb.cross(self.c - self.b);
        let n = self.n.to_array();
        // Opposite a: B×C = (b-o)×(c-b); opposite b: C×A = -(a-o)×(c-a); opposite c: A×B.
        Seen { x: e_bc.to_array(), y: (-e_ac).to_array(), z: e_ab.to_array(), n, t: dot(pa.to_array(), n) }
    }
}

/// The decision for one ray direction: (t, barycentrics of a, b, c) for 0 < t < tmax. A ray
/// exactly on an edge (value 0) counts for both triangles that share it.
#[inline(always)]
pub(crate) fn hit_seen(s: &Seen, d: [f32; 3], tmax: f32) -> Option<(f32, f32, f32, f32)> {
    let u = dot(d, s.x);
    let v = dot(d, s.y);
    let w = dot(d, s.z);
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let dn = dot(d, s.n);
    if dn == 0.0 {
        return None;
    }
    let t = s.t / dn;
    let sum = (u + v) + w;
    (t > 0.0 && t < tmax && sum != 0.0).then(|| (t, u / sum, v / sum, w / sum))
}

/// Ray/triangle test for 0 < t < tmax (see `Seen`).
#[inline(always)]
fn intersect(tri: &Tri, ray: &Ray, tmax: f32) -> Option<(f32, f32, f32, f32)> {
    hit_seen(&tri.seen_from(ray.org), ray.dir.to_array(), tmax)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_a_triangle_and_respects_tmax() {
        let tri = [Vec3::new(-1.0, -1.0, 1.0), Vec3::new(1.0, -1.0, 1.0), Vec3::new(0.0, 1.0, 1.0)];
        let (acc, _) = Accel::build(&[tri]);
        let r = Ray::new(Vec3::ZERO, Vec3::Z, f32::INFINITY);
        let h = acc.closest(&r).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
        assert!(acc.occluded(&r));
        assert!(!acc.occluded(&Ray::new(Vec3::ZERO, Vec3::Z, 0.5)));
        assert!(!acc.occluded(&Ray::new(Vec3::ZERO, -Vec3::Z, f32::INFINITY)));
        // -0.0 components must not make the ray miss.
        assert!(acc.occluded(&Ray::new(Vec3::ZERO, Vec3::new(-0.0, -0.0, 1.0), f32::INFINITY)));
    }

    #[test]
    fn short_hits_below_obvhs_epsilon_are_found() {
        let s = 1e-6;
        let tri = [Vec3::new(-s, -s, s), Vec3::new(s, -s, s), Vec3::new(0.0, s, s)];
        let (acc, _) = Accel::build(&[tri]);
        assert!(acc.occluded(&Ray::new(Vec3::ZERO, Vec3::Z, f32::INFINITY)));
    }

    #[test]
    fn pow2() {
        assert_eq!(pow2_at_least(1.0), 1.0);
        assert_eq!(pow2_at_least(1.5), 2.0);
        assert_eq!(pow2_at_least(1e4), 16384.0);
        assert_eq!(pow2_at_least(0.0), f32::MIN_POSITIVE);
    }
}
