//! The plan: union of tables and sweeps, duplicates merged, order stable, seeds independent of position.

use hemilab::plan::{Plan, estimate, format_jobs, plan, reference_jobs, reference_seed, replicate_seed};
use hemilab::spec::parse_spec;
use std::path::Path;

fn plan_of(text: &str) -> Plan {
    plan(&parse_spec(text, Path::new("exp/p.toml")).unwrap_or_else(|e| panic!("{e}")))
}

fn brief(p: &Plan) -> Vec<String> {
    p.jobs
        .iter()
        .map(|j| {
            format!(
                "{} {} {} {} {} {}",
                j.scene_name, j.distribution, j.sequence, j.seed_mode, j.rays, j.replicate
            )
        })
        .collect()
}

const SPEC: &str = r#"
scenes = ["a.toml", "b.toml"]
replicates = 2
resolution = [10, 5]
[[table]]
name = "t"
rays = [8, 16]
scenes = ["a"]
rows = [
  { distribution = "sine", sequence = "random" },
  { distribution = "sine-cosine", sequence = "fibonacci", seed_mode = "static" },
]
[[convergence]]
name = "c"
rays = [16, 32]
replicates = 3
rows = [
  { distribution = "sine", sequence = "random", seed_mode = "shift" },
  { distribution = "sine", sequence = "random", seed_mode = "static" },
]
"#;

#[test]
fn order_and_pruning_are_pinned() {
    let p = plan_of(SPEC);
    let expected = [
        // scene a: table t (rows × rays × replicates) …
        "a sine random rotation 8 0",
        "a sine random rotation 8 1",
        "a sine random rotation 16 0",
        "a sine random rotation 16 1",
        "a sine-cosine fibonacci static 8 0",
        "a sine-cosine fibonacci static 8 1",
        "a sine-cosine fibonacci static 16 0",
        "a sine-cosine fibonacci static 16 1",
        // … then sweep c: random+shift is random+rotation, so only what t lacks is new …
        "a sine random rotation 16 2",
        "a sine random rotation 32 0",
        "a sine random rotation 32 1",
        "a sine random rotation 32 2",
        // … static + random is a distinct (odd) estimator and stays.
        "a sine random static 16 0",
        "a sine random static 16 1",
        "a sine random static 16 2",
        "a sine random static 32 0",
        "a sine random static 32 1",
        "a sine random static 32 2",
        // scene b: table t is restricted to scene a, so only the sweep.
        "b sine random rotation 16 0",
        "b sine random rotation 16 1",
        "b sine random rotation 16 2",
        "b sine random rotation 32 0",
        "b sine random rotation 32 1",
        "b sine random rotation 32 2",
        "b sine random static 16 0",
        "b sine random static 16 1",
        "b sine random static 16 2",
        "b sine random static 32 0",
        "b sine random static 32 1",
        "b sine random static 32 2",
    ];
    assert_eq!(brief(&p), expected);
    let keys: std::collections::HashSet<String> = p.jobs.iter().map(|j| j.key()).collect();
    assert_eq!(keys.len(), p.jobs.len(), "keys must be unique");
}

#[test]
fn seeds_come_from_the_replicate_not_the_position() {
    let p = plan_of(SPEC);
    for j in &p.jobs {
        assert_eq!(j.seed, replicate_seed(1, j.replicate));
    }
    // Adding a table in front changes no existing job.
    let more = SPEC.replacen(
        "[[table]]",
        "[[table]]\nname = \"first\"\nrays = [2]\n\
         rows = [{ distribution = \"uniform\", sequence = \"sobol\" }]\n[[table]]",
        1,
    );
    let q = plan_of(&more);
    assert_eq!(q.jobs.len(), p.jobs.len() + 2 * 2);
    for j in &p.jobs {
        let same = q.jobs.iter().find(|k| k.key() == j.key()).expect("job kept");
        assert_eq!(same, j);
    }
}

#[test]
fn key_is_pinned() {
    // If this changes, every stored image and resume record is invalidated: bump the canonical
    // form's version on purpose, never by accident.
    let p = plan_of(SPEC);
    let j = &p.jobs[0];
    assert_eq!(
        j.canonical(),
        format!(
            "hemilab-job-v1;scene=a.toml;distribution=sine;sequence=random;seed_mode=rotation;rays=8;\
             replicate=0;seed={};resolution=10x5;ao_distance=scene",
            replicate_seed(1, 0)
        )
    );
    assert_eq!(replicate_seed(1, 0), 6791897765849424158, "seed derivation changed");
    assert_eq!(j.key(), "481a7ed8d2434d91");
    assert_eq!(j.key().len(), 16);
    assert!(j.file_stem().starts_with("a-sine-random-rotation-8r-0-"));
}

#[test]
fn estimate_counts_pixels_times_rays() {
    let p = plan_of(SPEC);
    let e = estimate(&p, |_| unreachable!("the spec sets the resolution"));
    let rays: u64 = p.jobs.iter().map(|j| 50 * j.rays as u64).sum();
    assert_eq!(e.total_rays, rays);
    assert_eq!(e.pixels, 50 * p.jobs.len() as u64);
    assert_eq!(e.jobs, 30);
    let text = format_jobs(&p);
    assert_eq!(text.lines().count(), 31, "{text}");
    for (i, j) in p.jobs.iter().enumerate() {
        assert!(text.lines().nth(i + 1).unwrap().trim_start().starts_with(&format!("{} ", i + 1)));
        assert!(text.contains(&j.key()));
    }
}

#[test]
fn scene_resolution_is_asked_for_when_not_overridden() {
    let p = plan_of(&SPEC.replace("resolution = [10, 5]\n", ""));
    assert!(p.jobs.iter().all(|j| j.resolution.is_none()));
    let e = estimate(&p, |j| if j.scene_name == "a" { [2, 2] } else { [1, 1] });
    let rays: u64 = p.jobs.iter().map(|j| if j.scene_name == "a" { 4 } else { 1 } * j.rays as u64).sum();
    assert_eq!(e.total_rays, rays);
}

#[test]
fn reference_jobs_use_their_own_seeds_and_the_reference_estimator() {
    let text = SPEC
        .replace("resolution = [10, 5]\n", "resolution = [10, 5]\n[reference]\nreplicates = 3\nseed = 9\n");
    let spec = parse_spec(&text, Path::new("exp/p.toml")).unwrap();
    let refs = reference_jobs(&spec, 1, 4096);
    assert_eq!(refs.len(), 3);
    for (i, j) in refs.iter().enumerate() {
        assert_eq!(j.scene_name, "b");
        assert_eq!(j.row(), spec.reference.estimator);
        assert_eq!((j.rays, j.replicate), (4096, i as u32));
        assert_eq!(j.seed, reference_seed(9, i as u32));
        assert_ne!(j.seed, replicate_seed(9, i as u32));
    }
    assert!(reference_jobs(&spec, 2, 4096).is_empty());
}

#[test]
fn realtime_order_is_pinned_and_single_frame_keys_stay() {
    let text = r#"
scenes = ["a.toml"]
replicates = 1
[[table]]
name = "rt"
rays = [1, 2]
distributions = ["sine-cosine"]
sequences = ["fibonacci"]
schedules = ["independent", "r1"]
pipelines = ["raw", "ema0.1+atrous"]
frames = 4
"#;
    let p = plan_of(text);
    let got: Vec<String> = p
        .jobs
        .iter()
        .map(|j| {
            format!(
                "{} {} {} f{}",
                j.measurement.schedule, j.rays, j.measurement.pipeline, j.measurement.frame
            )
        })
        .collect();
    let want = [
        "independent 1 raw f1",
        "independent 1 ema0.1+atrous f1",
        "independent 1 ema0.1+atrous f2",
        "independent 1 ema0.1+atrous f4",
        "independent 2 raw f1",
        "independent 2 ema0.1+atrous f1",
        "independent 2 ema0.1+atrous f2",
        "independent 2 ema0.1+atrous f4",
        "r1 1 raw f1",
        "r1 1 ema0.1+atrous f1",
        "r1 1 ema0.1+atrous f2",
        "r1 1 ema0.1+atrous f4",
        "r1 2 raw f1",
        "r1 2 ema0.1+atrous f1",
        "r1 2 ema0.1+atrous f2",
        "r1 2 ema0.1+atrous f4",
    ];
    assert_eq!(got, want);
    let keys: std::collections::HashSet<String> = p.jobs.iter().map(|j| j.key()).collect();
    assert_eq!(keys.len(), p.jobs.len(), "keys must be unique");
    // Each accumulated sequence is one series, rendered once by its frame-4 job; every other job
    // is a series of its own.
    let series = hemilab::plan::series(&p);
    let shape: Vec<(usize, Vec<usize>)> = series.iter().map(|s| (s.leader, s.members.clone())).collect();
    assert_eq!(
        shape,
        [
            (0, vec![0]),
            (3, vec![1, 2, 3]),
            (4, vec![4]),
            (7, vec![5, 6, 7]),
            (8, vec![8]),
            (11, vec![9, 10, 11]),
            (12, vec![12]),
            (15, vec![13, 14, 15]),
        ]
    );
    // A series is one timing unit (so one shard).
    for s in &series {
        let u = hemilab::plan::unit_key(&p.jobs[s.leader]);
        assert!(s.members.iter().all(|&i| hemilab::plan::unit_key(&p.jobs[i]) == u));
    }
    // The raw independent frame-1 job is the paper-table job: the same key as without the keys.
    let plain = plan_of(
        "scenes = [\"a.toml\"]\nreplicates = 1\n[[table]]\nname = \"rt\"\nrays = [1]\n\
         distributions = [\"sine-cosine\"]\nsequences = [\"fibonacci\"]\n",
    );
    assert!(p.jobs[0].measurement.is_single_frame());
    assert_eq!(p.jobs[0].key(), plain.jobs[0].key());
    assert!(!p.jobs[1].canonical().ends_with("ao_distance=scene"), "{}", p.jobs[1].canonical());
}
