//! The AO origin off every surface it lies on, not only off the triangle the primary ray hit
//!.
//!
//! `offset` lifts the origin off the hit triangle by a bound on the hit point's own error (pbrt-v4's
//! `OffsetRayOrigin`: Pharr, Jakob, Humphreys, "Physically Based Rendering", 4th ed., 6.8). Where
//! the primary ray hits an edge or a corner, other triangles pass through the hit point (or within
//! rounding of it): a wall meeting the floor. The lift, along the floor's normal, leaves the origin
//! on the wall's plane, where the triangle test cannot tell the side and so reports no hit
//! (`scene::accel::Seen`; pbrt's test likewise discards hits within its error bound of t = 0), or
//! even behind it, and about half the AO rays leave the room through the wall: a closed cube seen
//! by a centred camera had 18-22 such pixels at 1 ray and 36 at 32 rays out of 320 x 240, and they
//! are the darkest places of the image turned bright. So the origin is moved further, out of the
//! rounding band of every such neighbour, to the side the primary ray came from, and the move is
//! checked with the triangle test itself.
//!
//! Which neighbours ("walls"): triangles within a few bands of the origin (`reach`) whose plane
//! passes that near it and that rise in front of the hit triangle's plane (a triangle behind it or
//! in it, such as the other half of a quad or the far face of a convex edge, cannot be reached by
//! rays that leave the hit triangle's front). Near the hit triangle's edges, where its mesh's
//! neighbours meet it, they are looked for around the origin (`Accel::near`); elsewhere only among
//! the triangle's contacts (`scene::near::contacts`, listed once per triangle), so that a pixel in
//! the middle of a triangle with no contact (most pixels) costs one test of its barycentrics and
//! keeps its origin bit for bit.
//!
//! Which side is right: the primary ray's origin's (the eye's). The primary ray reached the hit
//! point through free space, and a segment that ends on a plane lies on one side of it, so the
//! eye's side of each plane through the hit point is the side the ray arrived on. Where the eye
//! itself is within rounding of the plane (a camera in the plane of a wall, looking along it), the
//! side of the hit triangle's body: the room's inside for a wall that meets it at a concave edge
//! (for a fin standing on it, either side is free).
//!
//! Limits: a sliver's plane is uncertain over a long way (`scene::near::reach_cap`), and the
//! origin is not moved farther than a small multiple of its own rounding, so a sliver is not
//! cleared; and a ray within about 1e-6 rad of parallel to a wall is never hit by it (`Seen`), so
//! from an origin that near the wall it may still pass through (the one ray of 1e8 uniform ones
//! that a sweep of rooms turned at random still lost leaves from the unmoved origin too).

use super::offset::{Lift, Plane, away};
use crate::scene::Accel;
use crate::scene::accel::T_ERR;
use glam::{DVec3, Vec3, Vec3Swizzles};

/// Scratch (kept per pixel loop, so nothing is allocated per pixel): the triangles near the
/// origin, the walk's stack and the neighbours that matter.
#[derive(Debug, Clone, Default)]
pub(super) struct Near {
    found: Vec<u32>,
    prims: Vec<u32>,
    stack: Vec<u32>,
    walls: Vec<Wall>,
}

/// A neighbour the origin must be on the right side of, where the triangle test can see it.
#[derive(Debug, Clone, Copy)]
struct Wall {
    prim: u32,
    /// The triangle's first vertex (as stored) and the unit normal of (b - a) × (c - a), in f64.
    a: DVec3,
    unit: DVec3,
    /// M / |N| (`Plane::m_over_n`).
    m_over_n: DVec3,
    /// The side the origin must be on: true for `unit`'s.
    positive: bool,
}

/// T_ERR Σ |a_i - x_i| M_i / |N|: the triangle test cannot tell which side of the plane (first
/// vertex a) a point x is on within about this distance of it (it needs |T| > T_ERR Σ |A_i| M_i,
/// see `Seen`).
fn band(a: DVec3, m_over_n: DVec3, x: DVec3) -> f64 {
    T_ERR as f64 * (a - x).abs().dot(m_over_n)
}

/// An ulp of the largest coordinate of x (f32), and then some.
fn ulp(x: DVec3) -> f64 {
    x.abs().max_element() * (1.0 / 8_388_608.0) + f32::from_bits(1) as f64
}

impl Wall {
    /// Triangle `prim` (vertices `v` as stored) in f64; None if it has no normal there.
    fn of(prim: u32, v: [DVec3; 3]) -> Option<Self> {
        let (e1, e2) = (v[1] - v[0], v[2] - v[0]);
        let n = e1.cross(e2);
        let m = (e1.yzx() * e2.zxy()).abs() + (e1.zxy() * e2.yzx()).abs();
        let unit = n.try_normalize()?;
        Some(Wall { prim, a: v[0], unit, m_over_n: m / n.length(), positive: true })
    }

    /// The unit normal on the right side.
    fn nu(&self) -> DVec3 {
        if self.positive { self.unit } else { -self.unit }
    }

    /// How far past the plane, on the right side, x must be for the test to see it there: twice
    /// the band (the computed T is off by up to one band) plus an ulp of each coordinate (rounding
    /// the origin to f32), with room to spare for the rounding of the bounds themselves.
    fn needs(&self, x: DVec3) -> f64 {
        2.0 * band(self.a, self.m_over_n, x) * (1.0 + 1.0 / 1024.0) + ulp(x) * self.unit.abs().element_sum()
    }

    /// How far from its plane and the hit triangle's, so from the edge they share, the origin must
    /// be for the triangle test's edge functions (from the origin, `Seen`) to tell the side of a
    /// ray that passes that edge at more than 2^-7 rad: their rounding, about 4u |a - x| |e|, over
    /// |e| times the distance to the edge, which the band (12u |a - x| M / |N|, M >= |N|) bounds
    /// as 32 bands give 2^-7. Nearer, a ray grazing one wall towards the edge may be judged to
    /// miss both walls (rotated rooms, uniform rays: 8 of 1e8 left through edges without it).
    fn edge(&self, x: DVec3) -> f64 {
        32.0 * band(self.a, self.m_over_n, x)
    }
}

/// Rounds of pushing before giving up (a round that finds a wall still unseen from as far as asked
/// doubles the distance asked).
const ROUNDS: i32 = 6;

/// The origin of `lift` (lifted off BVH triangle `prim`, of plane `plane`, at barycentrics
/// `bary`), moved where needed so that every neighbour whose plane it lies on is seen from the side
/// the primary ray came from. `eye`: the primary ray's origin. Almost every pixel is done after
/// the first test: away from the edges, with no contact there.
#[inline(always)]
pub(super) fn clear(
    acc: &Accel,
    prim: u32,
    bary: (f32, f32),
    plane: &Plane,
    lift: &Lift,
    eye: Vec3,
    near: &mut Near,
) -> Vec3 {
    let (b, c) = (bary.0 as f64, bary.1 as f64);
    let (a, z) = (1.0 - b - c, plane.edge_zone);
    near.prims.clear();
    // Not `>`: NaN (a triangle with no area in f64) counts as near an edge.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    let inside = a * a > z.x && b * b > z.y && c * c > z.z;
    if !inside {
        around(acc, prim, plane, lift, near);
    } else if let Some(contacts) = acc.contacts(prim) {
        // Away from the edges only contacts can be that near (`scene::near::contacts`).
        let front = lift.n64.dot(plane.n64) > 0.0;
        contacts.near_hit(bary.0, bary.1, front, |j| near.prims.push(j));
    } else {
        return lift.origin;
    }
    if near.prims.is_empty() {
        return lift.origin;
    }
    resolve(acc, prim, plane, lift, eye, near)
}

/// How far around the origin to look: a few bands of the hit triangle (a measure of its
/// neighbours' at this size, and of how far the origin is from the hit point), a few ulps of the
/// origin and a little of the edges (the barycentrics' rounding along the surface). Triangles and
/// planes farther away are seen from the origin as they are, or only by rays within a sliver of
/// their plane. At most half `Plane::cap` (`scene::near::reach_cap`).
fn reach(plane: &Plane, lift: &Lift) -> f64 {
    let edges = plane.e1.abs().max_element() + plane.e2.abs().max_element();
    let r = 4.0 * band(plane.a, plane.m_over_n, lift.p)
        + 4.0 * ulp(lift.origin.as_dvec3())
        + edges * (1.0 / 2_097_152.0);
    r.min(0.5 * plane.cap)
}

/// Near an edge or a vertex (`Plane::edge_zone`: within 16 times the greatest reach), where the
/// neighbours of its mesh meet the hit triangle (one rising at more than 1/16 rad passes within
/// reach of the plane only within 16 reach of the edge; through a shallower one, only rays within
/// that angle of the surface could leave): the triangles around the origin whose plane passes near
/// it, into `near.prims`.
#[cold]
fn around(acc: &Accel, prim: u32, plane: &Plane, lift: &Lift, near: &mut Near) {
    let (r, cap) = (reach(plane, lift) as f32, plane.cap as f32);
    acc.near(lift.origin, Vec3::splat(r), &mut near.found, &mut near.stack);
    near.prims.extend(near.found.iter().filter(|&&j| j != prim && acc.plane_near(j, lift.origin, cap)));
}

/// The origin moved off the walls among `near.prims` (see `wall`), or left as it is.
#[cold]
fn resolve(acc: &Accel, prim: u32, plane: &Plane, lift: &Lift, eye: Vec3, near: &mut Near) -> Vec3 {
    let reach = reach(plane, lift);
    near.walls.clear();
    for &j in &near.prims {
        if let Some(w) = wall(acc, j, plane, lift, eye, reach) {
            near.walls.push(w);
        }
    }
    if near.walls.is_empty() {
        return lift.origin;
    }
    push(acc, prim, plane, lift, lift.origin, &near.walls)
}

/// Triangle `j` as a wall to clear, if it matters (see the module's doc): on the side the primary
/// ray came from.
#[cold]
fn wall(acc: &Accel, j: u32, plane: &Plane, lift: &Lift, eye: Vec3, reach: f64) -> Option<Wall> {
    let v = acc.triangle(j).map(Vec3::as_dvec3);
    let o = lift.origin.as_dvec3();
    // It comes within reach of the origin, and rises in front of the hit triangle's plane (rays
    // leave from its front).
    let (lo, hi) = (v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2]));
    let rise = v.iter().map(|&x| lift.n64.dot(x - lift.p)).fold(f64::MIN, f64::max);
    if !((lo - o).max_element() <= reach && (o - hi).max_element() <= reach && rise > reach) {
        return None;
    }
    let mut w = Wall::of(j, v)?;
    let resolvable = w.needs(o) <= 0.5 * plane.cap;
    if !resolvable {
        return None; // a sliver: the test cannot see it from any origin this near (`reach_cap`)
    }
    // Its plane passes within a few of its own bands (and the hit triangle's) of the hit point
    // (not `>`: a NaN distance must fail too).
    let near = 4.0 * (band(w.a, w.m_over_n, o) + band(plane.a, plane.m_over_n, lift.p)) + 16.0 * ulp(o);
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    if !(w.unit.dot(lift.p - w.a).abs() <= near.max(reach).min(plane.cap)) {
        return None;
    }
    let e = eye.as_dvec3();
    let from_eye = w.unit.dot(e - w.a);
    w.positive = if from_eye.abs() > 2.0 * band(w.a, w.m_over_n, e) {
        from_eye > 0.0
    } else {
        // The eye in the plane: the side of the hit triangle's vertex farthest from it.
        let body = [plane.a, plane.a + plane.e1, plane.a + plane.e2].map(|x| w.unit.dot(x - w.a));
        let far = body.into_iter().fold(0.0f64, |m, d| if d.abs() > m.abs() { d } else { m });
        if far.abs() > reach { far > 0.0 } else { w.unit.dot(lift.n64) > 0.0 }
    };
    Some(w)
}

/// `o` moved until the test sees every wall from its right side, and every wall's plane and the
/// hit triangle's are as far from it as the farthest wall asks (`Wall::needs`, `Wall::edge`); left
/// where it is if that would take it farther than 64 `Plane::cap` (the distance asked over the
/// sine of half the angle at which two walls meet: room for 10° and more) or through any other
/// surface (the far face of a thin slab).
#[cold]
fn push(acc: &Accel, prim: u32, plane: &Plane, lift: &Lift, start: Vec3, walls: &[Wall]) -> Vec3 {
    let o = moved(acc, plane, lift, start, walls);
    let d = (o - start).as_dvec3();
    if d.abs().max_element() > 64.0 * plane.cap {
        return start;
    }
    let Some(dir) = d.try_normalize() else { return o };
    let (dir, len) = (dir.as_vec3(), (d.length() * (1.0 + 1.0 / 1024.0)) as f32);
    let (mut found, mut stack) = (Vec::new(), Vec::new());
    let mid = (start.as_dvec3() + d * 0.5).as_vec3();
    acc.near(mid, Vec3::splat(len), &mut found, &mut stack);
    let cleared = |j: u32| {
        let src = acc.source_index(j);
        j == prim || walls.iter().any(|w| acc.source_index(w.prim) == src)
    };
    if found.iter().any(|&j| !cleared(j) && acc.blocks(j, start, dir, len)) { start } else { o }
}

/// `push` before its checks. Each round moves along the sum of the unit normals of the planes
/// still too near (turned, if need be, so as not to approach the hit triangle's plane), far enough
/// for each, rounded away from the hit triangle as `offset` rounds.
fn moved(acc: &Accel, plane: &Plane, lift: &Lift, mut o: Vec3, walls: &[Wall]) -> Vec3 {
    let mut need =
        walls.iter().map(|w| w.needs(o.as_dvec3()).max(w.edge(o.as_dvec3()))).fold(0.0f64, f64::max);
    let (n, nu1) = (lift.normal.as_dvec3(), lift.n64);
    for _ in 0..ROUNDS {
        let o64 = o.as_dvec3();
        // A wall the test still cannot see from as far as asked: ask twice as far of every plane.
        if walls.iter().any(|w| acc.seen_side(w.prim, o) != Some(w.positive) && w.nu().dot(o64 - w.a) >= need)
        {
            need *= 2.0;
        }
        // The planes still too near: (unit normal on the right side, distance now).
        let mut short: Vec<(DVec3, f64)> = Vec::with_capacity(walls.len() + 1);
        if nu1.dot(o64 - lift.p) < need {
            short.push((nu1, nu1.dot(o64 - lift.p)));
        }
        for w in walls {
            let d = w.nu().dot(o64 - w.a);
            if acc.seen_side(w.prim, o) != Some(w.positive) || d < need {
                short.push((w.nu(), d));
            }
        }
        if short.is_empty() {
            return o;
        }
        // Each plane once (a quad's two triangles share theirs), or it would pull twice as hard.
        let mut u = DVec3::ZERO;
        for (k, &(nu, _)) in short.iter().enumerate() {
            if short[..k].iter().all(|&(m, _)| m.dot(nu) < 1.0 - 1e-9) {
                u += nu;
            }
        }
        // Along u, the distance to the hit triangle's exact plane changes by at least
        // δ (n·u - dir_err |u|_1): keep that positive, so the origin stays on its side.
        let least = 2.0 * plane.dir_err * u.abs().element_sum();
        if n.dot(u) < least {
            u += nu1 * ((least - n.dot(u)) / n.dot(nu1));
        }
        let Some(u) = u.try_normalize() else { return o };
        // Far enough for each plane that u leaves at a fair angle (at most 1024 times the distance
        // asked; one at a grazing angle is left to the next round's direction).
        let mut delta = 0.0f64;
        for &(nu, d) in &short {
            let c = nu.dot(u);
            if c * 1024.0 > 1.0 {
                delta = delta.max((need - d) / c);
            }
        }
        if !(delta > 0.0 && delta.is_finite()) {
            return o;
        }
        let q = o64 + u * delta;
        let sign = |i: usize| if n[i] != 0.0 { n[i] as f32 } else { u[i] as f32 };
        o = Vec3::new(away(q.x, sign(0)), away(q.y, sign(1)), away(q.z, sign(2)));
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three walls of a box corner and a floor, one edge and the corner hit exactly: the origin ends
    /// where the test sees every wall from inside, within a few bands of the hit point.
    /// The origin `clear` moves the hit of the ray from `eye` towards `target` to.
    fn cleared_origin(acc: &Accel, eye: Vec3, target: Vec3) -> Vec3 {
        let dir = (target - eye).normalize();
        let hit = acc.closest(&crate::scene::accel::Ray::new(eye, dir, f32::INFINITY)).unwrap();
        let plane = Plane::of(acc.triangle(hit.prim));
        let lift = plane.lift(hit.bary_b, hit.bary_c, dir);
        clear(acc, hit.prim, (hit.bary_b, hit.bary_c), &plane, &lift, eye, &mut Near::default())
    }

    #[test]
    fn clears_the_walls_of_an_edge_and_a_corner() {
        let v = Vec3::new;
        let quad = |a: Vec3, b: Vec3, c: Vec3, d: Vec3| [[a, b, c], [a, c, d]];
        let mut tris = Vec::new();
        tris.extend(quad(v(0., 0., 0.), v(2., 0., 0.), v(2., 2., 0.), v(0., 2., 0.))); // floor z = 0
        tris.extend(quad(v(0., 0., 0.), v(0., 2., 0.), v(0., 2., 2.), v(0., 0., 2.))); // wall x = 0
        tris.extend(quad(v(0., 0., 0.), v(2., 0., 0.), v(2., 0., 2.), v(0., 0., 2.))); // wall y = 0
        let (acc, _) = Accel::build(&tris);
        let eye = v(1.0, 1.0, 1.0);
        for target in [v(0.0, 0.7, 0.0), v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.3)] {
            let o = cleared_origin(&acc, eye, target);
            for prim in 0..acc.len() as u32 {
                let t = acc.triangle(prim);
                let inside = (t[1] - t[0]).cross(t[2] - t[0]).dot(v(1.0, 1.0, 1.0) - t[0]) > 0.0;
                assert_eq!(acc.seen_side(prim, o), Some(inside), "{target}: triangle {prim} from {o}");
            }
            assert!((o - target).abs().max_element() < 1e-5, "{target}: moved to {o}");
        }
    }

    /// A cube standing on a large floor (no shared vertices: a contact, away from the floor's
    /// edges), hit exactly at the foot of one of its faces: the origin ends where the test sees
    /// the floor from above and the face from outside, and rays into the face are blocked.
    #[test]
    fn clears_a_contact_in_the_middle_of_a_floor() {
        let v = Vec3::new;
        let quad = |a: Vec3, b: Vec3, c: Vec3, d: Vec3| [[a, b, c], [a, c, d]];
        let mut tris = quad(v(-2., -2., 0.), v(2., -2., 0.), v(2., 2., 0.), v(-2., 2., 0.)).to_vec();
        let p = |i: f32, j: f32, k: f32| v(0.3 + 0.25 * i, -0.5 + 0.25 * j, 0.25 * k);
        tris.extend(quad(p(1., 0., 0.), p(1., 1., 0.), p(1., 1., 1.), p(1., 0., 1.))); // x = 0.55
        tris.extend(quad(p(0., 0., 0.), p(0., 1., 0.), p(0., 1., 1.), p(0., 0., 1.)));
        tris.extend(quad(p(0., 0., 1.), p(1., 0., 1.), p(1., 1., 1.), p(0., 1., 1.)));
        let (acc, _) = Accel::build(&tris);
        let eye = v(1.25, -0.375, 0.5);
        for target in [v(0.55, -0.375, 0.0), v(0.55, -0.3, 0.0)] {
            let o = cleared_origin(&acc, eye, target);
            for prim in 0..acc.len() as u32 {
                let src = acc.source_index(prim);
                if src < 4 {
                    let t = acc.triangle(prim);
                    let outside = (t[1] - t[0]).cross(t[2] - t[0]).dot(eye - t[0]) > 0.0;
                    assert_eq!(acc.seen_side(prim, o), Some(outside), "{target}: triangle {src} from {o}");
                }
            }
            assert!((o - target).abs().max_element() < 1e-5, "{target}: moved to {o}");
            for k in 0..16 {
                let a = k as f32 * 0.19 - 1.5;
                let d = v(-a.cos(), a.sin() * 0.5, 0.3).normalize();
                let r = crate::scene::accel::Ray::new(o, d, f32::INFINITY);
                assert!(acc.occluded(&r), "{target}: ray {d} from {o} leaves through the face");
            }
        }
    }
}
