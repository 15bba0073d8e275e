//! Closest hits of up to 32 rays that share their origin: a tile's primary rays (a pinhole camera's
//! rays all start at the eye). As for the AO packets, what depends only on the origin is done once
//! per node (the child planes relative to it) and once per triangle (`Seen`); each ray costs a slab
//! test per node and 4 dot products per triangle (with AVX2, 8 rays at a time; the child masks go
//! through the shared branch-free transpose, and the directions are read only for the rays a test
//! finds). Children are visited nearest box first.
//!
//! The answers are bit-for-bit those of `Accel::closest` on each ray: the same node and triangle
//! arithmetic (no FMA), and a hit wins by the least (t, triangle) over all the triangles the ray
//! hits (`accel::closer`), which no visiting order changes. A ray's boxes are culled beyond its
//! best t so far, padded (see `node::child_planes`), so no box that holds a winning hit is ever
//! culled.

use super::STACK;
#[cfg(target_arch = "x86_64")]
use super::simd::wide;
use super::simd::{GROUPS, PACKET, Packet, box_dist2, lanes, present_children};
use crate::scene::accel::{Accel, Hit, LOOSE, closer};
use crate::scene::node::{child_planes, slabs};
use glam::{Vec3, Vec3A, Vec4};

impl Accel {
    /// For each of `dirs` (at most 32 unit vectors; rays from `origin`), what `closest` answers for
    /// that ray with `tmax`, in `hits` (as long as `dirs`).
    pub fn closest_from(&self, origin: Vec3, dirs: &[Vec3], tmax: f32, hits: &mut [Option<Hit>]) {
        assert!(dirs.len() <= PACKET && hits.len() == dirs.len(), "at most {PACKET} rays, one hit each");
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::is_x86_feature_detected as has;
            if has!("avx2") {
                // SAFETY: the CPU supports AVX2 (checked just above).
                return unsafe { self.closest_avx2(origin.into(), dirs, tmax, hits) };
            }
        }
        self.closest_packet::<false>(origin.into(), dirs, tmax, hits)
    }

    /// `closest_from` on the SSE2 kernels even where AVX2 is available (tests compare the two).
    #[doc(hidden)]
    pub fn closest_from_sse2(&self, origin: Vec3, dirs: &[Vec3], tmax: f32, hits: &mut [Option<Hit>]) {
        assert!(dirs.len() <= PACKET && hits.len() == dirs.len(), "at most {PACKET} rays, one hit each");
        self.closest_packet::<false>(origin.into(), dirs, tmax, hits)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn closest_avx2(&self, o: Vec3A, dirs: &[Vec3], tmax: f32, hits: &mut [Option<Hit>]) {
        self.closest_packet::<true>(o, dirs, tmax, hits)
    }

    #[inline(always)]
    fn closest_packet<const WIDE: bool>(&self, o: Vec3A, dirs: &[Vec3], tmax: f32, hits: &mut [Option<Hit>]) {
        hits.fill(None);
        let nodes = &self.bvh.nodes;
        if dirs.is_empty() || nodes.is_empty() {
            return;
        }
        let all = if dirs.len() >= 32 { u32::MAX } else { (1u32 << dirs.len()) - 1 };
        let mut p = Packet { d: [[Vec4::ZERO; GROUPS]; 3], inv: [[0.0; PACKET]; 3] };
        p.fill(dirs);
        // Each ray's direction as `Ray::new` makes it (-0.0 → +0.0, as `Packet::fill` did).
        // (Read when a triangle test needs it, not gathered up front: with AVX2 that is rare.)
        let dir = |i: usize| {
            let (v, l) = (i / 4, i % 4);
            [p.d[0][v][l], p.d[1][v][l], p.d[2][v][l]]
        };
        // A ray's best t so far: its boxes are culled beyond it.
        let mut bound = [tmax; PACKET];
        let mut stack = [(0u32, 0u32); STACK];
        let (mut top, widen) = (1usize, crate::scene::node::WIDEN);
        stack[0] = (0, all);
        while top > 0 {
            top -= 1;
            let (ni, live) = stack[top];
            let node = &nodes[ni as usize];
            let present = present_children(&node.child_meta);
            // Per child, the rays that enter it; and each child's squared distance from the origin.
            let cm: [u32; 8];
            let dist2: [f32; 8];
            #[cfg(target_arch = "x86_64")]
            if WIDE {
                // SAFETY: WIDE is only set by `closest_avx2`, on CPUs with AVX2.
                let pl = unsafe { wide::planes(node, o) };
                let mut acc = lanes::zero();
                let mut rays = live;
                while rays != 0 {
                    let i = rays.trailing_zeros() as usize;
                    rays &= rays - 1;
                    // SAFETY: as above.
                    let h = unsafe { wide::ray_hits(&pl, &p, i, bound[i], widen) } & present;
                    lanes::add_ray(&mut acc, h, i);
                }
                cm = lanes::to_array(acc);
                // SAFETY: as above.
                dist2 = unsafe { wide::box_dist2(&pl) };
            } else {
                (cm, dist2) = node_sse2(node, o, &p, live, &bound, present);
            }
            #[cfg(not(target_arch = "x86_64"))]
            {
                (cm, dist2) = node_sse2(node, o, &p, live, &bound, present);
            }
            // Leaves now; inner children onto the stack, the farthest first (the nearest pops next).
            let mut inner = [(0.0f32, 0u32, 0u32); 8];
            let mut n_inner = 0;
            for (c, &m) in cm.iter().enumerate() {
                if m == 0 {
                    continue;
                }
                let meta = node.child_meta[c];
                if node.imask & (1 << c) != 0 {
                    let slot = (meta & 0b11111) as u32 - 24;
                    let idx = node.child_base_idx + (node.imask as u32 & !(u32::MAX << slot)).count_ones();
                    inner[n_inner] = (dist2[c], idx, m);
                    n_inner += 1;
                    continue;
                }
                let first = node.primitive_base_idx + (meta & 0b11111) as u32;
                for prim in first..first + (meta >> 5).count_ones() {
                    let s = self.tris[prim as usize].seen_from(o);
                    if s.g == f32::INFINITY {
                        continue; // the origin is within the rounding of its plane: no ray hits it
                    }
                    // With AVX2, 8 rays' tests at once find the rays `closer` may accept (the same
                    // operations as its test, so exactly those); `closer` decides each of them.
                    let mut rays = m;
                    #[cfg(target_arch = "x86_64")]
                    if WIDE {
                        rays = 0;
                        for g in 0..PACKET / 8 {
                            let gm = (m >> (8 * g)) & 0xff;
                            if gm != 0 {
                                // SAFETY: WIDE is only set by `closest_avx2`, on CPUs with AVX2.
                                rays |=
                                    (unsafe { wide::hit8_within(&p, g, &s, &bound, LOOSE) } & gm) << (8 * g);
                            }
                        }
                    }
                    while rays != 0 {
                        let i = rays.trailing_zeros() as usize;
                        rays &= rays - 1;
                        if let Some(h) = closer(&s, dir(i), prim, tmax, hits[i], &self.bvh.primitive_indices)
                            && self.keeps(prim, h.bary_b, h.bary_c)
                        {
                            hits[i] = Some(h);
                            bound[i] = h.t;
                        }
                    }
                }
            }
            let inner = &mut inner[..n_inner];
            inner.sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
            for &(_, idx, m) in inner.iter() {
                stack[top] = (idx, m);
                top += 1;
            }
        }
    }
}

/// One node against the live rays, 4 children at a time (SSE2): the rays entering each child within
/// their bounds, and each child's squared distance from the origin.
#[inline(always)]
fn node_sse2(
    node: &obvhs::cwbvh::node::CwBvhNode,
    o: Vec3A,
    p: &Packet,
    live: u32,
    bound: &[f32; PACKET],
    present: u32,
) -> ([u32; 8], [f32; 8]) {
    let pl = child_planes(node, o);
    let mut cm = lanes::zero();
    let mut rays = live;
    while rays != 0 {
        let i = rays.trailing_zeros() as usize;
        rays &= rays - 1;
        let h = slabs(&pl, [p.inv[0][i], p.inv[1][i], p.inv[2][i]], bound[i]) & present;
        lanes::add_ray(&mut cm, h, i);
    }
    let cm = lanes::to_array(cm);
    let mut dist2 = [0.0f32; 8];
    for h in 0..2 {
        box_dist2(&pl, h).write_to_slice(&mut dist2[4 * h..4 * h + 4]);
    }
    (cm, dist2)
}
