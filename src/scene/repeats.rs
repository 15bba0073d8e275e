//! Triangles that repeat another exactly: a face written twice in an OBJ, a glTF mesh instanced
//! many times at one place. The tree stores a triangle's corners sorted (`accel::Tri::new`), so the
//! same three corners in any order are one and the same triangle to every query: a repeat blocks
//! exactly the rays its first copy blocks, at the same distance, and a primary ray takes the least
//! (t, input index) hit, and the copies' t are the same. Dropping repeats changes no image, bit for bit
//! (the kitchen has 2; its renders are identical with and without them). Keeping them made the load
//! superlinear: obvhs's PLOC builder pairs mutual nearest neighbours, and among thousands of
//! identical boxes every neighbour is equally near, so each pass merged few pairs (32,000 copies of
//! one face: 14 s, 87 % of it in `build_ploc_from_leaves`; 8,000: 2 s), and every ray that reached
//! them tested them all.
//!
//! Found by a hash of each triangle's corners (their bits, sorted), sorted with the input index, so
//! that only triangles of equal hash are compared: O(n log n), 12 bytes a triangle.

use super::alpha::Source;
use glam::Vec3;
use rayon::prelude::*;

/// For each triangle of `indices`, whether it is the copy that is kept of the triangles with the
/// same three corners (as f32 bits, in any order) and, in a scene with alpha masks, the same cutout
/// and the same texture coordinates at each corner (a repeat with another mask cuts other holes).
pub fn kept_copies(positions: &[Vec3], indices: &[[u32; 3]], alpha: Option<&Source>) -> Vec<bool> {
    let key = |t: usize| {
        let uv = |k: usize| alpha.map_or([0; 2], |a| a.uv[t][k].map(f32::to_bits));
        let mut corners: [([u32; 3], [u32; 2]); 3] =
            std::array::from_fn(|k| (positions[indices[t][k] as usize].to_array().map(f32::to_bits), uv(k)));
        corners.sort_unstable();
        (corners, alpha.map(|a| a.cutout[t]))
    };
    let hashes: Vec<u64> = (0..indices.len())
        .into_par_iter()
        .map(|t| {
            use std::hash::{Hash, Hasher};
            let mut h = std::collections::hash_map::DefaultHasher::new();
            key(t).hash(&mut h);
            h.finish()
        })
        .collect();
    let mut order: Vec<u32> = (0..indices.len() as u32).collect();
    order.par_sort_unstable_by_key(|&t| (hashes[t as usize], t));
    let mut kept = vec![true; indices.len()];
    // Within a run of equal hashes, the triangles are grouped by their corners (a run is one
    // triangle's copies, or rarely a collision of a few), and each group keeps one copy: the one
    // with the least vertex indices (sorted), then the least input index. Not simply the first:
    // which copy stays must not depend on the order of the triangles or of their corners (the fast
    // build reads neither, `cluster`, and pairs triangles by their vertex indices).
    let rank = |t: usize| {
        let mut v = indices[t];
        v.sort_unstable();
        (v, t)
    };
    let mut run_start = 0;
    while run_start < order.len() {
        let h = hashes[order[run_start] as usize];
        let run_end = order[run_start..]
            .iter()
            .position(|&t| hashes[t as usize] != h)
            .map_or(order.len(), |n| run_start + n);
        let mut groups: Vec<usize> = Vec::new(); // the copy each group keeps so far
        for &t in &order[run_start..run_end] {
            let t = t as usize;
            match groups.iter_mut().find(|g| key(**g) == key(t)) {
                None => groups.push(t),
                Some(g) if rank(t) < rank(*g) => {
                    kept[*g] = false;
                    *g = t;
                }
                Some(_) => kept[t] = false,
            }
        }
        run_start = run_end;
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_same_three_corners_repeat() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let tris = [[0, 1, 2], [0, 1, 2], [1, 2, 0], [0, 2, 1], [0, 1, 3], [0, 1, 2]];
        assert_eq!(kept_copies(&p, &tris, None), [true, false, false, false, true, false]);
        // Two vertices at the same place are the same corner.
        let q = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ZERO];
        assert_eq!(kept_copies(&q, &[[0, 1, 2], [3, 1, 2]], None), [true, false]);
        let mut source = Source::default();
        for cutout in [0, 1, 0] {
            source.push(cutout, [[0.0; 2]; 3]);
        }
        let same = [[0, 1, 2]; 3];
        assert_eq!(kept_copies(&p, &same, Some(&source)), [true, true, false]);
    }
}
