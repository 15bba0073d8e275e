//! Jittered strata. n = rows x cols exactly, with rows the largest divisor of n not above
//! sqrt(n) and cols = n / rows >= rows strata along x (= phi, the longer way round the
//! hemisphere) and rows along y (= theta). Every cell gets exactly one point. A perfect square
//! is a square grid; a prime n degrades to n strata in x only (y is then a plain jitter over
//! [0,1)) — honest one-point-per-stratum rather than a grid with empty or doubled cells.

use super::hash::{fix_add, fix_from_bits, fix_to_f32, hash};
use super::registry::{PixelSet, PointSequence, SequenceInfo};
use super::seed::StrataWalk;
use glam::Vec2;

/// (rows, cols) with rows * cols == n, rows <= cols, rows as large as possible.
pub fn grid(n: u32) -> (u32, u32) {
    let n = n.max(1);
    let mut rows = (n as f64).sqrt() as u32;
    while rows > 1 && !n.is_multiple_of(rows) {
        rows -= 1;
    }
    let rows = rows.max(1);
    (rows, n / rows)
}

/// Fills `out` with the jittered grid for n points, jitter keyed by `key`, shifted by (`dx`, `dy`)
/// mod 1.
pub fn fill(n: u32, key: u64, dx: u32, dy: u32, out: &mut [Vec2]) {
    let (_, cols) = grid(n);
    let first_col = StrataWalk::new(cols);
    let (mut xw, mut yw) = (first_col, StrataWalk::new(n / cols));
    let mut c = 0u32;
    for (i, p) in out.iter_mut().enumerate() {
        let h = hash(key, i as u64);
        let (x, y) = (xw.at(fix_from_bits(h)), yw.at(fix_from_bits(h << 24)));
        *p = Vec2::new(fix_to_f32(fix_add(x, dx)), fix_to_f32(fix_add(y, dy)));
        xw.advance();
        c += 1;
        if c == cols {
            (c, xw) = (0, first_col);
            yw.advance();
        }
    }
}

/// Its seed modes act the common way (`PixelSet::keyed`).
pub struct Stratified;

impl PointSequence for Stratified {
    fn info(&self) -> &SequenceInfo {
        &SequenceInfo {
            name: "stratified",
            label: "stratified",
            words: &[],
            fresh_per_pixel: false,
            shipped: None,
        }
    }

    fn fill(&self, set: &PixelSet, out: &mut [Vec2]) {
        let (key, dx, dy) = set.keyed();
        fill(set.count.max(1), key, dx, dy, out)
    }
}

#[cfg(test)]
mod tests {
    use super::grid;

    #[test]
    fn grid_factors_exactly_and_nearly_square() {
        assert_eq!(grid(16), (4, 4));
        assert_eq!(grid(32), (4, 8));
        assert_eq!(grid(8), (2, 4));
        assert_eq!(grid(7), (1, 7));
        assert_eq!(grid(1), (1, 1));
        for n in 1..2000 {
            let (r, c) = grid(n);
            assert!(r * c == n && r <= c);
        }
    }
}
