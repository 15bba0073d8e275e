//! Pure: which jobs of a plan shard K of N runs (`hemilab run --shard K/N`), so that one spec can
//! run as a batch-scheduler array (a Slurm job array, a Kubernetes Indexed Job) and be merged after.
//!
//! - **Disjoint and covering**: every job belongs to exactly one shard.
//! - **Whole timing units**: a unit is one configuration (scene, estimator, ray count) — the unit
//!   the timing protocol (`crate::timing`) compares times within: its replicates differ only in the
//!   seed, and it is rendered again until it has its timing repeats. All of a unit's jobs go to the
//!   same shard, so every unit's time samples come from one machine and one session, and a shard
//!   never re-renders a unit another shard also re-renders.
//! - **Balanced by cost**, not job count: a 1024-ray unit costs a thousand 1-ray units. Units are
//!   dealt out longest first, each to the shard with the least cost so far (Graham's LPT rule,
//!   Graham 1969, within 4/3 of the best possible makespan).
//! - **The same on every machine**: the cost is a fixed formula of the plan (pixels × rays and a
//!   fixed per-pixel overhead), never a measured speed, so shards started on different machines
//!   agree on the partition. A changed formula changes the partition, which is why `merge` checks
//!   coverage job by job rather than trusting it.

pub mod manifest;
pub mod merge;

pub use crate::plan::{unit_key, units};

use crate::plan::{Job, Plan};
use std::fmt;

/// Per-image cost of a pixel (primary ray, hit point, frame, point set, image) in AO-ray
/// equivalents, for balancing only: `hemilab plan` measured about 10 ms per image plus 47–74 ns per
/// AO ray on the kitchen at 160×120, i.e. about 10 rays per pixel. Its exact value moves the
/// balance by a few percent, never which jobs run.
pub const OVERHEAD_RAYS_PER_PIXEL: u64 = 10;

/// Shard K (0-based) of N.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Shard {
    pub index: u32,
    pub count: u32,
}

impl Shard {
    /// `index` < `count`, `count` ≥ 1, with a message that says what is allowed.
    pub fn new(index: u32, count: u32) -> Result<Self, String> {
        if count == 0 {
            return Err("the number of shards N must be at least 1".into());
        }
        if index >= count {
            return Err(format!(
                "shard {index} of {count} does not exist: shards are numbered from 0 to {} (0-based)",
                count - 1
            ));
        }
        Ok(Self { index, count })
    }

    /// `K/N`, e.g. `0/3`.
    pub fn parse(s: &str) -> Result<Self, String> {
        let bad = || format!("'{s}' is not a shard: write K/N with 0 <= K < N, e.g. 0/3, or `auto`");
        let (k, n) = s.trim().split_once('/').ok_or_else(bad)?;
        let k: u32 = k.trim().parse().map_err(|_| bad())?;
        let n: u32 = n.trim().parse().map_err(|_| bad())?;
        Self::new(k, n)
    }

    /// The default output directory name of the shard: `shard-K-of-N`.
    pub fn dir_name(&self) -> String {
        format!("shard-{}-of-{}", self.index, self.count)
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// `--shard`: a fixed shard, or `auto` from the batch scheduler's environment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShardArg {
    Fixed(Shard),
    Auto,
}

/// Relative cost of a unit: its renders (its jobs, or `min_renders` timing repeats if more) times
/// its pixels times (rays + the fixed per-pixel overhead).
pub fn unit_cost(jobs: usize, pixels: u64, rays: u32, min_renders: u32) -> u64 {
    let renders = (jobs as u64).max(min_renders as u64);
    renders.saturating_mul(pixels).saturating_mul(rays as u64 + OVERHEAD_RAYS_PER_PIXEL)
}

/// Deals `costs` to `n` shards (LPT): longest first, ties in input order, each to the least loaded
/// shard, ties to the lowest index. Returns the shard of every input.
pub fn assign(costs: &[u64], n: u32) -> Vec<u32> {
    let n = n.max(1) as usize;
    let mut order: Vec<usize> = (0..costs.len()).collect();
    order.sort_by(|&a, &b| costs[b].cmp(&costs[a]).then(a.cmp(&b)));
    let mut load = vec![0u64; n];
    let mut out = vec![0u32; costs.len()];
    for i in order {
        let s = (0..n).min_by_key(|&s| (load[s], s)).unwrap_or(0);
        load[s] = load[s].saturating_add(costs[i]);
        out[i] = s as u32;
    }
    out
}

/// The shard of every job of `plan` when split `n` ways. `resolution_of` gives the scene's own
/// resolution for jobs without an override; `min_renders` is the timing protocol's repeats.
pub fn partition(
    plan: &Plan,
    n: u32,
    resolution_of: impl Fn(&Job) -> [u32; 2],
    min_renders: u32,
) -> Vec<u32> {
    let units = units(plan);
    let costs: Vec<u64> = units
        .iter()
        .map(|u| {
            let job = &plan.jobs[u[0]];
            let [w, h] = job.resolution.unwrap_or_else(|| resolution_of(job));
            unit_cost(u.len(), w as u64 * h as u64, job.rays, min_renders)
        })
        .collect();
    let shard_of_unit = assign(&costs, n);
    let mut out = vec![0u32; plan.jobs.len()];
    for (u, jobs) in units.iter().enumerate() {
        for &j in jobs {
            out[j] = shard_of_unit[u];
        }
    }
    out
}

/// The jobs of `shard`, in plan order.
pub fn select(plan: &Plan, shard: Shard, resolution_of: impl Fn(&Job) -> [u32; 2], min_renders: u32) -> Plan {
    let of = partition(plan, shard.count, resolution_of, min_renders);
    let jobs =
        plan.jobs.iter().zip(&of).filter(|(_, s)| **s == shard.index).map(|(j, _)| j.clone()).collect();
    Plan { jobs }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_and_name() {
        assert_eq!(Shard::parse("1/3"), Ok(Shard { index: 1, count: 3 }));
        assert_eq!(Shard::parse(" 0 / 1 "), Ok(Shard { index: 0, count: 1 }));
        assert_eq!(Shard::parse("2/3").unwrap().dir_name(), "shard-2-of-3");
        assert_eq!(Shard::parse("2/3").unwrap().to_string(), "2/3");
        assert!(Shard::parse("3/3").unwrap_err().contains("0 to 2 (0-based)"));
        assert!(Shard::parse("0/0").unwrap_err().contains("at least 1"));
        for bad in ["", "1", "a/3", "1/b", "-1/3", "1/3/4", "auto"] {
            assert!(Shard::parse(bad).unwrap_err().contains("K/N"), "{bad}");
        }
    }

    #[test]
    fn lpt_is_pinned() {
        // Longest first: 9 → s0, 7 → s1, 6 → s2, 5 → s2 (6 is least), 4 → s1 (7), 2 → s0 (9)…
        assert_eq!(assign(&[2, 9, 4, 7, 5, 6], 3), vec![0, 0, 1, 1, 2, 2]);
        // Ties go to the earlier item and the lower shard.
        assert_eq!(assign(&[1, 1, 1, 1], 2), vec![0, 1, 0, 1]);
        assert_eq!(assign(&[5, 5], 1), vec![0, 0]);
        // More shards than work: the rest stay empty.
        assert_eq!(assign(&[3], 4), vec![0]);
        assert!(assign(&[], 3).is_empty());
    }

    #[test]
    fn lpt_balances_within_four_thirds_of_the_best() {
        let costs: Vec<u64> = (1..=40u64).map(|i| i * i * 37 % 1001 + 1).collect();
        for n in 1..=7u32 {
            let of = assign(&costs, n);
            let mut load = vec![0u64; n as usize];
            for (c, s) in costs.iter().zip(&of) {
                load[*s as usize] += c;
            }
            let total: u64 = costs.iter().sum();
            let lower = (total as f64 / n as f64).max(*costs.iter().max().unwrap() as f64);
            let worst = *load.iter().max().unwrap() as f64;
            assert!(worst <= 4.0 / 3.0 * lower + 1.0, "n {n}: {load:?}");
        }
    }

    #[test]
    fn cost_counts_timing_repeats_and_overhead() {
        assert_eq!(unit_cost(4, 100, 8, 3), 4 * 100 * (8 + OVERHEAD_RAYS_PER_PIXEL));
        assert_eq!(unit_cost(1, 100, 8, 3), 3 * 100 * (8 + OVERHEAD_RAYS_PER_PIXEL));
    }
}
