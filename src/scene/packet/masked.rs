//! The masked walk's one extra step (scenes with alpha masks only, `MASKED` in the walk): of a
//! triangle's hits, those its mask keeps.

use super::simd::Packet;
use crate::scene::accel::{Accel, Seen, hit_seen};

impl Accel {
    /// Of the rays in `rays` that hit slot `prim` (seen from their origin as `s`), those whose hit
    /// its alpha mask keeps: each ray's barycentrics exactly as `Accel::occluded` computes them
    /// (`hit_seen` on the same direction bits), so packets and single rays agree. Only called for
    /// scenes with masks.
    #[inline(never)]
    pub(super) fn unmasked(&self, prim: u32, s: &Seen, p: &Packet, rays: u32, tmax: f32) -> u32 {
        let mut keep = 0u32;
        let mut r = rays;
        while r != 0 {
            let i = r.trailing_zeros() as usize;
            r &= r - 1;
            let d = [p.d[0][i / 4][i % 4], p.d[1][i / 4][i % 4], p.d[2][i / 4][i % 4]];
            if let Some((_, _, b, c)) = hit_seen(s, d, tmax)
                && self.keeps(prim, b, c)
            {
                keep |= 1 << i;
            }
        }
        keep
    }
}
