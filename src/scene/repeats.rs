//! Triangles that repeat another exactly: a face written twice in an OBJ, a glTF mesh instanced
//! many times at one place. A repeat blocks exactly the rays its first copy blocks, at the same
//! distance (the same three corners in the same order give the triangle test the same numbers), and
//! a primary ray takes the least (t, input index) hit, which is the first copy's: dropping repeats
//! changes no image, bit for bit. Keeping them made the load superlinear: obvhs's PLOC builder pairs
//! mutual nearest neighbours, and among thousands of identical boxes every neighbour is equally
//! near, so each pass merged few pairs (32,000 copies of one face: 14 s, of which 87 % in
//! `build_ploc_from_leaves`; 8,000: 2 s), and every ray that reached them tested them all.
//!
//! Found by a hash of each triangle's corners (its bits), sorted with the input index, so that
//! only triangles of equal hash are compared, corner by corner: O(n log n), 12 bytes a triangle.

use super::alpha::Source;
use glam::Vec3;
use rayon::prelude::*;

/// For each triangle of `indices`, whether it is the first of its copies: no earlier triangle has
/// the same three corners in the same order (as f32 bits) and, in a scene with alpha masks, the
/// same cutout and texture coordinates (a repeat with another mask cuts other holes).
pub fn first_copies(positions: &[Vec3], indices: &[[u32; 3]], alpha: Option<&Source>) -> Vec<bool> {
    let key = |t: usize| {
        let corners = indices[t].map(|i| positions[i as usize].to_array().map(f32::to_bits));
        let mask = alpha.map(|a| (a.cutout[t], a.uv[t].map(|c| c.map(f32::to_bits))));
        (corners, mask)
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
    let mut first = vec![true; indices.len()];
    // Within a run of equal hashes (in input order), each triangle is compared with the distinct
    // ones before it: a run is one triangle's copies, or rarely a collision of a few.
    let mut run_start = 0;
    while run_start < order.len() {
        let h = hashes[order[run_start] as usize];
        let run_end = order[run_start..]
            .iter()
            .position(|&t| hashes[t as usize] != h)
            .map_or(order.len(), |n| run_start + n);
        let mut distinct: Vec<usize> = Vec::new();
        for &t in &order[run_start..run_end] {
            let t = t as usize;
            if distinct.iter().any(|&d| key(d) == key(t)) {
                first[t] = false;
            } else {
                distinct.push(t);
            }
        }
        run_start = run_end;
    }
    first
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_exact_repeats_in_the_same_order_go() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let tris = [[0, 1, 2], [0, 1, 2], [1, 2, 0], [0, 2, 1], [0, 1, 3], [0, 1, 2]];
        assert_eq!(first_copies(&p, &tris, None), [true, false, true, true, true, false]);
        // Two vertices at the same place are the same corner.
        let q = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ZERO];
        assert_eq!(first_copies(&q, &[[0, 1, 2], [3, 1, 2]], None), [true, false]);
        let mut source = Source::default();
        for cutout in [0, 1, 0] {
            source.push(cutout, [[0.0; 2]; 3]);
        }
        let same = [[0, 1, 2]; 3];
        assert_eq!(first_copies(&p, &same, Some(&source)), [true, true, false]);
    }
}
