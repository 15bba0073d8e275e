//! Ulichney's void-and-cluster method ("The void-and-cluster method for dither array generation",
//! Proc. SPIE 1913, 1993) on a toroidal grid of up to three axes (x, y, t), for any energy kernel
//! given as taps: the 2-D masks of [`super::blue_noise`] (a Gaussian over pixel distance) and the
//! spatiotemporal masks of [`super::stbn`] (Wolfe et al.'s energy: a Gaussian over spatial pairs
//! within a slice plus a Gaussian over temporal pairs within a pixel).
//!
//! The energy is an integer sum of quantized kernel taps (the only floating point is the taps,
//! each rounded once), so incremental updates are exact (no drift, no order dependence), and ties
//! are broken by the lowest index. The tightest cluster and the largest void are found in
//! O(row + log rows) instead of one O(N) scan per step: each row along x keeps its best pixel, a
//! binary tree over the rows keeps the best row, and a set() rescans only the rows its taps reach.
//! Same ranks, bit for bit, as the scans (the left subtree holds the lower indices, and it wins ties).

use super::hash::hash;

/// Quantization of the kernel: weight · 2^20, rounded; taps that round to 0 are dropped (exact).
pub const KERNEL_SCALE: f64 = (1u64 << 20) as f64;

/// The generator's state: the binary pattern, each pixel's energy, and the two search trees.
pub struct VoidAndCluster {
    /// Axis lengths (x, y, t); index = (t · ny + y) · nx + x.
    dims: [usize; 3],
    /// ((dx, dy, dt), weight) for every toroidal offset whose quantized weight is not 0.
    taps: Vec<([usize; 3], i64)>,
    /// The distinct (dy, dt) of the taps: which rows a set() touches, relative to its own.
    row_steps: Vec<(usize, usize)>,
    ones: Vec<bool>,
    energy: Vec<i64>,
    /// Highest energy among the ones; lowest energy among the zeros (as the highest negated).
    clusters: Tree,
    voids: Tree,
}

/// Gaussian weight exp(-d² / 2σ²), quantized.
pub fn gaussian_tap(d2: f64, sigma: f64) -> i64 {
    ((-d2 / (2.0 * sigma * sigma)).exp() * KERNEL_SCALE).round() as i64
}

/// Toroidal distance along an axis of length n.
fn wrap(d: usize, n: usize) -> f64 {
    d.min(n - d) as f64
}

impl VoidAndCluster {
    /// Energy = Gaussian (σ = `sigma_s`) over the toroidal distance of pairs in the same slice,
    /// plus Gaussian (σ = `sigma_t`) over the toroidal time distance of pairs in the same pixel.
    /// With one slice (`dims[2]` = 1) this is the 2-D Gaussian energy of Ulichney.
    pub fn new(dims: [usize; 3], sigma_s: f64, sigma_t: f64) -> Self {
        let [nx, ny, nt] = dims;
        let mut taps = Vec::new();
        for dy in 0..ny {
            for dx in 0..nx {
                let w = gaussian_tap(wrap(dx, nx).powi(2) + wrap(dy, ny).powi(2), sigma_s);
                if w > 0 {
                    taps.push(([dx, dy, 0], w));
                }
            }
        }
        for dt in 1..nt {
            let w = gaussian_tap(wrap(dt, nt).powi(2), sigma_t);
            if w > 0 {
                taps.push(([0, 0, dt], w));
            }
        }
        let mut row_steps: Vec<(usize, usize)> = taps.iter().map(|&([_, dy, dt], _)| (dy, dt)).collect();
        row_steps.sort_unstable();
        row_steps.dedup();
        let n = nx * ny * nt;
        let rows = ny * nt;
        Self {
            dims,
            taps,
            row_steps,
            ones: vec![false; n],
            energy: vec![0; n],
            clusters: Tree::new(rows),
            voids: Tree::new(rows),
        }
    }

    #[cfg(test)]
    pub fn taps(&self) -> &[([usize; 3], i64)] {
        &self.taps
    }

    fn len(&self) -> usize {
        self.energy.len()
    }

    /// Sets pixel `p` to `one`, updating the energy of every pixel the kernel reaches (exact) and
    /// the search trees' rows that changed.
    pub fn set(&mut self, p: usize, one: bool) {
        debug_assert_ne!(self.ones[p], one);
        self.ones[p] = one;
        let sign = if one { 1 } else { -1 };
        let [nx, ny, nt] = self.dims;
        let (px, py, pt) = (p % nx, (p / nx) % ny, p / (nx * ny));
        let add = |a: usize, d: usize, n: usize| if a + d >= n { a + d - n } else { a + d };
        for &([dx, dy, dt], w) in &self.taps {
            let q = (add(pt, dt, nt) * ny + add(py, dy, ny)) * nx + add(px, dx, nx);
            self.energy[q] += sign * w;
        }
        for i in 0..self.row_steps.len() {
            let (dy, dt) = self.row_steps[i];
            self.update_row(add(pt, dt, nt) * ny + add(py, dy, ny));
        }
    }

    /// Recomputes row `r`'s best entries in the trees that are kept.
    fn update_row(&mut self, r: usize) {
        let nx = self.dims[0];
        let (e, o) = (&self.energy[r * nx..(r + 1) * nx], &self.ones[r * nx..(r + 1) * nx]);
        if self.clusters.kept {
            self.clusters.set_row(r, best(r * nx, e, o, |e, one| if one { e } else { i64::MIN }));
        }
        if self.voids.kept {
            self.voids.set_row(r, best(r * nx, e, o, |e, one| if one { i64::MIN } else { -e }));
        }
    }

    /// Turns the trees on or off (an off tree costs nothing; turning one on rebuilds it).
    fn keep(&mut self, clusters: bool, voids: bool) {
        let fresh = (clusters && !self.clusters.kept, voids && !self.voids.kept);
        self.clusters.kept = clusters;
        self.voids.kept = voids;
        if fresh.0 || fresh.1 {
            for r in 0..self.dims[1] * self.dims[2] {
                self.update_row(r);
            }
        }
    }

    /// The one with the highest energy (first on ties).
    fn tightest_cluster(&self) -> usize {
        debug_assert!(self.clusters.kept);
        self.clusters.best().1
    }

    /// The zero with the lowest energy (first on ties).
    fn largest_void(&self) -> usize {
        debug_assert!(self.voids.kept);
        self.voids.best().1
    }

    /// Ulichney's three phases from a random initial pattern of about 10 % ones: the ranks,
    /// a permutation of 0..N in index order.
    pub fn ranks(mut self, seed: u64) -> Vec<u32> {
        let n = self.len();
        // Initial pattern: a partial Fisher–Yates shuffle picks n/10 distinct pixels.
        let ones = (n / 10).max(1);
        let mut order: Vec<usize> = (0..n).collect();
        for i in 0..ones {
            let j = i + (hash(seed, i as u64) % (n - i) as u64) as usize;
            order.swap(i, j);
            self.set(order[i], true);
        }
        self.keep(true, true);
        // Prototype binary pattern: move the tightest cluster into the largest void until the
        // void found is the pixel just removed (bounded, in case of a cycle of equal moves).
        for _ in 0..n {
            let c = self.tightest_cluster();
            self.set(c, false);
            let v = self.largest_void();
            self.set(v, true);
            if v == c {
                break;
            }
        }
        let prototype = (self.ones.clone(), self.energy.clone());
        let mut rank = vec![0u32; n];
        // Phase 1: remove the tightest cluster, ranks counting down from ones - 1.
        self.keep(true, false);
        for r in (0..ones).rev() {
            let c = self.tightest_cluster();
            self.set(c, false);
            rank[c] = r as u32;
        }
        (self.ones, self.energy) = prototype;
        self.keep(false, false);
        self.keep(false, true);
        // Phases 2 and 3: fill the largest void, ranks counting up. Ulichney's phase 3 (past half,
        // the tightest cluster of zeros) picks the same pixel: on the torus every pixel's kernel
        // sums to the same total, so zero-energy = total - one-energy.
        for r in ones..n {
            let v = self.largest_void();
            self.set(v, true);
            rank[v] = r as u32;
        }
        rank
    }
}

/// The highest key of a row (first on ties), as (key, index); (MIN, MAX) if no pixel qualifies.
#[inline]
fn best(base: usize, e: &[i64], ones: &[bool], key: impl Fn(i64, bool) -> i64) -> (i64, usize) {
    let mut b = (i64::MIN, usize::MAX);
    for (i, (&e, &o)) in e.iter().zip(ones).enumerate() {
        let k = key(e, o);
        if k > b.0 {
            b = (k, base + i);
        }
    }
    b
}

/// A binary tree over rows holding the best (key, index) of each subtree; the left child wins
/// ties, so the best is the first pixel in index order with the highest key.
struct Tree {
    leaves: usize,
    nodes: Vec<(i64, usize)>,
    kept: bool,
}

impl Tree {
    fn new(rows: usize) -> Self {
        let leaves = rows.next_power_of_two();
        Self { leaves, nodes: vec![(i64::MIN, usize::MAX); 2 * leaves], kept: false }
    }

    fn set_row(&mut self, r: usize, v: (i64, usize)) {
        let mut i = self.leaves + r;
        self.nodes[i] = v;
        while i > 1 {
            i /= 2;
            let (l, rt) = (self.nodes[2 * i], self.nodes[2 * i + 1]);
            let b = if rt.0 > l.0 { rt } else { l };
            if self.nodes[i] == b {
                break;
            }
            self.nodes[i] = b;
        }
    }

    fn best(&self) -> (i64, usize) {
        self.nodes[1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn incremental_energy_equals_the_sum_recomputed_from_scratch() {
        for dims in [[16, 16, 1], [8, 8, 8]] {
            let mut g = VoidAndCluster::new(dims, 1.5, 1.9);
            let n = dims.iter().product::<usize>();
            for i in 0..40 {
                let p = (hash(3, i) % n as u64) as usize;
                let one = !g.ones[p];
                g.set(p, one);
            }
            let [nx, ny, nt] = dims;
            for p in 0..n {
                let (px, py, pt) = (p % nx, (p / nx) % ny, p / (nx * ny));
                let brute: i64 = g
                    .taps
                    .iter()
                    .filter(|&&([dx, dy, dt], _)| {
                        let q = (((pt + nt - dt) % nt) * ny + (py + ny - dy) % ny) * nx + (px + nx - dx) % nx;
                        g.ones[q]
                    })
                    .map(|t| t.1)
                    .sum();
                assert_eq!(g.energy[p], brute, "{dims:?} pixel {p}");
            }
        }
    }

    /// The trees find what a scan of every pixel finds, ties to the lowest index.
    #[test]
    fn trees_agree_with_full_scans() {
        let mut g = VoidAndCluster::new([8, 4, 4], 1.5, 1.9);
        g.keep(true, true);
        for i in 0..60 {
            let p = (hash(9, i) % 128) as usize;
            let one = !g.ones[p];
            g.set(p, one);
            let scan_c = best(0, &g.energy, &g.ones, |e, one| if one { e } else { i64::MIN });
            let scan_v = best(0, &g.energy, &g.ones, |e, one| if one { i64::MIN } else { -e });
            if scan_c.1 != usize::MAX {
                assert_eq!(g.tightest_cluster(), scan_c.1);
            }
            assert_eq!(g.largest_void(), scan_v.1);
        }
    }
}
