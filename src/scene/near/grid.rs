//! Where on a triangle each of its contacts may matter: a grid over the barycentrics (b, c), each
//! cell listing the contacts whose plane and box come within `reach` of some point of the cell. A
//! large triangle (the kitchen's floor) has thousands of contacts, the furniture that stands on it,
//! but any one hit point is near few of them, or (almost always) none: the grid turns a scan of the
//! whole list into a look-up.

use glam::DVec3;
use std::sync::OnceLock;

// The contact data (`contacts` finds them, `Accel` keeps the table) lives here, beside the grid it
// holds, so that neither the tree nor the grid imports the search.

/// A contact as `Contacts::near_hit` first tests it: its plane's signed distance as an affine
/// function of the triangle's barycentrics (b, c), `f[0] + f[1] b + f[2] c`, and how far it rises
/// off the triangle's plane on the side of its normal and on the other.
#[derive(Debug, Clone, Copy)]
pub(super) struct Contact {
    pub prim: u32,
    pub f: [f64; 3],
    pub rise: [f64; 2],
}

/// A triangle's contacts and the distance they were gathered within (`reach_cap`).
#[derive(Debug, Clone)]
pub(crate) struct Contacts {
    pub(super) reach: f64,
    pub(super) list: Box<[Contact]>,
    /// Where on the triangle each may matter, for lists longer than `SHORT`.
    pub(super) grid: Option<Grid>,
}

/// Each triangle's `Contacts`, worked out on first use (`contacts`); None for none (most triangles), so that
/// the table costs 16 bytes a triangle.
pub(crate) type Table = Vec<OnceLock<Option<Box<Contacts>>>>;

/// Cells along each barycentric axis.
const SIDE: usize = 16;
/// Lists up to this long are scanned whole (about as fast as a look-up).
const SHORT: usize = 8;

/// Cell k's contacts are `index[start[k]..start[k + 1]]`, in list order.
#[derive(Debug, Clone)]
pub(super) struct Grid {
    start: Box<[u32]>,
    index: Box<[u32]>,
}

impl Grid {
    /// The grid of triangle `t` (vertices as stored) for `list` (`boxes`: the box of each one's
    /// part near the triangle's plane), or None for a short list.
    pub(super) fn of(t: [DVec3; 3], reach: f64, list: &[Contact], boxes: &[(DVec3, DVec3)]) -> Option<Grid> {
        if list.len() <= SHORT {
            return None;
        }
        let rows: Vec<[(usize, usize); SIDE]> =
            list.iter().zip(boxes).map(|(n, b)| cells(t, reach, n, *b)).collect();
        let mut count = vec![0u32; SIDE * SIDE];
        for r in &rows {
            for (i, &(k0, k1)) in r.iter().enumerate() {
                (k0..=k1).for_each(|k| count[i * SIDE + k] += 1);
            }
        }
        let mut start = Vec::with_capacity(SIDE * SIDE + 1);
        start.push(0u32);
        for c in &count {
            start.push(start.last().unwrap() + c);
        }
        let mut fill: Vec<u32> = start[..SIDE * SIDE].to_vec();
        let mut index = vec![0u32; *start.last().unwrap() as usize];
        for (j, r) in rows.iter().enumerate() {
            for (i, &(k0, k1)) in r.iter().enumerate() {
                for k in k0..=k1 {
                    index[fill[i * SIDE + k] as usize] = j as u32;
                    fill[i * SIDE + k] += 1;
                }
            }
        }
        Some(Grid { start: start.into_boxed_slice(), index: index.into_boxed_slice() })
    }

    /// The contacts of the cell holding barycentrics (b, c) (clamped to the grid).
    #[inline(always)]
    pub(super) fn cell(&self, b: f32, c: f32) -> &[u32] {
        let side = SIDE as f32;
        let (i, k) = ((b * side).clamp(0.0, side - 1.0) as usize, (c * side).clamp(0.0, side - 1.0) as usize);
        let cell = i * SIDE + k;
        &self.index[self.start[cell] as usize..self.start[cell + 1] as usize]
    }
}

/// The cells of each row of the grid (b in [i, i + 1] / SIDE; `(first, last)` along c, first >
/// last for none) where contact `n` may matter: within `reach` of its plane and of its box `(lo,
/// hi)`. The box bounds a rectangle of (b, c): a point of the plane within reach of the box projects
/// to itself, inside the projection of the widened box. In each row of it, the plane's strip
/// |f0 + f1 b + f2 c| <= reach bounds c to an interval. Cells are widened by a 64th of a cell on
/// each side: barycentrics rounded to f32 near a cell's edge may fall in the next one.
fn cells(t: [DVec3; 3], reach: f64, n: &Contact, (lo, hi): (DVec3, DVec3)) -> [(usize, usize); SIDE] {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    // (b, c) of the projection of x: the 2 x 2 normal equations of x - a = b e1 + c e2.
    let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = g11 * g22 - g12 * g12;
    let (lo, hi) = (lo - reach, hi + reach);
    let (mut b0, mut b1, mut c0, mut c1) =
        (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for corner in 0..8 {
        let x = DVec3::new(
            if corner & 1 == 0 { lo.x } else { hi.x },
            if corner & 2 == 0 { lo.y } else { hi.y },
            if corner & 4 == 0 { lo.z } else { hi.z },
        ) - t[0];
        let (r1, r2) = (e1.dot(x), e2.dot(x));
        let (b, c) = ((g22 * r1 - g12 * r2) / det, (g11 * r2 - g12 * r1) / det);
        (b0, b1, c0, c1) = (b0.min(b), b1.max(b), c0.min(c), c1.max(c));
    }
    if !(b0 <= b1 && c0 <= c1) {
        return [(0, SIDE - 1); SIDE]; // NaN (too thin a triangle for its normal equations): all
    }
    let [f0, f1, f2] = n.f;
    let side = SIDE as f64;
    let pad = 1.0 / (64.0 * side);
    let mut out = [(1, 0); SIDE];
    for (i, row) in out.iter_mut().enumerate() {
        let (r0, r1) = ((i as f64 / side - pad).max(b0), ((i + 1) as f64 / side + pad).min(b1));
        if r0 > r1 {
            continue;
        }
        // f2 c within [-reach - f0 - max(f1 b), reach - f0 - min(f1 b)] over the row's b.
        let (m0, m1) = ((f1 * r0).min(f1 * r1), (f1 * r0).max(f1 * r1));
        let (from, to) = (-reach - f0 - m1, reach - f0 - m0);
        let (mut lo_c, mut hi_c) = (c0.max(-pad), c1.min(1.0 - r0 + pad));
        if f2 > 0.0 {
            (lo_c, hi_c) = (lo_c.max(from / f2), hi_c.min(to / f2));
        } else if f2 < 0.0 {
            (lo_c, hi_c) = (lo_c.max(to / f2), hi_c.min(from / f2));
        } else if from > 0.0 || to < 0.0 {
            continue;
        }
        if lo_c <= hi_c {
            let cell = |c: f64| (c * side).floor().clamp(0.0, side - 1.0) as usize;
            *row = (cell(lo_c - pad), cell(hi_c + pad));
        }
    }
    out
}
