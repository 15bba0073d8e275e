//! The fast BVH build (`Effort::Fast`): obvhs's fastest preset over pairs of triangles
//! instead of triangles, then the pairs unfolded into the CWBVH's leaves.
//!
//! Why pairs: obvhs's builder holds about 200 bytes per primitive at its peak (PLOC's node arrays
//! and morton codes, then the BVH2 beside the BVH8 converter's table of 7 decisions for each of its
//! 2N nodes), so a 10 M-triangle build alone would pass the 1.6 GB. Two triangles that
//! share an edge (a quad's two halves, a strip's neighbours) make one primitive, which halves all of
//! it and the build time. The converter then makes leaves of one pair each, and `unfold` turns
//! every such leaf into a leaf of its one or two triangles: at most 2 triangles a leaf, as the full
//! build makes them. A pair's box is the union of its triangles' boxes, so the tree bounds every
//! triangle, and the traversal (`accel`) sees a CWBVH of triangles like any other.
//!
//! Why the pairs are found in space, not in the file: pairing only consecutive
//! triangles left a mesh whose quads' halves lie far apart in the file (or a shuffled one) with no
//! pairs, twice the build's memory and time. The triangles are put in Z order (Morton code of their
//! box centres, Morton 1966; ties broken by their corners), and each is paired with the triangle
//! sharing an edge with it, among its `WINDOW` neighbours on either side of that order, whose
//! union box has the least surface area, if that choice is mutual — the first step of PLOC's
//! locally ordered clustering (Meister and Bittner 2018), restricted to edge neighbours; a few such
//! passes over the still single triangles pair most of them. Nothing here reads the input order
//! of the triangles, of their corners or of the vertices (only the input indices that name the
//! result, and the order of triangles with the same three corners), so a shuffled mesh gets the
//! same pairs, in the same order, and obvhs the same boxes: the same tree. Every step after the
//! ordering reads the triangles in Z order, so that a shuffled mesh's reads are as near each
//! other as an ordered one's.

use super::accel::Tri;
use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::{Bvh2, node::Bvh2Node};
use obvhs::cwbvh::CwBvh;
use obvhs::ploc::{PlocBuilder, SortPrecision};
use rayon::prelude::*;
use std::cmp::Ordering;

/// Neighbours in Z order on each side that a triangle may pair with, and the passes (each over
/// the triangles still single, so their window reaches further). Measured on the 1 M grid
/// shuffled and on the kitchen (triangles left single): 4 and 6 leave 0.8 % and 9.6 %; 2 and 6,
/// 1.6 % and 11.8 %; 8 and 3, 0.4 % and 9.8 %, for twice the work of the first pass.
const WINDOW: usize = 4;
const PASSES: usize = 6;

/// A pair's second triangle when it has none.
const SINGLE: u32 = u32::MAX;

/// The fast build: the CWBVH over the triangles `indices` makes of `positions` (its slots naming
/// them by input index), the triangles in slot order, and the core build time (obvhs's measure:
/// ordering, pairing and unfolding excluded). The triangles are put in Z order first and every
/// later step reads them in that order, near the last read whatever the input order (a shuffled
/// mesh's reads through its own indices miss the cache nearly every time).
pub(super) fn fast(
    positions: &[Vec3],
    indices: Vec<[u32; 3]>,
    core: &mut std::time::Duration,
) -> (CwBvh, Vec<Tri>) {
    let order = z_order(positions, &indices);
    let tris: Vec<[u32; 3]> = order.par_iter().map(|&t| indices[t as usize]).collect();
    drop(indices);
    let mut bvh = fast_cwbvh(positions, &tris, core);
    let slots = bvh
        .primitive_indices
        .par_iter()
        .map(|&p| Tri::new(tris[p as usize].map(|k| Vec3A::from(positions[k as usize]))))
        .collect();
    drop(tris);
    bvh.primitive_indices.par_iter_mut().for_each(|p| *p = order[*p as usize]);
    (bvh, slots)
}

/// The CWBVH over `tris` (in Z order), its slots naming places in `tris`.
fn fast_cwbvh(positions: &[Vec3], tris: &[[u32; 3]], core: &mut std::time::Duration) -> CwBvh {
    let places = pairs(tris, positions);
    // obvhs's `build_cwbvh` with the fastest preset (whose reinsertion does nothing), spelt out so
    // that PLOC's leaves are made here, without the list of boxes it would copy them from
    // (160 MB at the peak of a 10 M build).
    let leaves: Vec<Bvh2Node> = places
        .par_iter()
        .enumerate()
        .map(|(k, pair)| {
            let mut b = Aabb::empty();
            for &p in pair.iter().filter(|&&p| p != SINGLE) {
                for i in tris[p as usize] {
                    b.extend(Vec3A::from(positions[i as usize]));
                }
            }
            Bvh2Node::new(b, 1, k as u32)
        })
        .collect();
    let total =
        leaves.par_iter().fold(Aabb::empty, |b, l| b.union(l.aabb())).reduce(Aabb::empty, |p, q| p.union(&q));
    let start = std::time::Instant::now();
    let mut bvh2 = Bvh2::default();
    bvh2.reset_for_reuse(leaves.len(), Some((0..leaves.len() as u32).collect()));
    let mut builder = PlocBuilder { current_nodes: leaves, ..PlocBuilder::new() };
    builder.build_ploc_from_leaves::<1, false>(&mut bvh2, total, SortPrecision::U64, 0);
    drop(builder);
    let mut bvh = obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh(&bvh2, 1, true, false);
    drop(bvh2);
    *core += start.elapsed();
    unfold(&mut bvh, &places);
    bvh
}

/// The triangles in Z order of their box centres (21 bits an axis over the centres' bounds), as
/// input indices. Box centres, not centroids: min and max do not depend on the order of a
/// triangle's corners. Equal codes are told apart by a hash of the corners, then by the corners
/// (sorted, compared by value), so only triangles with the same three corners keep their input
/// order, and those are alike for the tree.
fn z_order(positions: &[Vec3], indices: &[[u32; 3]]) -> Vec<u32> {
    let n = indices.len();
    let corners = |t: u32| indices[t as usize].map(|k| positions[k as usize]);
    // One gather through the indices (slow for a shuffled mesh), then reads in order.
    let seen: Vec<(Vec3, u32)> = indices
        .par_iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| positions[k as usize]);
            ((a.min(b).min(c) + a.max(b).max(c)) * 0.5, corner_hash([a, b, c]))
        })
        .collect();
    let (lo, hi) = seen
        .par_iter()
        .fold(|| (Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &(c, _)| (lo.min(c), hi.max(c)))
        .reduce(|| (Vec3::INFINITY, Vec3::NEG_INFINITY), |p, q| (p.0.min(q.0), p.1.max(q.1)));
    let top = ((1u32 << 21) - 1) as f32;
    let scale = (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE)).recip() * top;
    // (code, hash, triangle) in one integer: a plain sort, no comparator (rdst's radix sort, tried,
    // took 40 % longer: a second buffer and 12 passes).
    let mut keyed: Vec<u128> = (seen.par_iter().zip(0..n as u32))
        .map(|(&(c, hash), t)| {
            let q = ((c - lo) * scale).min(Vec3::splat(top)).as_uvec3();
            let code = spread(q.x) << 2 | spread(q.y) << 1 | spread(q.z);
            (code as u128) << 64 | (hash as u128) << 32 | t as u128
        })
        .collect();
    drop(seen);
    keyed.par_sort_unstable();
    let mut order: Vec<u32> = keyed.par_iter().map(|&k| k as u32).collect();
    let mut start = 0;
    for end in 1..=n {
        if end == n || keyed[end] >> 32 != keyed[start] >> 32 {
            if end - start > 1 {
                order[start..end]
                    .sort_unstable_by(|&p, &q| by_corners(corners(p), corners(q)).then(p.cmp(&q)));
            }
            start = end;
        }
    }
    order
}

/// A hash of a triangle's three corners that does not depend on their order (a sum of one hash
/// per corner, splitmix64's finalizer of its coordinates' bits).
fn corner_hash(v: [Vec3; 3]) -> u32 {
    let one = |p: Vec3| {
        let [x, y, z] = p.to_array().map(|c| c.to_bits() as u64);
        let mut h = x ^ y.rotate_left(21) ^ z.rotate_left(42);
        h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        h ^ (h >> 31)
    };
    (one(v[0]).wrapping_add(one(v[1])).wrapping_add(one(v[2])) >> 32) as u32
}

/// The 21 low bits of `v` spread to every third bit of the result (bit i to bit 3i).
fn spread(v: u32) -> u64 {
    let mut x = (v & 0x1f_ffff) as u64;
    x = (x | x << 32) & 0x001f_0000_0000_ffff;
    x = (x | x << 16) & 0x001f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    x = (x | x << 2) & 0x1249_2492_4924_9249;
    x
}

/// Two triangles by their corners, each sorted, compared axis by axis (a total order on values).
fn by_corners(p: [Vec3; 3], q: [Vec3; 3]) -> Ordering {
    let sorted = |mut v: [Vec3; 3]| {
        let key = |a: &Vec3| a.to_array().map(f32::to_bits);
        v.sort_unstable_by_key(key);
        v.map(|a| a.to_array().map(f32::to_bits))
    };
    sorted(p).cmp(&sorted(q))
}

/// The pairs of places in `tris` (`SINGLE` second where a triangle stays alone), in the order of
/// their first place (the smaller). Each pass: every still single triangle names its best edge
/// neighbour within `WINDOW` places of the single ones (least union box area, then the nearer
/// place, then the earlier one); two that name each other pair.
fn pairs(tris: &[[u32; 3]], positions: &[Vec3]) -> Vec<[u32; 2]> {
    let mut mate = vec![SINGLE; tris.len()];
    let mut live: Vec<u32> = (0..tris.len() as u32).collect();
    let mut matched = 0;
    for pass in 0..PASSES {
        let gathered: Vec<[u32; 3]>;
        let now = if pass == 0 {
            tris
        } else {
            gathered = live.par_iter().map(|&p| tris[p as usize]).collect();
            &gathered
        };
        let best: Vec<u32> =
            (0..live.len()).into_par_iter().map(|k| best_neighbour(now, k, positions)).collect();
        let mut paired = 0;
        for (k, &j) in best.iter().enumerate() {
            if j != SINGLE && (j as usize) > k && best[j as usize] == k as u32 {
                mate[live[k] as usize] = live[j as usize];
                mate[live[j as usize] as usize] = live[k];
                paired += 1;
            }
        }
        if paired == 0 {
            break;
        }
        matched += paired;
        live.retain(|&p| mate[p as usize] == SINGLE);
    }
    drop(live);
    let mut out = Vec::with_capacity(tris.len() - matched);
    for (p, &m) in mate.iter().enumerate() {
        if m == SINGLE {
            out.push([p as u32, SINGLE]);
        } else if m as usize > p {
            out.push([p as u32, m]);
        }
    }
    out
}

/// The place in `tri` of the best partner of `tri[k]` (see `pairs`), or `SINGLE`.
fn best_neighbour(tri: &[[u32; 3]], k: usize, positions: &[Vec3]) -> u32 {
    let me = tri[k];
    let bounds = |t: [u32; 3]| {
        let [a, b, c] = t.map(|i| Vec3A::from(positions[i as usize]));
        Aabb::new(a.min(b).min(c), a.max(b).max(c))
    };
    let mut mine = None;
    let mut best = (f32::INFINITY, usize::MAX, SINGLE);
    let first = k.saturating_sub(WINDOW);
    for (j, &other) in tri.iter().enumerate().take(k + 1 + WINDOW).skip(first) {
        if j == k || !share_edge(me, other) {
            continue;
        }
        let mine = *mine.get_or_insert_with(|| bounds(me));
        // Least area, then the nearer place, then the earlier one (j rises, so `<` keeps it).
        let candidate = (mine.union(&bounds(other)).half_area(), k.abs_diff(j), j as u32);
        if (candidate.0, candidate.1) < (best.0, best.1) {
            best = candidate;
        }
    }
    best.2
}

/// Two triangles with two corners (vertex indices) in common.
#[inline(always)]
fn share_edge(a: [u32; 3], b: [u32; 3]) -> bool {
    let has = |v: u32| (v == b[0]) as u32 + (v == b[1]) as u32 + (v == b[2]) as u32;
    has(a[0]) + has(a[1]) + has(a[2]) >= 2
}

/// Rewrites a CWBVH over pairs (one pair per leaf) into the same tree over their triangles: the
/// primitive list lists each pair's triangles in its place, and each node's base and each leaf's
/// offset and count (the unary high bits of `child_meta`) follow. A node's leaves hold at most 8
/// pairs, so offsets stay below 16, inside the 24 the encoding allows.
fn unfold(bvh: &mut CwBvh, pairs: &[[u32; 2]]) {
    // at[s]: where the triangles of the pair in slot s begin in the new list; at[slots]: the end.
    let mut at = Vec::with_capacity(bvh.primitive_indices.len() + 1);
    let mut tris = Vec::with_capacity(pairs.len() * 2);
    for &p in &bvh.primitive_indices {
        at.push(tris.len() as u32);
        tris.extend(pairs[p as usize].iter().filter(|&&t| t != SINGLE));
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
        assert!(share_edge([0, 1, 2], [2, 1, 5]));
        assert!(!share_edge([0, 1, 2], [2, 3, 4]));
    }

    /// A small rolling grid (quads split along a diagonal), its triangles and corners in a fixed
    /// pseudo-random order when `shuffle`.
    fn grid(n: u32, shuffle: bool) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let side = n + 1;
        let positions = (0..side * side)
            .map(|k| {
                let (x, z) = ((k % side) as f32 / n as f32, (k / side) as f32 / n as f32);
                Vec3::new(x, 0.05 * (7.0 * x).sin() * (5.0 * z).cos(), z)
            })
            .collect();
        let mut indices: Vec<[u32; 3]> = (0..n * n)
            .flat_map(|q| {
                let a = q / n * side + q % n;
                [[a, a + side, a + side + 1], [a, a + side + 1, a + 1]]
            })
            .collect();
        if shuffle {
            let mut state = 0x853c_49e6_748f_ea9bu64;
            for i in (1..indices.len()).rev() {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                indices.swap(i, (state >> 33) as usize % (i + 1));
                indices[i].rotate_left((state >> 20) as usize % 3);
            }
        }
        (positions, indices)
    }

    #[test]
    fn z_order_is_a_permutation_that_ignores_the_input_order() {
        let (positions, ordered) = grid(20, false);
        let (_, shuffled) = grid(20, true);
        let (a, b) = (z_order(&positions, &ordered), z_order(&positions, &shuffled));
        let mut seen = vec![false; a.len()];
        for &t in &a {
            assert!(!std::mem::replace(&mut seen[t as usize], true), "triangle {t} twice");
        }
        let as_sets = |order: &[u32], tris: &[[u32; 3]]| -> Vec<[u32; 3]> {
            order
                .iter()
                .map(|&t| {
                    let mut c = tris[t as usize];
                    c.sort();
                    c
                })
                .collect()
        };
        assert_eq!(as_sets(&a, &ordered), as_sets(&b, &shuffled), "the same triangles in the same order");
        assert_eq!(corner_hash([Vec3::X, Vec3::Y, Vec3::Z]), corner_hash([Vec3::Z, Vec3::X, Vec3::Y]));
    }

    /// obvhs's own check of a CWBVH (every node and slot reached once, every box inside its
    /// parent's, leaves bounding their triangles) on the unfolded tree, ordered and shuffled, and
    /// nearly every quad one pair (a few halves meet a neighbour first and pair across quads).
    #[test]
    fn the_unfolded_tree_passes_obvhs_validation() {
        let mut counts = Vec::new();
        for shuffle in [false, true] {
            let (positions, indices) = grid(24, shuffle);
            let soup: Vec<obvhs::triangle::Triangle> = indices
                .iter()
                .map(|t| {
                    let [v0, v1, v2] = t.map(|k| Vec3A::from(positions[k as usize]));
                    obvhs::triangle::Triangle { v0, v1, v2 }
                })
                .collect();
            let mut core = std::time::Duration::ZERO;
            let (bvh, slots) = fast(&positions, indices.clone(), &mut core);
            bvh.validate(&soup, false);
            assert_eq!(slots.len(), indices.len());
            let leaves: usize = bvh
                .nodes
                .iter()
                .map(|n| (0..8).filter(|&c| n.child_meta[c] != 0 && n.is_leaf(c)).count())
                .sum();
            assert!(leaves * 100 <= indices.len() * 53, "{leaves} leaves for {} triangles", indices.len());
            counts.push((leaves, bvh.nodes.len()));
        }
        assert_eq!(counts[0], counts[1], "ordered and shuffled: the same leaves and nodes");
    }

    #[test]
    fn spread_puts_bit_i_at_3i() {
        for i in 0..21 {
            assert_eq!(spread(1 << i), 1u64 << (3 * i));
        }
        assert_eq!(spread(u32::MAX), 0x1249_2492_4924_9249);
    }
}
