//! What lies right around a point: the triangles whose boxes come within a tiny distance of it, the
//! triangles that touch a triangle away from its edges (`contacts`), and how the triangle test sees
//! a triangle from a point. The AO origin needs them where the primary ray hits an edge, a corner
//! or a contact: lifted off its own triangle, it may still lie on a neighbour's plane, where the
//! triangle test cannot tell the side and so reports no hit (`accel::Seen`), and about half the rays
//! then leave through that neighbour (`render::clearance`).

pub(crate) mod contacts;
pub(crate) mod grid;

pub(crate) use contacts::reach_cap;

use super::accel::{Accel, dot, hit_seen};
use glam::{Vec3, Vec3A};
use obvhs::cwbvh::node::CwBvhNode;

impl Accel {
    /// The triangles (BVH slots) whose boxes overlap the box of half-sides `half` around `o`, into
    /// `out`, in the order of the walk. The boxes are the tree's own, padded as for the rays (see
    /// `node::child_planes`), so every triangle that passes through that box is listed (and some
    /// that do not). `stack`: scratch for the walk. The node test is done in each node's own 8-bit
    /// grid: the query box is rounded outwards to it, then compared with the 48 child planes as
    /// bytes.
    pub(crate) fn near(&self, o: Vec3, half: Vec3, out: &mut Vec<u32>, stack: &mut Vec<u32>) {
        out.clear();
        stack.clear();
        let nodes = &self.bvh.nodes;
        if nodes.is_empty() {
            return;
        }
        stack.push(0);
        while let Some(i) = stack.pop() {
            let node = &nodes[i as usize];
            let mut mask = overlapping(node, o, half);
            while mask != 0 {
                let c = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let meta = node.child_meta[c];
                if node.imask & (1 << c) != 0 {
                    let slot = (meta & 0b11111) as u32 - 24;
                    stack.push(node.child_base_idx + (node.imask as u32 & !(u32::MAX << slot)).count_ones());
                } else {
                    let first = node.primitive_base_idx + (meta & 0b11111) as u32;
                    out.extend(first..first + (meta >> 5).count_ones());
                }
            }
        }
    }

    /// Whether triangle `prim`'s plane may pass within `r` of `o` (a quick test in f32, with slack
    /// for its rounding: it may say yes for a plane a little farther, never no for one within r).
    #[inline(always)]
    pub(crate) fn plane_near(&self, prim: u32, o: Vec3, r: f32) -> bool {
        let tri = &self.tris[prim as usize];
        let n = Vec3A::from_vec4(tri.n);
        let rel = Vec3A::from_vec4(tri.a) - Vec3A::from(o);
        let reach = r + rel.abs().element_sum() * (1.0 / 1_048_576.0);
        let d = n.dot(rel);
        d * d <= reach * reach * n.length_squared()
    }

    /// Whether the triangle test finds triangle `prim` on the ray from `o` along unit `dir`
    /// within `tmax`.
    pub(crate) fn blocks(&self, prim: u32, o: Vec3, dir: Vec3, tmax: f32) -> bool {
        let d = (Vec3A::from(dir) + Vec3A::ZERO).to_array(); // -0.0 → +0.0, as `Ray::new`
        hit_seen(&self.tris[prim as usize].seen_from(o.into()), d, tmax).is_some()
    }

    /// Which side of triangle `prim`'s plane `o` is on, as the triangle test sees it from there:
    /// `Some(true)` on the side its normal (b - a) × (c - a) points to, `Some(false)` on the other,
    /// `None` where the test cannot tell (`Seen::g` infinite): then no ray from `o` can hit it.
    pub(crate) fn seen_side(&self, prim: u32, o: Vec3) -> Option<bool> {
        let tri = &self.tris[prim as usize];
        let s = tri.seen_from(o.into());
        // `seen_from` turns N to T's side; T = N·(a - o) < 0 iff o is on N's side.
        (s.g != f32::INFINITY).then(|| dot(s.n, tri.normal()) < 0.0)
    }
}

/// Bit c set iff child c of `node` is present and its box overlaps the box of half-sides `half`
/// around `o`. Child c's box is p + [q_min, q_max] e per axis (p, e: the node's origin and power-of-
/// two scale; obvhs rounds q_min down and q_max up). It overlaps iff q_min <= (o + r - p) / e and
/// q_max >= (o - r - p) / e: the query's bounds, padded as `child_planes` pads the boxes (2^-18 of
/// the extent from o, far more than the rounding here), clamped to the grid and truncated to
/// integers (which only widens them: q_max is compared with the truncated lower bound), are
/// compared with the children's bytes, all 8 children at once.
#[inline(always)]
fn overlapping(node: &CwBvhNode, o: Vec3, half: Vec3) -> u32 {
    let e = node.compute_extent();
    let rel = Vec3A::from(o) - Vec3A::from(node.p);
    let pad = (rel.abs() + e * 255.0) * (1.0 / 262_144.0) + Vec3A::from(half);
    let inv = e.recip(); // exact: e is a power of two
    let (hi, lo) = ((rel + pad) * inv, (rel - pad) * inv);
    // Not `hi < 0`: NaN must miss too.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    if !(hi.min_element() >= 0.0 && lo.max_element() <= 255.0) {
        return 0; // wholly outside the node's grid on some axis
    }
    let (hi, lo) = (hi.min(Vec3A::splat(255.0)), lo.max(Vec3A::ZERO));
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        // SAFETY: SSE2 is part of the x86_64 baseline. CwBvhNode is repr(C): its six [u8; 8]
        // plane arrays are contiguous (min x, max x, min y, ..., max z), and the three 16-byte
        // loads read exactly them, through a pointer to the whole node.
        unsafe {
            let base =
                (node as *const CwBvhNode as *const u8).add(std::mem::offset_of!(CwBvhNode, child_min_x));
            let axes = [0, 16, 32].map(|k| _mm_loadu_si128(base.add(k) as *const __m128i));
            // The bounds as bytes, each spread over a register: [hi × 8 | 255 × 8], [0 × 8 | lo × 8].
            let bytes = _mm_packus_epi16(
                _mm_packs_epi32(_mm_cvttps_epi32(hi.into()), _mm_cvttps_epi32(lo.into())),
                _mm_setzero_si128(),
            );
            let pairs = _mm_unpacklo_epi8(bytes, bytes);
            let (his, los) = (_mm_unpacklo_epi16(pairs, pairs), _mm_unpackhi_epi16(pairs, pairs));
            let upper = _mm_set_epi64x(-1, 0);
            let above = [
                _mm_shuffle_epi32::<0x00>(his),
                _mm_shuffle_epi32::<0x55>(his),
                _mm_shuffle_epi32::<0xaa>(his),
            ];
            let below = [
                _mm_shuffle_epi32::<0x00>(los),
                _mm_shuffle_epi32::<0x55>(los),
                _mm_shuffle_epi32::<0xaa>(los),
            ];
            // Saturating min - hi and lo - max are 0 where they hold.
            let mut miss = _mm_setzero_si128();
            for k in 0..3 {
                let (a, b) = (_mm_or_si128(above[k], upper), _mm_and_si128(below[k], upper));
                miss = _mm_or_si128(miss, _mm_or_si128(_mm_subs_epu8(axes[k], a), _mm_subs_epu8(b, axes[k])));
            }
            let fold = _mm_or_si128(miss, _mm_unpackhi_epi64(miss, miss));
            let zero = _mm_setzero_si128();
            let hit = _mm_movemask_epi8(_mm_cmpeq_epi8(fold, zero)) as u32;
            let meta = _mm_loadl_epi64(node.child_meta.as_ptr() as *const __m128i);
            let empty = _mm_movemask_epi8(_mm_cmpeq_epi8(meta, zero)) as u32;
            hit & !empty & 0xff
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let planes = [
            (node.child_min_x, node.child_max_x, hi.x as u8, lo.x as u8),
            (node.child_min_y, node.child_max_y, hi.y as u8, lo.y as u8),
            (node.child_min_z, node.child_max_z, hi.z as u8, lo.z as u8),
        ];
        let mut mask = 0u32;
        for c in 0..8 {
            let inside = planes.iter().all(|&(min, max, hi, lo)| min[c] <= hi && max[c] >= lo);
            mask |= ((inside && node.child_meta[c] != 0) as u32) << c;
        }
        mask
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fan of 40 small triangles around the origin and one far away: the query lists every
    /// triangle that comes within r (and, boxes being boxes, possibly a few more near them).
    #[test]
    fn lists_every_triangle_within_reach() {
        let mut tris = Vec::new();
        for i in 0..40 {
            let a = i as f32 * 0.157;
            let c = Vec3::new(a.cos(), a.sin(), 0.1 * a) * (0.01 + i as f32 * 0.02);
            tris.push([c, c + Vec3::new(0.01, 0.0, 0.0), c + Vec3::new(0.0, 0.01, 0.002)]);
        }
        tris.push([Vec3::splat(5.0), Vec3::new(6.0, 5.0, 5.0), Vec3::new(5.0, 6.0, 5.0)]);
        let (acc, _) = Accel::build(&tris);
        let (mut out, mut stack) = (Vec::new(), Vec::new());
        let probes = [(Vec3::ZERO, 0.05f32), (Vec3::new(0.3, 0.2, 0.0), 0.1), (Vec3::splat(5.0), 1e-6)];
        let more = (0..200).map(|i| (Vec3::new(i as f32 * 0.01 - 1.0, (i as f32 * 0.37).sin(), 0.3), 1e-4));
        for (o, r) in probes.into_iter().chain(more) {
            acc.near(o, Vec3::splat(r), &mut out, &mut stack);
            for (slot, &src) in acc.bvh.primitive_indices.iter().enumerate() {
                let t = tris[src as usize];
                let (lo, hi) = (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
                let within = (lo - o).cmple(Vec3::splat(r)).all() && (hi - o).cmpge(Vec3::splat(-r)).all();
                if within {
                    assert!(out.contains(&(slot as u32)), "{o} {r}: triangle {src} missing");
                }
            }
        }
        acc.near(Vec3::splat(-3.0), Vec3::splat(0.1), &mut out, &mut stack);
        assert!(out.is_empty(), "{out:?}");
    }

    #[test]
    fn tells_the_side_of_a_plane_only_where_the_test_can() {
        let (acc, _) = Accel::build(&[[Vec3::ZERO, Vec3::X, Vec3::Y]]);
        let t = acc.triangle(0); // in the stored (sorted) order, which N follows
        let n_up = (t[1] - t[0]).cross(t[2] - t[0]).z > 0.0;
        let above = acc.seen_side(0, Vec3::new(0.2, 0.2, 1e-6));
        let below = acc.seen_side(0, Vec3::new(0.2, 0.2, -1e-6));
        assert_eq!((above, below), (Some(n_up), Some(!n_up)));
        assert_eq!(acc.seen_side(0, Vec3::new(0.2, 0.2, 0.0)), None);
    }
}
