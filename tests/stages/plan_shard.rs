//! Shards (`hemilab run --shard K/N`): disjoint, covering, whole timing units, balanced by cost,
//! and pinned, so that shards started on different machines agree on the partition.

use crate::support::common;

use hemilab::plan::{Plan, plan};
use hemilab::shard::{self, Shard};
use hemilab::spec::parse_spec;
use std::collections::HashSet;
use std::path::Path;

fn plan_of(path: &Path, text: &str) -> Plan {
    plan(&parse_spec(text, path).unwrap_or_else(|e| panic!("{e}")))
}

fn paper() -> Plan {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/paper.toml");
    plan_of(&path, &std::fs::read_to_string(&path).unwrap())
}

fn tiny() -> Plan {
    plan_of(Path::new("tiny.toml"), &common::tiny_spec(64, ""))
}

/// Every spec here overrides the resolution; the scene's own is never asked for.
fn no_scene(_: &hemilab::plan::Job) -> [u32; 2] {
    panic!("the spec sets the resolution")
}

#[test]
fn shards_are_disjoint_cover_the_plan_and_keep_units_whole() {
    for p in [paper(), tiny()] {
        for n in 1..=9u32 {
            let mut seen = HashSet::new();
            let mut count = 0;
            for k in 0..n {
                let s = shard::select(&p, Shard::new(k, n).unwrap(), no_scene, 3);
                count += s.jobs.len();
                for j in &s.jobs {
                    assert!(seen.insert(j.key()), "job {} in two shards (n {n})", j.file_stem());
                }
                // Plan order is kept within a shard.
                let pos: Vec<usize> =
                    s.jobs.iter().map(|j| p.jobs.iter().position(|q| q == j).unwrap()).collect();
                assert!(pos.windows(2).all(|w| w[0] < w[1]));
            }
            assert_eq!(count, p.jobs.len(), "n {n}: every job once");
            let of = shard::partition(&p, n, no_scene, 3);
            for unit in shard::units(&p) {
                assert!(unit.iter().all(|&j| of[j] == of[unit[0]]), "n {n}: a unit is split");
            }
        }
    }
}

#[test]
fn paper_shards_are_balanced_by_cost() {
    let p = paper();
    let units = shard::units(&p);
    let cost = |u: &Vec<usize>| shard::unit_cost(u.len(), 160 * 120, p.jobs[u[0]].rays, 3);
    let total: u64 = units.iter().map(cost).sum();
    let biggest = units.iter().map(cost).max().unwrap();
    for n in [2u32, 3, 4, 8, 16] {
        let of = shard::partition(&p, n, no_scene, 3);
        let mut load = vec![0u64; n as usize];
        for u in &units {
            load[of[u[0]] as usize] += cost(u);
        }
        let ideal = (total as f64 / n as f64).max(biggest as f64);
        let worst = *load.iter().max().unwrap() as f64;
        assert!(worst <= 1.05 * ideal, "n {n}: loads {load:?}, ideal {ideal}");
    }
}

#[test]
fn a_sweep_is_split_by_cost_not_job_count() {
    // One row from 1 to 1024 rays: the 1024-ray unit alone costs about as much as all the others.
    let text = r#"
scenes = ["a.toml"]
resolution = [10, 10]
replicates = 4
[[convergence]]
name = "c"
rays = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024]
rows = [ { distribution = "sine-cosine", sequence = "fibonacci", seed_mode = "shift" } ]
"#;
    let p = plan_of(Path::new("s.toml"), text);
    let shards: Vec<Plan> =
        (0..2).map(|k| shard::select(&p, Shard::new(k, 2).unwrap(), no_scene, 3)).collect();
    let rays = |s: &Plan| s.jobs.iter().map(|j| j.rays as u64 + shard::OVERHEAD_RAYS_PER_PIXEL).sum::<u64>();
    let (a_jobs, b_jobs) = (shards[0].jobs.len(), shards[1].jobs.len());
    assert!(shards[0].jobs.iter().any(|j| j.rays == 1024));
    assert!(a_jobs <= 12 && b_jobs >= 32, "{a_jobs} and {b_jobs} jobs");
    let (a, b) = (rays(&shards[0]) as f64, rays(&shards[1]) as f64);
    assert!((a / b - 1.0).abs() < 0.05, "{a} vs {b}");
}

#[test]
fn tiny_partition_is_pinned() {
    // Units of the tiny spec and their costs (3 renders × 432 px × (rays + overhead)): the three
    // 4-ray units first, one per shard, then the 2-ray ones, then the 1-ray ones to the lightest.
    let p = tiny();
    let of = shard::partition(&p, 3, no_scene, 3);
    let brief = |k: u32| -> Vec<String> {
        p.jobs
            .iter()
            .zip(&of)
            .filter(|(_, s)| **s == k)
            .map(|(j, _)| {
                format!("{} {} {} {} {}", j.distribution, j.sequence, j.seed_mode, j.rays, j.replicate)
            })
            .collect()
    };
    assert_eq!(
        brief(0),
        [
            "uniform random rotation 2 0",
            "uniform random rotation 2 1",
            "uniform random rotation 4 0",
            "uniform random rotation 4 1",
            "sine-cosine fibonacci static 1 0",
            "sine-cosine fibonacci static 1 1",
        ]
    );
    assert_eq!(
        brief(1),
        [
            "sine-cosine fibonacci static 2 0",
            "sine-cosine fibonacci static 2 1",
            "sine-cosine fibonacci static 4 0",
            "sine-cosine fibonacci static 4 1",
            "sine-cosine fibonacci shift 1 0",
            "sine-cosine fibonacci shift 1 1",
        ]
    );
    assert_eq!(
        brief(2),
        [
            "sine-cosine fibonacci shift 2 0",
            "sine-cosine fibonacci shift 2 1",
            "sine-cosine fibonacci shift 4 0",
            "sine-cosine fibonacci shift 4 1",
        ]
    );
}
