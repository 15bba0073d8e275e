//! The fast BVH build (`Effort::Fast`, issue 29): obvhs's fastest preset over pairs of triangles
//! instead of triangles, then the pairs unfolded into the CWBVH's leaves.
//!
//! Why pairs: obvhs's builder holds about 200 bytes per primitive at its peak (PLOC's node arrays
//! and morton codes, then the BVH2 beside the BVH8 converter's table of 7 decisions for each of its
//! 2N nodes), so a 10 M-triangle build alone would pass the 1.6 GB. Consecutive triangles of
//! a mesh file that share an edge (a quad's two halves, a strip's neighbours) make one primitive,
//! which halves all of it and the build time. The converter then makes leaves of one pair each, and
//! `unfold` turns every such leaf into a leaf of its one or two triangles: at most 2 triangles a
//! leaf, as the full build makes them. A pair's box is the union of its triangles' boxes, so the
//! tree bounds every triangle, and the traversal (`accel`) sees a CWBVH of triangles like any other.

use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::cwbvh::CwBvh;

/// The CWBVH over `indices` (triangles of `positions`), its leaves holding triangle indices, and
/// the core build time (obvhs's measure: pairing and unfolding excluded).
pub(super) fn fast_cwbvh(positions: &[Vec3], indices: &[[u32; 3]], core: &mut std::time::Duration) -> CwBvh {
    // starts[k]: the first triangle of pair k; starts[k + 1] - starts[k] is 1 or 2.
    let mut starts = Vec::with_capacity(indices.len() / 2 + 2);
    let mut i = 0;
    while i < indices.len() {
        starts.push(i as u32);
        i += if i + 1 < indices.len() && share_edge(indices[i], indices[i + 1]) { 2 } else { 1 };
    }
    starts.push(indices.len() as u32);
    let boxes: Vec<Aabb> = starts
        .windows(2)
        .map(|w| {
            let mut b = Aabb::empty();
            for t in &indices[w[0] as usize..w[1] as usize] {
                for &k in t {
                    b.extend(Vec3A::from(positions[k as usize]));
                }
            }
            b
        })
        .collect();
    let params = obvhs::BvhBuildParams { max_prims_per_leaf: 1, ..obvhs::BvhBuildParams::fastest_build() };
    let mut bvh = obvhs::cwbvh::builder::build_cwbvh(&boxes, params, core);
    drop(boxes);
    unfold(&mut bvh, &starts);
    bvh
}

/// Two triangles with two corners in common.
fn share_edge(a: [u32; 3], b: [u32; 3]) -> bool {
    a.iter().filter(|k| b.contains(k)).count() >= 2
}

/// Rewrites a CWBVH over pairs (`starts`, one pair per leaf) into the same tree over their
/// triangles: the primitive list lists each pair's triangles in its place, and each node's base
/// and each leaf's offset and count (the unary high bits of `child_meta`) follow. A node's leaves
/// hold at most 8 pairs, so offsets stay below 16, inside the 24 the encoding allows.
fn unfold(bvh: &mut CwBvh, starts: &[u32]) {
    // at[s]: where the triangles of the pair in slot s begin in the new list; at[slots]: the end.
    let mut at = Vec::with_capacity(bvh.primitive_indices.len() + 1);
    let mut tris = Vec::with_capacity(starts.len() * 2);
    for &p in &bvh.primitive_indices {
        at.push(tris.len() as u32);
        tris.extend(starts[p as usize]..starts[p as usize + 1]);
    }
    at.push(tris.len() as u32);
    for node in &mut bvh.nodes {
        let base = node.primitive_base_idx as usize;
        let new_base = at.get(base).copied().unwrap_or(tris.len() as u32);
        for meta in &mut node.child_meta {
            let offset = (*meta & 0b1_1111) as usize;
            // Empty slots are 0 and inner children have offsets 24..32 (left alone).
            if *meta == 0 || offset >= 24 {
                continue;
            }
            let pairs = (*meta >> 5).count_ones() as usize;
            let (first, end) = (at[base + offset], at[base + offset + pairs]);
            let count = end - first;
            debug_assert!((1..=3).contains(&count) && first - new_base < 24);
            *meta = (first - new_base) as u8 | ((0b111u8 >> (3 - count)) << 5);
        }
        node.primitive_base_idx = new_base;
    }
    bvh.primitive_indices = tris;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_only_edge_neighbours() {
        assert!(share_edge([0, 1, 2], [0, 2, 3]));
        assert!(!share_edge([0, 1, 2], [2, 3, 4]));
    }
}
