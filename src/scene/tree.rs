//! Countable measures of a built tree (a mesh's build must not depend on its triangle
//! order), for tests and benchmarks: they compare trees without timing them.

use super::Accel;

/// A CWBVH's size and quality.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreeStats {
    /// 8-wide nodes.
    pub nodes: usize,
    /// Leaves (children that hold triangles).
    pub leaves: usize,
    /// Triangle slots (a spatial split puts one triangle in several).
    pub slots: usize,
    /// The surface area heuristic's cost (MacDonald and Booth 1990) with unit costs: the sum over
    /// every child box of its area relative to the root's, times 1 for an inner child or its
    /// triangle count for a leaf. The expected number of boxes and triangles a random ray through
    /// the root tests, from the tree's own (quantized) child boxes.
    pub sah: f64,
    /// Bytes of the nodes, the slot list and the triangles.
    pub bytes: usize,
}

impl Accel {
    /// The tree's `TreeStats`.
    pub fn tree_stats(&self) -> TreeStats {
        let nodes = &self.bvh.nodes;
        let area = |b: obvhs::aabb::Aabb| b.half_area() as f64;
        let root = nodes.first().map_or(1.0, |n| area(n.aabb())).max(f64::MIN_POSITIVE);
        let (mut leaves, mut sah) = (0, 0.0);
        for node in nodes {
            for c in (0..8).filter(|&c| !node.is_child_empty(c)) {
                let cost = if node.is_leaf(c) {
                    leaves += 1;
                    node.child_primitives(c).1 as f64
                } else {
                    1.0
                };
                sah += area(node.child_aabb(c)) / root * cost;
            }
        }
        TreeStats {
            nodes: nodes.len(),
            leaves,
            slots: self.bvh.primitive_indices.len(),
            sah,
            bytes: std::mem::size_of_val(&nodes[..])
                + std::mem::size_of_val(&self.bvh.primitive_indices[..])
                + std::mem::size_of_val(&self.tris[..]),
        }
    }
}
