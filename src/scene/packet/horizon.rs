//! The cone a pixel's AO rays rise in above the surface its origin lies on: a packet's shared
//! culling skips the boxes below it (see `Horizon`).

use super::simd::Packet;
use glam::{Vec3, Vec3A, Vec4};

/// A plane through the origin that no ray of the packet goes below, and the least slope `s` at
/// which they rise above it: a ray reaches height s·r only at distance r, so a box whose top is
/// below s × its distance from the origin cannot be reached (the plane alone culls only boxes
/// wholly below it). The cone matters next to the surface the origin lies on: the origin is
/// lifted off it by a few ulps only, less than the boxes' padding, so without the cone every
/// box of that surface near the pixel would be entered.
#[derive(Debug, Clone, Copy)]
pub(super) struct Horizon {
    pub n: Vec3A,
    /// s², s the least d·n of the packet less 2e-6 (computed d·n is within a few ulps of the true
    /// value, and the support and distance of a box within a few ulps of theirs).
    pub slope2: f32,
}

#[inline(always)]
pub(super) fn horizon(dirs: &[Vec3], normal: Option<Vec3>) -> Option<Horizon> {
    let n = normal?;
    from_least(dirs.iter().map(|d| d.dot(n)).fold(f32::INFINITY, f32::min), n)
}

/// `horizon` of the first `len` rays of a filled packet (the same least d·n: the same products and
/// sums, lane by lane).
#[inline(always)]
pub(super) fn horizon_of(p: &Packet, len: usize, n: Vec3) -> Option<Horizon> {
    let (nx, ny, nz) = (Vec4::splat(n.x), Vec4::splat(n.y), Vec4::splat(n.z));
    let mut least = Vec4::splat(f32::INFINITY);
    for g in 0..len.div_ceil(4) {
        let dn = (p.d[0][g] * nx + p.d[1][g] * ny) + p.d[2][g] * nz;
        // Lanes past `len` hold zero directions: keep them out.
        let lanes = (len - 4 * g).min(4);
        let valid = Vec4::from_array([0, 1, 2, 3].map(|l| if l < lanes { 0.0 } else { f32::INFINITY }));
        least = least.min(dn + valid);
    }
    from_least(least.min_element(), n)
}

/// The horizon of rays whose least d·n is `least` (none if some ray is within 1e-6 of the plane).
#[inline(always)]
fn from_least(least: f32, n: Vec3) -> Option<Horizon> {
    let s = (least - 2e-6).max(0.0);
    (least > 1e-6).then_some(Horizon { n: n.into(), slope2: s * s })
}
