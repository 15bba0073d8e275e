//! The ray-tracing core: obvhs's CWBVH for the tree and its traversal loop, with our own node and
//! triangle tests.
//!
//! Why not obvhs's own `ray_traverse_miss`: its 8-wide node test clamps the entry distance to a
//! hard-coded 1e-4 and ignores `ray.tmin` (obvhs 0.4.0, `cwbvh/simd.rs`), so boxes whose exit lies
//! closer than 1e-4 are culled and short AO hits are lost (scenes scaled by 1e-3 leak light), and it
//! picks the slab order from `dir < 0` but the slab distances from `1/dir`, which disagree for -0.0.
//! Our node test clamps at 0, takes the order from the sign of the inverse it uses, and is otherwise
//! the same arithmetic. The triangle test is watertight (Woop, Benthin, Wald 2013, JCGT 2(1)), so a
//! closed mesh never lets a ray slip between two triangles that share an edge.

use glam::{UVec2, Vec3, Vec3A, Vec4};
use obvhs::cwbvh::{CwBvh, node::CwBvhNode};

/// One triangle by its three vertices (edges would not be shared bit-exactly between neighbours).
#[derive(Debug, Clone, Copy)]
struct Tri {
    a: Vec3A,
    b: Vec3A,
    c: Vec3A,
}

/// The BVH and the triangles in BVH order, so a leaf's primitives are read contiguously.
pub struct Accel {
    bvh: CwBvh,
    tris: Vec<Tri>,
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

/// A ray prepared for traversal: the shear of the watertight test and the slab inverses.
pub struct Ray {
    org: Vec3A,
    dir: Vec3A,
    inv: Vec3A,
    neg: [bool; 3],
    tmax: f32,
    /// Rows of the shear transform: (x, y) project onto the plane normal to the dominant axis, z scales.
    rx: Vec3A,
    ry: Vec3A,
    rz: Vec3A,
}

/// Slabs use 1/dir; a zero component would give 0 * inf = NaN, so tiny components are clamped.
fn safe_inv(x: f32) -> f32 {
    const TINY: f32 = 1e-20;
    1.0 / if x.abs() < TINY { TINY.copysign(x) } else { x }
}

impl Ray {
    /// `dir` need not be unit length; distances are in units of |dir|.
    pub fn new(org: Vec3, dir: Vec3, tmax: f32) -> Self {
        let dir = Vec3A::from(dir) + Vec3A::ZERO; // -0.0 → +0.0 (obvhs bug 1)
        let inv = Vec3A::new(safe_inv(dir.x), safe_inv(dir.y), safe_inv(dir.z));
        let a = dir.abs();
        let kz = if a.x > a.y {
            if a.x > a.z { 0 } else { 2 }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        if dir[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let unit = |k: usize| Vec3A::from(Vec3::AXES[k]);
        let (sx, sy, sz) = (dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]);
        Self {
            org: org.into(),
            dir,
            inv,
            neg: [inv.x < 0.0, inv.y < 0.0, inv.z < 0.0],
            tmax,
            rx: unit(kx) - sx * unit(kz),
            ry: unit(ky) - sy * unit(kz),
            rz: sz * unit(kz),
        }
    }
}

impl Accel {
    /// Builds the CWBVH (obvhs medium preset) and returns it with the core build time in seconds.
    pub fn build(triangles: &[[Vec3; 3]]) -> (Self, f64) {
        let soup: Vec<obvhs::triangle::Triangle> = triangles
            .iter()
            .map(|t| obvhs::triangle::Triangle { v0: t[0].into(), v1: t[1].into(), v2: t[2].into() })
            .collect();
        let mut core = std::time::Duration::ZERO;
        let bvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(
            &soup,
            obvhs::BvhBuildParams::medium_build(),
            &mut core,
        );
        let mut tris = Vec::with_capacity(bvh.primitive_indices.len());
        let mut scale = Vec::with_capacity(bvh.primitive_indices.len());
        for &i in &bvh.primitive_indices {
            let t = &soup[i as usize];
            tris.push(Tri { a: t.v0, b: t.v1, c: t.v2 });
            let m = t.v0.abs().max(t.v1.abs()).max(t.v2.abs()).max_element();
            scale.push(pow2_at_least(m));
        }
        (Self { bvh, tris, scale }, core.as_secs_f64())
    }

    pub fn triangle(&self, prim: u32) -> [Vec3; 3] {
        let t = &self.tris[prim as usize];
        [t.a.into(), t.b.into(), t.c.into()]
    }

    pub fn scale(&self, prim: u32) -> f32 {
        self.scale[prim as usize]
    }

    /// obvhs's tree, for the benchmark's plain-obvhs baseline.
    pub fn bvh(&self) -> &CwBvh {
        &self.bvh
    }

    /// The triangles in BVH order (index = obvhs's callback id).
    pub fn triangles_in_bvh_order(&self) -> impl Iterator<Item = [Vec3A; 3]> + '_ {
        self.tris.iter().map(|t| [t.a, t.b, t.c])
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

/// Watertight ray/triangle test (Woop, Benthin, Wald 2013). Returns (t, barycentrics of a, b, c)
/// for 0 < t < tmax.
#[inline(always)]
fn intersect(tri: &Tri, ray: &Ray, tmax: f32) -> Option<(f32, f32, f32, f32)> {
    let a = tri.a - ray.org;
    let b = tri.b - ray.org;
    let c = tri.c - ray.org;
    let (ax, ay) = (ray.rx.dot(a), ray.ry.dot(a));
    let (bx, by) = (ray.rx.dot(b), ray.ry.dot(b));
    let (cx, cy) = (ray.rx.dot(c), ray.ry.dot(c));
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    // An edge exactly through the ray: decide in double precision, as the paper does.
    if u == 0.0 || v == 0.0 || w == 0.0 {
        let d = |p: f32, q: f32, r: f32, s: f32| (p as f64 * q as f64 - r as f64 * s as f64) as f32;
        u = d(cx, by, cy, bx);
        v = d(ax, cy, ay, cx);
        w = d(bx, ay, by, ax);
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    let t_scaled = u * ray.rz.dot(a) + v * ray.rz.dot(b) + w * ray.rz.dot(c);
    let inside = if det > 0.0 {
        t_scaled > 0.0 && t_scaled < tmax * det
    } else {
        t_scaled < 0.0 && t_scaled > tmax * det
    };
    if !inside {
        return None;
    }
    let inv = 1.0 / det;
    let t = t_scaled * inv;
    (t > 0.0 && t < tmax).then_some((t, u * inv, v * inv, w * inv))
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
