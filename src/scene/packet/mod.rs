//! A pixel's AO rays traced together over obvhs's CWBVH nodes: they share their origin, so one
//! walk of the 8-wide tree serves up to 32 of them. Per node, what depends only on the origin is
//! done once (child planes relative to the origin; the distance from the origin to each child box,
//! culling boxes beyond d; boxes below the cone the packet's rays rise in above the surface's
//! tangent plane; boxes holding the origin, which every ray enters); only the slab test is per ray,
//! one ray against all 8 children.
//! Per triangle, `Seen` is done once and each ray costs 4 dot products, 4 or 8 rays at a time. The
//! previous pixel's occluders are tried first (`Occluders`).
//!
//! The answers are bit-for-bit those of `Accel::occluded` on each ray: the same triangle
//! arithmetic in the same order (SSE2 or AVX2, no FMA); the box tests are padded, so they cull a
//! subset of what exact boxes would, and any-hit answers do not depend on the order of the tests.

mod closest;
mod horizon;
mod masked;
mod simd;

use super::accel::Accel;
use super::node::{Ray, child_planes, slabs};
use glam::{Vec3, Vec3A, Vec4};
use horizon::{Horizon, horizon, horizon_of};
pub use simd::PACKET;
#[cfg(target_arch = "x86_64")]
use simd::wide;
use simd::{Cull, GROUPS, Packet, box_dist2, groups_of, hit_group, lanes, present_children};

/// Asks for node `idx`'s cache lines (80 bytes: two or three lines) as it goes on the stack, ahead of
/// its visit: at d = ∞ a packet's last rays walk far across the tree, and each node's fetch would
/// otherwise wait for the visit of the one before (kitchen query alone, d = ∞: 1.05 -> 1.02 s for 8
/// repeats, d = 1: 0.486 -> 0.475 s; within the noise of `hemilab bench`, which runs obvhs between
/// repeats; prefetching the leaves' triangles as well was slower, 1.07 s).
#[inline(always)]
fn prefetch_node(nodes: &[obvhs::cwbvh::node::CwBvhNode], idx: u32) {
    #[cfg(target_arch = "x86_64")]
    if let Some(n) = nodes.get(idx as usize) {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let p = n as *const obvhs::cwbvh::node::CwBvhNode as *const i8;
        let last = std::mem::size_of::<obvhs::cwbvh::node::CwBvhNode>() - 1;
        // SAFETY: prefetching is a hint; it never faults, whatever the address.
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>(p);
            _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(last / 2));
            _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(last));
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (nodes, idx);
}

/// 7 siblings per level over obvhs's maximum depth of 32, plus the 8 children of the last node.
const STACK: usize = 256;

/// A pixel's directions as separate x, y, z arrays of equal length.
#[derive(Debug, Clone, Copy)]
pub struct Soa<'a> {
    pub x: &'a [f32],
    pub y: &'a [f32],
    pub z: &'a [f32],
}

/// Triangles that blocked rays of the previous packet (the neighbouring pixel, on the same
/// thread): tested first, since neighbouring pixels tend to share occluders. Only the speed depends
/// on it: a ray is blocked iff some triangle blocks it, whichever is tried first.
#[derive(Debug, Clone, Default)]
pub struct Occluders {
    prims: [u32; OCCLUDERS],
    /// How many rays each blocked first (the next packet tries the best blockers first).
    counts: [u32; OCCLUDERS],
    len: usize,
    /// The `Accel::id` the triangles belong to: a thread's cache outlives a scene (a thread-local in
    /// the renderer), and another scene's triangle numbers may not even exist in this one.
    owner: u64,
    /// The traversal stack, kept to spare each packet zeroing its own.
    stack: Vec<(u32, u32)>,
}

/// At most this many live rays: a node's children are culled by the rays' own slab tests only.
const FEW: u32 = 4;

/// Triangles remembered from one packet for the next.
const OCCLUDERS: usize = 32;

/// The occluders found while tracing one packet (becomes the cache for the next).
struct Found {
    prims: [u32; OCCLUDERS],
    counts: [u32; OCCLUDERS],
    len: usize,
}

impl Found {
    /// Records that `prim` blocked `rays` rays no earlier triangle had blocked.
    #[inline(always)]
    fn push(&mut self, prim: u32, rays: u32) {
        if self.len < OCCLUDERS {
            self.prims[self.len] = prim;
            self.counts[self.len] = rays;
            self.len += 1;
        }
    }
}

impl Occluders {
    pub fn new() -> Self {
        Self::default()
    }

    /// Best blockers first (a stable insertion sort of at most 16 entries, once per packet).
    fn sort(&mut self) {
        for k in 1..self.len {
            let mut j = k;
            while j > 0 && self.counts[j - 1] < self.counts[j] {
                self.counts.swap(j - 1, j);
                self.prims.swap(j - 1, j);
                j -= 1;
            }
        }
    }
}

impl Accel {
    /// For each of `dirs` (any number; rays from `origin`), whether something lies on it with
    /// 0 < t < tmax: the same answers as `occluded` on each ray, traced 32 at a time. `normal`,
    /// if given, is the surface normal at the origin (the rays' hemisphere); it only speeds up.
    pub fn occluded_from(
        &self,
        origin: Vec3,
        normal: Option<Vec3>,
        dirs: &[Vec3],
        tmax: f32,
        blocked: &mut [bool],
        cache: &mut Occluders,
    ) {
        self.occluded_from_impl(true, origin, normal, dirs, tmax, blocked, cache);
    }

    /// `occluded_from` on the SSE2 kernels even where AVX2 is available (tests compare the two).
    #[doc(hidden)]
    pub fn occluded_from_sse2(
        &self,
        origin: Vec3,
        normal: Option<Vec3>,
        dirs: &[Vec3],
        tmax: f32,
        blocked: &mut [bool],
        cache: &mut Occluders,
    ) {
        self.occluded_from_impl(false, origin, normal, dirs, tmax, blocked, cache);
    }

    /// `occluded_from` on directions given as separate x, y, z arrays (what the warps write,
    /// `sampling::batch::Directions`), answering with one mask per 32 rays (bit i of `masks[k]`:
    /// ray 32k + i is blocked). The renderer's and the benchmark's query: no array of `Vec3` or
    /// `bool` on the way.
    pub fn occluded_soa(
        &self,
        origin: Vec3,
        normal: Option<Vec3>,
        dirs: Soa,
        tmax: f32,
        masks: &mut [u32],
        cache: &mut Occluders,
    ) {
        let n = dirs.x.len();
        assert!(dirs.y.len() == n && dirs.z.len() == n && masks.len() == n.div_ceil(PACKET));
        let mut p = Packet { d: [[Vec4::ZERO; GROUPS]; 3], inv: [[0.0; PACKET]; 3] };
        for (k, mask) in masks.iter_mut().enumerate() {
            let r = k * PACKET..((k + 1) * PACKET).min(n);
            let len = r.len();
            if len == 1 {
                // A lone ray (1 ray a pixel, or the 33rd): the single-ray walk is the same answer
                // and faster than a packet's setup (kitchen, d = 1: 176 against 231 ns a ray). Two
                // rays a pixel take the same time either way (whole renders of the kitchen and
                // Sponza, both walks on AVX2, 2026-12-07); from 4 the packet's occluder cache wins.
                let d = Vec3::new(dirs.x[r.start], dirs.y[r.start], dirs.z[r.start]);
                *mask = self.occluded(&Ray::new(origin, d, tmax)) as u32;
                continue;
            }
            p.fill_soa(&dirs.x[r.clone()], &dirs.y[r.clone()], &dirs.z[r]);
            let up = normal.and_then(|n| horizon_of(&p, len, n));
            *mask = self.packet_dispatch(true, origin.into(), up, &p, len, tmax, cache);
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn occluded_from_impl(
        &self,
        wide: bool,
        origin: Vec3,
        normal: Option<Vec3>,
        dirs: &[Vec3],
        tmax: f32,
        blocked: &mut [bool],
        cache: &mut Occluders,
    ) {
        let mut p = Packet { d: [[Vec4::ZERO; GROUPS]; 3], inv: [[0.0; PACKET]; 3] };
        for (chunk, out) in dirs.chunks(PACKET).zip(blocked.chunks_mut(PACKET)) {
            let up = horizon(chunk, normal);
            p.fill(chunk);
            let mask = self.packet_dispatch(wide, origin.into(), up, &p, chunk.len(), tmax, cache);
            for (i, b) in out.iter_mut().enumerate() {
                *b = (mask >> i) & 1 != 0;
            }
        }
    }

    /// The same code compiled for AVX2 when the CPU has it (VEX three-operand forms and wider
    /// moves; no FMA, which would change the rounding), else for the SSE2 baseline. Either way
    /// every operation is the same IEEE operation, so the answers are identical.
    #[allow(clippy::too_many_arguments)]
    fn packet_dispatch(
        &self,
        wide: bool,
        o: Vec3A,
        up: Option<Horizon>,
        p: &Packet,
        len: usize,
        tmax: f32,
        cache: &mut Occluders,
    ) -> u32 {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::is_x86_feature_detected as has;
            // Masked scenes have their own AVX2 copy, whose `wide::node` and `wide::hit8` are
            // instances of their own (`COPY`): sharing them once made the unmasked copy +5 to +14 %
            // instructions on the kitchen's query. Sponza's query (d = 2): 36 % less time than on
            // the SSE2 walk, its renders at 4 rays a pixel 30 % less (2026-12-07).
            if wide && has!("avx2") && has!("popcnt") && has!("bmi1") {
                // SAFETY: the CPU supports AVX2, POPCNT and BMI1 (checked just above).
                return unsafe {
                    match self.alpha.is_some() {
                        true => self.occluded_packet_avx2::<true>(o, up, p, len, tmax, cache),
                        false => self.occluded_packet_avx2::<false>(o, up, p, len, tmax, cache),
                    }
                };
            }
        }
        // Two copies of the walk: scenes without masks run one with no mask test in it at all.
        match self.alpha.is_some() {
            true => self.occluded_packet::<false, true>(o, up, p, len, tmax, cache),
            false => self.occluded_packet::<false, false>(o, up, p, len, tmax, cache),
        }
    }

    /// `occluded_packet` compiled for AVX2: one instance for scenes without masks, one for masked.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,popcnt,bmi1")]
    unsafe fn occluded_packet_avx2<const MASKED: bool>(
        &self,
        o: Vec3A,
        up: Option<Horizon>,
        p: &Packet,
        len: usize,
        tmax: f32,
        cache: &mut Occluders,
    ) -> u32 {
        self.occluded_packet::<true, MASKED>(o, up, p, len, tmax, cache)
    }

    /// Bit i set: ray i (of at most 32) is blocked. `MASKED`: the scene has alpha masks, and a hit
    /// counts only where its mask keeps it (`unmasked`).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // h indexes the halves of six plane arrays
    fn occluded_packet<const WIDE: bool, const MASKED: bool>(
        &self,
        o: Vec3A,
        up: Option<Horizon>,
        p: &Packet,
        len: usize,
        tmax: f32,
        cache: &mut Occluders,
    ) -> u32 {
        let nodes = &self.bvh.nodes;
        if len == 0 || nodes.is_empty() {
            return 0;
        }
        if cache.owner != self.id {
            (cache.owner, cache.len) = (self.id, 0);
        }
        let all = if len >= 32 { u32::MAX } else { (1u32 << len) - 1 };
        // Nothing farther than d from the origin can be hit (|dir| = 1 up to rounding; keep slack).
        let reach2 = {
            let r = tmax * (1.0 + 1.0 / 1024.0);
            r * r
        };
        // Without a horizon, a zero normal makes the support test below never cull (0 >= 0).
        let (n, slope2) = up.map_or((Vec3A::ZERO, 0.0), |h| (h.n, h.slope2));
        let cull = Cull { n: n.to_array(), slope2, reach2 };
        let mut blocked = 0u32;
        let mut found = Found { prims: [0; OCCLUDERS], counts: [0; OCCLUDERS], len: 0 };
        // Test triangle `prim` against the rays in `live`; remember it if it blocks a new one.
        let mut test = |prim: u32, live: u32, blocked: &mut u32| {
            if live == 0 {
                return;
            }
            let s = self.tris[prim as usize].seen_from(o);
            if s.g == f32::INFINITY {
                return; // the origin is within the rounding of its plane: no ray can hit it
            }
            let mut new = 0u32;
            #[cfg(target_arch = "x86_64")]
            if WIDE {
                for g in 0..PACKET / 8 {
                    let gm = (live >> (8 * g)) & 0xff;
                    if gm != 0 {
                        // SAFETY: WIDE is only set by `occluded_packet_avx2`, on CPUs with AVX2.
                        new |= (unsafe { wide::hit8::<MASKED>(p, g, &s, tmax) } & gm) << (8 * g);
                    }
                }
                if MASKED && new != 0 {
                    new = self.unmasked(prim, &s, p, new, tmax);
                }
                if new != 0 {
                    *blocked |= new;
                    found.push(prim, new.count_ones());
                }
                return;
            }
            let mut gs = groups_of(live);
            while gs != 0 {
                let g = gs.trailing_zeros() as usize / 4;
                gs &= gs - 1;
                new |= (hit_group(p, g, &s, tmax) & (live >> (4 * g)) & 0xf) << (4 * g);
            }
            if MASKED && new != 0 {
                new = self.unmasked(prim, &s, p, new, tmax);
            }
            if new != 0 {
                *blocked |= new;
                found.push(prim, new.count_ones());
            }
        };
        for &prim in &cache.prims[..cache.len] {
            // One ray left: its walk costs less than the rest of the cache (kitchen query, callgrind:
            // d = inf 1172.5 -> 1150.3 M instructions, d = 1 658.8 -> 654.3 M; stopping at 2-4 rays
            // or at none saves less).
            if (all & !blocked).count_ones() <= 1 {
                break;
            }
            test(prim, all & !blocked, &mut blocked);
        }
        let mut stack = std::mem::take(&mut cache.stack);
        stack.clear();
        stack.reserve(STACK);
        if blocked & all != all {
            stack.push((0u32, all));
        }
        'walk: while let Some((ni, m)) = stack.pop() {
            let live = m & !blocked;
            if live == 0 {
                continue;
            }
            let node = &nodes[ni as usize];
            let present = present_children(&node.child_meta);
            // With few rays left the shared tests cost more than they spare: their slabs decide.
            let few = live.count_ones() <= FEW;
            #[cfg(target_arch = "x86_64")]
            let (cm, hit) = if WIDE {
                // SAFETY: WIDE is only set by `occluded_packet_avx2`, on CPUs with AVX2.
                unsafe { wide::node::<MASKED>(node, o, p, live, few, &cull, tmax, present) }
            } else {
                self.node_sse2(node, o, p, live, few, &cull, tmax, present)
            };
            #[cfg(not(target_arch = "x86_64"))]
            let (cm, hit) = self.node_sse2(node, o, p, live, few, &cull, tmax, present);
            // Inner children (imask, as obvhs's `is_leaf`) go on the stack; leaves are tested now.
            let mut kids = hit & node.imask as u32;
            while kids != 0 {
                let c = kids.trailing_zeros() as usize;
                kids &= kids - 1;
                let slot = (node.child_meta[c] & 0b11111) as u32 - 24;
                let idx = node.child_base_idx + (node.imask as u32 & !(u32::MAX << slot)).count_ones();
                stack.push((idx, cm[c]));
                prefetch_node(nodes, idx);
            }
            let mut leaves = hit & !(node.imask as u32);
            while leaves != 0 {
                let c = leaves.trailing_zeros() as usize;
                leaves &= leaves - 1;
                let meta = node.child_meta[c];
                let first = node.primitive_base_idx + (meta & 0b11111) as u32;
                for prim in first..first + (meta >> 5).count_ones() {
                    test(prim, cm[c] & !blocked, &mut blocked);
                }
                if blocked & all == all {
                    break 'walk;
                }
            }
            // No sorting by distance: it cost more in mispredicted branches than it saved (kitchen,
            // d = inf: 11.2 -> 12.2 M rays/s without it; the occluder cache finds most blockers).
        }
        cache.stack = stack;
        cache.len = found.len;
        cache.prims[..found.len].copy_from_slice(&found.prims[..found.len]);
        cache.counts[..found.len].copy_from_slice(&found.counts[..found.len]);
        cache.sort();
        blocked & all
    }
}

impl Accel {
    /// `wide::node` with SSE2, 4 children at a time: the same culling, the same answers.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    #[allow(clippy::needless_range_loop)] // h indexes the halves of six plane arrays
    fn node_sse2(
        &self,
        node: &obvhs::cwbvh::node::CwBvhNode,
        o: Vec3A,
        p: &Packet,
        live: u32,
        few: bool,
        cull: &Cull,
        tmax: f32,
        present: u32,
    ) -> ([u32; 8], u32) {
        let pl = child_planes(node, o);
        let (nx, ny, nz) = (Vec4::splat(cull.n[0]), Vec4::splat(cull.n[1]), Vec4::splat(cull.n[2]));
        let (slope2, reach2) = (Vec4::splat(cull.slope2), Vec4::splat(cull.reach2));
        // Shared by all rays: distance from the origin to each child box, whether the box reaches
        // above the rays' cone (`Horizon`), whether it holds the origin. Only culling aids (the
        // slab test alone is exact).
        let (mut near, mut inside) = (present, 0u32);
        if !few {
            near = 0;
            for h in 0..2 {
                let d2 = box_dist2(&pl, h);
                let support = (pl[0][h] * nx).max(pl[1][h] * nx)
                    + (pl[2][h] * ny).max(pl[3][h] * ny)
                    + (pl[4][h] * nz).max(pl[5][h] * nz);
                let above = support.cmpge(Vec4::ZERO) & (support * support).cmpge(slope2 * d2);
                near |= (d2.cmple(reach2) & above).bitmask() << (4 * h);
                inside |= d2.cmpeq(Vec4::ZERO).bitmask() << (4 * h);
            }
            (near, inside) = (near & present, inside & near & present);
        }
        let want = near & !inside;
        let mut cm = lanes::zero();
        if want != 0 {
            // Per ray: its slabs against the 8 children, 4 at a time.
            let mut rays = live;
            while rays != 0 {
                let i = rays.trailing_zeros() as usize;
                rays &= rays - 1;
                let hits = slabs(&pl, [p.inv[0][i], p.inv[1][i], p.inv[2][i]], tmax);
                lanes::add_ray(&mut cm, hits & want, i);
            }
        }
        let mut cm = lanes::to_array(cm);
        let mut hit = inside;
        for (c, m) in cm.iter_mut().enumerate() {
            if inside & (1 << c) != 0 {
                *m = live;
            }
            hit |= ((*m != 0) as u32) << c;
        }
        (cm, hit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packet_matches_single_rays_on_a_small_mesh() {
        // A unit cube with an open top, seen from inside: rays up escape, the others hit.
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let quad = |a: Vec3, b: Vec3, c: Vec3, d: Vec3| [[a, b, c], [a, c, d]];
        let mut tris = Vec::new();
        tris.extend(quad(v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)));
        tris.extend(quad(v(0., 0., 0.), v(0., 1., 0.), v(0., 1., 1.), v(0., 0., 1.)));
        tris.extend(quad(v(1., 0., 0.), v(1., 1., 0.), v(1., 1., 1.), v(1., 0., 1.)));
        tris.extend(quad(v(0., 0., 0.), v(1., 0., 0.), v(1., 0., 1.), v(0., 0., 1.)));
        tris.extend(quad(v(0., 1., 0.), v(1., 1., 0.), v(1., 1., 1.), v(0., 1., 1.)));
        let (acc, _) = Accel::build(&tris);
        let o = Vec3::new(0.3, 0.4, 0.5);
        let dirs: Vec<Vec3> = (0..70)
            .map(|i| {
                let (t, p) = (i as f32 * 0.37, i as f32 * 1.3);
                Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos()).normalize()
            })
            .collect();
        for tmax in [0.2, 0.45, f32::INFINITY] {
            let mut got = vec![false; dirs.len()];
            acc.occluded_from(o, None, &dirs, tmax, &mut got, &mut Occluders::new());
            for (d, g) in dirs.iter().zip(&got) {
                let want = acc.occluded(&Ray::new(o, *d, tmax));
                assert_eq!(*g, want, "dir {d} tmax {tmax}");
            }
        }
    }
}
