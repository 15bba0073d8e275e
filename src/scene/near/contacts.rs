//! The triangles that touch a triangle away from its edges: what stands on a floor, a shelf against
//! a wall, two meshes that cut through each other. Near its edges a triangle meets its own mesh's
//! neighbours, and `render::clearance` looks around the origin there (`Accel::near`, one walk down
//! the tree); away from them only these can pass within rounding of an origin lifted off it, and
//! they are few and fixed. So they are listed once per triangle, the first time a primary ray hits
//! it (most triangles never are: the kitchen's 320 x 240 view hits 1,929 of its 56,913), and a hit
//! away from the edges only looks up the few near it: most triangles have none (the kitchen: half
//! its pixels; a large one, its floor, thousands, which a grid sorts out: `grid`).

use super::grid::{Contact, Contacts, Grid};
use crate::scene::accel::{Accel, T_ERR};
use glam::{DVec3, Vec3, Vec3Swizzles};

/// The farthest `render::clearance` looks around an origin lifted off triangle `t` (vertices as
/// stored, in f64): twice a bound, anywhere on the triangle, on what it looks within (4 bands of
/// the triangle's plane, 4 ulps of the origin, 2^-21 of the edges), but never more than 2^-16 of
/// its size and distance from the eye. A sliver's band is large (the side of a slab 1e-4 thick and
/// 2 long, tilted: 0.01), and so is that of a neighbour it sees; moving the origin that far is no
/// longer a correction of rounding (in the slab it would cross the far face).
pub(crate) fn reach_cap(t: [DVec3; 3]) -> f64 {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let n = e1.cross(e2).length();
    let m = (e1.yzx() * e2.zxy()).abs() + (e1.zxy() * e2.yzx()).abs();
    let (lo, hi) = (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
    let band = T_ERR as f64 * (hi - lo).dot(m) / n.max(f64::MIN_POSITIVE);
    let ulp = lo.abs().max(hi.abs()).max_element() * (1.0 / 8_388_608.0) + f32::from_bits(1) as f64;
    let edges = e1.abs().max_element() + e2.abs().max_element();
    let bound = 2.0 * (4.0 * band + 4.0 * ulp * (1.0 + 1.0 / 1024.0) + edges * (1.0 / 2_097_152.0));
    let limit = (lo.abs().max(hi.abs()).max_element() + edges) * (1.0 / 65_536.0);
    bound.min(limit)
}

impl Contacts {
    /// Calls `f` with each contact, in BVH order, that may matter for a hit at barycentrics (`b`,
    /// `c`) seen from the side of the triangle's normal (`front`) or from the other: those that
    /// rise on that side and whose plane passes within `reach` of the hit point (and, for a long
    /// list, whose box does: `grid`).
    #[inline(always)]
    pub fn near_hit(&self, b: f32, c: f32, front: bool, mut f: impl FnMut(u32)) {
        let (bb, cc, side) = (b as f64, c as f64, !front as usize);
        // Slack for the rounding of the affine form against the renderer's own distances.
        let reach = self.reach * (1.0 + 1.0 / 1024.0);
        let mut test = |q: &Contact| {
            if q.rise[side] > 0.0 && (q.f[0] + q.f[1] * bb + q.f[2] * cc).abs() <= reach {
                f(q.prim);
            }
        };
        match &self.grid {
            None => self.list.iter().for_each(&mut test),
            Some(g) => g.cell(b, c).iter().for_each(|&k| test(&self.list[k as usize])),
        }
    }
}

impl Accel {
    /// The contacts of triangle `prim` (BVH slot), None if it has none: the triangles, one slot per
    /// input triangle, that come within `reach_cap` of its plane without lying in it, whose planes
    /// and boxes come within it of the triangle, and whose part that near its plane reaches, seen
    /// along its normal, the part of the triangle that `render::clearance` leaves to them (`Inner`:
    /// farther from the edges than it looks around the origin). A neighbour in its mesh, beyond an
    /// edge or a vertex, does not.
    pub(crate) fn contacts(&self, prim: u32) -> Option<&Contacts> {
        self.contacts[prim as usize].get_or_init(|| self.find_contacts(prim)).as_deref()
    }

    fn find_contacts(&self, prim: u32) -> Option<Box<Contacts>> {
        let t = self.triangle(prim).map(Vec3::as_dvec3);
        let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
        let unit = e1.cross(e2).try_normalize()?;
        let reach = reach_cap(t);
        let (lo, hi) = (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
        let (mut found, mut stack) = (Vec::new(), Vec::new());
        // The box in f32 around its rounded centre: widened by more than that rounding.
        let centre = (lo + hi) * 0.5;
        let half = ((hi - lo) * 0.5 + reach + centre.abs() * (1.0 / 4_194_304.0)) * (1.0 + 1.0 / 1_048_576.0);
        self.near(centre.as_vec3(), half.as_vec3(), &mut found, &mut stack);
        found.sort_unstable();
        let (mut list, mut boxes) = (Vec::new(), Vec::new());
        let own = self.source_index(prim);
        let inner = Inner::of(t, reach);
        for j in found {
            let v = self.triangle(j).map(Vec3::as_dvec3);
            let s = v.map(|x| unit.dot(x - t[0]));
            let off = [s[0].min(s[1]).min(s[2]), s[0].max(s[1]).max(s[2])];
            let (lj, hj) = (v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2]));
            let touches = off[0] <= reach && off[1] >= -reach && (off[0] != 0.0 || off[1] != 0.0);
            let boxed = (lj - hi).max_element() <= reach && (lo - hj).max_element() <= reach;
            if !(touches && boxed) || j == prim || self.source_index(j) == own {
                continue;
            }
            // Near the edges only (a neighbour of its mesh, or one like it): the look around the
            // origin there finds it. Whole first (most neighbours lie beyond an edge), then the part
            // near the plane.
            if !inner.meets(&Polygon { v: [v[0], v[1], v[2], v[0], v[0]], len: 3 }) {
                continue;
            }
            let Some(uj) = (v[1] - v[0]).cross(v[2] - v[0]).try_normalize() else { continue };
            let cut = t.map(|x| uj.dot(x - v[0]));
            if cut.iter().all(|&d| d > reach) || cut.iter().all(|&d| d < -reach) {
                continue; // its plane passes beside the triangle
            }
            let Some(part) = clipped(v, s, reach) else { continue };
            if !inner.meets(&part) {
                continue;
            }
            let clip = part.bounds();
            let f = [uj.dot(t[0] - v[0]), uj.dot(e1), uj.dot(e2)];
            list.push(Contact { prim: j, f, rise: [off[1], -off[0]] });
            boxes.push(clip);
        }
        if self.bvh.uses_spatial_splits {
            // One slot per input triangle (spatial splits put one in several): the first.
            let mut keep: Vec<usize> = (0..list.len()).collect();
            keep.sort_unstable_by_key(|&k| (self.source_index(list[k].prim), list[k].prim));
            keep.dedup_by_key(|k| self.source_index(list[*k].prim));
            keep.sort_unstable();
            list = keep.iter().map(|&k| list[k]).collect();
            boxes = keep.iter().map(|&k| boxes[k]).collect();
        }
        if list.is_empty() {
            return None;
        }
        let grid = Grid::of(t, reach, &list, &boxes);
        Some(Box::new(Contacts { reach, list: list.into_boxed_slice(), grid }))
    }
}

/// A convex polygon of at most 5 vertices.
#[derive(Debug, Clone, Copy)]
struct Polygon {
    v: [DVec3; 5],
    len: usize,
}

impl Polygon {
    /// Its box, widened by a rounding's worth.
    fn bounds(&self) -> (DVec3, DVec3) {
        let (lo, hi) = self.v[..self.len]
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), &p| (l.min(p), h.max(p)));
        let slack = lo.abs().max(hi.abs()).max_element() * (1.0 / 1_099_511_627_776.0);
        (lo - slack, hi + slack)
    }
}

/// The part of triangle `v` within `r` of a plane (`s`: its vertices' signed distances from it),
/// or None if no part is.
fn clipped(v: [DVec3; 3], s: [f64; 3], r: f64) -> Option<Polygon> {
    // Sutherland-Hodgman against s <= r, then s >= -r: at most 5 vertices.
    let mut poly = [(DVec3::ZERO, 0.0f64); 5];
    for k in 0..3 {
        poly[k] = (v[k], s[k]);
    }
    let mut len = 3;
    for sign in [1.0, -1.0] {
        let mut out = [(DVec3::ZERO, 0.0f64); 5];
        let mut n = 0;
        for k in 0..len {
            let (p, sp) = poly[k];
            let (q, sq) = poly[(k + 1) % len];
            let (dp, dq) = (sign * sp - r, sign * sq - r);
            if dp <= 0.0 && n < 5 {
                out[n] = (p, sp);
                n += 1;
            }
            if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) && n < 5 {
                let w = dp / (dp - dq);
                out[n] = (p + (q - p) * w, sp + (sq - sp) * w);
                n += 1;
            }
        }
        (poly, len) = (out, n);
    }
    (len > 0).then(|| Polygon { v: poly.map(|p| p.0), len })
}

/// The part of a triangle that `render::clearance` leaves to its contacts: the points farther from
/// every edge than it looks around the origin there (16 times its reach, never less than 4 ulps of
/// the nearest coordinates to the eye and 2^-21 of the edges), less the greatest reach (`cap`:
/// how far from the plane and from a point a contact still counts). In barycentric coordinates
/// (b, c), with the map from space onto them.
struct Inner {
    a: DVec3,
    e1: DVec3,
    e2: DVec3,
    g: [f64; 3],
    det: f64,
    /// The shrunk triangle's corners in (b, c); None if nothing is left of it.
    corners: Option<[[f64; 2]; 3]>,
}

impl Inner {
    fn of(t: [DVec3; 3], cap: f64) -> Self {
        let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
        let (lo, hi) = (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
        // The smallest largest coordinate of a point of the box (the ulp the reach is least at).
        let nearest = DVec3::ZERO.clamp(lo, hi).abs().max_element();
        let edges = e1.abs().max_element() + e2.abs().max_element();
        let least = 4.0 * nearest * (1.0 / 8_388_608.0) + edges * (1.0 / 2_097_152.0);
        let depth = 16.0 * least * (1.0 - 1.0 / 1024.0) - 0.5 * cap;
        let area2 = e1.cross(e2).length();
        // Barycentric k at least depth / height_k.
        let [sa, sb, sc] = [(t[2] - t[1]).length(), e2.length(), e1.length()].map(|l| depth * l / area2);
        let corners = (sa + sb + sc < 1.0 && sa.is_finite() && sb.is_finite() && sc.is_finite()).then_some([
            [sb, sc],
            [1.0 - sa - sc, sc],
            [sb, 1.0 - sa - sb],
        ]);
        let g = [e1.dot(e1), e1.dot(e2), e2.dot(e2)];
        Inner { a: t[0], e1, e2, g, det: g[0] * g[2] - g[1] * g[1], corners }
    }

    /// (b, c) of the projection of x onto the triangle's plane.
    fn bary(&self, x: DVec3) -> [f64; 2] {
        let (r1, r2) = (self.e1.dot(x - self.a), self.e2.dot(x - self.a));
        [(self.g[2] * r1 - self.g[1] * r2) / self.det, (self.g[0] * r2 - self.g[1] * r1) / self.det]
    }

    /// Whether the projection of `part` meets the shrunk triangle (separating axes: the edges of
    /// both; a degenerate map counts as meeting).
    fn meets(&self, part: &Polygon) -> bool {
        let Some(tri) = self.corners else { return false };
        let mut poly = [[0.0; 2]; 5];
        for (q, &x) in poly.iter_mut().zip(&part.v[..part.len]) {
            *q = self.bary(x);
        }
        let poly = &poly[..part.len];
        if poly.iter().flatten().any(|x| !x.is_finite()) {
            return true;
        }
        // The shrunk triangle's own sides first, in barycentrics: b >= b0, c >= c0, b + c <= s.
        let ([b0, c0], s) = (tri[0], tri[1][0] + tri[1][1]);
        if poly.iter().all(|x| x[0] < b0)
            || poly.iter().all(|x| x[1] < c0)
            || poly.iter().all(|x| x[0] + x[1] > s)
        {
            return false;
        }
        let span = |pts: &[[f64; 2]], axis: [f64; 2]| {
            pts.iter().fold((f64::MAX, f64::MIN), |(l, h), x| {
                let d = x[0] * axis[0] + x[1] * axis[1];
                (l.min(d), h.max(d))
            })
        };
        let separates = |pts: &[[f64; 2]], k: usize| {
            let (p, q) = (pts[k], pts[(k + 1) % pts.len()]);
            let axis = [q[1] - p[1], p[0] - q[0]];
            let ((l1, h1), (l2, h2)) = (span(&tri, axis), span(poly, axis));
            axis != [0.0, 0.0] && (h1 < l2 || h2 < l1)
        };
        !((0..3).any(|k| separates(&tri, k)) || (0..poly.len()).any(|k| separates(poly, k)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closed cubes of side 0.2 (12 triangles) standing at `spots` on a 4 x 4 floor at z = 0 (2
    /// triangles, listed first).
    fn cubes_on_a_floor(spots: &[(f32, f32)]) -> Vec<[Vec3; 3]> {
        let v = Vec3::new;
        let quad = |a: Vec3, b: Vec3, c: Vec3, d: Vec3| [[a, b, c], [a, c, d]];
        let mut tris = quad(v(-2., -2., 0.), v(2., -2., 0.), v(2., 2., 0.), v(-2., 2., 0.)).to_vec();
        for &(x, y) in spots {
            let p = |i: f32, j: f32, k: f32| v(x + 0.2 * i, y + 0.2 * j, 0.2 * k);
            let faces = [
                [p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.), p(0., 1., 0.)],
                [p(0., 0., 1.), p(1., 0., 1.), p(1., 1., 1.), p(0., 1., 1.)],
                [p(0., 0., 0.), p(1., 0., 0.), p(1., 0., 1.), p(0., 0., 1.)],
                [p(0., 1., 0.), p(1., 1., 0.), p(1., 1., 1.), p(0., 1., 1.)],
                [p(0., 0., 0.), p(0., 1., 0.), p(0., 1., 1.), p(0., 0., 1.)],
                [p(1., 0., 0.), p(1., 1., 0.), p(1., 1., 1.), p(1., 0., 1.)],
            ];
            tris.extend(faces.iter().flat_map(|f| quad(f[0], f[1], f[2], f[3])));
        }
        tris
    }

    /// Barycentrics (b, c) of floor point (x, y) on BVH triangle `prim`, if it is inside.
    fn bary(acc: &Accel, prim: u32, x: f32, y: f32) -> Option<(f32, f32)> {
        let [a, b, c] = acc.triangle(prim).map(Vec3::as_dvec3);
        let (e1, e2, q) = (b - a, c - a, DVec3::new(x as f64, y as f64, 0.0) - a);
        let det = e1.x * e2.y - e1.y * e2.x;
        let (u, w) = ((q.x * e2.y - q.y * e2.x) / det, (e1.x * q.y - e1.y * q.x) / det);
        (u >= 0.0 && w >= 0.0 && u + w <= 1.0).then_some((u as f32, w as f32))
    }

    /// The floor's contacts are the cubes' side faces (not their bottoms, in its plane; no cube
    /// corner is on the floor's diagonal, near which `render::clearance` looks around instead); a
    /// hit at the foot of a face is near the triangle there, one in the open is near none.
    /// With one cube the list is scanned, with nine it has a grid: the same answers.
    #[test]
    fn what_stands_on_a_floor_is_near_its_foot_only() {
        for spots in [
            &[(0.3f32, -0.5f32)][..],
            &[
                (0.3, -0.5),
                (-1.2, 0.9),
                (1.1, 1.45),
                (-0.4, -1.5),
                (0.9, 0.2),
                (-1.6, -0.2),
                (0.0, 1.6),
                (1.5, -1.4),
                (-0.9, 0.1),
            ],
        ] {
            let tris = cubes_on_a_floor(spots);
            let (acc, _) = Accel::build(&tris);
            let floor: Vec<u32> = (0..acc.len() as u32).filter(|&p| acc.source_index(p) < 2).collect();
            let sides = |src: u32| src >= 2 && ((src - 2) % 12) >= 4;
            for &f in &floor {
                let Some(c) = acc.contacts(f) else { continue };
                assert!(c.list.iter().all(|q| sides(acc.source_index(q.prim))), "only side faces");
                assert_eq!(c.grid.is_some(), c.list.len() > 8);
            }
            let mut all: Vec<u32> = floor
                .iter()
                .filter_map(|&f| acc.contacts(f))
                .flat_map(|c| c.list.iter().map(|q| acc.source_index(q.prim)))
                .collect();
            all.sort();
            all.dedup();
            let missing: Vec<u32> =
                (2..tris.len() as u32).filter(|&s| sides(s) && !all.contains(&s)).collect();
            assert!(missing.is_empty(), "{} cubes: side triangles {missing:?} missing", spots.len());
            for &(x, y) in spots {
                // Just outside the foot of the face x = x0 (the cube's side faces 4, 5 are x = const).
                for (px, py, face) in [(x - 1e-6, y + 0.1, 4u32), (x + 0.2 + 1e-6, y + 0.07, 5)] {
                    let (f, (b, c)) = floor.iter().find_map(|&f| Some((f, bary(&acc, f, px, py)?))).unwrap();
                    let mut near = Vec::new();
                    acc.contacts(f).unwrap().near_hit(b, c, true, |j| near.push(acc.source_index(j)));
                    acc.contacts(f).unwrap().near_hit(b, c, false, |j| near.push(acc.source_index(j)));
                    let k = spots.iter().position(|s| *s == (x, y)).unwrap() as u32;
                    // The face's first triangle holds its foot (the second meets the floor at a corner).
                    let want = 2 + 12 * k + 2 * face;
                    assert!(near.contains(&want), "({px}, {py}): {near:?} lacks {want}");
                }
            }
            for (px, py) in [(-1.9f32, 1.9f32), (1.9, -0.8)] {
                let (f, (b, c)) = floor.iter().find_map(|&f| Some((f, bary(&acc, f, px, py)?))).unwrap();
                if let Some(c0) = acc.contacts(f) {
                    let mut n = 0;
                    c0.near_hit(b, c, true, |_| n += 1);
                    assert_eq!(n, 0, "({px}, {py}) is in the open");
                }
            }
        }
    }
}
