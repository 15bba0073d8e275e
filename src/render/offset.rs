//! Where a pixel's AO rays start: the primary hit point, lifted off its triangle by a bound on the
//! point's own floating-point error, never by the size of the coordinates.
//!
//! The approach is pbrt-v4's (Pharr, Jakob, Humphreys, "Physically Based Rendering", 4th ed., 6.8:
//! error bounds carried from the intersection, then `OffsetRayOrigin`: move along the normal by
//! dot(|n|, error) and round away from the surface). Here the hit point is interpolated from the
//! barycentrics in f64 (once per pixel), so its error is essentially the final rounding to f32, and
//! the lift is a few ulps of the point's coordinates. That is enough because the triangle test
//! never reports a hit it cannot prove to be in front of the origin (`scene::accel::Seen`): an
//! origin that is on the right side of its triangle, by any margin, cannot hit it, however large it
//! is. (The scale-aware offset this replaces lifted every origin on a 10 km ground quad by 0.125.)

use glam::{DVec3, Vec3, Vec3Swizzles};

/// f64 unit roundoff.
const U64: f64 = f64::EPSILON / 2.0;

/// Higham's γ_n = n u / (1 - n u): the relative error bound of n roundings.
fn gamma(n: f64) -> f64 {
    n * U64 / (1.0 - n * U64)
}

/// The AO origin and the unit normal for a primary hit at barycentrics (`bary_b`, `bary_c`) of
/// triangle `tri` = [a, b, c] (the f32 vertices as traced), facing against `incoming` (the primary
/// ray's direction). The origin is on the normal's side of the triangle's exact plane (or on it);
/// the normal is the exact plane's, rounded to f32.
pub fn ao_origin(tri: [Vec3; 3], bary_b: f32, bary_c: f32, incoming: Vec3) -> (Vec3, Vec3) {
    Plane::of(tri).ao_origin(bary_b, bary_c, incoming)
}

/// What `ao_origin` needs of a triangle whatever the point on it: its edges and unit normal in f64
/// and the bound on that normal's direction. Neighbouring pixels mostly hit the same triangle, so
/// the renderer keeps the last one (the square roots and the division are most of the work).
#[derive(Debug, Clone, Copy)]
pub struct Plane {
    pub(super) a: DVec3,
    pub(super) e1: DVec3,
    pub(super) e2: DVec3,
    pub(super) n64: DVec3,
    /// Bound on |ν - n|, ν the exact plane's unit normal, n its f32 rounding.
    pub(super) dir_err: f64,
    /// M / |N| (M: the magnitudes N is made of): how the triangle test's rounding bound on the
    /// plane's distance grows with the distance from vertex a (`clearance::band`).
    pub(super) m_over_n: DVec3,
    /// The farthest `clearance` looks around an origin on it (`scene::near::reach_cap`).
    pub(super) cap: f64,
    /// Within 8 `cap` of an edge (16 times the greatest reach) `clearance` looks around the
    /// origin, beyond it only at the triangle's contacts. The hit point's distance from the edge
    /// opposite vertex k is its barycentric k times the vertex's height h_k: this holds
    /// (8 cap / h_k)², for k = a, b, c, to compare the squared barycentrics with (no root a pixel).
    pub(super) edge_zone: DVec3,
}

/// An AO origin with what `clearance` needs to clear it of the neighbouring triangles too.
#[derive(Debug, Clone, Copy)]
pub(super) struct Lift {
    /// The hit point (f64, on the plane up to `err`).
    pub p: DVec3,
    /// The origin (on the normal's side of the plane) and the unit normal, facing the incoming ray.
    pub origin: Vec3,
    pub normal: Vec3,
    /// The normal in f64, facing the incoming ray.
    pub n64: DVec3,
}

impl Plane {
    pub fn of(tri: [Vec3; 3]) -> Self {
        let [a, b, c] = tri.map(Vec3::as_dvec3);
        let (e1, e2) = (b - a, c - a);
        let normal = e1.cross(e2);
        // The f64 normal's direction is off by about γ4 |M| / |N| (M: the magnitudes N is made of);
        // rounding it to f32 adds 2^-24 per component. Degenerate in f64 (f32 rounding made the
        // area): no plane to speak of, so any direction, with the largest possible direction error.
        let m = (e1.yzx() * e2.zxy()).abs() + (e1.zxy() * e2.yzx()).abs();
        let (n64, dir_err) = match normal.try_normalize() {
            Some(n) => (n, gamma(8.0) * m.length() / normal.length() + 1.0 / 16_777_216.0),
            None => (DVec3::Z, 2.0),
        };
        let area2 = normal.length_squared();
        let m_over_n = m / area2.sqrt().max(f64::MIN_POSITIVE);
        let cap = crate::scene::near::reach_cap([a, b, c]);
        // (8 cap / h_k)² = 64 cap² |opposite edge|² / |N|².
        let edges2 = DVec3::new((c - b).length_squared(), e2.length_squared(), e1.length_squared());
        let edge_zone = edges2 * (64.0 * cap * cap / area2);
        Self { a, e1, e2, n64, dir_err, m_over_n, cap, edge_zone }
    }

    /// `ao_origin` of this triangle.
    #[inline(always)]
    pub fn ao_origin(&self, bary_b: f32, bary_c: f32, incoming: Vec3) -> (Vec3, Vec3) {
        let l = self.lift(bary_b, bary_c, incoming);
        (l.origin, l.normal)
    }

    /// `ao_origin` with the hit point, the f64 normal and the lift.
    #[inline(always)]
    pub(super) fn lift(&self, bary_b: f32, bary_c: f32, incoming: Vec3) -> Lift {
        let (a, dir_err) = (self.a, self.dir_err);
        let (wb, wc) = (self.e1 * bary_b as f64, self.e2 * bary_c as f64);
        // On the plane for any barycentrics (their error moves the point along the surface, not off
        // it); off by at most γ5 (|a| + |wb| + |wc|): the edges, the products, two sums.
        let p = a + wb + wc;
        let err = (a.abs() + wb.abs() + wc.abs()) * gamma(5.0);
        let mut n64 = self.n64;
        if n64.dot(incoming.as_dvec3()) > 0.0 {
            n64 = -n64;
        }
        let n = n64.as_vec3();

        // Distance of the rounded origin o from the exact plane (unit normal ν, |ν - n| <= dir_err):
        // ν·(o - p_exact) >= h (1 - dir_err) - [dot(|n|, err) + dir_err (|err|_1 + Σ ulp(o_i))] - the
        // f64 rounding of p + h n; rounding each o_i away from the surface (towards sign n_i) only
        // adds. So h = 2 × the bracket plus that rounding keeps o on the normal's side.
        let ulps = p.abs().element_sum() * (4.0 / 8_388_608.0) + 3.0 * f32::from_bits(1) as f64;
        let h = 2.0
            * (n.abs().as_dvec3().dot(err)
                + dir_err * (err.element_sum() + ulps)
                + gamma(3.0) * p.abs().element_sum());
        let o = p + n.as_dvec3() * h;
        let origin = Vec3::new(away(o.x, n.x), away(o.y, n.y), away(o.z, n.z));
        Lift { p, origin, normal: n, n64 }
    }
}

/// `x` rounded to f32, away from the surface: up if `dir` > 0, down if `dir` < 0 (pbrt-v4's
/// `OffsetRayOrigin` rounds so), to nearest if `dir` = 0.
#[inline(always)]
pub(super) fn away(x: f64, dir: f32) -> f32 {
    let r = x as f32;
    if dir > 0.0 && (r as f64) < x {
        r.next_up()
    } else if dir < 0.0 && (r as f64) > x {
        r.next_down()
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The origin is on the normal's side of the plane, by at most a few ulps of its coordinates,
    /// at every size and distance from the origin; the normal faces the incoming ray.
    #[test]
    fn lifts_by_ulps_of_the_point_not_of_the_triangle() {
        for (scale, at) in [(1.0f32, 0.0f32), (5000.0, 0.0), (1e-3, 3.0), (1.0, 1000.0), (1e3, -1e4)] {
            // A tilted triangle, and a point well inside it.
            let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z) * scale + Vec3::splat(at);
            let tri = [v(-1.0, -1.0, 0.1), v(1.0, -0.8, -0.2), v(0.1, 1.0, 0.3)];
            for (bb, bc) in [(0.3f32, 0.3f32), (0.01, 0.98), (0.5, 0.0)] {
                let (o, n) = ao_origin(tri, bb, bc, -Vec3::Z);
                assert!(n.z > 0.0 && (n.length() - 1.0).abs() < 1e-6, "{n}");
                let [a, b, c] = tri.map(Vec3::as_dvec3);
                let nu = (b - a).cross(c - a).normalize();
                let nu = if nu.z < 0.0 { -nu } else { nu };
                let height = nu.dot(o.as_dvec3() - a);
                assert!(height >= 0.0, "scale {scale} at {at}: origin {height} below the plane");
                let p = a + (b - a) * bb as f64 + (c - a) * bc as f64;
                let ulp = p.abs().max_element() * f32::EPSILON as f64;
                assert!(height <= 8.0 * ulp, "scale {scale} at {at}: lifted {height} ({ulp} ulp)");
            }
        }
    }

    /// A hit on the plane z = 0 of a 10 km triangle (axis-aligned: the point's z is exact) is lifted
    /// by almost nothing (the scale-aware offset lifted it by 0.125).
    #[test]
    fn exact_on_an_axis_aligned_plane() {
        let tri =
            [Vec3::new(-5000.0, -5000.0, 0.0), Vec3::new(5000.0, -5000.0, 0.0), Vec3::new(0.0, 5000.0, 0.0)];
        let (o, n) = ao_origin(tri, 0.25, 0.5, Vec3::new(0.2, 0.1, -1.0).normalize());
        assert_eq!(n, Vec3::Z);
        assert!(o.z >= 0.0 && o.z < 1e-9, "{o}");
    }
}
