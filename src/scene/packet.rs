//! A pixel's AO rays traced together: they share their origin, so one walk of the 8-wide tree
//! serves up to 32 of them. Per node, what depends only on the origin is done once (child planes
//! relative to the origin, the distance from the origin to each child box, whether it contains the
//! origin); only the slab test is per ray, 4 rays per SSE register. Per triangle, `Seen` is done
//! once and each ray costs 4 dot products. The answers are bit-for-bit those of `Accel::occluded`:
//! same triangle arithmetic; the box tests here are padded, so they cull a subset of what exact
//! boxes would (and never a box holding a hit the triangle test reports).

use super::accel::{Accel, Seen, safe_inv};
use glam::{Vec3, Vec3A, Vec4};
use obvhs::cwbvh::node::CwBvhNode;

/// Rays per packet.
pub const PACKET: usize = 32;
const GROUPS: usize = PACKET / 4;

/// 7 siblings per level over obvhs's maximum depth of 32, plus the 8 children of the last node.
const STACK: usize = 256;

struct Packet {
    d: [[Vec4; GROUPS]; 3],
    inv: [[Vec4; GROUPS]; 3],
}

impl Packet {
    fn new(dirs: &[Vec3]) -> Self {
        let mut d = [[0.0f32; PACKET]; 3];
        for (i, v) in dirs.iter().enumerate() {
            let v = *v + Vec3::ZERO; // -0.0 → +0.0, exactly as `Ray::new`
            d[0][i] = v.x;
            d[1][i] = v.y;
            d[2][i] = v.z;
        }
        let lanes = |a: &[f32; PACKET], f: fn(f32) -> f32| {
            std::array::from_fn(|g| Vec4::new(f(a[4 * g]), f(a[4 * g + 1]), f(a[4 * g + 2]), f(a[4 * g + 3])))
        };
        let id = |x| x;
        Self {
            d: [lanes(&d[0], id), lanes(&d[1], id), lanes(&d[2], id)],
            inv: [lanes(&d[0], safe_inv), lanes(&d[1], safe_inv), lanes(&d[2], safe_inv)],
        }
    }
}

#[inline(always)]
fn q4(v: &[u8; 8], h: usize) -> Vec4 {
    Vec4::new(v[4 * h] as f32, v[4 * h + 1] as f32, v[4 * h + 2] as f32, v[4 * h + 3] as f32)
}

/// The 8 child boxes of `node` relative to `o`, padded outwards by 2^-18 of their extent from `o`
/// (far more than the rounding of the planes and of the triangle test's edge values).
#[inline(always)]
fn child_planes(node: &CwBvhNode, o: Vec3A) -> [[f32; 8]; 6] {
    let e = node.compute_extent();
    let rel = Vec3A::from(node.p) - o;
    let pad = (rel.abs() + e * 255.0) * (1.0 / 262144.0);
    let mut out = [[0.0f32; 8]; 6];
    let axes = [
        (&node.child_min_x, &node.child_max_x, rel.x, e.x, pad.x),
        (&node.child_min_y, &node.child_max_y, rel.y, e.y, pad.y),
        (&node.child_min_z, &node.child_max_z, rel.z, e.z, pad.z),
    ];
    for (k, (lo, hi, r, e, p)) in axes.into_iter().enumerate() {
        for h in 0..2 {
            let l = Vec4::splat(r - p) + q4(lo, h) * e;
            let u = Vec4::splat(r + p) + q4(hi, h) * e;
            out[2 * k][4 * h..4 * h + 4].copy_from_slice(&l.to_array());
            out[2 * k + 1][4 * h..4 * h + 4].copy_from_slice(&u.to_array());
        }
    }
    out
}

/// Which lanes of group `g` hit `s` within (0, tmax): the vector form of `accel::hit_seen`.
#[inline(always)]
fn hit_group(p: &Packet, g: usize, s: &Seen, tmax: f32) -> u32 {
    let (dx, dy, dz) = (p.d[0][g], p.d[1][g], p.d[2][g]);
    let dotv = |q: [f32; 3]| (dx * Vec4::splat(q[0]) + dy * Vec4::splat(q[1])) + dz * Vec4::splat(q[2]);
    let (u, v, w) = (dotv(s.x), dotv(s.y), dotv(s.z));
    let z = Vec4::ZERO;
    let neg = u.cmplt(z) | v.cmplt(z) | w.cmplt(z);
    let pos = u.cmpgt(z) | v.cmpgt(z) | w.cmpgt(z);
    let dn = dotv(s.n);
    let t = Vec4::splat(s.t) / dn;
    let sum = (u + v) + w;
    let hit = !(neg & pos) & dn.cmpne(z) & t.cmpgt(z) & t.cmplt(Vec4::splat(tmax)) & sum.cmpne(z);
    hit.bitmask()
}

impl Accel {
    /// For each of `dirs` (any number; rays from `origin`), whether something lies on it with
    /// 0 < t < tmax: the same answers as `occluded` on each ray, traced 32 at a time.
    pub fn occluded_from(&self, origin: Vec3, dirs: &[Vec3], tmax: f32, blocked: &mut [bool]) {
        for (chunk, out) in dirs.chunks(PACKET).zip(blocked.chunks_mut(PACKET)) {
            let mask = self.occluded_packet(origin.into(), chunk, tmax);
            for (i, b) in out.iter_mut().enumerate() {
                *b = (mask >> i) & 1 != 0;
            }
        }
    }

    /// Bit i set: ray i (of at most 32) is blocked.
    fn occluded_packet(&self, o: Vec3A, dirs: &[Vec3], tmax: f32) -> u32 {
        let nodes = &self.bvh.nodes;
        if dirs.is_empty() || nodes.is_empty() {
            return 0;
        }
        let all = if dirs.len() >= 32 { u32::MAX } else { (1u32 << dirs.len()) - 1 };
        let p = Packet::new(dirs);
        // Nothing farther than d from the origin can be hit (|dir| = 1 up to rounding; keep slack).
        let reach2 = {
            let r = tmax * (1.0 + 1.0 / 1024.0);
            r * r
        };
        let widen = Vec4::splat(1.0 + 8.0 * f32::EPSILON);
        let tmax4 = Vec4::splat(tmax);
        let mut blocked = 0u32;
        let mut stack = [(0u32, 0u32); STACK];
        stack[0] = (0, all);
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let (ni, m) = stack[sp];
            let m = m & !blocked;
            if m == 0 {
                continue;
            }
            let node = &nodes[ni as usize];
            let planes = child_planes(node, o);
            let mut inner: [(f32, u32, u32); 8] = [(0.0, 0, 0); 8];
            let mut n_inner = 0;
            for c in 0..8 {
                let meta = node.child_meta[c];
                if meta == 0 {
                    continue;
                }
                let (lx, hx, ly, hy, lz, hz) =
                    (planes[0][c], planes[1][c], planes[2][c], planes[3][c], planes[4][c], planes[5][c]);
                let gap = |l: f32, h: f32| l.max(-h).max(0.0);
                let (gx, gy, gz) = (gap(lx, hx), gap(ly, hy), gap(lz, hz));
                let dist2 = gx * gx + gy * gy + gz * gz;
                if dist2 > reach2 {
                    continue;
                }
                let live = m & !blocked;
                let cm = if dist2 == 0.0 {
                    live // the box holds the origin: every ray starts inside it
                } else {
                    let mut cm = 0u32;
                    let (l, h) = ([lx, ly, lz], [hx, hy, hz]);
                    for g in 0..GROUPS {
                        let gm = (live >> (4 * g)) & 0xf;
                        if gm == 0 {
                            continue;
                        }
                        let mut tn = Vec4::ZERO;
                        let mut tf = tmax4;
                        for k in 0..3 {
                            let t0 = Vec4::splat(l[k]) * p.inv[k][g];
                            let t1 = Vec4::splat(h[k]) * p.inv[k][g];
                            tn = tn.max(t0.min(t1));
                            tf = tf.min(t0.max(t1));
                        }
                        cm |= (tn.cmple(tf * widen).bitmask() & gm) << (4 * g);
                    }
                    cm
                };
                if cm == 0 {
                    continue;
                }
                let slot = (meta & 0b11111) as u32;
                if slot >= 24 {
                    let idx = node.child_base_idx + (node.imask as u32 & !(u32::MAX << (slot - 24))).count_ones();
                    inner[n_inner] = (dist2, idx, cm);
                    n_inner += 1;
                    continue;
                }
                let first = node.primitive_base_idx + slot;
                for prim in first..first + (meta >> 5).count_ones() {
                    let s = self.tris[prim as usize].seen_from(o);
                    let live = cm & !blocked;
                    for g in 0..GROUPS {
                        let gm = (live >> (4 * g)) & 0xf;
                        if gm != 0 {
                            blocked |= (hit_group(&p, g, &s, tmax) & gm) << (4 * g);
                        }
                    }
                    if blocked & all == all {
                        return all;
                    }
                }
            }
            // Nearest child on top of the stack: near boxes are the likeliest to block.
            let inner = &mut inner[..n_inner];
            inner.sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
            for &(_, idx, cm) in inner.iter() {
                stack[sp] = (idx, cm);
                sp += 1;
            }
        }
        blocked & all
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
            acc.occluded_from(o, &dirs, tmax, &mut got);
            for (d, g) in dirs.iter().zip(&got) {
                let want = acc.occluded(&super::super::accel::Ray::new(o, *d, tmax));
                assert_eq!(*g, want, "dir {d} tmax {tmax}");
            }
        }
    }
}
